"""Curved-beam (Winkler-Bach) normal stress on the cuts of a curved member.

A cut square to a member's curved centreline is a section of chords [a_k, b_k] in a coordinate v
along the cut (``SectionTable``: ``lower``, ``upper``, centroid v_bar = ``neutral_axis``, area A).
The member's signed curvature kappa [1/m] puts its centre of curvature on the cut at v = 1/kappa
(kappa > 0: toward +v). Plane sections stay plane and turn about that centre, so a fibre's stretch
is linear in v and its length proportional to 1 - kappa v (its distance from the centre, times
|kappa|): the normal strain (and stress) is (c0 + c1 v) / (1 - kappa v), a combination
alpha + beta g(v) of 1 and the hyperbola g(v) = v / (1 - kappa v). The two constants follow from
the resultants, int sigma dA = N and int sigma (v - v_bar) dA = M (M about the centroid, positive
putting +v fibres in tension):

    sigma(v) = N / A + M (g(v) - g_bar) / J,  g_bar = (1/A) int g dA,  J = int g (v - v_bar) dA.

g(v) - g_bar and J change by the same factor when v is measured from another point of the cut
(g of the shifted coordinate is an affine function of g), so they are taken about the centroid,
w = v - v_bar, where the centre of curvature is at w = 1/k with k = kappa / (1 - kappa v_bar):

    g(w) = w / (1 - k w),  J = int w^2 / (1 - k w) dA = I + k L,  L = int w^3 / (1 - k w) dA,
    g_bar = k J / A        (g = w + k w g and int w dA = 0).

(With g(v) = v / (1 - kappa v) about the cut's origin the mean is v_bar / c + g_bar / c^2 and the
stiffness J / c^2, c = 1 - kappa v_bar: the same gain (g - g_bar) / J.)

So sigma = N/A + M (g(w) / J - k / A). With k = 0 this is N/A + M w / I, the straight beam, with the
table's own I; the curved part enters only through k L, with no 1/k anywhere. On a chord,
int w^3 / (1 - k w) dw = [w^4 Q(k w)] with

    Q(z) = sum_m z^m / (m + 4) = (-log(1 - z) - z - z^2/2 - z^3/3) / z^4,

evaluated by its series where |z| < ``SERIES_LIMIT`` (there the closed form loses digits to
cancellation) and in closed form beyond. For a rectangle of radii ri..ro (depth h, centroid radius
R) this is Winkler-Bach's sigma = N/A + M (r_n - r) / (A e r), r_n = h / ln(ro/ri), e = R - r_n.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from linkstress.errors import GeometryError
from linkstress.geometry.sections import SectionTable

CURVED_BEAM_LIMIT = 0.1
"""|kappa| x section depth above which a member is a curved beam (its radius under ten depths).

The straight beam's bending stress on a rectangle misses Winkler-Bach's by about h / (3 R) at the
outer fibres (below it at the inner, above it at the outer): 3.3 % at ten depths, 11 % at three,
33 % at one. Past ten depths the straight beam's error is under the 3 % or so that beam and FEA
stresses differ by anyway; within them it grows fast, so the curved formula takes over there."""

SERIES_LIMIT = 0.5
"""|z| below which Q(z) is summed as its series: the closed form's relative rounding error grows as
about 4e-15 / |z| toward z = 0 (measured), 8e-15 at |z| = 0.5."""

SERIES_TERMS = 52
"""Terms of Q's series: at |z| = 0.5 the rest, under |z|^52 / 56 / (1 - |z|) = 8e-18, is below
5e-17 of Q (Q >= 0.179 for |z| <= 0.5)."""


@dataclass(frozen=True)
class CurvedSections:
    """Curved-beam properties of S cuts, each array (S,); v along the cut [m], as in ``SectionTable``.

    ``x`` the stations [m] (member frame); ``curvature`` kappa [1/m]: the centre of curvature is at
    v = 1 / kappa. ``centroid`` v_bar [m], ``area`` A [m^2], ``centroid_curvature``
    k = kappa / (1 - kappa v_bar) [1/m] (the same centre seen from the centroid: at w = v - v_bar = 1/k),
    ``stiffness`` J = int w^2 / (1 - k w) dA [m^4] (the second moment I where kappa = 0).
    """

    x: NDArray[np.float64]
    curvature: NDArray[np.float64]
    centroid: NDArray[np.float64]
    area: NDArray[np.float64]
    centroid_curvature: NDArray[np.float64]
    stiffness: NDArray[np.float64]

    @property
    def mean_g(self) -> NDArray[np.float64]:
        """g_bar = (1/A) int g dA = k J / A [m] of g(w) = w / (1 - k w), about the centroid."""
        return self.centroid_curvature * self.stiffness / self.area

    def gain(self, v: ArrayLike, at: int | slice | ArrayLike = slice(None)) -> NDArray[np.float64]:
        """(g(w) - g_bar) / J [1/m^3] at fibres ``v`` [m] of the stations ``at``: sigma = N/A + M gain.

        ``v`` has the shape of the selected stations (one fibre each) or that plus a trailing axis of
        fibres, e.g. (S,) or (S, F) for every station. Where kappa = 0 it is (v - v_bar) / I. A fibre
        at or beyond the centre of curvature is a GeometryError.
        """
        v = np.asarray(v, float)
        selected = (self.centroid_curvature[at], self.centroid[at], self.area[at], self.stiffness[at])
        # station values along the leading axes of v, the same for each of its fibres
        trailing = (1,) * (v.ndim - np.ndim(selected[0]))
        k, centroid, area, stiffness = (np.reshape(q, np.shape(q) + trailing) for q in selected)
        w = v - centroid
        gap = 1 - k * w
        if not (gap > 0).all():
            bad = np.broadcast_to(v, np.broadcast_shapes(v.shape, gap.shape))[~(gap > 0)][0]
            raise GeometryError(f"fibre v = {bad:.6g} m lies at or beyond its cut's centre of curvature")
        return w / (gap * stiffness) - k / area

    def neutral_axis_shift(self) -> NDArray[np.float64]:
        """e [m] (S,): how far the neutral axis under pure bending (sigma = 0) lies from the centroid,
        toward the centre of curvature, at v_bar + sign(kappa) e; 0 where kappa = 0.

        sigma = 0 where g(w) = g_bar, at w_n = g_bar / (1 + k g_bar). For a rectangle of radii
        ri..ro this is Winkler-Bach's e = R - h / ln(ro / ri).
        """
        g_bar = self.mean_g
        return np.abs(g_bar) / (1 + self.centroid_curvature * g_bar)


def curved_sections(table: SectionTable, curvature: ArrayLike) -> CurvedSections:
    """Curved-beam properties of the cuts of ``table`` with signed ``curvature`` kappa [1/m]
    (a scalar or one per station; 0 for a straight member), from the table's chords and thickness.

    Raises GeometryError where a chord reaches the centre of curvature (1 - kappa v <= 0 on it):
    the section reaches past its centre of curvature, so the cut is not square to a centreline of
    that radius.
    """
    kappa = np.broadcast_to(np.asarray(curvature, float), table.x.shape).copy()
    if not np.isfinite(kappa).all():
        bad = np.flatnonzero(~np.isfinite(kappa))[0]
        raise GeometryError(
            f"station x = {table.x[bad]:.6g} m: curvature must be finite, got {float(kappa[bad])!r} 1/m"
        )
    past = centre_reach(table, kappa) >= 1
    if past.any():
        i = np.flatnonzero(past)[0]
        raise GeometryError(
            f"station x = {table.x[i]:.6g} m: the section reaches past its centre of curvature: material at "
            f"v = {table.bottom[i]:.6g}..{table.top[i]:.6g} m, centre at v = {1 / kappa[i]:.6g} m "
            f"(curvature {kappa[i]:.6g} 1/m); a curved member's cut must stop short of its centre"
        )
    present = table.present
    centroid = table.neutral_axis
    k = kappa / (1 - kappa * centroid)
    # Padding chords are empty: w = 0 at both ends adds nothing.
    lo = np.where(present, table.lower - centroid[:, None], 0.0)
    hi = np.where(present, table.upper - centroid[:, None], 0.0)
    cubic = (hi**4 * cubic_kernel(k[:, None] * hi) - lo**4 * cubic_kernel(k[:, None] * lo)).sum(axis=1)
    stiffness = table.second_moment + k * table.thickness * cubic
    return CurvedSections(table.x, kappa, centroid, table.area, k, stiffness)


def centre_reach(table: SectionTable, curvature: NDArray[np.float64]) -> NDArray[np.float64]:
    """(S,): how far each section's material reaches toward its centre of curvature, kappa v at its
    fibre nearest the centre [-] (1: at the centre; 0 where kappa = 0)."""
    kappa = np.asarray(curvature, float)[:, None]
    reach = np.maximum(kappa * table.lower, kappa * table.upper)
    return np.where(table.present, reach, 0.0).max(axis=1)


def cubic_kernel(z: ArrayLike) -> NDArray[np.float64]:
    """Q(z) = sum_{m >= 0} z^m / (m + 4) = (-log(1 - z) - z - z^2/2 - z^3/3) / z^4 for z < 1 [-].

    d/dw [w^4 Q(k w)] = w^3 / (1 - k w). Series below ``SERIES_LIMIT`` in |z|, closed form above;
    relative error under 1e-14 either side.
    """
    z = np.asarray(z, float)
    q = np.empty_like(z)
    small = np.abs(z) < SERIES_LIMIT
    zs = z[small]
    series = np.zeros_like(zs)
    for m in range(SERIES_TERMS - 1, -1, -1):
        series = series * zs + 1 / (m + 4)
    q[small] = series
    zl = z[~small]
    q[~small] = -(np.log1p(-zl) + zl * (1 + zl * (1 / 2 + zl / 3))) / zl**4
    return q


def theory_of(curvature: ArrayLike, depth: ArrayLike) -> NDArray[np.str_]:
    """"curved" where |``curvature``| [1/m] x ``depth`` [m] (the cut's extent across the member, outer
    fibre to outer fibre) exceeds ``CURVED_BEAM_LIMIT`` (a radius under ten section depths), else
    "straight"; elementwise."""
    curved = np.abs(np.asarray(curvature, float)) * np.asarray(depth, float) > CURVED_BEAM_LIMIT
    return np.where(curved, "curved", "straight")
