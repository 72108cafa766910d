"""Placing the closed-form groups on a block of path positions: the crank, the dyads and the
blocks that ride on sliders.

A placer is made once per group (its lengths and drawn assembly sign, checked against the
drawing) and run on every block. It reads the known points and tracks of its block, adds its
links' tracks and the joints it solved, and returns the group's clearance (B,) [m^2] (positive
where it closes, zero at a toggle, negative where it cannot; ``dyads``) with the conditioning of
its rate equations (a ``Closure``), or None where it always closes.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.linkage import dyads
from linkstress.kinematics.linkage.graph import Joint, LinkageGraph
from linkstress.kinematics.linkage.groups import Group
from linkstress.kinematics.linkage.tracks import Point, Track, Values, through

FloatArray = NDArray[np.float64]


class Closure:
    """How a group closes over a block: its clearance (B,) [m^2] and the conditioning of its rate
    equations, |det| over the product of its rows' norms: its least value over the block (nan if
    any is nan) and, when asked for, every value (B,)."""

    def __init__(self, clearance: FloatArray, least: float, conditioning: Callable[[], FloatArray]) -> None:
        self.clearance, self.least, self._conditioning = clearance, least, conditioning

    @classmethod
    def of(cls, clearance: FloatArray, conditioning: FloatArray) -> Closure:
        return cls(clearance, np.min(conditioning), lambda: conditioning)

    def conditioning(self) -> FloatArray:
        return self._conditioning()


class Block:
    """A block of path positions being solved: the inputs ``x`` (B,) with the seeds of the rates
    (the input's first and second derivatives, per unit time or per unit input), the tracks of the
    links known so far (``tracks``, and those ``load(name)`` gives: solved before the block) and the
    points of the joints found so far (a pin's joints share one: ``pin_of``)."""

    def __init__(self, graph: LinkageGraph, pin_of: dict[Joint, object], x: FloatArray, seed1: Values,
                 seed2: Values, tracks: dict[str, Track], load: Callable[[str], Track] | None = None) -> None:
        self.graph, self.pin_of, self.x, self.seed1, self.seed2 = graph, pin_of, x, seed1, seed2
        self.tracks, self.load = tracks, load
        self.points: dict[object, Point | Callable[[], Point]] = {}

    def track(self, name: str) -> Track:
        """A known link's track."""
        if name not in self.tracks:
            self.tracks[name] = self.load(name)
        return self.tracks[name]

    def joint(self, joint: Joint) -> Point:
        """Where a joint of a known link is, with its rates."""
        key = self.pin_of[joint]
        point = self.points.get(key)
        if point is None:
            point = self.track(joint.link).point(self.graph.local[joint.link][joint.index])
        elif callable(point):
            point = point()
        self.points[key] = point
        return point

    def found(self, joint: Joint, point: Point | Callable[[], Point]) -> None:
        """A group solved ``joint`` at ``point`` (or a function that makes it, when first asked for)."""
        self.points[self.pin_of[joint]] = point

    def keep(self, joints, tracks) -> None:
        """Forget every point but those of ``joints`` and every track but those of ``tracks`` (and
        the ground's): what no later group reads leaves the cache."""
        keys = {self.pin_of[j] for j in joints}
        self.points = {key: p for key, p in self.points.items() if key in keys}
        self.tracks = {name: t for name, t in self.tracks.items() if name in tracks or name == self.graph.ground}

    def line(self, k: int) -> tuple[Point, Values, Values, Track]:
        """Slider k's line on its guide: its point Q (the line's joint i), its unit direction
        (ux, uy) and the guide's track."""
        g = self.graph
        slider = g.sliders[k]
        i, j = slider.line
        guide = self.track(slider.on)
        d = g.local[slider.on][j] - g.local[slider.on][i]
        dx, dy = d / math.hypot(*d)
        ux, uy = (guide.cos * dx, guide.sin * dx) if dy == 0.0 else (guide.cos * dx - guide.sin * dy,
                                                                      guide.sin * dx + guide.cos * dy)
        return self.joint(Joint(slider.on, i)), ux, uy, guide


def crank_offset(graph: LinkageGraph) -> float:
    """The input crank's frame angle less its input angle [rad] (both as drawn)."""
    joints = graph.links[graph.input.link]
    direction = joints[graph.input.to] - joints[graph.input.pivot]
    return graph.drawn_angles[graph.input.link] - math.atan2(direction[1], direction[0])


def placer(graph: LinkageGraph, group: Group):
    """The placer of a closed-form ``group``."""
    kinds = {"crank": CrankPlacer, "RRR": RRRPlacer, "RRP": RRPPlacer, "RPR": RPRPlacer}
    return kinds[group.kind](graph, group)


class _Placer:
    """``links``: the links it places; ``reads``: the known joints it reads; ``guides``: the known
    links whose tracks it reads."""

    guides: tuple[str, ...] = ()

    def __init__(self, graph: LinkageGraph, group: Group) -> None:
        self.graph, self.group, self.links = graph, group, group.links

    def length(self, link: str, i: int, j: int) -> float:
        local = self.graph.local[link]
        length = float(math.hypot(*(local[j] - local[i])))
        if length <= 0:
            raise LinkageError(
                f"{self.graph.key}: joints {i} and {j} of link {link!r} coincide, so the {self.group.label} cannot fix "
                "its angle; draw them apart"
            )
        return length

    def sign(self, value: float) -> float:
        if value == 0:
            raise LinkageError(
                f"{self.graph.key}: the {self.group.label} is drawn at a toggle (its links in line), so the drawing "
                "does not say which assembly to follow; draw the mechanism at another input"
            )
        return value


class CrankPlacer(_Placer):
    """The input link: turned to the input angle (plus the drawn offset of its frame) about its
    pivot on the ground; its rates are the seeds."""

    def __init__(self, graph: LinkageGraph, group: Group) -> None:
        super().__init__(graph, group)
        (self.crank, self.ground), = group.pairs
        self.offset = crank_offset(graph)
        self.reads = (self.ground,)

    def place(self, block: Block) -> None:
        angle = block.x + self.offset if self.offset else block.x
        local = self.graph.local[self.crank.link][self.crank.index]
        block.tracks[self.crank.link] = Track(angle, block.seed1, block.seed2, local, block.joint(self.ground),
                                              (*cos_sin(angle), 1.0))
        return None


def cos_sin(angle: FloatArray) -> tuple[FloatArray, FloatArray]:
    """cos and sin of ``angle`` [rad] from one tangent of its half, t = tan(angle / 2):
    cos = (1 - t^2) / (1 + t^2), sin = 2 t / (1 + t^2), within an ulp of numpy's cos and sin (which
    cost a libm call each per element, as tan does)."""
    t = np.tan(0.5 * angle)
    tt = t * t
    scale = 1.0 / (1.0 + tt)
    return (1.0 - tt) * scale, 2.0 * t * scale


class RRRPlacer(_Placer):
    """Two links and three pins: the free joint C where the circles about the known A and B meet."""

    def __init__(self, graph: LinkageGraph, group: Group) -> None:
        super().__init__(graph, group)
        (j1, j2), = [p for p in group.pairs if p[1].link in group.links]
        by_link = {p[0].link: p for p in group.pairs if p[1].link not in group.links}
        self.c1, self.c2 = j1, j2
        (self.a_joint, self.a_known), (self.b_joint, self.b_known) = by_link[j1.link], by_link[j2.link]
        self.r1 = self.length(j1.link, self.a_joint.index, j1.index)
        self.r2 = self.length(j2.link, self.b_joint.index, j2.index)
        self.side = self.sign(dyads.rrr_sign(graph.drawn(self.a_known), graph.drawn(self.b_known), graph.drawn(j1)))
        self.conditioning = self.side / (self.r1 * self.r2)
        self.reads = (self.a_known, self.b_known)

    def place(self, block: Block) -> Closure:
        local = self.graph.local
        a, b = block.joint(self.a_known), block.joint(self.b_known)
        s = dyads.rrr(a, b, self.r1, self.r2, self.side)
        first, second = self.c1.link, self.c2.link
        block.found(self.c1, s.c)  # made only if a later group or the output reads it
        block.tracks[first] = through(local[first][self.a_joint.index], local[first][self.c1.index], a, s.cax, s.cay,
                                      s.w1, s.al1)
        block.tracks[second] = through(local[second][self.b_joint.index], local[second][self.c2.index], b, s.cbx,
                                       s.cby, s.w2, s.al2)
        # |det| = sign det, so the least conditioning is det's least (or greatest) times 1 / (r1 r2)
        least = (np.min(s.det) if self.side > 0 else np.max(s.det)) * self.conditioning
        return Closure(s.clearance, least, lambda: s.det * self.conditioning)


class RRPPlacer(_Placer):
    """One link pinned at the known A whose point B slides on a known line."""

    def __init__(self, graph: LinkageGraph, group: Group) -> None:
        super().__init__(graph, group)
        (self.pin, self.known), = group.pairs
        self.k = group.slides[0]
        self.point = graph.sliders[self.k].point
        self.r = self.length(self.pin.link, self.pin.index, self.point.index)
        self.side = self.sign(dyads.rrp_sign(graph.drawn(self.known), graph.drawn(self.point),
                                             graph.line_direction(graph.sliders[self.k])))
        slider = graph.sliders[self.k]
        self.reads, self.guides = (self.known, Joint(slider.on, slider.line[0])), (slider.on,)

    def place(self, block: Block) -> Closure:
        link, local = self.pin.link, self.graph.local[self.pin.link]
        a = block.joint(self.known)
        q, ux, uy, guide = block.line(self.k)
        b, clearance, ratio = dyads.rrp(a, self.r, q, ux, uy, guide.w, guide.al, self.side)
        bax, bay = b.x - a.x, b.y - a.y
        r2 = self.r * self.r
        w = dyads.spin(bax, bay, b.x1 - a.x1, b.y1 - a.y1, r2)
        al = dyads.spin(bax, bay, b.x2 - a.x2, b.y2 - a.y2, r2)
        block.found(self.point, b)
        block.tracks[link] = through(local[self.pin.index], local[self.point.index], a, bax, bay, w, al)
        return Closure.of(clearance, ratio)


class RPRPlacer(_Placer):
    """One link pinned at the known A whose line holds a known point B."""

    def __init__(self, graph: LinkageGraph, group: Group) -> None:
        super().__init__(graph, group)
        (self.pin, self.known), = group.pairs
        slider = graph.sliders[group.slides[0]]
        self.point = slider.point
        local = graph.local[self.pin.link]
        self.i, j = slider.line
        d = local[j] - local[self.i]
        self.u_local = d / math.hypot(*d)
        n_local = np.array([-self.u_local[1], self.u_local[0]])
        self.offset = float(n_local @ (local[self.i] - local[self.pin.index]))
        self.normal_angle = math.atan2(n_local[1], n_local[0])
        self.side = self.sign(dyads.rpr_sign(graph.line_direction(slider), graph.drawn(self.known),
                                             graph.drawn(self.point)))
        self.reads = (self.known, self.point)

    def place(self, block: Block) -> Closure:
        link, local = self.pin.link, self.graph.local[self.pin.link]
        a, b = block.joint(self.known), block.joint(self.point)
        angle, clearance = dyads.rpr(a, b, self.normal_angle, self.offset, self.side)
        cos, sin = np.cos(angle), np.sin(angle)
        posed = Track(angle, 0.0, 0.0, local[self.pin.index], a, (cos, sin, 1.0))
        q = posed.point(local[self.i])
        ux, uy = cos * self.u_local[0] - sin * self.u_local[1], sin * self.u_local[0] + cos * self.u_local[1]
        w, al, ratio = dyads.rpr_rates(a, b, q, ux, uy)
        block.tracks[link] = Track(angle, w, al, local[self.pin.index], a, (cos, sin, 1.0))
        return Closure.of(clearance, ratio)


class Rider:
    """A slider's block: pinned to the slider's point (the block's joint 0) and turning with the guide."""

    def __init__(self, graph: LinkageGraph, block: str) -> None:
        self.name, self.links = block, (block,)
        self.slider = graph.sliders[graph.blocks[block]]
        turn = graph.drawn_angles[block] - graph.drawn_angles[self.slider.on]
        self.turn = (turn, math.cos(turn), math.sin(turn))
        self.reads, self.guides = (self.slider.point,), (self.slider.on,)

    def place(self, block: Block) -> None:
        guide = block.track(self.slider.on)
        turn, c, s = self.turn
        ux, uy, k = guide.turn
        block.tracks[self.name] = Track(guide.angle + turn, guide.w, guide.al, np.zeros(2), block.joint(self.slider.point),
                                        (ux * c - uy * s, uy * c + ux * s, k))
