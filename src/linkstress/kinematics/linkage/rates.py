"""Velocities and accelerations per group from its constraints: exact, no finite differences.

Rates are per unit input (``tracks``): q' = dq/dx, q'' = d2q/dx2. A dyad's come from two
equations in its free point (the reference's natural coordinates), solved by Cramer's rule for all
positions at once; any other group's from its Jacobian in link poses (``constraints``), one small
batched solve per position.

- RRR, C joined to A by r1 and to B by r2: (C - A).C' = (C - A).A', (C - B).C' = (C - B).B';
  (C - A).C'' = (C - A).A'' - |C' - A'|^2, and likewise for B.
- RRP, B at distance r from A and on the guide's line through Q along u (n = k x u, the guide
  turning at theta_g'): (B - A).B' = (B - A).A', n.B' = n.Q' + theta_g' u.(B - Q); and
  n.B'' = n.Q'' + theta_g'' u.(B - Q) + theta_g'^2 n.(B - Q) + 2 theta_g' u.(B' - Q').
- RPR, a link pinned at A whose line (through its point Q, along u) holds the known B:
  theta' = n.(B' - A') / u.(B - A),
  theta'' = [n.(B'' - A'') - theta'^2 n.(B - Q) + theta'^2 n.(Q - A) - 2 theta' u.(B' - Q')] / u.(B - A).
- A link through two points A, C: theta' = (C - A) x (C' - A') / |C - A|^2, and theta'' likewise
  from C'' - A'' (rigid-body kinematics: the relative acceleration's normal part is radial).

A zero determinant is a toggle: the rates there are not finite and the position is infeasible.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

SINGULAR = 1e-10
"""A group's system whose |det| is below this fraction of the product of its rows' norms is singular."""


def _dot(a, b):
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]


def _cross(a, b):
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def _solve2(r1: FloatArray, r2: FloatArray, b1: FloatArray, b2: FloatArray) -> tuple[FloatArray, FloatArray]:
    """v (F, 2) with r1.v = b1, r2.v = b2 (Cramer), and |det| over the rows' norms (F,)."""
    det = _cross(r1, r2)
    with np.errstate(divide="ignore", invalid="ignore"):
        v = np.column_stack([(b1 * r2[:, 1] - b2 * r1[:, 1]) / det, (r1[:, 0] * b2 - r2[:, 0] * b1) / det])
        ratio = np.abs(det) / np.sqrt(_dot(r1, r1) * _dot(r2, r2))
    return v, ratio


def rrr_rates(c, a, a1, a2, b, b1, b2):
    """C' and C'' (F, 2) of an RRR dyad's free joint, and its conditioning (F,)."""
    ca, cb = c - a, c - b
    c1, ratio = _solve2(ca, cb, _dot(ca, a1), _dot(cb, b1))
    va, vb = c1 - a1, c1 - b1
    c2, _ = _solve2(ca, cb, _dot(ca, a2) - _dot(va, va), _dot(cb, b2) - _dot(vb, vb))
    return c1, c2, ratio


def rrp_rates(b, a, a1, a2, q, q1, q2, u, w, al):
    """B' and B'' (F, 2) of an RRP dyad's point on the guide's line, the guide turning at w, al
    (F,) per unit input; and the conditioning (F,)."""
    n = np.column_stack([-u[:, 1], u[:, 0]])
    ba, bq = b - a, b - q
    b1, ratio = _solve2(ba, n, _dot(ba, a1), _dot(n, q1) + w * _dot(u, bq))
    va = b1 - a1
    second = _dot(n, q2) + al * _dot(u, bq) + w * w * _dot(n, bq) + 2 * w * _dot(u, b1 - q1)
    b2, _ = _solve2(ba, n, _dot(ba, a2) - _dot(va, va), second)
    return b1, b2, ratio


def rpr_rates(a, a1, a2, b, b1, b2, q, u):
    """theta' and theta'' (F,) of an RPR dyad's link (pinned at A, its line through its point Q
    along u holding B), and the conditioning (F,)."""
    n = np.column_stack([-u[:, 1], u[:, 0]])
    ba = b - a
    den = _dot(u, ba)
    with np.errstate(divide="ignore", invalid="ignore"):
        w = _dot(n, b1 - a1) / den
        qa = q - a
        q1 = a1 + w[:, None] * np.column_stack([-qa[:, 1], qa[:, 0]])
        al = (_dot(n, b2 - a2) - w * w * _dot(n, b - q) + w * w * _dot(n, qa) - 2 * w * _dot(u, b1 - q1)) / den
        ratio = np.abs(den) / np.sqrt(_dot(ba, ba))
    return w, al, ratio


def angle_rates(a, a1, a2, c, c1, c2):
    """theta' and theta'' (F,) of a link through A and C (F, 2) from their derivatives."""
    r = c - a
    r2 = _dot(r, r)
    return _cross(r, c1 - a1) / r2, _cross(r, c2 - a2) / r2


def regular(matrix: FloatArray) -> NDArray[np.bool_]:
    """(B,) True where the square systems (B, m, m) are far from singular."""
    sign, logdet = np.linalg.slogdet(matrix)
    with np.errstate(divide="ignore"):
        log_rows = np.log(np.einsum("pij,pij->pi", matrix, matrix)).sum(axis=1) / 2
    return (sign != 0) & np.isfinite(logdet) & (logdet - log_rows > np.log(SINGULAR))


def batched_solve(matrix: FloatArray, rhs: FloatArray) -> tuple[FloatArray, NDArray[np.bool_]]:
    """x (B, m, k) or (B, m) with matrix x = rhs where regular, nan elsewhere; and where regular."""
    good = regular(matrix)
    x = np.full(rhs.shape, np.nan)
    if good.any():
        column = rhs.ndim == 2
        solved = np.linalg.solve(matrix[good], rhs[good][..., None] if column else rhs[good])
        x[good] = solved[..., 0] if column else solved
    return x, good


def group_rates(equations, q: FloatArray) -> tuple[FloatArray, FloatArray, NDArray[np.bool_], FloatArray]:
    """q' and q'' (B, m) of a group at its coordinates ``q`` (B, m) from its Jacobian
    (``constraints.GroupEquations``): J q' = -Phi_x, J q'' = -Phi_x' terms - the quadratic terms.
    Also where the Jacobian is regular (B,) and its determinant's sign (B,)."""
    jacobian, rhs, rows = equations.rate_systems(q)
    q1, good = batched_solve(jacobian, rhs)
    q2, _ = batched_solve(jacobian, equations.second_rhs(q, np.nan_to_num(q1), rows))
    sign = np.sign(np.linalg.det(jacobian))
    return q1, q2, good, sign
