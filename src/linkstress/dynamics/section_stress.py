"""Beam-section stresses along a link: normal, Jourawski shear and von Mises at every fibre.

At station x with N, V, M (see ``internal_forces``) and the section's A, I, y_na and first moment
Q(y) (``linkstress.sections``), at fibre y of the plate of thickness t, with u = y - y_na:

    sigma = N / A + M u / I,   tau = V Q(y) / (I t),   sigma_vM = sqrt(sigma^2 + 3 tau^2).

Within one material chord [a, b], Q(y) = (t / 2)(C - u^2) with C = 2 Q(b) / t + (b - y_na)^2, so
sigma_vM^2 = (n + m u)^2 + 3 w^2 (C - u^2)^2 (n = N/A, m = M/I, w = V / 2I) is a quartic in u with a
positive leading term: its largest value on the chord is at an end or at its only interior local
maximum, the middle real root of the cubic f'(u) = 0 (``fibre_peaks``). Near a pin hole beam theory
does not hold: stations closer to a hole's centre than one local section depth are flagged, and
their values are nominal.

Distributed body load. The d'Alembert (and gravity) load acts through the depth, and elementary
beam theory misses the part of sigma it causes. For a solid section of half-depth c under a
transverse body load b_y [N/m^3] uniform through the depth, the Airy stress function
phi = a x^2 y + b y^3 + d (x^2 y^3 - y^5 / 5) with free edges (sigma_y = tau = 0 at y = +-c) gives
d = -b_y / (4 c^2) and, beside M y / I (same M), the self-equilibrated term

    delta_sigma(v) = (b_y / c^2) (v^3 - 3 c^2 v / 5),   v measured from mid-depth,

(+0.4 b_y c at the top fibre), while its shear stress is exactly Jourawski's. It is added on every
single-chord section, with b_y = rho (g - a_O - alpha k x r)_y at the station (the part of the
d'Alembert load uniform through the depth); sigma is then a cubic in u and the chord's interior
maxima are found by ``fibre_peaks.single_chord_peak``. On the stubby seed bars the term is 2-4 % of
the nominal stress and takes the beam-versus-FEA difference there from up to 3.8 % to under 0.6 %;
near a link's free ends, where N and M fade, it is most of the stress. Sections split by holes get
no correction (their values are nominal anyway).

Every stress is linear in the load coefficients, so N, V, M and the outer fibres' sigma over a
sweep are products of the (P, Q) coefficients with (Q, S) bases made once per link, evaluated in
blocks of positions; only the (position, station) pairs where a bound says a chord's interior can
beat its outer fibres are searched further.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.fibre_peaks import cubic_peak, has_cubic_peak, single_chord_peak
from linkstress.dynamics.internal_forces import ALPHA, FREE_Y, ForceBasis, InternalForces, force_basis, load_coefficients
from linkstress.dynamics.pin_holes import PinHoleEstimate, pin_hole_estimates
from linkstress.loads import LinkLoadCase
from linkstress.profile import LinkProfile
from linkstress.sections import SectionTable
from linkstress.threads import blas_alone, in_parallel



@dataclass(frozen=True)
class SectionStresses:
    """Stresses along one link over P positions and S stations, member frame.

    ``forces``: N, V, M. ``von_mises`` (P, S) [Pa]: the largest von Mises over the section's fibres,
    reached at ``fibre_y`` (P, S) [m]; ``sigma``/``tau`` (P, S) [Pa] at that fibre (made when asked
    for, from the section forces). ``near_hole`` (S,):
    station within one section depth of a hole's centre (nominal values only); ``pin_holes``: the
    Kt x nominal estimate at each pin hole (``pin_holes.py``), labelled as an estimate. ``max_von_mises`` (P,) and
    ``max_at`` (P, 2) [m]: the largest over all stations; ``max_away_from_holes`` likewise over
    stations not near a hole (None where every station is near one).
    """

    sections: SectionTable
    forces: InternalForces
    von_mises: NDArray[np.float64]
    fibre_y: NDArray[np.float64]
    near_hole: NDArray[np.bool_]
    pin_holes: tuple[PinHoleEstimate, ...]
    shape: "_SectionShape"
    body_load: NDArray[np.float64]
    """(P, 2): (g - a_O)_y [m/s^2] and alpha [rad/s^2], for sigma's body-load term."""

    @property
    def sigma(self) -> NDArray[np.float64]:
        """(P, S) [Pa]: sigma at the critical fibre, N / A + M u / I and, on single chords, the
        body-load term."""
        shape, forces = self.shape, self.forces
        u = self.fibre_y - self.sections.neutral_axis
        beta = shape.density * (self.body_load[:, :1] - self.body_load[:, 1:] * shape.x) * shape.inverse_square_half
        return _sigma(forces.normal * shape.inv_area, forces.moment * shape.inv_inertia, u, beta, shape.half)

    @property
    def tau(self) -> NDArray[np.float64]:
        """(P, S) [Pa]: Jourawski's V Q(y) / (I t) at the critical fibre."""
        first_moment = self.sections.first_moment(self.fibre_y.T).T
        return self.forces.shear * self.shape.inv_inertia * first_moment / self.sections.thickness

    @property
    def x(self) -> NDArray[np.float64]:
        return self.sections.x

    @property
    def max_von_mises(self) -> NDArray[np.float64]:
        return self.von_mises.max(axis=1)

    @property
    def max_at(self) -> NDArray[np.float64]:
        k = self.von_mises.argmax(axis=1)
        rows = np.arange(len(k))
        return np.column_stack([self.x[k], self.fibre_y[rows, k]])

    @property
    def max_away_from_holes(self) -> NDArray[np.float64] | None:
        """(P,) largest von Mises over the stations not near a hole; None when every station is."""
        away = self.von_mises[:, ~self.near_hole]
        return away.max(axis=1) if away.shape[1] else None


def default_stations(link: LinkProfile, frame_joints: tuple[int, int], count: int) -> NDArray[np.float64]:
    """``count`` stations [m] at the centres of equal cells over the link's extent (never on an end,
    where a rounded link's section shrinks to a point)."""
    lo, hi = link.x_extent(*frame_joints)
    return lo + (hi - lo) * (np.arange(count) + 0.5) / count


NEAR_HOLE_SLACK = 1e-9
"""A station exactly one depth from a pin (the midpoint of a bar as long as two depths) is not near it."""


def near_holes(link: LinkProfile, frame_joints: tuple[int, int], sections: SectionTable) -> NDArray[np.bool_]:
    """Stations closer (along x) to a hole's centre than the local section depth (St-Venant: a pin's
    load spreads into a beam-like stress state about one depth from where it is applied)."""
    centres = link.frame(*frame_joints).to_local(link.holes[0])[:, 0]
    depth = sections.top - sections.bottom
    return (np.abs(sections.x[:, None] - centres) < (depth * (1 - NEAR_HOLE_SLACK))[:, None]).any(axis=1)


def section_stresses(
    link: LinkProfile,
    loads: LinkLoadCase,
    stations: NDArray[np.float64],
) -> SectionStresses:
    """Stresses at ``stations`` [m] (member frame of ``loads.frame_joints``) for every position.

    Candidates for the largest von Mises of a section: its outer fibres (free edges, tau = 0), the
    ends of chords at holes, and each chord's interior maximum where shear matters. Every stress is
    linear in the load coefficients (``load_coefficients``), so N, V, M and the outer fibres' sigma
    are each one product of those with a basis made once per link. Blocks of positions run on
    every core, BLAS on one thread (``linkstress.threads``).
    """
    return links_section_stresses([(link, loads, stations)])[0]


def links_section_stresses(
    jobs: Sequence[tuple[LinkProfile, LinkLoadCase, NDArray[np.float64]]],
) -> list[SectionStresses]:
    """``section_stresses(link, loads, stations)`` for each job: the blocks of positions of every
    link share the cores, so that no core waits at the end of one link's blocks."""
    with blas_alone():
        sweeps = [_Sweep.of(*job) for job in jobs]
        pairs = sum(sweep.fibres.von_mises.size for sweep in sweeps)
        in_parallel(
            _evaluate, [(sweep, block) for sweep in sweeps for block in sweep.blocks()], threads=pairs >= THREADED_PAIRS,
        )
        return [sweep.result() for sweep in sweeps]


def _evaluate(item: tuple["_Sweep", slice]) -> None:
    sweep, positions = item
    sweep.evaluate(positions)


@dataclass(frozen=True)
class _Sweep:
    """One link's section stresses over the sweep, being filled block by block."""

    link: LinkProfile
    loads: LinkLoadCase
    table: SectionTable
    basis: ForceBasis
    shape: "_SectionShape"
    fibre_bases: tuple[NDArray[np.float64], ...]
    coefficients: NDArray[np.float64]
    forces: InternalForces
    fibres: "_Fibres"

    @classmethod
    def of(cls, link: LinkProfile, loads: LinkLoadCase, stations: NDArray[np.float64]) -> "_Sweep":
        table = link.sections(stations, *loads.frame_joints)
        basis = force_basis(link, loads, table)
        shape = _SectionShape.of(table, link.density)
        coefficients = load_coefficients(loads)
        size = (len(coefficients), len(table.x))
        normal, shear, moment, von_mises, u = (np.empty(size) for _ in range(5))
        forces = InternalForces(table.x, normal, shear, moment, np.empty(size[0]))
        fibres = _Fibres(von_mises, u)
        return cls(link, loads, table, basis, shape, shape.fibre_basis(basis), coefficients, forces, fibres)

    def blocks(self) -> list[slice]:
        """Near-equal blocks of at most ``POSITION_BLOCK`` positions."""
        count = len(self.coefficients)
        edges = np.linspace(0, count, -(-count // POSITION_BLOCK) + 1).round().astype(int)
        return [slice(lo, hi) for lo, hi in zip(edges[:-1], edges[1:])]

    def evaluate(self, p: slice) -> None:
        """Every fibre candidate of positions ``p``: the writes touch only those rows."""
        basis, shape, forces, fibres = self.basis, self.shape, self.forces, self.fibres
        mean, spread, body = self.fibre_bases
        c = self.coefficients[p]
        normal, shear, moment = forces.normal[p], forces.shear[p], forces.moment[p]
        for out, b in ((normal, basis.normal), (shear, basis.shear), (moment, basis.moment)):
            np.matmul(c, b, out=out)
        forces.mismatch[p] = basis.mismatch(c, normal, shear, moment)
        block = fibres.block(p)
        size_n, size_m = shape.outer_fibres(c @ mean, c @ spread, block)
        # a crank turning steadily about a fixed pivot, without gravity, has no body load
        loaded = c[:, [FREE_Y, ALPHA]].any()
        at_single, at_split, chord = shape.interior_candidates(
            size_n, size_m, block.von_mises, np.abs(c @ body) if loaded else None, normal, shear, moment
        )
        offset = p.start * len(shape.x)
        shape.single_interiors(forces, self.coefficients, at_single + offset, fibres)
        shape.hole_end_fibres(forces, fibres, p)
        shape.split_interiors(forces, at_split + offset, chord, fibres)
        block.u += self.table.neutral_axis  # now the fibre's y

    def result(self) -> SectionStresses:
        frame_joints = self.loads.frame_joints
        fibres = self.fibres
        return SectionStresses(
            self.table, self.forces, fibres.von_mises, fibres.u,
            near_holes(self.link, frame_joints, self.table), pin_hole_estimates(self.link, self.loads),
            self.shape, self.coefficients[:, [FREE_Y, ALPHA]],
        )


THREADED_PAIRS = 50_000
"""(Position, station) pairs from which the blocks run on threads: below it, about one block of
positions, handing work to threads costs more than it saves."""

BODY_TERM = 0.1925
"""Half the 0.385 of the body-load term in ``interior_candidates``' test."""

POSITION_BLOCK = 512
"""Most positions evaluated together: (block x stations) arrays stay in cache, faster than
whole-sweep arrays on a long sweep (this is blocking, not a loop over positions), and the blocks
run on every core (``linkstress.threads``); on two cores 512 beat 128 and 256 (more calls per
position contend for the interpreter lock) and 1,024 (fewer blocks to share)."""


@dataclass(frozen=True)
class _Chords:
    """Chords of the stations split by holes, one entry per chord: station ``at``, ends' offsets
    ``ua``, ``ub`` from the neutral axis, and C (``cubic_peak``)."""

    at: NDArray[np.intp]
    ua: NDArray[np.float64]
    ub: NDArray[np.float64]
    c: NDArray[np.float64]


@dataclass(frozen=True)
class _HoleEdges:
    """Chord ends at holes, one entry per end: station ``at``, offset ``u`` from the neutral axis,
    and the chord's C; ``layers``: the ends in groups of distinct stations (a station's k-th end in
    group k), so that each group writes a station once."""

    at: NDArray[np.intp]
    u: NDArray[np.float64]
    c: NDArray[np.float64]

    @cached_property
    def layers(self) -> list[NDArray[np.intp]]:
        order = np.argsort(self.at, kind="stable")
        ordered = self.at[order]
        starts = np.flatnonzero(np.append(True, ordered[1:] != ordered[:-1]))
        rank = np.empty(len(order), np.intp)
        rank[order] = np.arange(len(order)) - np.repeat(starts, np.diff(np.append(starts, len(order))))
        return [np.flatnonzero(rank == k) for k in range(rank.max() + 1)] if len(rank) else []


@dataclass(frozen=True)
class _SectionShape:
    """What the fibre search needs of the sections, independent of the loads: per station, and the
    chords of split sections, and the chord ends at holes (station, offset u, C)."""

    x: NDArray[np.float64]
    inv_area: NDArray[np.float64]
    inv_inertia: NDArray[np.float64]
    middle: NDArray[np.float64]
    reach: NDArray[np.float64]
    half: NDArray[np.float64]
    inverse_square_half: NDArray[np.float64]
    lever: NDArray[np.float64]
    shear_gain: NDArray[np.float64]
    density: float
    split: _Chords
    hole_ends: _HoleEdges

    @classmethod
    def of(cls, table: SectionTable, density: float) -> "_SectionShape":
        solid = (table.area > 0) & (table.second_moment > 0)
        yna = table.neutral_axis
        half = (table.top - table.bottom) / 2
        single = solid & (table.n_chords == 1) & (half > 0)
        inv_inertia = np.where(solid, 1.0 / np.where(solid, table.second_moment, 1.0), 0.0)
        count = table.n_chords[:, None]
        at, k = np.nonzero((solid[:, None] & (count > 1)) & (count > np.arange(table.lower.shape[1])))
        ua, ub = table.lower[at, k] - yna[at], table.upper[at, k] - yna[at]
        c = 2 * table.first_moment(table.upper)[at, k] / table.thickness + ub * ub
        # a chord's lower end is at a hole above the first chord; its upper end below the last
        below, above = k > 0, table.n_chords[at] > k + 1
        return cls(
            x=table.x,
            inv_area=np.where(solid, 1.0 / np.where(solid, table.area, 1.0), 0.0),
            inv_inertia=inv_inertia,
            # the outer fibres at u = middle +- reach
            middle=(table.top + table.bottom) / 2 - yna,
            reach=half,
            half=np.where(single, half, 0.0),
            inverse_square_half=np.where(single, 1.0 / np.where(single, half * half, 1.0), 0.0),
            # delta_sigma at the top fibre is 0.4 b_y c (minus it at the bottom), b_y = rho (free - alpha x)
            lever=np.where(single, 0.4 * density * half, 0.0),
            # (8/9) w^2 c^4 per V^2 on single chords (zero elsewhere), for interior_candidates
            shear_gain=np.where(single, (8 / 9) * inv_inertia**2 * half**4, 0.0),
            density=density,
            split=_Chords(at, ua, ub, c),
            hole_ends=_HoleEdges(
                np.concatenate([at[below], at[above]]),
                np.concatenate([ua[below], ub[above]]),
                np.concatenate([c[below], c[above]]),
            ),
        )

    def fibre_basis(self, basis: ForceBasis) -> tuple[NDArray[np.float64], ...]:
        """Per unit load coefficient, (Q, S) each: the mean and half the difference of sigma at the
        top and bottom fibres, N / A + M u / I and the body-load term +-0.4 b_y c,
        b_y = rho ((g - a_O)_y - alpha x); and 0.1925 b_y c on single chords (zero elsewhere), for
        ``interior_candidates``."""
        along = basis.normal * self.inv_area
        mean = along + basis.moment * (self.inv_inertia * self.middle)
        spread = basis.moment * (self.inv_inertia * self.reach)
        spread[FREE_Y] += self.lever
        spread[ALPHA] -= self.x * self.lever
        body = np.zeros_like(mean)
        body[FREE_Y] = self.lever * (BODY_TERM / 0.4)
        body[ALPHA] = -self.x * self.lever * (BODY_TERM / 0.4)
        return mean, spread, body

    def outer_fibres(self, mean, spread, fibres: "_Fibres"):
        """The larger of the top and bottom fibres' |sigma| = |mean +- spread| (P, S) (free edges,
        tau = 0) into ``fibres``: |mean| + |spread|, at the top where mean and spread have one sign
        (by the sign of their product, zeros signed: a tie under pure axial load goes to the top in
        tension, to the bottom in compression). Returns |mean| and |spread| (``spread`` made its
        absolute value in place)."""
        side = mean * spread
        np.copysign(self.reach, side, out=fibres.u)
        fibres.u += self.middle
        size_n = np.abs(mean)
        size_m = np.abs(spread, out=spread)
        np.add(size_n, size_m, out=fibres.von_mises)
        return size_n, size_m

    def interior_candidates(self, size_n, size_m, outer, body, normal, shear, moment):
        """Flat (position, station) indices where a single chord's interior may hold the section's
        maximum, and (flat index, chord) pairs for the chords of split sections; necessary
        conditions, so none is missed. Section forces, the outer fibres' |mean| and |spread| of
        sigma and their von Mises ``outer`` = |mean| + |spread|, and ``body`` = 0.1925 |b_y| c (None
        where there is no body load) are (P, S).

        A single chord is symmetric about the neutral axis (half-depth c, C = c^2). With the body
        term, sigma(u) = n + m_e u - beta u (c^2 - u^2), m_e = m + 0.4 beta c^2, so the outer fibres
        give E = |n| + |m_e| c and an interior fibre at |u| = v gives at most
        (|n| + |m_e| v + |beta| v (c^2 - v^2))^2 + 3 w^2 (c^2 - v^2)^2. Factoring out c - v and
        bounding the rest over v in [0, c], it can beat E^2 only if

            (32/9) w^2 c^4 + 2 b c (2|n| + 2|m_e| c + 0.385 b c) > |m_e| c (2|n| + |m_e| c),

        b = |b_y|, where |n| = |mean| and |m_e| c = |spread|; divided by 4, with B = 0.1925 b c:
        (4 / 0.1925) B (E + B) + (8/9) w^2 c^4 > |m_e| c (|n| + E). Chords of sections split by
        holes (no body term) are searched where the cubic of ``cubic_peak`` has three real roots.
        """
        gain = shear * shear
        gain *= self.shear_gain
        if body is not None:
            body_term = outer + body
            body_term *= body
            body_term *= 4 / BODY_TERM
            gain += body_term
        size_n += outer
        size_n *= size_m
        single = np.flatnonzero(gain > size_n)
        at = self.split.at
        n, m, w = normal[:, at] * self.inv_area[at], moment[:, at] * self.inv_inertia[at], shear[:, at] * self.inv_inertia[at]
        pairs = np.flatnonzero(has_cubic_peak(n, m, w / 2, self.split.c))
        rows, chord = np.divmod(pairs, len(at))
        return single, rows * len(self.x) + at[chord], chord

    def hole_end_fibres(self, forces: InternalForces, fibres: "_Fibres", positions: slice) -> None:
        """Chord ends at holes (these few stations, at ``positions``) that beat ``fibres``."""
        ends = self.hole_ends
        first = np.arange(len(forces.normal))[positions][:, None] * len(self.x)
        for layer in ends.layers:
            at = ends.at[layer]
            n = forces.normal[positions][:, at] * self.inv_area[at]
            m = forces.moment[positions][:, at] * self.inv_inertia[at]
            w = forces.shear[positions][:, at] * (self.inv_inertia[at] / 2)
            u, c = (np.broadcast_to(v[layer], n.shape).ravel() for v in (ends.u, ends.c))
            self._consider(fibres, (first + at).ravel(), n.ravel(), m.ravel(), w.ravel(), c, u, 0.0, np.tile(at, len(n)))

    def single_interiors(self, forces: InternalForces, coefficients, flat, fibres: "_Fibres") -> None:
        """Interior maxima of single chords (with the body-load term) at flat indices ``flat``.

        In s = u / c: sigma = n + (m - 0.6 beta c^2) c s + beta c^3 s^3 with beta c^3 = b_y c, and
        3 tau^2 = 3 w^2 c^4 (1 - s^2)^2 (``single_chord_peak``). Where there is no body load (a crank
        turning steadily about a fixed pivot, without gravity) sigma is linear and the maximum is in
        closed form, as on split sections (``cubic_peak``)."""
        if not len(flat):
            return
        n, m, w, at = self._reduced(forces, flat)
        half = self.half[at]
        c = half * half
        rows = flat // len(self.x)
        body = self.density * (coefficients[rows, FREE_Y] - coefficients[rows, ALPHA] * self.x[at]) * half
        plain = body == 0
        if plain.any():
            k = np.flatnonzero(plain & has_cubic_peak(n, m, w, c))
            u = np.clip(cubic_peak(n[k], m[k], w[k], c[k]), -half[k], half[k])
            self._consider(fibres, flat[k], n[k], m[k], w[k], c[k], u, 0.0, at[k])
            loaded = np.flatnonzero(~plain)
            n, m, w, at, half, c, body, flat = (v[loaded] for v in (n, m, w, at, half, c, body, flat))
            if not len(flat):
                return
        reached = fibres.von_mises.reshape(-1)[flat]
        k, s, peak = single_chord_peak(n, m * half - 0.6 * body, body, 3 * (w * c) ** 2, reached * reached)
        fibres.keep_larger(flat[k], np.sqrt(peak), s * half[k])

    def split_interiors(self, forces: InternalForces, flat, chord, fibres: "_Fibres") -> None:
        """Interior maxima of the split sections' chords ``chord`` at flat indices ``flat``."""
        if not len(flat):
            return
        n, m, w, at = self._reduced(forces, flat)
        split = self.split
        c = split.c[chord]
        u = np.clip(cubic_peak(n, m, w, c), split.ua[chord], split.ub[chord])
        self._consider(fibres, flat, n, m, w, c, u, 0.0, at, repeated=True)

    def _reduced(self, forces: InternalForces, flat):
        """n = N / A, m = M / I, w = V / 2I at flat (position, station) indices, and the stations."""
        at = flat % len(self.x)
        inv_inertia = self.inv_inertia[at]
        return (
            forces.normal.reshape(-1)[flat] * self.inv_area[at],
            forces.moment.reshape(-1)[flat] * inv_inertia,
            forces.shear.reshape(-1)[flat] * (inv_inertia / 2),
            at,
        )

    def _consider(self, fibres, flat, n, m, w, c, u, beta, at, repeated: bool = False) -> None:
        """Fibre offset u at the flat indices: sigma with the body-load term, tau, von Mises."""
        sigma = _sigma(n, m, u, beta, self.half[at])
        tau = w * (c - u * u)
        fibres.keep_larger(flat, np.sqrt(sigma * sigma + 3 * tau * tau), u, repeated)


def _sigma(n, m, u, beta, half):
    """sigma at offset u from the neutral axis: n + m u and the body-load term beta u (u^2 - 0.6 c^2)
    of a single chord of half-depth c (beta = b_y / c^2; zero on split sections)."""
    return n + m * u + beta * u * (u * u - 0.6 * half * half)


@dataclass
class _Fibres:
    """The critical fibre of every (position, station) so far: von Mises and offset u from the
    neutral axis there (views into the result arrays)."""

    von_mises: NDArray[np.float64]
    u: NDArray[np.float64]

    def block(self, positions: slice) -> "_Fibres":
        return _Fibres(self.von_mises[positions], self.u[positions])

    def keep_larger(self, flat, f, u, repeated: bool = False) -> None:
        """Where candidate von Mises ``f`` beats the fibre so far at flat indices ``flat``, take it;
        with ``repeated`` (an index may occur more than once), the largest of its candidates."""
        best = self.von_mises.reshape(-1)
        wins = np.flatnonzero(f > best[flat])
        if repeated and len(wins) > 1:
            order = np.lexsort((f[wins], flat[wins]))
            wins = wins[order]
            last = np.append(flat[wins][1:] != flat[wins][:-1], True)
            wins = wins[last]
        flat = flat[wins]
        best[flat] = f[wins]
        self.u.reshape(-1)[flat] = u[wins]
