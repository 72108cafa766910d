"""Closed-form plane elasticity solutions that the FEA is verified against.

Stresses are returned as (3, Q) arrays (sigma_xx, sigma_yy, tau_xy) [Pa] at points (2, Q) [m], so
that the exact traction sigma . n can be applied on any truncated boundary. Plates have thickness
t [m]; forces and moments are totals over the thickness.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray


def polar_to_cartesian(
    theta: NDArray[np.float64],
    s_rr: NDArray[np.float64],
    s_tt: NDArray[np.float64],
    s_rt: NDArray[np.float64],
) -> NDArray[np.float64]:
    """(sigma_xx, sigma_yy, tau_xy) (3, Q) from polar components at angles ``theta`` [rad] (stress rotation)."""
    c, s = np.cos(theta), np.sin(theta)
    return np.array(
        [
            s_rr * c * c + s_tt * s * s - 2 * s_rt * s * c,
            s_rr * s * s + s_tt * c * c + 2 * s_rt * s * c,
            (s_rr - s_tt) * s * c + s_rt * (c * c - s * s),
        ]
    )


def kirsch_stress(points: NDArray[np.float64], S: float, a: float) -> NDArray[np.float64]:
    """Infinite plate with a hole of radius ``a`` [m] at the origin under remote tension ``S`` [Pa] along x.

    Timoshenko & Goodier, Theory of Elasticity, 3rd ed., section 35, eq. (61); sigma_theta = 3 S at
    (0, +-a): Kt = 3.
    """
    x, y = points
    r2 = x * x + y * y
    theta = np.arctan2(y, x)
    q2, q4 = a * a / r2, (a * a / r2) ** 2
    c2, s2 = np.cos(2 * theta), np.sin(2 * theta)
    s_rr = S / 2 * (1 - q2) + S / 2 * (1 + 3 * q4 - 4 * q2) * c2
    s_tt = S / 2 * (1 + q2) - S / 2 * (1 + 3 * q4) * c2
    s_rt = -S / 2 * (1 - 3 * q4 + 2 * q2) * s2
    return polar_to_cartesian(theta, s_rr, s_tt, s_rt)


def cantilever_stress(
    points: NDArray[np.float64], P: float, L: float, D: float, t: float
) -> NDArray[np.float64]:
    """Cantilever of length ``L``, depth ``D`` [m], clamped at x = 0, end shear ``P`` [N] (-y) at x = L.

    Timoshenko & Goodier, section 21 (parabolic end shear), as written by Augarde & Deeks, Finite
    Elements in Analysis and Design 44 (2008) 595-601, eq. (1): sigma_xx = P (L - x) y / I,
    sigma_yy = 0, tau_xy = -P (D^2/4 - y^2) / (2 I), I = t D^3 / 12 [m^4].
    """
    x, y = points
    i = t * D**3 / 12
    return np.array([P * (L - x) * y / i, np.zeros_like(x), -P * (D * D / 4 - y * y) / (2 * i)])


def cantilever_displacement(
    points: NDArray[np.float64], P: float, L: float, D: float, t: float, E: float, nu: float
) -> NDArray[np.float64]:
    """Displacements (2, Q) [m] of :func:`cantilever_stress` (plane stress; Augarde & Deeks eq. (2))."""
    x, y = points
    ei = E * t * D**3 / 12
    ux = P * y / (6 * ei) * ((6 * L - 3 * x) * x + (2 + nu) * (y * y - D * D / 4))
    uy = -P / (6 * ei) * (3 * nu * y * y * (L - x) + (4 + 5 * nu) * D * D * x / 4 + (3 * L - x) * x * x)
    return np.array([ux, uy])


def cantilever_tip_deflection(P: float, L: float, D: float, t: float, E: float, nu: float) -> float:
    """Deflection [m] (negative: along -y) of the axis at x = L: -P L^3 / (3 E I) - (4 + 5 nu) P D^2 L / (24 E I)."""
    return float(cantilever_displacement(np.array([[L], [0.0]]), P, L, D, t, E, nu)[1, 0])


def lame_stress(points: NDArray[np.float64], p: float, a: float, b: float) -> NDArray[np.float64]:
    """Thick ring a <= r <= b [m] under internal pressure ``p`` [Pa] (Lame; Timoshenko & Goodier, section 28).

    sigma_r = p a^2 / (b^2 - a^2) (1 - b^2 / r^2), sigma_theta = p a^2 / (b^2 - a^2) (1 + b^2 / r^2).
    """
    x, y = points
    r2 = x * x + y * y
    k = p * a * a / (b * b - a * a)
    return polar_to_cartesian(np.arctan2(y, x), k * (1 - b * b / r2), k * (1 + b * b / r2), np.zeros_like(x))


def lame_hoop_stress(r: NDArray[np.float64] | float, p: float, a: float, b: float) -> NDArray[np.float64]:
    """sigma_theta [Pa] of :func:`lame_stress` at radius ``r`` [m]; at r = a: p (a^2 + b^2) / (b^2 - a^2)."""
    return p * a * a / (b * b - a * a) * (1 + b * b / np.asarray(r, float) ** 2)


def curved_bar_polar(r: NDArray[np.float64], M: float, a: float, b: float, t: float):
    """sigma_r, sigma_theta [Pa] at radius ``r`` in a curved bar a <= r <= b in pure bending by ``M`` [N m].

    Golovin's solution, Timoshenko & Goodier section 29, eqs. (a), (b) with M per unit thickness M/t:
    with N = (b^2 - a^2)^2 - 4 a^2 b^2 ln(b/a)^2,
    sigma_r = -4 M / (t N) (a^2 b^2 / r^2 ln(b/a) + b^2 ln(r/b) + a^2 ln(a/r)),
    sigma_theta = -4 M / (t N) (-a^2 b^2 / r^2 ln(b/a) + b^2 ln(r/b) + a^2 ln(a/r) + b^2 - a^2).
    M > 0 puts the inner fibre in tension.
    """
    r = np.asarray(r, float)
    lba = math.log(b / a)
    n = (b * b - a * a) ** 2 - 4 * a * a * b * b * lba * lba
    k = -4 * M / (t * n)
    common = b * b * np.log(r / b) + a * a * np.log(a / r)
    s_rr = k * (a * a * b * b / (r * r) * lba + common)
    s_tt = k * (-a * a * b * b / (r * r) * lba + common + b * b - a * a)
    return s_rr, s_tt


def curved_bar_stress(
    points: NDArray[np.float64], M: float, a: float, b: float, t: float
) -> NDArray[np.float64]:
    """Cartesian stresses (3, Q) of :func:`curved_bar_polar`, bar centred on the origin."""
    x, y = points
    s_rr, s_tt = curved_bar_polar(np.hypot(x, y), M, a, b, t)
    return polar_to_cartesian(np.arctan2(y, x), s_rr, s_tt, np.zeros_like(x))


def winkler_bach_stress(
    r: NDArray[np.float64] | float, M: float, a: float, b: float, t: float
) -> NDArray[np.float64]:
    """Curved-beam (Winkler-Bach) hoop stress [Pa] at radius ``r`` of a rectangular section a..b, depth b - a.

    sigma = M (r_n - r) / (A e r), with A = t (b - a), neutral radius r_n = (b - a) / ln(b/a) and
    e = R - r_n, R = (a + b) / 2 (Boresi & Schmidt, Advanced Mechanics of Materials, 6th ed.,
    eqs. 9.19 and 9.23, sign as :func:`curved_bar_polar`).
    """
    area = t * (b - a)
    r_n = (b - a) / math.log(b / a)
    e = (a + b) / 2 - r_n
    return M * (r_n - np.asarray(r, float)) / (area * e * np.asarray(r, float))


def straight_beam_stress(
    y: NDArray[np.float64] | float, M: float, depth: float, t: float
) -> NDArray[np.float64]:
    """Straight-beam bending stress -M y / I [Pa] at ``y`` from the mid-depth, I = t depth^3 / 12.

    With y measured outward (away from the centre of curvature), the sign matches
    :func:`curved_bar_polar` (M > 0: inner fibre, y = -depth / 2, in tension).
    """
    return -M * np.asarray(y, float) / (t * depth**3 / 12)


def spinning_bar_normal_force(
    x: NDArray[np.float64] | float, rho: float, area: float, omega: float, L: float
):
    """Axial force N(x) [N] in a bar of length ``L`` spinning at ``omega`` [rad/s] about its middle.

    x [m] from the middle; from the free body of the outer part: N = rho A omega^2 (L^2/4 - x^2) / 2.
    """
    return rho * area * omega**2 * (L * L / 4 - np.asarray(x, float) ** 2) / 2
