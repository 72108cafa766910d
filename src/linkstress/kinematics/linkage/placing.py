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


def _rotated(angle: FloatArray, local: FloatArray) -> FloatArray:
    c, s = np.cos(angle), np.sin(angle)
    return np.column_stack([c * local[0] - s * local[1], s * local[0] + c * local[1]])


class Placer:
    """Places the groups of ``graph`` on tracks over F path positions."""

    def __init__(self, graph: LinkageGraph, tracks: dict[str, Track]) -> None:
        self.graph, self.tracks = graph, tracks

    def known_point(self, joint: Joint):
        """Position and derivatives (F, 2) of a known link's joint."""
        return self.tracks[joint.link].point(self.graph.local[joint.link][joint.index])

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

    def place(self, group: Group, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Solve a closed-form ``group`` at path inputs ``x`` (F,): (clearance, conditioning)."""
        if group.kind == "crank":
            return self._crank(group, x)
        if group.kind == "RRR":
            return self._rrr(group)
        if group.kind == "RRP":
            return self._rrp(group)
        return self._rpr(group)

    def _crank(self, group: Group, x):
        (crank, ground), = group.pairs
        g = self.graph
        direction = g.links[crank.link][g.input.to] - g.links[crank.link][g.input.pivot]
        offset = g.drawn_angles[crank.link] - math.atan2(direction[1], direction[0])
        track = self.tracks[crank.link]
        pivot, pivot1, pivot2 = self.known_point(ground)
        track.angle[:] = x + offset
        track.origin[:] = dyads.origin_from(pivot, g.local[crank.link][crank.index], track.angle)
        track.angle1[:], track.angle2[:] = 1.0, 0.0
        track.set_rates_about(slice(None), pivot, pivot1, pivot2)
        ones = np.ones(len(x))
        return ones, ones

    def _outer(self, group: Group):
        outer = [p for p in group.pairs if p[1].link not in group.links]
        inner = [p for p in group.pairs if p[1].link in group.links]
        return outer, inner

    def _rrr(self, group: Group):
        g = self.graph
        outer, ((j1, j2),) = self._outer(group)
        by_link = {p[0].link: p for p in outer}
        first, second = j1.link, j2.link
        (a_joint, a_known), (b_joint, b_known) = by_link[first], by_link[second]
        r1 = self._length(first, a_joint.index, j1.index, group)
        r2 = self._length(second, b_joint.index, j2.index, group)
        sign = self._sign(dyads.rrr_sign(g.drawn(a_known), g.drawn(b_known), g.drawn(j1)), group)
        a, a1, a2 = self.known_point(a_known)
        b, b1, b2 = self.known_point(b_known)
        c, clearance = dyads.rrr(a, b, r1, r2, sign)
        c1, c2, ratio = rates.rrr_rates(c, a, a1, a2, b, b1, b2)
        for link, pivot, joint_pivot, joint_c, p, p1, p2 in (
            (first, a_joint, a_joint, j1, a, a1, a2), (second, b_joint, b_joint, j2, b, b1, b2),
        ):
            self._through(link, joint_pivot.index, joint_c.index, p, p1, p2, c, c1, c2)
        return clearance, ratio

    def _through(self, link, i, j, a, a1, a2, c, c1, c2) -> None:
        """Link ``link`` with its joint i at A and joint j at C (positions and derivatives)."""
        local = self.graph.local[link]
        track = self.tracks[link]
        track.angle[:], track.origin[:] = dyads.pose_through(a, local[i], c, local[j])
        track.angle1[:], track.angle2[:] = rates.angle_rates(a, a1, a2, c, c1, c2)
        track.set_rates_about(slice(None), a, a1, a2)

    def _line(self, k: int):
        """The guide's line of slider ``k``: its point Q (with derivatives), direction u (F, 2) and
        the guide's angle derivatives (F,)."""
        g = self.graph
        slider = g.sliders[k]
        guide = self.tracks[slider.on]
        i, j = slider.line
        q = guide.point(g.local[slider.on][i])
        u = _rotated(guide.angle, _unit(g.local[slider.on][j] - g.local[slider.on][i]))
        return q, u, guide.angle1, guide.angle2

    def _rrp(self, group: Group):
        g = self.graph
        (pin, known), = group.pairs
        slider = g.sliders[group.slides[0]]
        link = pin.link
        r = self._length(link, pin.index, slider.point.index, group)
        sign = self._sign(dyads.rrp_sign(g.drawn(known), g.drawn(slider.point), g.line_direction(slider)), group)
        a, a1, a2 = self.known_point(known)
        (q, q1, q2), u, w, al = self._line(group.slides[0])
        b, clearance = dyads.rrp(a, r, q, u, sign)
        b1, b2, ratio = rates.rrp_rates(b, a, a1, a2, q, q1, q2, u, w, al)
        self._through(link, pin.index, slider.point.index, a, a1, a2, b, b1, b2)
        return clearance, ratio

    def _rpr(self, group: Group):
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
        a, a1, a2 = self.known_point(known)
        b, b1, b2 = self.known_point(slider.point)
        track = self.tracks[link]
        angle, clearance = dyads.rpr(a, b, math.atan2(n_local[1], n_local[0]), offset, sign)
        track.angle[:] = angle
        track.origin[:] = dyads.origin_from(a, local[pin.index], angle)
        q = track.position(local[i])
        u = _rotated(angle, u_local)
        track.angle1[:], track.angle2[:], ratio = rates.rpr_rates(a, a1, a2, b, b1, b2, q, u)
        track.set_rates_about(slice(None), a, a1, a2)
        return clearance, ratio

    def ride(self, block: str) -> None:
        """A block: pinned to its slider's point (its joint 0) and turning with the guide."""
        g = self.graph
        slider = g.sliders[g.blocks[block]]
        guide, track = self.tracks[slider.on], self.tracks[block]
        p, p1, p2 = self.known_point(slider.point)
        track.angle[:] = guide.angle + (g.drawn_angles[block] - g.drawn_angles[slider.on])
        track.angle1[:], track.angle2[:] = guide.angle1, guide.angle2
        track.origin[:], track.origin1[:], track.origin2[:] = p, p1, p2
