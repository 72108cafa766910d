"""Following the drawn assembly along a sweep: every group in order over the whole input path.

The path runs from the drawn input (the crank's angle as drawn, taken the short way round to the
first sample; or the slider's stroke as drawn) through every sample in the order given. Where a step
between neighbours is longer than ``MAX_STEP`` the path gets points between them, so that 30 deg
samples follow the same assembly as 1 deg ones and a sweep may start away from the drawn input. The
closed-form dyads keep their drawn assembly sign over the whole path; other groups are continued by
Newton in blocks (``triads``). Rows are flagged as ``flags`` says.

The path is solved a block of ``BLOCK`` positions at a time, the blocks spread over the machine's
cores (``linkstress.threads``): each block's temporaries stay in the core's cache, and a sweep's
memory is touched once, where the results are written. A linkage of closed-form groups only is
solved in one pass, every group in turn on each block, its rates seeded with the input's speed and
acceleration (rates per unit time: no chain rule afterwards), and written straight to the link
motions. A linkage with a Newton group keeps every link's pose along the path (``PathTracks``), as
the Newton continuation reads it anywhere, with rates per unit input, and writes the link motions
in a last pass by the chain rule.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.blockwork import plan, run
from linkstress.kinematics.linkage.constraints import GroupEquations
from linkstress.kinematics.linkage.flags import TOGGLE, PathFlags, messages, newton_events
from linkstress.kinematics.linkage.graph import Joint, LinkageGraph
from linkstress.kinematics.linkage.groups import Group
from linkstress.kinematics.linkage.outputs import Outputs, pin_keys
from linkstress.kinematics.linkage.placing import Block, Rider, placer
from linkstress.kinematics.linkage.rates import group_rates
from linkstress.kinematics.linkage.tracks import PathTracks, Track
from linkstress.kinematics.linkage.triads import march
from linkstress.kinematics.motion import InputMotion
from linkstress.kinematics.results import JointMotion, LinkMotion, MachineMotion
from linkstress.threads import in_parallel

FloatArray = NDArray[np.float64]

MAX_STEP = (math.radians(2.0), 0.005)
"""The longest step of the path: 2 deg of a crank; for a stroke, this fraction of the mechanism's size."""
BLOCK = 16384
"""Path positions solved together: a block's few hundred temporaries stay in a core's cache."""


@dataclass(frozen=True)
class Path:
    """The input path ``x`` (F,): the drawn input first, then the samples with points between;
    ``rows`` (P,) the path index of each sample; ``step_of`` (F,) the sample row whose step holds each
    path point (-1 for the drawn pose)."""

    x: FloatArray
    rows: NDArray[np.intp]
    step_of: NDArray[np.intp]


def input_path(drawn: float, samples: FloatArray, longest: float, periodic: bool) -> Path:
    """The path from ``drawn`` through ``samples`` (P,), no step longer than ``longest``; a
    ``periodic`` input (an angle [rad]) goes from the drawn one to the first sample the short way."""
    start = samples[0] + math.remainder(drawn - samples[0], 2 * math.pi) if periodic else drawn
    knots = np.concatenate([[start], samples])
    deltas = np.diff(knots)
    if max(deltas.max(), -deltas.min()) <= longest:  # a dense sweep: the samples themselves
        return Path(knots, np.arange(1, len(knots)), np.arange(-1, len(samples)))
    pieces = np.maximum(np.ceil(np.abs(deltas) / longest).astype(np.intp), 1)
    ends = np.cumsum(pieces)
    step_of = np.repeat(np.arange(len(samples)), pieces)
    within = np.arange(len(step_of)) - np.repeat(ends - pieces, pieces) + 1
    x = np.concatenate([[start], knots[step_of] + within / pieces[step_of] * deltas[step_of]])
    x[ends] = samples
    return Path(x, ends, np.concatenate([[-1], step_of]))


@dataclass(frozen=True)
class LinkageMotion:
    """A linkage over P positions: the graph, its groups in solving order and every link's motion.

    ``joints["LINK:i"]``: every link joint's motion (ground frame); ``strokes[k]``: slider k's
    point along its line from the line's joint i, + toward j [m], with its velocity [m/s] and
    acceleration [m/s^2] (P,) each. Both are made when first read."""

    graph: LinkageGraph
    groups: tuple[Group, ...]
    links: dict[str, LinkMotion]

    @cached_property
    def joints(self) -> dict[str, JointMotion]:
        joints = {}
        for name, motion in self.links.items():
            for k, local in enumerate(self.graph.local[name]):
                joints[str(Joint(name, k))] = JointMotion(*motion.point(local))
        return joints

    @cached_property
    def strokes(self) -> tuple[tuple[FloatArray, FloatArray, FloatArray], ...]:
        return tuple(_stroke(self.graph, k, self.links, self.joints) for k in range(len(self.graph.sliders)))

    @cached_property
    def pin_positions(self) -> tuple[FloatArray, ...]:
        """Each of ``graph.all_pins``' position (P, 2) [m]: its first joint's."""
        return tuple(self.joints[str(pin[0])].position for pin in self.graph.all_pins)


def solve_linkage(graph: LinkageGraph, motion: InputMotion) -> MachineMotion:
    """Positions, velocities and accelerations of every link and joint of ``graph`` over ``motion``
    (the crank's angles [rad], or the input slider's strokes [m], with their rates)."""
    with np.errstate(invalid="ignore", divide="ignore"):  # where a group cannot close: nan, then flagged
        return _solve(graph, motion)


def _solve(graph: LinkageGraph, motion: InputMotion) -> MachineMotion:
    stroke = graph.input.is_stroke
    drawn = graph.drawn_stroke(graph.sliders[graph.input.slider]) if stroke else _drawn_angle(graph)
    path = input_path(drawn, motion.angle, MAX_STEP[1] * graph.size if stroke else MAX_STEP[0], not stroke)
    if all(group.closed_form for group in graph.groups):
        sweep = _Sweep(graph, path, motion)
        sweep.closed_forms(range(len(graph.groups)), outputs=True)
        return sweep.machine_motion()
    shortest = MIN_STEP * (graph.size if stroke else 1.0)
    for round_ in range(REFINEMENTS + 1):
        sweep = _Sweep(graph, path, motion, along_path=True)
        lost = sweep.staged()
        lost = lost[np.abs(path.x[lost] - path.x[lost - 1]) > shortest]
        if not len(lost) or round_ == REFINEMENTS:
            break
        path = refined(path, lost)
    sweep.write_outputs()
    return sweep.machine_motion()


REFINEMENTS = 12
"""Times the path may be refined where a Newton group lost its assembly within one step."""
MIN_STEP = 1e-4
"""A step no shorter than this (rad, or times the mechanism's size for a stroke) is not refined."""


def refined(path: Path, steps: NDArray[np.intp]) -> Path:
    """``path`` with a point halfway along each step into the path indices ``steps``."""
    at = np.sort(steps)
    x = np.insert(path.x, at, 0.5 * (path.x[at - 1] + path.x[at]))
    step_of = np.insert(path.step_of, at, path.step_of[at])
    rows = path.rows + np.searchsorted(at, path.rows, side="right")
    return Path(x, rows, step_of)


class _Sweep:
    """One solve of ``graph`` over ``path``: the groups' flags, the link motions at the samples and,
    ``along_path``, every link's pose along the path (rates per unit input)."""

    def __init__(self, graph: LinkageGraph, path: Path, motion: InputMotion, along_path: bool = False) -> None:
        self.graph, self.path, self.motion = graph, path, motion
        self.groups = graph.groups
        self.pin_of = pin_keys(graph)
        n_path = len(path.x)
        self.flags = PathFlags(self.groups, n_path)
        self.ground = Track.ground(graph.drawn_angles[graph.ground], graph.links[graph.ground][0])
        self.store = PathTracks(graph.moving, graph.ground, graph.drawn_angles[graph.ground],
                                graph.links[graph.ground][0], n_path) if along_path else None
        self.outputs = Outputs(graph, self.pin_of, len(path.rows))
        self.events: list[tuple[int, str]] = []
        self.blocks = [slice(lo, min(lo + BLOCK, n_path)) for lo in range(0, n_path, BLOCK)]

    def closed_forms(self, indices, outputs: bool = False) -> None:
        """Place the closed-form groups ``indices`` (and their riders) on every block; write their
        links to the store (along the path) or, ``outputs``, to the link motions."""
        items = [(g, placer(self.graph, self.groups[g]), tuple(Rider(self.graph, r) for r in self.groups[g].riders))
                 for g in indices]
        for g in indices:
            if self.groups[g].kind != "crank":
                self.flags.expect(g)
        self._run(plan(items), outputs)
        for g in indices:
            if self.groups[g].kind != "crank":
                self.events += self.flags.dyad_events(g, self.path)

    def _run(self, steps, outputs: bool = False) -> None:
        """``steps`` on every block, on every core."""
        tiny = {step.group: TOGGLE * _scale(self.graph, self.groups[step.group]) for step in steps}

        def work(rows: slice) -> None:
            samples, local = self.samples(rows)
            block = self.block(rows, samples, local)
            if outputs:
                def hand_on(block, links):
                    if samples.stop > samples.start:
                        self.outputs.write(block, links, samples, local)
            else:
                def hand_on(block, links):
                    for name in links:
                        self.store.store(name, rows, block.track(name), block.joint(Joint(name, 0)))
            bad = run(block, steps, hand_on, lambda g, closure: self.flags.record(g, rows, closure, tiny[g]))
            if outputs and bad is not None and samples.stop > samples.start:
                self.outputs.fill(samples, bad[local])

        in_parallel(work, self.blocks)

    def samples(self, rows: slice) -> tuple[slice, slice | NDArray[np.intp]]:
        """The samples whose path positions lie in ``rows`` (consecutive) and those positions'
        indices in the block (a slice where they are consecutive)."""
        at = self.path.rows
        k0, k1 = np.searchsorted(at, [rows.start, rows.stop])
        local = at[k0:k1] - rows.start
        if k1 > k0 and local[-1] - local[0] == k1 - k0 - 1:
            local = slice(int(local[0]), int(local[-1]) + 1)
        return slice(int(k0), int(k1)), local

    def block(self, rows: slice, samples: slice, local) -> Block:
        """A block over path positions ``rows``: its rates per unit input along the path, else per
        unit time (the input's speed and acceleration at the samples, 0 between them)."""
        if self.store is not None:
            seed1, seed2 = 1.0, 0.0
        elif isinstance(local, slice) and local == slice(0, rows.stop - rows.start):
            seed1, seed2 = self.motion.speed[samples], self.motion.acceleration[samples]
        else:
            seed1, seed2 = np.zeros(rows.stop - rows.start), np.zeros(rows.stop - rows.start)
            seed1[local], seed2[local] = self.motion.speed[samples], self.motion.acceleration[samples]
        load = None if self.store is None else (lambda name: self.store.window(name, rows))
        return Block(self.graph, self.pin_of, self.path.x[rows], seed1, seed2, {self.graph.ground: self.ground}, load)

    def staged(self) -> NDArray[np.intp]:
        """Every group in order along the path, the closed-form ones a run at a time; the path
        indices where a Newton group failed right after a position where it closed."""
        lost = np.zeros(0, np.intp)
        run: list[int] = []
        for g, group in enumerate(self.groups):
            if group.closed_form:
                run.append(g)
                continue
            if run:
                self.closed_forms(run)
                run = []
            lost = np.union1d(lost, self.newton(g))
        if run:
            self.closed_forms(run)
        return lost

    def newton(self, g: int) -> NDArray[np.intp]:
        """Newton group g continued along the path, its poses and rates stored, its riders placed."""
        graph, group, path, store = self.graph, self.groups[g], self.path, self.store
        closed = self.flags.closed(g)
        marched = march(graph, group, store, path.x, _start(graph, group), graph.size if graph.input.is_stroke else 1.0,
                        closed)
        failed = closed & ~marched.closed
        lost = 1 + np.flatnonzero(failed[1:] & marched.closed[:-1])
        fails = _newton_rates(graph, group, store, marched)
        self.flags.mark(g, slice(None), fails)
        self.events += newton_events(group, path, marched.restarts, _jacobian_flips(graph, group, store, path, marched,
                                                                                   fails), fails)
        if group.riders:
            self._run(plan([(g, None, tuple(Rider(graph, r) for r in group.riders))]))
        return lost

    def write_outputs(self) -> None:
        """The link motions at the samples from the stored poses, by the chain rule."""
        feasible = self.flags.closed()

        def work(rows: slice) -> None:
            samples, local = self.samples(rows)
            if samples.stop == samples.start:
                return
            block = self.block(rows, samples, local)
            scale = (self.motion.speed[samples], self.motion.acceleration[samples])
            self.outputs.write(block, self.graph.moving, samples, local, scale)
            self.outputs.fill(samples, ~feasible[rows][local])

        in_parallel(work, self.blocks)

    def machine_motion(self) -> MachineMotion:
        graph, path, motion = self.graph, self.path, self.motion
        feasible = self.flags.closed()[path.rows] if self.flags.fails else np.ones(len(path.rows), bool)
        unit = "m" if graph.input.is_stroke else "deg"
        values = motion.angle if graph.input.is_stroke else motion.angle_deg
        crossings = messages(graph.name, self.events, feasible, lambda row: _step_text(row, unit, values))
        if feasible.all():
            reasons = ("",) * len(path.rows)
        else:
            reasons = tuple(np.asarray(self.flags.texts, dtype=object)[self.flags.status()[path.rows]].tolist())
        links = self.outputs.motions(motion, feasible)
        return MachineMotion(
            motion.angle, motion.speed, motion.acceleration, motion.time, feasible, reasons, links, {},
            crossings, linkage=LinkageMotion(graph, self.groups, links),
        )


def _drawn_angle(graph: LinkageGraph) -> float:
    joints = graph.links[graph.input.link]
    d = joints[graph.input.to] - joints[graph.input.pivot]
    return math.atan2(d[1], d[0])


def _scale(graph: LinkageGraph, group: Group) -> float:
    """The square of the largest distance between the group's links' joints [m^2]."""
    points = np.vstack([graph.local[name] for name in group.links])
    return max(float(np.ptp(points, axis=0).max()), graph.size * 1e-6) ** 2 * 4


def _start(graph: LinkageGraph, group: Group) -> FloatArray:
    """The group's drawn coordinates (3 n,): each link's origin and frame angle."""
    return np.concatenate([[*graph.links[name][0], graph.drawn_angles[name]] for name in group.links])


def _newton_rates(graph, group, store: PathTracks, marched) -> NDArray[np.bool_]:
    """Write a Newton group's poses and rates (per unit input) to the store; where it fails (F,)."""
    rows = np.flatnonzero(marched.closed)
    good = np.zeros(len(marched.q), bool)
    for name in group.links:
        for array in store.arrays[name].values():
            array[~marched.closed] = np.nan
    if len(rows):
        q = marched.q[rows]
        q1, q2, regular, _ = group_rates(GroupEquations(graph, group, store, rows), q)
        for k, name in enumerate(group.links):
            a, c = store.arrays[name], 3 * k
            angle = np.remainder(q[:, c + 2] + np.pi, 2 * np.pi) - np.pi
            for field, value in (("angle", angle), ("cos", np.cos(angle)), ("sin", np.sin(angle)),
                                 ("x", q[:, c]), ("y", q[:, c + 1]), ("w", q1[:, c + 2]), ("x1", q1[:, c]),
                                 ("y1", q1[:, c + 1]), ("al", q2[:, c + 2]), ("x2", q2[:, c]), ("y2", q2[:, c + 1])):
                a[field][rows] = value
        good[rows] = regular & np.all(np.isfinite(q1) & np.isfinite(q2), axis=1)
    return ~good


def _jacobian_flips(graph, group, store, path, marched, fails) -> list[int]:
    """The path indices where a Newton group's Jacobian changes sign from the position before."""
    good = np.flatnonzero(~fails)
    if len(good) <= 1:
        return []
    _, jacobian = GroupEquations(graph, group, store, good).residual_jacobian(marched.q[good], path.x[good])
    sign = np.sign(np.linalg.det(jacobian))
    flips = np.flatnonzero((sign[1:] != sign[:-1]) & (good[1:] == good[:-1] + 1))
    return [int(good[k + 1]) for k in flips.tolist()]


def _step_text(row: int, unit: str, values: FloatArray) -> str:
    before = "the drawn pose" if row == 0 else f"input {values[row - 1]:.6g} {unit}"
    return f"the step from {before} to input {values[row]:.6g} {unit}"


def _stroke(graph: LinkageGraph, k: int, links: dict[str, LinkMotion], joints: dict[str, JointMotion]):
    """Slider k's stroke [m] and its rates along its line: s = u.(P - Q)."""
    slider = graph.sliders[k]
    i, j = slider.line
    local = graph.local[slider.on]
    direction = local[j] - local[i]
    guide = links[slider.on]
    q, qv, qa = guide.point(local[i])
    u_point = guide.point(local[i] + direction / math.hypot(*direction))
    u = u_point[0] - q
    u_rate = u_point[1] - qv
    u_acc = u_point[2] - qa
    point = joints[str(slider.point)]
    d, dv, da = point.position - q, point.velocity - qv, point.acceleration - qa

    def dot(a, b):
        return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]

    return dot(u, d), dot(u_rate, d) + dot(u, dv), dot(u_acc, d) + 2 * dot(u_rate, dv) + dot(u, da)
