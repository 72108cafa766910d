"""Velocities and accelerations of a group without a closed form, from its constraints: exact, no
finite differences.

Rates are per unit input (``tracks``): q' = dq/dx, q'' = d2q/dx2. A group solved by Newton gets
its rates from its Jacobian in link poses (``constraints``): J q' = -Phi_x and J q'' = -(the known
links' q'' terms) - (the terms quadratic in q'), one small batched solve per position. (A dyad's
rates are closed-form, beside its positions: ``dyads``.)

A singular Jacobian is a toggle: the rates there are not finite and the position is infeasible.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

SINGULAR = 1e-10
"""A group's system whose |det| is below this fraction of the product of its rows' norms is singular."""


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
