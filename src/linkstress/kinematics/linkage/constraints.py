"""A group's constraint equations in link poses: residuals, Jacobian and the terms of its rates.

Each link of a group has three coordinates q = (O_x, O_y, theta): its member frame's origin [m]
and angle [rad]. A material point is P = O + R(theta) l, so dP/dtheta = k x r with r = R l.
Equations (the reference's "Rates from the constraints", in pose rather than natural coordinates):

- pin: P_a - P_b = 0 (two rows);
- slider: n . (P - Q) = 0, the point P on the line through the guide's point Q along u, n = k x u,
  u = R(theta_g) u_b: dF/dO_p = n, dF/dtheta_p = r_p . u, dF/dO_g = -n, dF/dtheta_g = -u . (P - O_g);
- stroke (a slider input): u . (P - Q) - x = 0: dG/dO_p = u, dG/dtheta_p = -n . r_p, dG/dO_g = -u,
  dG/dtheta_g = n . (P - O_g).

Differentiating twice along the input x (q' = dq/dx): J q' = -dPhi/dx (1 for the stroke), and
J q'' = -b with b the terms quadratic in q' (Nikravesh's gamma, with the sign moved): pin
-theta_a'^2 r_a + theta_b'^2 r_b; slider -theta_g'^2 n.d - 2 theta_g' u.d' - theta_p'^2 n.r_p +
theta_g'^2 n.r_q (d = P - Q); stroke -theta_g'^2 u.d + 2 theta_g' n.d' - theta_p'^2 u.r_p +
theta_g'^2 u.r_q.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.graph import LinkageGraph
from linkstress.kinematics.linkage.groups import Group
from linkstress.kinematics.linkage.tracks import PathTracks

FloatArray = NDArray[np.float64]


@dataclass
class _Pose:
    angle: FloatArray
    origin: FloatArray
    angle1: FloatArray | None = None
    origin1: FloatArray | None = None


def _rot(angle: FloatArray, local: FloatArray) -> FloatArray:
    c, s = np.cos(angle), np.sin(angle)
    return np.column_stack([c * local[0] - s * local[1], s * local[0] + c * local[1]])


def _perp(v: FloatArray) -> FloatArray:
    """k x v."""
    return np.column_stack([-v[:, 1], v[:, 0]])


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]


class GroupEquations:
    """The equations of ``group`` at positions ``rows`` of ``tracks`` (known links solved there)."""

    def __init__(self, graph: LinkageGraph, group: Group, tracks: PathTracks, rows) -> None:
        self.graph, self.group, self.tracks, self.rows = graph, group, tracks, rows
        self.index = {name: k for k, name in enumerate(group.links)}
        self.size = 3 * len(group.links)
        self.lines = {}
        for k in set(group.slides) | ({group.stroke} if group.stroke is not None else set()):
            slider = graph.sliders[k]
            local = graph.local[slider.on]
            i, j = slider.line
            direction = local[j] - local[i]
            self.lines[k] = (local[i], direction / np.hypot(*direction))

    def _poses(self, q: FloatArray | None, q1: FloatArray | None = None) -> dict[str, _Pose]:
        poses = {}
        names = {j.link for pair in self.group.pairs for j in pair}
        for k in set(self.group.slides) | ({self.group.stroke} if self.group.stroke is not None else set()):
            names |= {self.graph.sliders[k].point.link, self.graph.sliders[k].on}
        for name in names:
            if name in self.index:
                c = 3 * self.index[name]
                pose = _Pose(q[:, c + 2], q[:, c:c + 2])
                if q1 is not None:
                    pose.angle1, pose.origin1 = q1[:, c + 2], q1[:, c:c + 2]
            else:
                t, rows = self.tracks, self.rows
                pose = _Pose(t.angle(name, rows), t.origin(name, rows), t.angle(name, rows, 1), t.origin(name, rows, 1))
            poses[name] = pose
        return poses

    def terms(self, q: FloatArray, x: FloatArray | None = None):
        """Residual (B, m) and the Jacobian's blocks: a list per equation row of (link, (B, 3))."""
        poses = self._poses(q)
        rows: list[tuple[FloatArray, list[tuple[str, FloatArray]]]] = []
        local = self.graph.local
        for a, b in self.group.pairs:
            pa, pb = poses[a.link], poses[b.link]
            ra, rb = _rot(pa.angle, local[a.link][a.index]), _rot(pb.angle, local[b.link][b.index])
            gap = pa.origin + ra - pb.origin - rb
            for axis in (0, 1):
                blocks = []
                for name, r, sign in ((a.link, ra, 1.0), (b.link, rb, -1.0)):
                    coeff = np.zeros((len(gap), 3))
                    coeff[:, axis] = sign
                    coeff[:, 2] = sign * _perp(r)[:, axis]
                    blocks.append((name, coeff))
                rows.append((gap[:, axis], blocks))
        for k in self.group.slides:
            rows.append(self._line_row(poses, k, stroke=False))
        if self.group.stroke is not None:
            value, blocks = self._line_row(poses, self.group.stroke, stroke=True)
            rows.append((value - x, blocks))
        return rows

    def _line_row(self, poses, k: int, stroke: bool):
        slider = self.graph.sliders[k]
        q_local, u_local = self.lines[k]
        pp, pg = poses[slider.point.link], poses[slider.on]
        rp = _rot(pp.angle, self.graph.local[slider.point.link][slider.point.index])
        u = _rot(pg.angle, u_local)
        n = _perp(u)
        point = pp.origin + rp
        d = point - pg.origin - _rot(pg.angle, q_local)
        arm = point - pg.origin
        along, across = (u, n) if stroke else (n, u)
        sign = -1.0 if stroke else 1.0
        coeff_p = np.column_stack([along, sign * _dot(rp, across)])
        coeff_g = np.column_stack([-along, -sign * _dot(arm, across)])
        return _dot(along, d), [(slider.point.link, coeff_p), (slider.on, coeff_g)]

    def residual_jacobian(self, q: FloatArray, x: FloatArray | None = None) -> tuple[FloatArray, FloatArray]:
        """Residual (B, m) and Jacobian (B, m, m) in the group's coordinates."""
        rows = self.terms(q, x)
        residual = np.column_stack([value for value, _ in rows])
        jacobian = np.zeros((len(residual), self.size, self.size))
        for e, (_, blocks) in enumerate(rows):
            for name, coeff in blocks:
                if name in self.index:
                    c = 3 * self.index[name]
                    jacobian[:, e, c:c + 3] += coeff
        return residual, jacobian

    def rate_systems(self, q: FloatArray) -> tuple[FloatArray, FloatArray, list]:
        """Jacobian (B, m, m), right-hand side of J q' (B, m), and the equation rows (for
        ``second_rhs``)."""
        rows = self.terms(q, np.zeros(len(q)) if self.group.stroke is not None else None)
        jacobian = np.zeros((len(q), self.size, self.size))
        rhs = np.zeros((len(q), self.size))
        for e, (_, blocks) in enumerate(rows):
            for name, coeff in blocks:
                if name in self.index:
                    c = 3 * self.index[name]
                    jacobian[:, e, c:c + 3] += coeff
                else:
                    t = self.tracks
                    known = np.column_stack([t.origin(name, self.rows, 1), t.angle(name, self.rows, 1)])
                    rhs[:, e] -= np.einsum("bk,bk->b", coeff, known)
        if self.group.stroke is not None:
            rhs[:, -1] += 1.0
        return jacobian, rhs, rows

    def second_rhs(self, q: FloatArray, q1: FloatArray, rows: list) -> FloatArray:
        """Right-hand side of J q'' (B, m): the known links' q'' terms and the quadratic terms."""
        rhs = np.zeros((len(q), self.size))
        for e, (_, blocks) in enumerate(rows):
            for name, coeff in blocks:
                if name not in self.index:
                    t = self.tracks
                    known = np.column_stack([t.origin(name, self.rows, 2), t.angle(name, self.rows, 2)])
                    rhs[:, e] -= np.einsum("bk,bk->b", coeff, known)
        rhs -= self._quadratic(q, q1)
        return rhs

    def _quadratic(self, q: FloatArray, q1: FloatArray) -> FloatArray:
        poses = self._poses(q, q1)
        local = self.graph.local
        columns = []
        for a, b in self.group.pairs:
            pa, pb = poses[a.link], poses[b.link]
            ra, rb = _rot(pa.angle, local[a.link][a.index]), _rot(pb.angle, local[b.link][b.index])
            bias = -(pa.angle1**2)[:, None] * ra + (pb.angle1**2)[:, None] * rb
            columns += [bias[:, 0], bias[:, 1]]
        ks = list(self.group.slides) + ([self.group.stroke] if self.group.stroke is not None else [])
        for k, stroke in zip(ks, [False] * len(self.group.slides) + [True]):
            slider = self.graph.sliders[k]
            q_local, u_local = self.lines[k]
            pp, pg = poses[slider.point.link], poses[slider.on]
            rp = _rot(pp.angle, local[slider.point.link][slider.point.index])
            rq = _rot(pg.angle, q_local)
            u = _rot(pg.angle, u_local)
            n = _perp(u)
            d = pp.origin + rp - pg.origin - rq
            d1 = (pp.origin1 + pp.angle1[:, None] * _perp(rp)) - (pg.origin1 + pg.angle1[:, None] * _perp(rq))
            wp2, wg = pp.angle1**2, pg.angle1
            if stroke:
                columns.append(-wg * wg * _dot(u, d) + 2 * wg * _dot(n, d1) - wp2 * _dot(u, rp) + wg * wg * _dot(u, rq))
            else:
                columns.append(-wg * wg * _dot(n, d) - 2 * wg * _dot(u, d1) - wp2 * _dot(n, rp) + wg * wg * _dot(n, rq))
        return np.column_stack(columns)
