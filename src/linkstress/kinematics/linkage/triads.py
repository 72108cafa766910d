"""Where a triad (or any group without a closed form) is solved: Newton on its constraints,
continued along the input path from the drawn pose.

A class-3 group (a floating ternary link held by three binary links, as in the Acimep eight-link
mechanism) has no practical closed form (the reference's "Class 3"). Its 3 n pose coordinates are
found by Newton-Raphson on its equations (``constraints``), vectorised over a block of positions at
once. Each block starts from a Taylor prediction about the last solved position,
q(x) = q(x0) + q'(x0) (x - x0) + q''(x0) (x - x0)^2 / 2, with q' and q'' exact (``rates``): the
assembly is continued, not guessed. A block is taken when every position converges near its
prediction; else the leading good positions are taken and the span halves. A position that cannot
be solved from the last solved one even over a tiny span cannot close: it is infeasible, and the
next position that solves again is flagged (``restarts``), never silently taken as the same
assembly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.linkage.constraints import GroupEquations
from linkstress.kinematics.linkage.graph import LinkageGraph
from linkstress.kinematics.linkage.groups import Group
from linkstress.kinematics.linkage.rates import batched_solve, group_rates
from linkstress.kinematics.linkage.tracks import PathTracks

FloatArray = NDArray[np.float64]

ITERATIONS = 30
RESIDUAL = 1e-13
"""Converged when every equation's residual is below this fraction of the mechanism's size (angles
enter the pin equations through lever arms of that size)."""
SPANS = (0.1, 0.5, 1e-6)
"""The block's reach from the last solved position: first, largest and smallest, in input units
(rad for an angle; for a stroke, times the mechanism's size)."""
JUMP = (0.1, 0.3)
"""A solution further than this from its prediction (fraction of the mechanism's size for the
origins, rad for the angles) is another assembly, not the continued one."""
MAX_BLOCK = 65536


@dataclass(frozen=True)
class Marched:
    """The group's coordinates (F, m) along the path, where it closed (F,), and the path indices
    where it solved again after positions where it could not (``restarts``)."""

    q: FloatArray
    closed: NDArray[np.bool_]
    restarts: tuple[int, ...]


def newton(equations: GroupEquations, guess: FloatArray, x: FloatArray, size: float) -> tuple[FloatArray, NDArray[np.bool_]]:
    """The group's coordinates (B, m) from ``guess`` by Newton-Raphson, and where it converged (B,)."""
    q = guess.copy()
    tolerance = RESIDUAL * size
    done = np.zeros(len(q), bool)
    for _ in range(ITERATIONS):
        residual, jacobian = equations.residual_jacobian(q, x)
        done = np.all(np.abs(residual) <= tolerance, axis=1)
        if done.all():
            break
        step, good = batched_solve(jacobian, -residual)
        move = good & ~done & np.all(np.isfinite(step), axis=1)
        if not move.any():
            break
        q[move] += step[move]
    # one more step where converged: quadratic convergence takes the residual to round-off
    residual, jacobian = equations.residual_jacobian(q, x)
    step, good = batched_solve(jacobian, -residual)
    polish = done & good & np.all(np.isfinite(step), axis=1)
    q[polish] += step[polish]
    return q, done & np.all(np.isfinite(q), axis=1)


def march(graph: LinkageGraph, group: Group, tracks: PathTracks, x: FloatArray, start: FloatArray,
          unit: float, usable: NDArray[np.bool_]) -> Marched:
    """Solve ``group`` along the input path ``x`` (F,) from the drawn coordinates ``start`` (m,) at
    ``x[0]``, at the positions where the links before it are ``usable`` (F,); ``unit`` scales the
    spans (1 for an angle, the mechanism's size for a stroke)."""
    size = graph.size
    n, m = len(x), len(start)
    q = np.full((n, m), np.nan)
    closed = np.zeros(n, bool)
    first, ok = newton(GroupEquations(graph, group, tracks, np.array([0])), start[None, :], x[:1], size)
    if not ok[0]:
        raise LinkageError(f"{graph.key}: the {group.label} does not close at the drawn pose; check its joints")
    q[0], closed[0] = first[0], True
    where = np.flatnonzero(usable)
    where = where[where > 0]
    anchor, taylor = 0, _taylor(graph, group, tracks, q, 0)
    span, largest, smallest = (s * unit for s in SPANS)
    restarts: list[int] = []
    gap = False
    i = 0
    while i < len(where):
        gap = gap or where[i] != anchor + 1 and not closed[where[i] - 1]
        window = np.abs(x[where[i:i + MAX_BLOCK]] - x[anchor])
        beyond = np.flatnonzero(window > span)
        stop = i + max(int(beyond[0]) if len(beyond) else len(window), 1)
        if gap:
            stop = i + 1
        rows = where[i:stop]
        dx = (x[rows] - x[anchor])[:, None]
        if gap:  # across positions where it could not close: from the last closed pose
            guess = np.broadcast_to(q[anchor], (len(rows), m)).copy()
        else:
            guess = q[anchor] + dx * taylor[0] + 0.5 * dx * dx * taylor[1]
        solution, converged = newton(GroupEquations(graph, group, tracks, rows), guess, x[rows], size)
        good = converged & (gap | _near(solution, guess, group, size))
        lead = int(np.argmin(good)) if not good.all() else len(good)
        if lead:
            q[rows[:lead]], closed[rows[:lead]] = solution[:lead], True
            if gap:
                restarts.append(int(rows[0]))
            gap = False
            anchor = int(rows[lead - 1])
            taylor = _taylor(graph, group, tracks, q, anchor)
            i += lead
            span = min(2 * span, largest) if lead == len(good) else max(span / 2, smallest)
        elif len(rows) > 1 and span > smallest:
            span = max(span / 2, smallest)
        else:
            gap = True
            i += 1
    return Marched(q, closed, tuple(restarts))


def _taylor(graph, group, tracks, q, row) -> tuple[FloatArray, FloatArray]:
    q1, q2, good, _ = group_rates(GroupEquations(graph, group, tracks, np.array([row])), q[row:row + 1])
    if not good[0]:
        return np.zeros(q.shape[1]), np.zeros(q.shape[1])
    return q1[0], q2[0]


def _near(solution: FloatArray, guess: FloatArray, group: Group, size: float) -> NDArray[np.bool_]:
    """Where the solution (B, m) is the continued assembly: near its prediction."""
    jump = np.abs(solution - guess)
    origins = jump.reshape(len(jump), -1, 3)[..., :2].max(axis=(1, 2))
    angles = jump.reshape(len(jump), -1, 3)[..., 2].max(axis=1)
    return (origins <= JUMP[0] * size) & (angles <= JUMP[1])
