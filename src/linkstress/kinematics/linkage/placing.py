"""Placing a closed-form group's links on the input path: the crank, the dyads and the blocks that ride on sliders.

Each function reads the known links' ``Track``s, writes its group's (positions and rates per unit
input, ``rates``) and returns the group's clearance (F,) [m^2]: positive where it closes, zero at a
toggle, negative where it cannot (``dyads``), with the conditioning of its rate equations (F,).
The assembly signs come from the drawn pose (``signs``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.linkage import dyads, rates
from linkstress.kinematics.linkage.graph import Joint, LinkageGraph
from linkstress.kinematics.linkage.groups import Group
from linkstress.kinematics.linkage.tracks import Track

FloatArray = NDArray[np.float64]


def _unit(v: FloatArray) -> FloatArray:
    return v / math.hypot(*v)


def _turned(c: FloatArray, s: FloatArray, local: FloatArray) -> FloatArray:
    """R local (F, 2) for rotations of cosine ``c`` and sine ``s`` (F,)."""
    return np.column_stack([c * local[0] - s * local[1], s * local[0] + c * local[1]])


class Placer:
    """Places the groups of ``graph`` on tracks over F path positions."""

    def __init__(self, graph: LinkageGraph, tracks: dict[str, Track]) -> None:
        self.graph, self.tracks = graph, tracks

    def known_point(self, joint: Joint, rows: slice):
        """Position and derivatives (B, 2) of a known link's joint at path positions ``rows``."""
        return self.tracks[joint.link].point(self.graph.local[joint.link][joint.index], rows)

    def _length(self, link: str, i: int, j: int, group: Group) -> float:
        local = self.graph.local[link]
        length = float(math.hypot(*(local[j] - local[i])))
        if length <= 0:
            raise LinkageError(
                f"{self.graph.key}: joints {i} and {j} of link {link!r} coincide, so the {group.label} cannot fix "
                "its angle; draw them apart"
            )
        return length

    def _sign(self, value: float, group: Group) -> float:
        if value == 0:
            raise LinkageError(
                f"{self.graph.key}: the {group.label} is drawn at a toggle (its links in line), so the drawing "
                "does not say which assembly to follow; draw the mechanism at another input"
            )
        return value

    def place(self, group: Group, x: FloatArray, rows: slice) -> tuple[FloatArray, FloatArray]:
        """Solve a closed-form ``group`` at the path positions ``rows`` of inputs ``x`` (F,):
        (clearance, conditioning) there."""
        if group.kind == "crank":
            return self._crank(group, x, rows)
        if group.kind == "RRR":
            return self._rrr(group, rows)
        if group.kind == "RRP":
            return self._rrp(group, rows)
        return self._rpr(group, rows)

    def _crank(self, group: Group, x, rows):
        (crank, ground), = group.pairs
        g = self.graph
        direction = g.links[crank.link][g.input.to] - g.links[crank.link][g.input.pivot]
        offset = g.drawn_angles[crank.link] - math.atan2(direction[1], direction[0])
        track = self.tracks[crank.link]
        pivot, pivot1, pivot2 = self.known_point(ground, rows)
        track.set_angle(rows, x[rows] + offset)
        track.origin[rows] = dyads.origin_from(pivot, g.local[crank.link][crank.index], track.cos[rows], track.sin[rows])
        track.angle1[rows], track.angle2[rows] = 1.0, 0.0
        track.set_rates_about(rows, pivot, pivot1, pivot2)
        ones = np.ones(len(pivot))
        return ones, ones

    def _outer(self, group: Group):
        outer = [p for p in group.pairs if p[1].link not in group.links]
        inner = [p for p in group.pairs if p[1].link in group.links]
        return outer, inner

    def _rrr(self, group: Group, rows):
        g = self.graph
        outer, ((j1, j2),) = self._outer(group)
        by_link = {p[0].link: p for p in outer}
        first, second = j1.link, j2.link
        (a_joint, a_known), (b_joint, b_known) = by_link[first], by_link[second]
        r1 = self._length(first, a_joint.index, j1.index, group)
        r2 = self._length(second, b_joint.index, j2.index, group)
        sign = self._sign(dyads.rrr_sign(g.drawn(a_known), g.drawn(b_known), g.drawn(j1)), group)
        a, a1, a2 = self.known_point(a_known, rows)
        b, b1, b2 = self.known_point(b_known, rows)
        c, clearance = dyads.rrr(a, b, r1, r2, sign)
        c1, c2, ratio = rates.rrr_rates(c, a, a1, a2, b, b1, b2)
        self._through(first, a_joint.index, j1.index, (a, a1, a2), (c, c1, c2), rows)
        self._through(second, b_joint.index, j2.index, (b, b1, b2), (c, c1, c2), rows)
        return clearance, ratio

    def _through(self, link, i, j, at_i, at_j, rows) -> None:
        """Link ``link`` with its joint i at A and joint j at C (each position and its derivatives)."""
        (a, a1, a2), (c, c1, c2) = at_i, at_j
        local = self.graph.local[link]
        track = self.tracks[link]
        angle, cos, sin, track.origin[rows] = dyads.pose_through(a, local[i], c, local[j])
        track.set_angle(rows, angle, cos, sin)
        track.angle1[rows], track.angle2[rows] = rates.angle_rates(a, a1, a2, c, c1, c2)
        track.set_rates_about(rows, a, a1, a2)

    def _line(self, k: int, rows):
        """The guide's line of slider ``k``: its point Q (with derivatives), direction u (F, 2) and
        the guide's angle derivatives (F,)."""
        g = self.graph
        slider = g.sliders[k]
        guide = self.tracks[slider.on]
        i, j = slider.line
        q = guide.point(g.local[slider.on][i], rows)
        u = _turned(guide.cos[rows], guide.sin[rows], _unit(g.local[slider.on][j] - g.local[slider.on][i]))
        return q, u, guide.angle1[rows], guide.angle2[rows]

    def _rrp(self, group: Group, rows):
        g = self.graph
        (pin, known), = group.pairs
        slider = g.sliders[group.slides[0]]
        link = pin.link
        r = self._length(link, pin.index, slider.point.index, group)
        sign = self._sign(dyads.rrp_sign(g.drawn(known), g.drawn(slider.point), g.line_direction(slider)), group)
        a, a1, a2 = self.known_point(known, rows)
        (q, q1, q2), u, w, al = self._line(group.slides[0], rows)
        b, clearance = dyads.rrp(a, r, q, u, sign)
        b1, b2, ratio = rates.rrp_rates(b, a, a1, a2, q, q1, q2, u, w, al)
        self._through(link, pin.index, slider.point.index, (a, a1, a2), (b, b1, b2), rows)
        return clearance, ratio

    def _rpr(self, group: Group, rows):
        g = self.graph
        (pin, known), = group.pairs
        slider = g.sliders[group.slides[0]]
        link = pin.link
        local = g.local[link]
        i, j = slider.line
        u_local = _unit(local[j] - local[i])
        n_local = np.array([-u_local[1], u_local[0]])
        offset = float(n_local @ (local[i] - local[pin.index]))
        sign = self._sign(dyads.rpr_sign(g.line_direction(slider), g.drawn(known), g.drawn(slider.point)), group)
        a, a1, a2 = self.known_point(known, rows)
        b, b1, b2 = self.known_point(slider.point, rows)
        track = self.tracks[link]
        angle, clearance = dyads.rpr(a, b, math.atan2(n_local[1], n_local[0]), offset, sign)
        track.set_angle(rows, angle)
        track.origin[rows] = dyads.origin_from(a, local[pin.index], track.cos[rows], track.sin[rows])
        q = track.position(local[i], rows)
        u = _turned(track.cos[rows], track.sin[rows], u_local)
        track.angle1[rows], track.angle2[rows], ratio = rates.rpr_rates(a, a1, a2, b, b1, b2, q, u)
        track.set_rates_about(rows, a, a1, a2)
        return clearance, ratio

    def ride(self, block: str, rows: slice = slice(None)) -> None:
        """A block: pinned to its slider's point (its joint 0) and turning with the guide."""
        g = self.graph
        slider = g.sliders[g.blocks[block]]
        guide, track = self.tracks[slider.on], self.tracks[block]
        p, p1, p2 = self.known_point(slider.point, rows)
        track.set_angle(rows, guide.angle[rows] + (g.drawn_angles[block] - g.drawn_angles[slider.on]))
        track.angle1[rows], track.angle2[rows] = guide.angle1[rows], guide.angle2[rows]
        track.origin[rows], track.origin1[rows], track.origin2[rows] = p, p1, p2
