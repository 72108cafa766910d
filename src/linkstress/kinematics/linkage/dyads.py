"""Where a dyad is solved: closed-form positions, velocities and accelerations of the RRR, RRP and
RPR groups, vectorised over a block of positions.

Each function takes the known points (``tracks.Point``: position and its two derivatives, x and y
apart) and returns the new point or angle with its rates, and the group's clearance (B,):
positive where it closes, zero at a toggle, negative where it cannot close. The assembly sign
``sign`` (+1 or -1) is fixed from the drawn pose (``*_sign``) and kept along a sweep (the
reference's "Branch continuity"); a pose whose sign is zero is drawn at a toggle. The rates are
exact: the constraints differentiated once and twice (the reference's "Rates from the
constraints"); a dyad's 2 x 2 systems are solved in closed form.

- RRR: the free joint C is at distance r1 from the known A and r2 from the known B. With
  d = B - A, x = (r1^2 - r2^2 + |d|^2) / (2 |d|^2), h^2 = r1^2 / |d|^2 - x^2 (heights as fractions
  of |d|): C - A = x d + sign h k x d (circle-circle intersection; clearance h^2 |d|^2).
  Rates: C' = A' + w1 k x (C - A) = B' + w2 k x (C - B) give, with det = (C - A) x (C - B) =
  sign h |d|^2, w1 = (B' - A').(C - B) / det and w2 = (B' - A').(C - A) / det; and
  C'' = A'' + al1 k x (C - A) - w1^2 (C - A) = B'' + al2 k x (C - B) - w2^2 (C - B) give al1, al2
  the same way from e = B'' - A'' + w1^2 (C - A) - w2^2 (C - B).
- RRP: a link pinned at the known A holds its point B, at distance r from A, on the known line
  Q + t u: t^2 + 2 t u.(Q - A) + |Q - A|^2 - r^2 = 0, t = -u.(Q - A) + sign sqrt(disc),
  disc = r^2 - (n.(Q - A))^2, n = k x u (circle-line; clearance disc). Rates (the guide turning at
  w_g, al_g): (B - A).B' = (B - A).A', n.B' = n.Q' + w_g u.(B - Q);
  (B - A).B'' = (B - A).A'' - |B' - A'|^2,
  n.B'' = n.Q'' + al_g u.(B - Q) + w_g^2 n.(B - Q) + 2 w_g u.(B' - Q').
- RPR: a link pinned at the known A carries a line on which the known point B lies. In the link's
  frame the line's normal n_b and its distance e = n_b.(q - a) from the pivot are constant, so
  n(theta).(B - A) = e: theta = phi - psi + sign acos(e / |B - A|), phi the angle of B - A, psi of
  n_b (clearance |B - A|^2 - e^2). Rates, Q the line's point and u its direction:
  theta' = n.(B' - A') / u.(B - A),
  theta'' = [n.(B'' - A'') - theta'^2 n.(B - Q) + theta'^2 n.(Q - A) - 2 theta' u.(B' - Q')] / u.(B - A).

A zero determinant is a toggle: the rates there are not finite and the position is infeasible.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.tracks import Point, Values

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class RRR:
    """An RRR dyad solved over a block: the known A; C - A and C - B (x, y apart); the angular
    rates and accelerations of the link A-C (w1, al1) and of B-C (w2, al2); the clearance h^2 (B,)
    [m^2]; and det = (C - A) x (C - B) (B,) [m^2]."""

    a: Point
    cax: FloatArray
    cay: FloatArray
    cbx: FloatArray
    cby: FloatArray
    w1: FloatArray
    al1: FloatArray
    w2: FloatArray
    al2: FloatArray
    clearance: FloatArray
    det: FloatArray

    def c(self) -> Point:
        """The free joint C: C = A + (C - A), C' = A' + w1 k x (C - A),
        C'' = A'' + al1 k x (C - A) - w1^2 (C - A)."""
        a, cax, cay, w, al = self.a, self.cax, self.cay, self.w1, self.al1
        ww = w * w
        return Point(a.x + cax, a.y + cay, a.x1 - w * cay, a.y1 + w * cax,
                     a.x2 - al * cay - ww * cax, a.y2 + al * cax - ww * cay)


def rrr(a: Point, b: Point, r1: float, r2: float, sign: float) -> RRR:
    """C at distance ``r1`` [m] from A and ``r2`` from B, on the side ``sign``, with the rates of
    its links (nan where it cannot close)."""
    dx, dy = b.x - a.x, b.y - a.y
    d2 = dx * dx + dy * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / d2
        along = 0.5 * (r1 * r1 - r2 * r2) * inv + 0.5
        h2 = r1 * r1 * inv - along * along
        height = sign * np.sqrt(h2)
        cax, cay = along * dx - height * dy, along * dy + height * dx
        cbx, cby = cax - dx, cay - dy
        det = height * d2
        inv_det = 1.0 / det
        # velocities: w1 k x (C - A) - w2 k x (C - B) = B' - A' = s (vx, vy)
        vx, vy, s = _relative(b.x1, b.y1, a.x1, a.y1)
        rate = inv_det if s > 0 else -inv_det
        w1 = (vx * cbx + vy * cby) * rate
        w2 = (vx * cax + vy * cay) * rate
        # accelerations: al1 k x (C - A) - al2 k x (C - B) = B'' - A'' + w1^2 (C - A) - w2^2 (C - B)
        ww1, ww2 = w1 * w1, w2 * w2
        ex = _shifted(ww1 * cax - ww2 * cbx, b.x2, a.x2)
        ey = _shifted(ww1 * cay - ww2 * cby, b.y2, a.y2)
        al1 = (ex * cbx + ey * cby) * inv_det
        al2 = (ex * cax + ey * cay) * inv_det
    return RRR(a, cax, cay, cbx, cby, w1, al1, w2, al2, h2 * d2, det)


def _relative(px: Values, py: Values, qx: Values, qy: Values) -> tuple[Values, Values, float]:
    """P - Q as s (x, y): (x, y) = -Q and s = -1 where P is at rest (a float 0), no pass over the
    arrays for it."""
    if isinstance(px, float) and px == 0.0 and py == 0.0:
        return qx, qy, -1.0
    if isinstance(qx, float) and qx == 0.0 and qy == 0.0:
        return px, py, 1.0
    return px - qx, py - qy, 1.0


def _shifted(v: FloatArray, p: Values, q: Values) -> FloatArray:
    """v + p - q, in place, skipping a float 0."""
    if not (isinstance(p, float) and p == 0.0):
        v += p
    if not (isinstance(q, float) and q == 0.0):
        v -= q
    return v


def rrr_sign(a: FloatArray, b: FloatArray, c: FloatArray) -> float:
    """The RRR assembly sign of C against A -> B, as drawn (each (2,))."""
    return float(np.sign(_cross(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1])))


def rrp(a: Point, r: float, q: Point, ux: Values, uy: Values, w: Values, al: Values,
        sign: float) -> tuple[Point, FloatArray, FloatArray]:
    """B on the line through Q along the unit (ux, uy), turning at ``w``, ``al``, at distance ``r``
    [m] from A, with its rates; the discriminant (B,) [m^2] and the rate equations' |det| over
    their rows' norms (B,)."""
    nx, ny = -uy, ux
    wx, wy = q.x - a.x, q.y - a.y
    along = ux * wx + uy * wy
    normal = ux * wy - uy * wx
    disc = r * r - normal * normal
    t = -along + sign * np.sqrt(np.maximum(disc, 0.0))
    bx, by = q.x + t * ux, q.y + t * uy
    bax, bay = bx - a.x, by - a.y
    bqx, bqy = bx - q.x, by - q.y
    det = bax * ny - bay * nx
    u_bq = ux * bqx + uy * bqy
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_det = 1.0 / det
        x1, y1 = _solve2(bax, bay, nx, ny, bax * a.x1 + bay * a.y1, nx * q.x1 + ny * q.y1 + w * u_bq, inv_det)
        vx, vy = x1 - a.x1, y1 - a.y1
        first = bax * a.x2 + bay * a.y2 - (vx * vx + vy * vy)
        second = (nx * q.x2 + ny * q.y2 + al * u_bq + w * w * (nx * bqx + ny * bqy)
                  + 2 * w * (ux * (x1 - q.x1) + uy * (y1 - q.y1)))
        x2, y2 = _solve2(bax, bay, nx, ny, first, second, inv_det)
        ratio = np.abs(det) / np.sqrt(bax * bax + bay * bay)
    return Point(bx, by, x1, y1, x2, y2), disc, ratio


def rrp_sign(a: FloatArray, b: FloatArray, u: FloatArray) -> float:
    """The RRP assembly sign as drawn: which side of the foot of the perpendicular from A the point B is."""
    return float(np.sign(u @ (b - a)))


def rpr(a: Point, b: Point, normal_angle: float, offset: float, sign: float) -> tuple[FloatArray, FloatArray]:
    """The angle theta (B,) [rad] of a link pinned at A whose line (normal at ``normal_angle`` [rad]
    in the link's frame, ``offset`` [m] from the pivot) passes through B; and the clearance
    |B - A|^2 - offset^2 (B,) [m^2]."""
    wx, wy = b.x - a.x, b.y - a.y
    w2 = wx * wx + wy * wy
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.clip(offset / np.sqrt(w2), -1.0, 1.0)
    theta = np.arctan2(wy, wx) - normal_angle + sign * np.arccos(ratio)
    return theta, np.where(w2 > 0, w2 - offset * offset, -1.0)


def rpr_rates(a: Point, b: Point, q: Point, ux: Values, uy: Values) -> tuple[FloatArray, FloatArray, FloatArray]:
    """theta' and theta'' (B,) of an RPR dyad's link (pinned at A, its line through its point Q
    along the unit (ux, uy) holding B; Q's rates are unused: Q' = A' + theta' k x (Q - A)), and
    the conditioning (B,)."""
    nx, ny = -uy, ux
    bax, bay = b.x - a.x, b.y - a.y
    den = ux * bax + uy * bay
    with np.errstate(divide="ignore", invalid="ignore"):
        w = (nx * (b.x1 - a.x1) + ny * (b.y1 - a.y1)) / den
        qax, qay = q.x - a.x, q.y - a.y
        qx1, qy1 = a.x1 - w * qay, a.y1 + w * qax
        al = (nx * (b.x2 - a.x2) + ny * (b.y2 - a.y2) - w * w * (nx * (b.x - q.x) + ny * (b.y - q.y))
              + w * w * (nx * qax + ny * qay) - 2 * w * (ux * (b.x1 - qx1) + uy * (b.y1 - qy1))) / den
        ratio = np.abs(den) / np.sqrt(bax * bax + bay * bay)
    return w, al, ratio


def rpr_sign(u: FloatArray, a: FloatArray, b: FloatArray) -> float:
    """The RPR assembly sign as drawn: the side of the foot of the perpendicular from the pivot A
    on which B lies along the line's direction ``u``."""
    return float(np.sign(u @ (b - a)))


def spin(ax: FloatArray, ay: FloatArray, vx: FloatArray, vy: FloatArray, r2: float) -> FloatArray:
    """The angular rate of a link through A and C from C - A = (ax, ay), |C - A|^2 = ``r2`` and the
    relative rate (C - A)' = (vx, vy): (C - A) x (C - A)' / |C - A|^2 (rigid-body kinematics: the
    relative motion's normal part is radial)."""
    return (ax * vy - ay * vx) * (1.0 / r2)


def _solve2(r1x, r1y, r2x, r2y, b1, b2, inv_det):
    """v with r1.v = b1, r2.v = b2 (Cramer), given 1 / (r1 x r2)."""
    return (b1 * r2y - b2 * r1y) * inv_det, (r1x * b2 - r2x * b1) * inv_det


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx
