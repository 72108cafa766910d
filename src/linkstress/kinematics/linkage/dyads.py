"""Where a dyad is solved: closed-form positions of the RRR, RRP and RPR groups, vectorised.

Every function takes (F,) or (F, 2) arrays over F positions and returns the new point or angle with
the group's clearance (F,): positive where it closes, zero at a toggle, negative where it cannot
close. The assembly sign ``sign`` (+1 or -1) is fixed from the drawn pose (``*_sign``) and kept
along a sweep (the reference's "Branch continuity"); a pose whose sign is zero is drawn at a toggle.

- RRR: the free joint C is at distance r1 from the known A and r2 from the known B. With
  d = |B - A|, x = (r1^2 - r2^2 + d^2) / (2 d), h^2 = r1^2 - x^2:
  C = A + x e + sign h k x e (circle-circle intersection; clearance h^2).
- RRP: a link pinned at the known A holds its point B, at distance r from A, on the known line
  Q + t u: t^2 + 2 t u.(Q - A) + |Q - A|^2 - r^2 = 0, t = -u.(Q - A) + sign sqrt(disc),
  disc = r^2 - (n.(Q - A))^2, n = k x u (circle-line; clearance disc).
- RPR: a link pinned at the known A carries a line on which the known point B lies. In the link's
  frame the line's normal n_b and its distance e = n_b.(q - a) from the pivot are constant, so
  n(theta).(B - A) = e: theta = phi - psi + sign acos(e / |B - A|), phi the angle of B - A, psi of
  n_b (clearance |B - A|^2 - e^2).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def rrr(a: FloatArray, b: FloatArray, r1: float, r2: float, sign: float) -> tuple[FloatArray, FloatArray]:
    """C (F, 2) at distance ``r1`` [m] from A (F, 2) and ``r2`` from B (F, 2), and h^2 (F,) [m^2]."""
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    d2 = dx * dx + dy * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        along = (r1 * r1 - r2 * r2 + d2) / (2.0 * d2)
        h2 = r1 * r1 - along * along * d2
        height = sign * np.sqrt(np.maximum(h2, 0.0) / d2)
    c = np.empty_like(a)
    c[:, 0] = a[:, 0] + along * dx - height * dy
    c[:, 1] = a[:, 1] + along * dy + height * dx
    return c, np.where(d2 > 0, h2, -1.0)


def rrr_sign(a: FloatArray, b: FloatArray, c: FloatArray) -> float:
    """The RRR assembly sign of C against A -> B, as drawn (each (2,))."""
    return float(np.sign(_cross(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1])))


def rrp(a: FloatArray, r: float, q: FloatArray, u: FloatArray, sign: float) -> tuple[FloatArray, FloatArray]:
    """B (F, 2) on the line Q (F, 2) + t u (F, 2, unit) at distance ``r`` [m] from A (F, 2), and
    the discriminant (F,) [m^2]."""
    wx, wy = q[:, 0] - a[:, 0], q[:, 1] - a[:, 1]
    along = u[:, 0] * wx + u[:, 1] * wy
    normal = u[:, 0] * wy - u[:, 1] * wx
    disc = r * r - normal * normal
    t = -along + sign * np.sqrt(np.maximum(disc, 0.0))
    return q + t[:, None] * u, disc


def rrp_sign(a: FloatArray, b: FloatArray, u: FloatArray) -> float:
    """The RRP assembly sign as drawn: which side of the foot of the perpendicular from A the point B is."""
    return float(np.sign(u @ (b - a)))


def rpr(a: FloatArray, b: FloatArray, normal_angle: float, offset: float, sign: float) -> tuple[FloatArray, FloatArray]:
    """The angle theta (F,) [rad] of a link pinned at A (F, 2) whose line (normal at ``normal_angle``
    [rad] in the link's frame, ``offset`` [m] from the pivot) passes through B (F, 2); and the
    clearance |B - A|^2 - offset^2 (F,) [m^2]."""
    wx, wy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    w2 = wx * wx + wy * wy
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.clip(offset / np.sqrt(w2), -1.0, 1.0)
    theta = np.arctan2(wy, wx) - normal_angle + sign * np.arccos(ratio)
    return theta, np.where(w2 > 0, w2 - offset * offset, -1.0)


def rpr_sign(u: FloatArray, a: FloatArray, b: FloatArray) -> float:
    """The RPR assembly sign as drawn: the side of the foot of the perpendicular from the pivot A
    on which B lies along the line's direction ``u``."""
    return float(np.sign(u @ (b - a)))


def pose_through(a: FloatArray, a_local: FloatArray, b: FloatArray, b_local: FloatArray):
    """The angle (F,) [rad], its cosine and sine (F,) and origin (F, 2) [m] of a link whose points
    ``a_local`` and ``b_local`` (2,) [m, member frame] are at A and B (F, 2): the rotation taking
    b_local - a_local onto B - A, without trigonometry but the angle's one arctan2."""
    lx, ly = b_local - a_local
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    norm = np.sqrt(dx * dx + dy * dy) * np.hypot(lx, ly)
    cos, sin = (lx * dx + ly * dy) / norm, (lx * dy - ly * dx) / norm
    return np.arctan2(sin, cos), cos, sin, origin_from(a, a_local, cos, sin)


def origin_from(a: FloatArray, a_local: FloatArray, cos: FloatArray, sin: FloatArray) -> FloatArray:
    """The origin (F, 2) of a link at the angle of ``cos``, ``sin`` (F,) whose point ``a_local`` (2,) is at A (F, 2)."""
    origin = np.empty_like(a)
    origin[:, 0] = a[:, 0] - (cos * a_local[0] - sin * a_local[1])
    origin[:, 1] = a[:, 1] - (sin * a_local[0] + cos * a_local[1])
    return origin
