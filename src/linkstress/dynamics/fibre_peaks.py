"""The largest von Mises over one material chord of a section: where in the chord it is reached.

Along a chord, with u the offset from the neutral axis, sigma is a polynomial in u and Jourawski's
tau = w (C - u^2), so sigma_vM^2 = sigma^2 + 3 tau^2 is a polynomial too; its largest value on the
chord is at an end or at an interior local maximum. ``section_stress`` takes the ends itself and
asks this module for the interior candidates.

- A chord of a section split by holes carries sigma = n + m u: sigma_vM^2 is a quartic and its
  interior maximum is the middle root of a cubic, in closed form (``cubic_peak``).
- A single (solid) chord of half-depth c carries the body-load term as well. In s = u / c in
  [-1, 1], sigma_vM^2 = g(s) = (a + b s + d s^3)^2 + e (1 - s^2)^2, a sextic with at most two
  maxima on the whole line (its slope, a quintic, has at most five roots: minimum, maximum, minimum,
  maximum, minimum). ``single_chord_peak`` samples nine fibres, bounds g between
  each pair of samples, and solves g' = 0 where a bracket may hold the maximum.
"""

from __future__ import annotations

from functools import lru_cache

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
    cube = 2 * radius**3
    cos_arg = np.clip(np.divide(-q, cube, out=np.zeros_like(cube), where=cube > 0), -1.0, 1.0)
    return 2 * radius * np.cos(np.arccos(cos_arg) / 3 - 2 * np.pi / 3)


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


SAMPLES = 9
"""Fibres sampled per bracket of the search (``single_chord_peak``), its ends included."""
FEW_ENTRIES_SAMPLES = 2048
"""Where the entries are few, the first pass samples more fibres (up to ``MOST_SAMPLES``), as many as
make this many values: on short arrays a numpy call costs the same whatever its length, and denser
samples leave almost no bracket undecided for a second pass."""
MOST_SAMPLES = 257
LEVELS = 3
"""Passes of the search: the first samples the chord (at spacing 1/4 on long arrays), each later one
samples the brackets still undecided at an eighth of their width."""
NEWTON_STEPS = 6
SURE_STEPS = 3
CONVERGED = 1e-9
"""After ``SURE_STEPS`` Newton steps, an entry whose last step moved it by less than this (relative to
its bracket and offset) has converged: the next step would move it by the square of that."""

_UNIT = np.linspace(0.0, 1.0, SAMPLES)


def _first_samples(count: int) -> int:
    """Fibres sampled by the first pass over ``count`` entries: 2^k + 1, from ``SAMPLES`` to
    ``MOST_SAMPLES``, the most that keep samples x entries within ``FEW_ENTRIES_SAMPLES``."""
    samples = SAMPLES
    while 2 * samples - 1 <= MOST_SAMPLES and (2 * samples - 1) * count <= FEW_ENTRIES_SAMPLES:
        samples = 2 * samples - 1
    return samples


@lru_cache(maxsize=None)
def _chord_samples(count: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``count`` fibres evenly over the chord, as fractions of it (s = -1 + 2 t), and the matrix
    (4 count, 6) that takes the coefficients (a^2 + e, 2ab, b^2 - 2e, 2ad, 2bd + e, d^2) of g's
    powers (1, s, s^2, s^3, s^4, s^6) to g, g'/2, and g -+ (2h/3) g'/2 (h the spacing) there: the
    samples and the ends of each bracket's bound."""
    unit = np.linspace(0.0, 1.0, count)
    s = -1.0 + 2.0 * unit
    powers = np.array([0, 1, 2, 3, 4, 6])
    g = s[:, None] ** powers
    half_slope = powers * s[:, None] ** np.maximum(powers - 1, 0) / 2
    reach = (2 / 3) * (2 / (count - 1)) * half_slope
    return unit, np.vstack([g, half_slope, g + reach, g - reach])


def single_chord_peak(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    d: NDArray[np.float64],
    e: NDArray[np.float64],
    floor: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]:
    """Where g(s) = (a + b s + d s^3)^2 + e (1 - s^2)^2 is largest for s in [-1, 1] (arrays of one
    shape, e >= 0), for the entries where it beats ``floor`` (g reached already, at the outer
    fibres); without ``floor``, for every entry. Returns the indices of those entries, their s and
    g there.

    g is sampled at nine fibres (more where the entries are few: ``FEW_ENTRIES_SAMPLES``); every
    sample is at most the best value b so far. Between two samples
    h apart, in t = (s - s0) / h, g is its cubic Hermite interpolant (values g0, g1, slopes g'0, g'1
    at the ends), whose Bezier control points are g0, c1 = g0 + h g'0 / 3, c2 = g1 - h g'1 / 3, g1,
    plus an error of at most (h^4 / 24) max|g''''| t^2 (1 - t)^2. With g0, g1 <= b and
    t^2 (1 - t)^2 <= t (1 - t) / 4, g(t) - b <= t (1 - t) (3 (max(c1, c2) - b) + h^4 max|g''''| / 96),
    so an interior point beats b only where

        max(c1, c2) + (h^4 / 288) max|g''''| > b,

    with max|g''''| <= 24 |2 b d + e| + 360 d^2 on the chord. In a bracket where g' falls from
    positive to negative the maximum is the root of g', found by Newton's steps kept inside the
    bracket. A bracket that may still beat the best value found but shows no such sign change (a
    maximum and a minimum between two samples) is sampled again at an eighth of its width, up to
    ``LEVELS`` passes; what is undecided after that is a bracket 2^-8 wide, which can exceed the
    result by no more than its bound.
    """
    count = len(a)
    best = np.full(count, -np.inf) if floor is None else np.array(floor, float)
    at = np.full(count, np.nan)
    rows, lo, width = np.arange(count), np.full(count, -1.0), np.full(count, 2.0)
    for level in range(LEVELS):
        if not len(rows):
            break
        rows, lo, width = _search(a, b, d, e, rows, lo, width, best, at, first=level == 0)
    kept = np.flatnonzero(~np.isnan(at))
    return kept, at[kept], best[kept]


def _search(a, b, d, e, rows, lo, width, best, at, first):
    """One pass over the brackets [lo, lo + width] of entries ``rows``: samples, then Newton's steps
    where g' changes sign downward; raises ``best`` and ``at`` in place and returns the brackets
    between samples that are still undecided.

    Sample k of entry c is at lo[c] + width[c] k / (samples - 1); an element (k, c) of the
    (samples - 1, entries) bracket masks has the flat index f = k n + c, which is also that of
    its left sample in the (samples, entries) arrays (f + n its right one): every pick is a flat
    one, several times cheaper than indexing by (row, column) pairs."""
    if not first:
        a, b, d, e = a[rows], b[rows], d[rows], e[rows]
    fourth = 2 * b * d + e
    square = d * d
    if first:
        unit, matrix = _chord_samples(_first_samples(len(rows)))
        g, m, up, down = np.split(matrix @ np.stack([a * a + e, 2 * a * b, b * b - 2 * e, 2 * a * d, fourth, square]), 4)
    else:
        unit = _UNIT
        s = lo + width * unit[:, None]
        g, m = _g(s, a, b, d, e), _half_slope(s, _slope_terms(a, b, d, e))
        reach = m * ((2 / 3) * width / (len(unit) - 1))
        up, down = g + reach, g - reach
    n = len(rows)
    top = g.max(axis=0)
    above = np.flatnonzero(top > best[rows])
    peak = lo[above] + width[above] * unit[_row_of_max(g, top)[above]]
    if first:  # one bracket per entry: no np.maximum.at
        best[rows[above]], at[rows[above]] = top[above], peak
    else:
        _raise(best, at, rows[above], top[above], peak)
    h = width / (len(unit) - 1)
    error = (h**4 / 288) * (24 * np.abs(fourth) + 360 * square)
    threshold = best[rows] - error
    bracket = up[:-1] > threshold
    bracket |= down[1:] > threshold
    rising = m > 0
    crossing = rising[:-1] & ~rising[1:]
    crossing &= m[1:] < 0
    crossing &= bracket
    g, m, up, down = g.reshape(-1), m.reshape(-1), up.reshape(-1), down.reshape(-1)
    f = np.flatnonzero(crossing)
    if len(f):
        c = f % n
        s0 = lo[c] + width[c] * unit[f // n]
        slope = _slope_terms(a[c], b[c], d[c], e[c])
        peak = _newton(s0, s0 + h[c], g[f], g[f + n], m[f], m[f + n], slope)
        _raise(best, at, rows[c], _g(peak, a[c], b[c], d[c], e[c]), peak)
    bracket &= ~crossing
    f = np.flatnonzero(bracket)
    c = f % n
    still = np.maximum(up[f], down[f + n]) > best[rows[c]] - error[c]
    f, c = f[still], c[still]
    if not len(f):
        return rows[c], lo[c], h[c]
    s0 = lo[c] + width[c] * unit[f // n]
    open_ = ~_monotone(s0, h[c], m[f], m[f + n], _slope_terms(a[c], b[c], d[c], e[c]), d[c])
    return rows[c[open_]], s0[open_], h[c[open_]]


def _monotone(lo, h, m0, m1, slope, d):
    """Where g' keeps one sign over [lo, lo + h], so that g has no peak inside: g'/2 is at least
    (or at most) its cubic Hermite interpolant's control points m0, m0 + h m0' / 3, m1 - h m1' / 3,
    m1 (m' = g''/2 at the ends) less the interpolation error (h^4 / 384) max|g'''''| / 2, with
    g''''' = 720 d^2 s. The brackets a peak just past a sample leaves undecided by the bound on g
    are decided here, without sampling them again."""
    sign = np.sign(m0)
    bend = _bend_terms(slope)
    k0, k1 = _half_bend(lo, bend), _half_bend(lo + h, bend)
    low = np.minimum(np.minimum(m0, m1) * sign, np.minimum((m0 + h * k0 / 3) * sign, (m1 - h * k1 / 3) * sign))
    return (sign == np.sign(m1)) & (low > (h**4 / 384) * 360 * d * d)


def _g(s, a, b, d, e):
    sigma = a + s * (b + d * s * s)
    shape = 1 - s * s
    return sigma * sigma + e * shape * shape


def _slope_terms(a, b, d, e):
    """(c0, c1, c2, c3, c5) of g'(s) / 2 = c5 s^5 + c3 s^3 + c2 s^2 + c1 s + c0: a b, b^2 - 2 e, 3 a d,
    4 b d + 2 e, 3 d^2."""
    return a * b, b * b - 2 * e, 3 * a * d, 4 * b * d + 2 * e, 3 * d * d


def _bend_terms(slope):
    """(k0, k1, k2, k4) of g''(s) / 2 = k4 s^4 + k2 s^2 + k1 s + k0, from ``_slope_terms``."""
    c0, c1, c2, c3, c5 = slope
    return c1, 2 * c2, 3 * c3, 5 * c5


def _half_slope(s, slope):
    c0, c1, c2, c3, c5 = slope
    ss = s * s
    return (((c5 * ss + c3) * s + c2) * s + c1) * s + c0


def _half_bend(s, bend):
    k0, k1, k2, k4 = bend
    ss = s * s
    return (k4 * ss + k2) * ss + k1 * s + k0


def _newton(lo, hi, g_lo, g_hi, m_lo, m_hi, slope):
    """The root of g' in [lo, hi] where g'(lo) > 0 > g'(hi), a peak of g: from the peak of the
    bracket's cubic Hermite interpolant, ``SURE_STEPS`` plain Newton steps, which from so close a
    start land on it; an entry whose steps leave the bracket, end where g'' >= 0 (a trough) or are
    still moving starts again with the safeguarded steps (``_guarded_newton``)."""
    start = lo + (hi - lo) * _hermite_peak(g_hi - g_lo, (hi - lo) * 2 * m_lo, (hi - lo) * 2 * m_hi)
    bend_terms = _bend_terms(slope)
    s = start
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for _ in range(SURE_STEPS):
            bend = _half_bend(s, bend_terms)
            step = _half_slope(s, slope) / bend
            s = s - step
        # where a step was not finite, no comparison holds
        landed = (s >= lo) & (s <= hi) & (bend < 0) & (np.abs(step) <= CONVERGED * (hi - lo + np.abs(s)))
    again = np.flatnonzero(~landed)
    if len(again):
        s[again] = _guarded_newton(
            start[again], lo[again], hi[again], [t[again] for t in slope], [t[again] for t in bend_terms]
        )
    return s


def _guarded_newton(s, lo, hi, slope, bend):
    """Newton's steps kept in the bracket [lo, hi] (which shrinks by the sign of g'), bisection where
    they would leave it; after ``SURE_STEPS`` only the entries still moving take further steps."""
    s, lo, hi, last = _newton_steps(s, lo, hi, slope, bend, SURE_STEPS)
    going = np.flatnonzero(np.abs(s - last) > CONVERGED * (hi - lo + np.abs(s)))
    if len(going):
        s[going] = _newton_steps(
            s[going], lo[going], hi[going], [t[going] for t in slope], [t[going] for t in bend], NEWTON_STEPS - SURE_STEPS
        )[0]
    return s


def _newton_steps(s, lo, hi, slope_terms, bend_terms, steps):
    """``steps`` safeguarded Newton steps; returns s, the bracket, and s before the last step."""
    last = s
    for _ in range(steps):
        slope, bend = _half_slope(s, slope_terms), _half_bend(s, bend_terms)
        rising = (slope > 0).view(np.uint8)
        # lo = s where g' rises, hi = s where it falls: by arithmetic, since np.where on a mask
        # of no pattern costs several times more
        lo = lo + rising * (s - lo)
        hi = s + rising * (hi - s)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = s - slope / bend  # where bend = 0: not finite, so not in the bracket
        last, s = s, (lo + hi) / 2
        np.copyto(s, step, where=(step >= lo) & (step <= hi))
    return s, lo, hi, last


def _hermite_peak(rise, p0, p1):
    """Where in t in (0, 1) the cubic H with H(1) - H(0) = ``rise``, H'(0) = p0 > 0 > H'(1) = p1
    peaks: the root of H'(t) = A t^2 + B t + p0 in (0, 1), 2 p0 / (sqrt(B^2 - 4 A p0) - B) for
    either sign of A (clipped, where rounding takes the denominator to nothing)."""
    a = 3 * (p0 + p1 - 2 * rise)
    b = 2 * (3 * rise - 2 * p0 - p1)
    with np.errstate(divide="ignore"):
        return np.clip(2 * p0 / (np.sqrt(np.maximum(b * b - 4 * a * p0, 0.0)) - b), 0.0, 1.0)


def _row_of_max(g, top):
    """Per column of g, the first row where it equals ``top``, its column maximum, as argmax would
    give it (argmax along the first axis makes a strided pass several times slower)."""
    from_last = np.arange(len(g) - 1, -1, -1, dtype=np.uint16)[:, None]
    return len(g) - 1 - ((g == top).view(np.uint8) * from_last).max(axis=0)


def _raise(best, at, rows, g, s):
    """best[rows] = max(best[rows], g), and at[rows] = s where g wins; of a row repeated in ``rows``,
    its largest g."""
    before = best[rows]
    np.maximum.at(best, rows, g)
    wins = (g > before) & (g == best[rows])
    at[rows[wins]] = s[wins]
