"""The largest von Mises over one material chord of a section: where in the chord it is reached.

Along a chord, with u the offset from the neutral axis, sigma is a polynomial in u and Jourawski's
tau = w (C - u^2), so sigma_vM^2 = sigma^2 + 3 tau^2 is a polynomial too; its largest value on the
chord is at an end or at an interior local maximum. ``section_stress`` takes the ends itself and
asks this module for the interior candidates.

- A chord of a section split by holes carries sigma = n + m u: sigma_vM^2 is a quartic and its
  interior maximum is the middle root of a cubic, in closed form (``cubic_peak``).
- A single (solid) chord of half-depth c carries the body-load term as well. In s = u / c in
  [-1, 1], sigma_vM^2 = g(s) = (a + b s + d s^3)^2 + e (1 - s^2)^2, whose derivative is a quintic
  with up to three maxima in the chord. ``single_chord_peak`` samples nine fibres and climbs from
  each sample that is higher than its neighbours, taking only the Newton steps that raise g.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

INTERIOR_SLACK = 1e-9
"""Relative slack of the three-root test, so that rounding never hides a maximum at a double root."""


def cubic_peak(n, m, w, c):
    """The offset u of the interior local maximum of (n + m u)^2 + 3 w^2 (C - u^2)^2, arrays of one
    shape with w != 0 (``c`` is C).

    d/du / 2 = 6 w^2 u^3 + (m^2 - 6 w^2 C) u + m n; where it has three real roots
    (``has_cubic_peak``) the middle one is the maximum (Cardano's trigonometric solution; clipping the
    cosine's argument takes a double root where rounding put three roots at two, and elsewhere the
    result is some real fibre offset, never a NaN).
    """
    w6 = 6 * w * w
    p = (m * m - w6 * c) / w6
    q = m * n / w6
    radius = np.sqrt(np.maximum(-p / 3, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        cos_arg = np.clip(-q / (2 * radius**3), -1.0, 1.0)
    return 2 * radius * np.cos(np.arccos(np.nan_to_num(cos_arg)) / 3 - 2 * np.pi / 3)


def has_cubic_peak(n, m, w, c):
    """Where the cubic of ``cubic_peak`` has three real roots, as a mask.

    With P = m^2 - 6 w^2 C and Q = m n (the cubic's p and q times 6 w^2 > 0), three roots need
    P < 0 and 27 q^2 < -4 p^3, that is 27 Q^2 6 w^2 < -4 P^3: no division, so it runs on whole
    arrays of sections where w may be zero (then there is no interior maximum).
    """
    w6 = 6 * w * w
    with np.errstate(over="ignore", invalid="ignore"):
        p = m * m - w6 * c
        q = m * n
        return (p < 0) & (27 * q * q * w6 < -4 * (1 + INTERIOR_SLACK) * p * p * p)


GRID = np.linspace(-1.0, 1.0, 9)
"""Fibres s sampled by ``single_chord_peak``: a peak of g between two samples shows as a sample
higher than its neighbours."""
CLIMB_STEPS = 4


def single_chord_peak(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    d: NDArray[np.float64],
    e: NDArray[np.float64],
    floor: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """Where g(s) = (a + b s + d s^3)^2 + e (1 - s^2)^2 is largest for s in [-1, 1] (arrays of one
    shape, e >= 0): a climb from every sample of ``GRID`` that is at least as high as its
    neighbours, the highest summit kept.

    With ``floor`` (the larger of g(-1) and g(1), reached already at the outer fibres), only the
    entries whose g may exceed it are climbed: between samples h apart g exceeds the higher sample
    by at most h^2 / 8 max|g''|, and |g''| <= sum k (k - 1) |p_k| on the chord for g = sum p_k s^k.
    Returns the indices of the entries climbed and their s.
    """
    sampled = np.stack([a, b, d], axis=1) @ np.stack([np.ones_like(GRID), GRID, GRID**3])
    sampled *= sampled
    sampled += e[:, None] * (1 - GRID * GRID) ** 2
    summit = np.ones(sampled.shape, bool)
    summit[:, 1:] &= sampled[:, 1:] >= sampled[:, :-1]
    summit[:, :-1] &= sampled[:, :-1] >= sampled[:, 1:]
    if floor is not None:
        # p2 = b^2 - 2e, p3 = 2ad, p4 = 2bd + e, p6 = d^2
        bend = 2 * np.abs(b * b - 2 * e) + 12 * np.abs(a * d) + 12 * np.abs(2 * b * d + e) + 30 * d * d
        h = GRID[1] - GRID[0]
        summit &= sampled + (h * h / 8) * bend[:, None] > floor[:, None]
        # An end whose neighbour sample is lower: g there is at most g(end) - |g'(end)| t + bend t^2 / 2
        # at a distance t inside, never above the end (reached already) while t <= 2 |g'(end)| / bend.
        # g'(+-1) = 2 sigma(+-1) sigma'(+-1): the shear term's slope vanishes at the free edges.
        slope_bottom = 2 * (a - b - d) * (b + 3 * d)
        slope_top = 2 * (a + b + d) * (b + 3 * d)
        summit[:, 0] &= -slope_bottom < bend * h / 2
        summit[:, -1] &= slope_top < bend * h / 2
    rows, k = np.nonzero(summit)
    if not len(rows):
        return rows, GRID[k]
    s, g = _climb(GRID[k], a[rows], b[rows], d[rows], e[rows], GRID[np.maximum(k - 1, 0)], GRID[np.minimum(k + 1, len(GRID) - 1)])
    # rows come sorted: reduce each row's run of starts
    starts_run = np.r_[True, rows[1:] != rows[:-1]]
    first = np.flatnonzero(starts_run)
    best = np.maximum.reduceat(g, first)[np.cumsum(starts_run) - 1]
    return rows[first], np.maximum.reduceat(np.where(g == best, s, -np.inf), first)


def _climb(s, a, b, d, e, lo, hi):
    """Steps up g from ``s`` within [lo, hi], each kept only where g rises (else the next is halved):
    Newton's on g'(s) = 0 where g is concave, else a quarter of the bracket uphill; returns the
    fibres and g at them."""

    def g_at(s):
        sigma = a + s * (b + d * s * s)
        shape = 1 - s * s
        return sigma * sigma + e * shape * shape

    best = g_at(s)
    # g'(s) / 2 = 3 d^2 s^5 + (4 b d + 2 e) s^3 + 3 a d s^2 + (b^2 - 2 e) s + a b
    c5, c3, c2, c1, c0 = 3 * d * d, 4 * b * d + 2 * e, 3 * a * d, b * b - 2 * e, a * b
    scale = np.ones_like(s)
    for _ in range(CLIMB_STEPS):
        ss = s * s
        slope = (((c5 * ss + c3) * s + c2) * s + c1) * s + c0
        bend = (5 * c5 * ss + 3 * c3) * ss + 2 * c2 * s + c1
        uphill = np.copysign((hi - lo) / 4, slope)  # where g is not concave
        step = np.clip(np.divide(-slope, bend, out=uphill, where=bend < 0), lo - s, hi - s)
        trial = s + scale * step
        value = g_at(trial)
        rises = value > best
        scale = np.where(rises, 1.0, scale / 2)
        s = np.where(rises, trial, s)
        best = np.where(rises, value, best)
    return s, best
