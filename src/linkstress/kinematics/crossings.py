"""Steps of a sweep that pass a toggle or change point of a loop between two feasible samples.

A loop's closed form keeps one sign of its square root (``branch``). The discriminant under that
root (sin^2 of the four-bar's angle at B, cos^2 of the slider-crank's rod angle) vanishes only at
the loop's branch points, which are closed-form crank angles:

- a toggle, a simple zero: the discriminant changes sign and the loop cannot assemble just past
  it. Two feasible samples on either side mean the sweep jumped a gap the crank cannot turn through.
- a change point (all links aligned; Norton, Design of Machinery, sec. 2.13), a double zero: the
  discriminant touches zero and comes back, so both samples are feasible. A motion continuing
  smoothly through it changes the root's sign; a fixed root therefore continues in the other
  assembly mode, with a jump in every angular velocity across the step.

A step crosses a branch point when a 2 pi representative of the point's crank angle lies strictly
between the two samples' crank angles and both samples are feasible. A sample at the point itself is
infeasible and reported as such, so it is never also counted as a crossing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.results import Crossing

CHANGE_POINT_TOLERANCE = 1e-9
"""Lengths whose sums (S + L and P + Q, or the slider's |e -+ b| and a) agree to this fraction of
their total make a change-point linkage."""

KIND_CHANGE_POINT, KIND_TOGGLE = "change point", "toggle"
TURN = 2.0 * math.pi


@dataclass(frozen=True)
class BranchPoint:
    """A crank angle [rad] (ground frame) where the loop's two roots meet; ``kind`` is
    ``KIND_CHANGE_POINT`` (the loop assembles on both sides) or ``KIND_TOGGLE`` (on one side only)."""

    angle: float
    kind: str


def find_crossings(
    points: tuple[BranchPoint, ...],
    theta2: NDArray[np.float64],
    steps: NDArray[np.float64],
    valid: NDArray[np.bool_],
    branch: str,
    mode_side: NDArray[np.float64] | None = None,
    mode_names: tuple[str, str] | None = None,
) -> tuple[Crossing, ...]:
    """Every step k -> k + 1 between two ``valid`` samples that passes one of ``points`` strictly,
    ordered by row.

    theta2 (P,) [rad]: crank angles; steps (P - 1,) [rad]: how far the crank turns from each sample
    to the next (counter-clockwise positive); ``branch``: the root the loop follows. ``mode_side``
    (P,): where > 0 a row is in ``mode_names[0]``, else in ``mode_names[1]``."""
    lo = np.minimum(steps, 0.0)
    lo += theta2[:-1]
    hi = np.abs(steps)
    hi += lo
    pairs = valid[:-1] & valid[1:]
    first = np.empty_like(lo)  # reused: fresh (P,) temporaries per point cost more than the arithmetic
    over = np.empty(lo.shape, bool)
    found = []
    for point in points:
        np.subtract(lo, point.angle, out=first)
        first /= TURN
        np.floor(first, out=first)
        first += 1.0
        first *= TURN
        first += point.angle  # the point's lowest representative above lo
        np.less(first, hi, out=over)
        over &= pairs
        steps_over = np.flatnonzero(over)
        last = point.angle + TURN * (np.ceil((hi[steps_over] - point.angle) / TURN) - 1.0)
        angles = np.where(steps[steps_over] >= 0, first[steps_over], last)
        named = point.kind == KIND_CHANGE_POINT and mode_names is not None
        for row, angle in zip((steps_over + 1).tolist(), angles.tolist()):
            mode = (mode_names[0] if mode_side[row] > 0 else mode_names[1]) if named else ""
            found.append(Crossing(row, angle, point.kind, branch, mode, " or ".join(mode_names) if named else ""))
    return tuple(sorted(found, key=lambda crossing: (crossing.position, crossing.angle)))


def wrapped_steps(angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """Turns [rad] between consecutive angles known only modulo 2 pi, taken the short way."""
    return np.mod(np.diff(angle) + math.pi, TURN) - math.pi


def distinct_digits(first: float, second: float, least: int = 6) -> tuple[str, str]:
    """``first`` and ``second`` with at least ``least`` significant digits and as many more as it
    takes to tell them apart (179.9999999 and 180.0000001, not 180 and 180); 17 at most, which
    tells any two doubles apart."""
    for digits in range(least, 18):
        a, b = f"{first:.{digits}g}", f"{second:.{digits}g}"
        if a != b:
            return a, b
    return a, b


ROOT_SIDES = {
    "four-bar": {"open": "B left of A -> O4", "crossed": "B right of A -> O4"},
    "slider-crank": {
        "open": "slider ahead of the crank pin along the line",
        "crossed": "slider behind the crank pin along the line",
    },
}


def describe(mechanism: str, kind: str, crossing: Crossing, before_deg: float, after_deg: float, main: bool) -> str:
    """One line saying which loop crossed what between which input angles [deg], and what the rows
    from there follow. ``main``: the loop's crank is the machine's input, so the crossed crank
    angle is an input angle; a driven loop's is its own crank's angle."""
    point = math.degrees(crossing.angle)
    where = f"at input {point:.6g} deg" if main else f"(its crank at {point % 360.0:.6g} deg)"
    other = "crossed" if crossing.root == "open" else "open"
    root = f"the {crossing.root} root ({ROOT_SIDES[kind][crossing.root]})"
    before, after = distinct_digits(before_deg, after_deg)
    between = f"between input {before} and {after} deg"
    head = f"mechanism {mechanism}: {crossing.kind} {where} crossed {between}: "
    if crossing.kind == KIND_TOGGLE:
        return head + (
            "the loop cannot assemble just past a toggle, so the crank cannot turn this way from the row "
            f"before to this one (it stops and reverses at the toggle); rows from here follow {root}"
        )
    modes = f" ({crossing.modes})" if crossing.modes else ""
    mode = f"the {crossing.mode} mode" if crossing.mode else "the other assembly mode than the rows before"
    return head + (
        f"all links align there and the linkage can leave it in either assembly mode{modes}; rows from "
        f"here follow {root}, which is {mode} (a smooth motion through the change point would continue "
        f"on the {other} root): angular velocities and joint forces jump across this step; to follow "
        f"the smooth motion instead, analyze the rows from here with mechanisms.{mechanism}.branch = \"{other}\""
    )
