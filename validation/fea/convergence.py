"""Mesh convergence: a refinement study with a Richardson estimate of the nominal stresses' error.

The link is solved on three (or more) meshes, each ``ratio`` times finer than the last. Three
quantities are followed from mesh to mesh: the von Mises stresses at given nominal points (fibres
of the comparison stations), the section resultants N, V, M at the meshed cuts, and the peak von
Mises anywhere in the link. Each is judged by its change between the two finest meshes: the nominal
stresses are converged below ``tolerance`` (CONVERGED_CHANGE, 0.5 %) of the largest of them at
that position, the peak below PEAK_CONVERGED_CHANGE (5 %) of itself over each of the last two
refinements; the resultants' change is
measured in ``compare`` (against RESULTANT_CONVERGED_CHANGE), with the measure of their error.

The discretisation error of the finest mesh is estimated by Richardson extrapolation with the
observed order of accuracy, following Celik et al., "Procedure for estimation and reporting of
uncertainty due to discretization in CFD applications", J. Fluids Eng. 130 (2008) 078001, eqs. 1-7
(representative spacing h = sqrt(area / elements), so unequal refinement ratios are allowed).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from linkstress.loads import LinkLoadCase
from linkstress.geometry.profile import LinkProfile
from linkstress.stress_state import von_mises
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.cache import DiskCache
from linkstress.validation.fea.link import LinkFEAResult, join_results, solve_link
from linkstress.validation.fea.mesh import MeshSettings

CONVERGED_CHANGE = 0.005
"""Largest change of the nominal von Mises between the two finest meshes, relative to the largest
of them at a position, for them to count as converged."""
RESULTANT_CONVERGED_CHANGE = 0.02
"""Largest change of the section resultants between the two finest meshes (the measure of
``compare.resultant_error``) for them to count as converged. Statics gives their exact value, which
validate's RESULTANT_LIMIT checks on the finest mesh; this limit flags a mesh that has not settled.
Measured on the seed crank: its cut five hole radii from the torqued pin O2 moved 1.1 % between the
two finest default meshes (0.47, 1.10, 0.06 % from statics on the three), the other links' cuts
0.04-0.19 %."""
PEAK_CONVERGED_CHANGE = 0.05
"""Largest change of the FEA's peak von Mises over each of the last two refinements (the three
finest meshes), relative to the finer mesh, for it to count as converged. A peak sits at a hole's
rim or a corner, where the stress is steep and converges more slowly than a nominal one; a peak
that moves more than this is not a number to take a safety factor from. Both refinements count:
a sharp re-entrant notch's corner stress (singular, it grows without bound) went 74.9 -> 90.0 ->
85.8 -> 101.6 MPa over four meshes 1.5 x finer each, 4.8 % over the third refinement alone."""
MIN_ORDER, MAX_ORDER = 1e-3, 20.0
TRUSTED_ORDER = 0.5
"""Below this observed order the extrapolation overshoots (a concave edge creeping at order 0.02
put it 1.1 % off on the banana coupler): the estimate falls back to the last change."""
ORDER_ITERATIONS = 80


@dataclass(frozen=True)
class RichardsonEstimate:
    """Per quantity: observed ``order`` p, ``extrapolated`` value, ``error`` = |extrapolated - finest|.

    ``gci``: Celik's fine-grid convergence index 1.25 |phi_1 - phi_2| / (r21^p - 1), in the
    quantity's units. ``determined`` is False where the three values do not converge monotonically
    (a change of sign, no change, or an order outside (0, 20]): there the order is 0, the
    extrapolation is the finest value and ``error`` and ``gci`` fall back to the last change
    |phi_1 - phi_2|.
    """

    order: NDArray[np.float64]
    extrapolated: NDArray[np.float64]
    error: NDArray[np.float64]
    gci: NDArray[np.float64]
    determined: NDArray[np.bool_]


def richardson(values: ArrayLike, spacing: ArrayLike) -> RichardsonEstimate:
    """Richardson estimate from ``values`` (3, ...) on meshes of representative ``spacing`` (3,) [m].

    Any order of the three meshes; the finest (smallest spacing) is phi_1 (Celik et al. eqs. 3-7).
    """
    phi = np.asarray(values, float)
    h = np.asarray(spacing, float)
    if phi.shape[0] != 3 or h.shape != (3,):
        raise ValueError(f"Richardson needs three meshes, got values {phi.shape} and spacing {h.shape}")
    order = np.argsort(h)
    h1, h2, h3 = h[order]
    phi1, phi2, phi3 = phi[order]
    if not h1 < h2 < h3:
        raise ValueError(f"the three mesh spacings must differ, got {h.tolist()}")
    r21, r32 = h2 / h1, h3 / h2
    e21, e32 = phi2 - phi1, phi3 - phi2
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = e32 / e21
        determined = np.isfinite(ratio) & (ratio > 0)
        p = _observed_order(np.log(np.where(determined, ratio, 1.0)), r21, r32)
        determined &= np.isfinite(p) & (p >= TRUSTED_ORDER)
        p = np.where(determined, p, 0.0)
        gain = np.where(determined, r21**p - 1, 1.0)
        extrapolated = np.where(determined, phi1 + (phi1 - phi2) / gain, phi1)
    change = np.abs(e21)
    error = np.where(determined, np.abs(extrapolated - phi1), change)
    gci = np.where(determined, 1.25 * change / gain, change)
    return RichardsonEstimate(p, extrapolated, error, gci, determined)


def _observed_order(log_ratio: NDArray[np.float64], r21: float, r32: float) -> NDArray[np.float64]:
    """p solving ln(e32 / e21) = p ln r21 + ln((r32^p - 1) / (r21^p - 1)) (Celik eq. 5, s = 1), by bisection.

    The right side grows monotonically from ln(ln r32 / ln r21) at p = 0; no root in (0, MAX_ORDER]
    gives nan (order not determined).
    """

    def side(p):
        return p * math.log(r21) + np.log(np.expm1(p * math.log(r32)) / np.expm1(p * math.log(r21)))

    lo = np.full(np.shape(log_ratio), MIN_ORDER)
    hi = np.full(np.shape(log_ratio), MAX_ORDER)
    bracketed = (side(lo) <= log_ratio) & (log_ratio <= side(hi))
    for _ in range(ORDER_ITERATIONS):
        mid = (lo + hi) / 2
        below = side(mid) < log_ratio
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return np.where(bracketed, (lo + hi) / 2, np.nan)


@dataclass(frozen=True)
class ConvergenceStudy:
    """Nominal von Mises ``values`` (levels, P, Q) [Pa] on ever finer meshes, coarsest first.

    ``spacing`` (levels,) [m]: sqrt(area / elements); ``change`` (P,): largest change of the nominal
    values between the two finest levels over the largest finest value, per position (0 without
    nominal points); ``richardson`` from the three finest levels; ``finest``: the finest level's
    full result. ``peaks`` (levels, P) [Pa]: the largest von Mises anywhere in the link;
    ``resultants`` (levels, 3, P, S + C): N [N], V [N], M [N m] at the meshed cuts, the stations
    ``settings[0].stations`` then the segments ``settings[0].cuts`` (either may be none), member frame.
    """

    settings: tuple[MeshSettings, ...]
    spacing: NDArray[np.float64]
    dofs: NDArray[np.int64]
    seconds: NDArray[np.float64]
    values: NDArray[np.float64]
    change: NDArray[np.float64]
    tolerance: float
    richardson: RichardsonEstimate
    finest: LinkFEAResult
    peaks: NDArray[np.float64]
    resultants: NDArray[np.float64]

    @property
    def converged(self) -> bool:
        """The nominal values changed by less than ``tolerance`` at every position (the peak and the
        resultants are judged apart: ``peak_change``, ``compare.LinkComparison.convergence``)."""
        return bool((self.change < self.tolerance).all())

    @property
    def has_nominal(self) -> bool:
        """Whether the study followed any nominal point."""
        return self.values.shape[-1] > 0

    @property
    def peak_changes(self) -> NDArray[np.float64]:
        """(levels - 1, P) [-]: |change of the peak von Mises over each refinement| over the finer value."""
        finer, coarser = self.peaks[1:], self.peaks[:-1]
        return np.divide(np.abs(finer - coarser), finer, out=np.zeros_like(finer), where=finer > 0)

    @property
    def peak_change(self) -> NDArray[np.float64]:
        """(P,) [-]: the peak's change over the last refinement (between the two finest meshes)."""
        return self.peak_changes[-1]

    @property
    def relative_error(self) -> NDArray[np.float64]:
        """Richardson error estimate (P,) of the finest mesh over its largest nominal value, per position."""
        return _relative(self.richardson.error, self.values[-1])


REFINEMENT_RATIO = 1.5
"""Each mesh of a refinement study is this much finer than the last."""


def convergence_study(
    link: LinkProfile,
    loads: LinkLoadCase,
    settings: MeshSettings,
    points: ArrayLike,
    levels: int = 3,
    ratio: float = REFINEMENT_RATIO,
    tolerance: float = CONVERGED_CHANGE,
    cut_axes: tuple[ArrayLike, ArrayLike] | None = None,
    cache: DiskCache | None = None,
) -> ConvergenceStudy:
    """Solve ``link`` on ``levels`` meshes from ``settings``, each ``ratio`` finer, and follow the
    von Mises stresses at the nominal ``points`` (Q, 2) [m, member frame of the load case; Q may be
    0], the peak von Mises and the resultants at the cuts ``settings.stations`` and
    ``settings.cuts``, those taken across ``cut_axes`` = (tangents (C, 2), reference points (C, 2)
    [m]) (``LinkFEAResult.cut_resultants``; needed when there are cut segments). Each level's mesh
    from and into ``cache`` when given."""
    if settings.cuts and cut_axes is None:
        raise FEAError("a convergence study over cut segments needs their tangents and reference points")
    if levels < 3:
        raise FEAError(f"a convergence study needs at least three mesh levels, got {levels}")
    if not ratio > 1:
        raise FEAError(f"the refinement ratio must be > 1, got {ratio}")
    points = np.asarray(points, float).reshape(-1, 2)
    area = link.area
    meshes, spacing, dofs, seconds, values, peaks, resultants = [], [], [], [], [], [], []
    result = None
    for level in range(levels):
        level_settings = settings.refined(ratio**level)
        result = solve_link(link, loads, level_settings, cache)
        meshes.append(level_settings)
        spacing.append(math.sqrt(area / result.n_elements))
        dofs.append(result.dofs)
        seconds.append(result.mesh_seconds + result.solve_seconds)
        values.append(von_mises(result.stress_at(points)) if len(points) else np.zeros((result.n_positions, 0)))
        peaks.append(result.von_mises_peak)
        resultants.append(_resultants(result, settings.stations, cut_axes))
    return _study(
        tuple(meshes), np.array(spacing), np.array(dofs), np.array(seconds), np.array(values), tolerance, result,
        np.array(peaks), np.array(resultants),
    )


def join_studies(parts: Sequence[ConvergenceStudy]) -> ConvergenceStudy:
    """One study over the positions of ``parts`` in their order, each of the same link on the same
    meshes at a block of positions: what one study of them all gives (its changes and Richardson
    estimates are per position); times add up. FEAError when the blocks' meshes differ."""
    first = parts[0]
    if any(p.settings != first.settings or not np.array_equal(p.dofs, first.dofs) for p in parts):
        raise FEAError(f"link {first.finest.link.name!r}: its blocks of positions were meshed differently; solve it in one block")
    return _study(
        first.settings, first.spacing, first.dofs, np.sum([p.seconds for p in parts], axis=0),
        np.concatenate([p.values for p in parts], axis=1), first.tolerance, join_results([p.finest for p in parts]),
        np.concatenate([p.peaks for p in parts], axis=1), np.concatenate([p.resultants for p in parts], axis=2),
    )


def _study(settings, spacing, dofs, seconds, values, tolerance, finest, peaks, resultants) -> ConvergenceStudy:
    """The study of these levels, its changes and Richardson estimate made from their values."""
    return ConvergenceStudy(
        settings=settings,
        spacing=spacing,
        dofs=dofs,
        seconds=seconds,
        values=values,
        change=_relative(np.abs(values[-1] - values[-2]), values[-1]),
        tolerance=tolerance,
        richardson=richardson(values[-3:], spacing[-3:]),
        finest=finest,
        peaks=peaks,
        resultants=resultants,
    )


def _resultants(
    result: LinkFEAResult, stations: tuple[float, ...], cut_axes: tuple[ArrayLike, ArrayLike] | None
) -> NDArray[np.float64]:
    """(3, P, S + C): N [N], V [N], M [N m] at the meshed cuts ``stations`` [m], then at the
    meshed segments across ``cut_axes`` (tangents, reference points); either may be none."""
    parts = [np.zeros((3, result.n_positions, 0))]
    if stations:
        cut = result.section_resultants(stations)
        parts.append(np.stack([cut.normal, cut.shear, cut.moment]))
    if len(result.plane.segments):
        cut = result.cut_resultants(result.plane.segments, *cut_axes)
        parts.append(np.stack([cut.normal, cut.shear, cut.moment]))
    return np.concatenate(parts, axis=-1)


def _relative(difference: NDArray[np.float64], finest: NDArray[np.float64]) -> NDArray[np.float64]:
    """max over points of ``difference`` (P, Q) over max |finest| (P,), 0 where nothing is loaded."""
    scale = np.abs(finest).max(axis=-1, initial=0.0)
    worst = difference.max(axis=-1, initial=0.0)
    return np.divide(worst, scale, out=np.zeros_like(worst), where=scale > 0)
