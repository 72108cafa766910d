"""Following the drawn assembly along a sweep: every group in order over the whole input path.

The path runs from the drawn input (the crank's angle as drawn, taken the short way round to the
first sample; or the slider's stroke as drawn) through every sample in the order given. Where a step
between neighbours is longer than ``MAX_STEP`` the path gets points between them, so that 30 deg
samples follow the same assembly as 1 deg ones and a sweep may start away from the drawn input. The
closed-form dyads keep their drawn assembly sign over the whole path in one vectorised pass; other
groups are continued by Newton in blocks (``triads``).

Each sample row is flagged, naming the group's links:

- infeasible where a group cannot close, or at a toggle (its rate equations singular);
- a warning where the step into it (from the previous sample, or from the drawn pose for the first)
  passes a change point of a group (a dyad's clearance dips to zero and back: its height h, the
  square root of the clearance, comes down to zero in a V within a sampling step; a Newton group's
  Jacobian changes sign), or passes inputs where a group cannot close, or where a Newton group
  solved again after positions where it could not. The rows keep the drawn assembly of closed-form
  groups; nothing switches assembly without a flag.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.constraints import GroupEquations
from linkstress.kinematics.linkage.graph import Joint, LinkageGraph
from linkstress.kinematics.linkage.groups import Group
from linkstress.kinematics.linkage.placing import Placer
from linkstress.kinematics.linkage.rates import SINGULAR, group_rates
from linkstress.kinematics.linkage.tracks import Track
from linkstress.kinematics.linkage.triads import march
from linkstress.kinematics.motion import InputMotion
from linkstress.kinematics.results import JointMotion, LinkMotion, MachineMotion, fixed_link
from linkstress.threads import cores, even_blocks, in_parallel

FloatArray = NDArray[np.float64]

MAX_STEP = (math.radians(2.0), 0.005)
"""The longest step of the path: 2 deg of a crank; for a stroke, this fraction of the mechanism's size."""
TOGGLE = 1e-12
"""A clearance below this fraction of the group's size squared, or rate equations conditioned worse
than ``rates.SINGULAR``, is a toggle."""
V_DEPTH = 0.5
"""A dyad's height whose V-shaped dip reaches within this fraction of one sampling step's change of
zero passes (or grazes) a change point."""


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
    if np.abs(deltas).max() <= longest:  # a dense sweep: the samples themselves
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
    shortest = MIN_STEP * (graph.size if stroke else 1.0)
    for round_ in range(REFINEMENTS + 1):
        solved = _solve_path(graph, path, stroke)
        lost = solved[-1]
        lost = lost[np.abs(path.x[lost] - path.x[lost - 1]) > shortest]
        if not len(lost) or round_ == REFINEMENTS:
            break
        path = refined(path, lost)
    return _machine_motion(graph, graph.groups, *solved[:-1], path, motion)


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


def _solve_path(graph: LinkageGraph, path: Path, stroke: bool):
    """Every group over ``path``: (tracks, closed, status, texts, events, lost) with ``lost`` the path
    indices where a Newton group failed right after a position where it closed."""
    n_path = len(path.x)
    tracks = {name: Track.empty(n_path) for name in graph.links}
    tracks[graph.ground] = Track.fixed(graph.drawn_angles[graph.ground], graph.links[graph.ground][0], n_path)
    placer = Placer(graph, tracks)
    closed = np.ones(n_path, bool)
    status = np.zeros(n_path, np.intp)
    texts = [""]
    events: list[tuple[int, str]] = []
    lost = np.zeros(0, np.intp)
    for group in graph.groups:
        if group.closed_form:
            fails, toggles, height = _placed(placer, group, path.x, TOGGLE * _scale(graph, group))
            if group.kind != "crank":
                events += _dyad_events(path, height, fails, group)
            reasons = np.where(toggles, 2, 1)
        else:
            marched = march(graph, group, tracks, path.x, _start(graph, group), graph.size if stroke else 1.0, closed)
            failed = closed & ~marched.closed
            lost = np.union1d(lost, 1 + np.flatnonzero(failed[1:] & marched.closed[:-1]))
            fails = _newton_rates(graph, group, tracks, marched)
            events += _newton_events(graph, group, tracks, path, marched, fails)
            reasons = np.ones(n_path, np.intp)
        for block in group.riders:
            in_parallel(lambda rows, block=block: placer.ride(block, rows), _blocks(n_path))
        new = closed & fails
        if new.any():
            base = len(texts)
            texts += [f"the {group.label} cannot close", f"toggle of the {group.label}: its rates are unbounded"]
            status[new] = base + reasons[new] - 1
        closed &= ~fails
    return tracks, closed, status, texts, events, lost


CHUNK = 16384
"""Path positions placed together: a closed-form group's temporaries of a chunk stay in the
processor's cache (a million positions at once ran 16 times slower than 100,000)."""


def _blocks(count: int) -> list[slice]:
    """The path's positions in chunks of at most ``CHUNK``, at least one per core."""
    return even_blocks(count, max(cores(), -(-count // CHUNK)) if count >= CHUNK else 1)


def _placed(placer: Placer, group: Group, x: FloatArray, tiny: float):
    """A closed-form group placed over the whole path, chunk by chunk on every core. Where it
    fails (F,): it cannot close (clearance < 0), or at a toggle (``toggles``: clearance below
    ``tiny`` [m^2], or its rate equations singular); and its height (F,) [m], the clearance's square
    root, for the change points."""
    fails, toggles, height = np.empty(len(x), bool), np.empty(len(x), bool), np.empty(len(x))

    def work(rows: slice) -> None:
        clearance, ratio = placer.place(group, x, rows)
        toggle = (np.abs(clearance) <= tiny) | ~(ratio > SINGULAR)
        fails[rows] = toggle | ~(clearance >= 0)
        toggles[rows] = toggle & (clearance >= 0)
        height[rows] = np.sqrt(np.maximum(clearance, 0.0))

    in_parallel(work, _blocks(len(x)))
    return fails, toggles, height


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


def _newton_rates(graph, group, tracks, marched) -> NDArray[np.bool_]:
    """Write a Newton group's poses and rates to its tracks; where it fails (F,)."""
    rows = np.flatnonzero(marched.closed)
    good = np.zeros(len(marched.q), bool)
    for name in group.links:
        t = tracks[name]
        for array in (t.angle, t.origin, t.angle1, t.origin1, t.angle2, t.origin2, t.cos, t.sin):
            array[~marched.closed] = np.nan
    if len(rows):
        q = marched.q[rows]
        q1, q2, regular, _ = group_rates(GroupEquations(graph, group, tracks, rows), q)
        for k, name in enumerate(group.links):
            t, c = tracks[name], 3 * k
            t.origin[rows] = q[:, c:c + 2]
            t.set_angle(rows, np.remainder(q[:, c + 2] + np.pi, 2 * np.pi) - np.pi)
            t.origin1[rows], t.angle1[rows] = q1[:, c:c + 2], q1[:, c + 2]
            t.origin2[rows], t.angle2[rows] = q2[:, c:c + 2], q2[:, c + 2]
        good[rows] = regular & np.all(np.isfinite(q1) & np.isfinite(q2), axis=1)
    return ~good


def _step_text(path: Path, row: int, unit: str, values: FloatArray) -> str:
    before = "the drawn pose" if row == 0 else f"input {values[row - 1]:.6g} {unit}"
    return f"the step from {before} to input {values[row]:.6g} {unit}"


def _dyad_events(path: Path, height: FloatArray, fails: NDArray[np.bool_], group: Group) -> list[tuple[int, str]]:
    """(sample row, what) for steps passing a change point of a closed-form group, or inputs where
    it cannot close, between two samples where it closes."""
    events = []
    inside = np.ones(len(path.x), bool)
    inside[path.rows] = False
    inside[0] = False
    for row in np.unique(path.step_of[inside & fails]).tolist():
        events.append((row, "gap"))
    h, x = height, path.x
    if len(h) >= 5:
        mid = 1 + np.flatnonzero((h[1:-1] < h[:-2]) & (h[1:-1] <= h[2:]))
        mid = mid[(mid >= 2) & (mid <= len(h) - 3)]
        window = np.stack([mid - 2, mid - 1, mid, mid + 1, mid + 2])
        steps = np.sign(np.diff(x[window], axis=0))
        steady = ~fails[window].any(axis=0) & (steps == steps[0]).all(axis=0) & (steps[0] != 0)
        for f in mid[steady].tolist():
            left = (h[f - 1] - h[f - 2]) / (x[f - 1] - x[f - 2])
            right = (h[f + 2] - h[f + 1]) / (x[f + 2] - x[f + 1])
            if left * right >= 0 or right == left:
                continue
            at = (h[f + 1] - h[f - 1] + left * x[f - 1] - right * x[f + 1]) / (left - right)
            depth = h[f - 1] + left * (at - x[f - 1])
            reach = V_DEPTH * min(abs(left), abs(right)) * abs(x[f + 1] - x[f - 1]) / 2
            if depth <= reach:
                row = int(path.step_of[f + 1] if (at - x[f]) * (x[f + 1] - x[f]) > 0 else path.step_of[f])
                events.append((row, "change"))
    return [(row, kind + "|" + group.label) for row, kind in events if row >= 0]


def _newton_events(graph, group, tracks, path, marched, fails) -> list[tuple[int, str]]:
    events = [(int(path.step_of[f]), "restart|" + group.label) for f in marched.restarts]
    good = np.flatnonzero(~fails)
    if len(good) > 1:
        _, jacobian = GroupEquations(graph, group, tracks, good).residual_jacobian(marched.q[good], path.x[good])
        sign = np.sign(np.linalg.det(jacobian))
        flips = np.flatnonzero((sign[1:] != sign[:-1]) & (good[1:] == good[:-1] + 1))
        events += [(int(path.step_of[good[k + 1]]), "change|" + group.label) for k in flips.tolist()]
    inside = np.ones(len(path.x), bool)
    inside[path.rows] = False
    inside[0] = False
    events += [(row, "gap|" + group.label) for row in np.unique(path.step_of[inside & fails]).tolist()]
    return [(row, what) for row, what in events if row >= 0]


WHAT = {
    "change": "passes a change point of the {label} (its links come into line, or within a sampling step of it): "
              "the rows from here keep that group's drawn assembly, which a smooth motion may leave there",
    "gap": "passes inputs where the {label} cannot close: the rows from here keep its drawn assembly; sample the "
           "sweep more finely there to see where",
    "restart": "passes inputs where the mechanism cannot close; the {label} was solved again from its last closed "
               "position and may be in another assembly from here: check it",
}


def _machine_motion(graph, groups, tracks, closed, status, texts, events, path, motion) -> MachineMotion:
    rows = path.rows
    feasible = closed[rows]
    unit = "m" if graph.input.is_stroke else "deg"
    values = motion.angle if graph.input.is_stroke else motion.angle_deg
    crossings = []
    for row, what in sorted(set(events)):
        kind, label = what.split("|", 1)
        if not (feasible[row] and (row == 0 or feasible[row - 1] or kind == "restart")):
            continue
        crossings.append((row, f"mechanism {graph.name}: {_step_text(path, row, unit, values)} "
                               + WHAT[kind].format(label=label)))
    speed, acceleration = motion.speed, motion.acceleration
    dense = len(rows) == len(path.x) - 1  # no points between samples: the rows are a slice
    pick = slice(1, len(path.x)) if dense else rows
    links = {name: _link_motion(graph, name, track, pick, feasible, motion) for name, track in tracks.items()}
    if feasible.all():
        reasons = ("",) * len(rows)
    else:
        reasons = tuple(np.asarray(texts, dtype=object)[status[rows]].tolist())
    return MachineMotion(
        motion.angle, speed, acceleration, motion.time, feasible, reasons, links, {},
        tuple(crossings), linkage=LinkageMotion(graph, groups, links),
    )


def _link_motion(graph, name, track, pick, feasible, motion) -> LinkMotion:
    """Link ``name``'s motion at the sample rows ``pick`` of its track: rates per unit input times
    the input's speed and acceleration (chain rule), finite filler where infeasible. Made in
    place in the track's arrays, chunk by chunk (the track is not read again)."""
    n = len(feasible)
    if name == graph.ground:
        return fixed_link(graph.frames[name], graph.drawn_angles[name], graph.links[name][0], n)
    angle, origin = track.angle[pick], track.origin[pick]
    w1, w2, o1, o2 = track.angle1[pick], track.angle2[pick], track.origin1[pick], track.origin2[pick]
    everywhere = bool(feasible.all())

    def work(out: slice) -> None:
        if not everywhere:
            bad = ~feasible[out]
            for array in (angle, w1, w2):
                array[out][bad] = 0.0
            for array in (origin, o1, o2):
                array[out][bad] = 0.0
        w, a = motion.speed[out], motion.acceleration[out]
        w2[out] *= w * w
        w2[out] += w1[out] * a
        w1[out] *= w
        o2[out] *= (w * w)[:, None]
        o2[out] += o1[out] * a[:, None]
        o1[out] *= w[:, None]

    in_parallel(work, _blocks(n))
    return LinkMotion(graph.frames[name], angle, w1, w2, origin, o1, o2)


def _filled(values: FloatArray, feasible: NDArray[np.bool_]) -> FloatArray:
    """``values`` with finite filler (0) at infeasible positions."""
    shape = (len(feasible),) + (1,) * (values.ndim - 1)
    return np.where(feasible.reshape(shape), values, 0.0)


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
