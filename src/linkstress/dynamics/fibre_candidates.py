"""Where a section's largest von Mises can be: the candidate fibres and how each is evaluated.

A section's candidates (``section_stress`` derives the stresses): its outer fibres (free edges,
tau = 0), each single chord's interior maximum (with the body-load term a section depth from every
hole: ``fibre_peaks``), each split chord's interior maximum (closed form) and the chord ends at
holes. ``SectionShape`` holds what they need of the sections, independent of the loads; ``Fibres``
keeps, per (position, station), the largest von Mises found so far and its fibre.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.fibre_peaks import cubic_peak, has_cubic_peak, single_chord_peak
from linkstress.dynamics.internal_forces import BODY, ForceBasis, InternalForces
from linkstress.geometry.curved_beam import CurvedSections, curved_sections
from linkstress.geometry.sections import SectionTable

BODY_TERM = 0.1925
"""Half the 0.385 of the body-load term in ``interior_candidates``' test."""


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
    and the chord's C; ``stations`` (n,): the stations split by holes, and ``table`` (2 (k - 1), n)
    their ends (k chords at most), the two edges of a station's j-th hole in rows 2j and 2j + 1, -1
    where it has fewer holes."""

    at: NDArray[np.intp]
    u: NDArray[np.float64]
    c: NDArray[np.float64]
    stations: NDArray[np.intp]
    table: NDArray[np.intp]

    @classmethod
    def of(cls, stations, at, chord, count, ua, ub, c) -> "_HoleEdges":
        """From the chords of split sections (station ``at``, index ``chord`` in its section of
        ``count`` chords, ends ``ua``, ``ub``, C): below the j-th hole the upper end of chord j,
        above it the lower end of chord j + 1."""
        below, above = chord + 1 < count, chord > 0
        ends = np.concatenate([np.flatnonzero(below), np.flatnonzero(above)])
        rows = np.concatenate([2 * chord[below], 2 * chord[above] - 1])
        table = np.full((2 * (count.max(initial=1) - 1), len(stations)), -1)
        table[rows, np.searchsorted(stations, at[ends])] = np.arange(len(ends))
        edge = np.concatenate([ub[below], ua[above]])
        return cls(at[ends], edge, c[ends], stations, table)


@dataclass(frozen=True)
class SectionShape:
    """What the fibre search needs of the sections, independent of the loads: per station, and the
    chords of split sections, and the chord ends at holes (station, offset u, C). ``half``: a single
    chord's half-depth c (zero elsewhere); ``corrected_half``: c on the single chords that get the
    body-load term (zero elsewhere); ``body_gain`` (4, S): the body load across the section,
    b = rho (g - a(c)) . n [N/m^3] at the axis point c, per unit of (g - a_O)_x, (g - a_O)_y, alpha
    and omega^2 (``body_gains``)."""

    x: NDArray[np.float64]
    inv_area: NDArray[np.float64]
    inv_inertia: NDArray[np.float64]
    middle: NDArray[np.float64]
    reach: NDArray[np.float64]
    half: NDArray[np.float64]
    corrected_half: NDArray[np.float64]
    shear_gain: NDArray[np.float64]
    body_gain: NDArray[np.float64]
    split: _Chords
    hole_ends: _HoleEdges

    @classmethod
    def of(cls, table: SectionTable, body_gain: NDArray[np.float64], body_term: NDArray[np.bool_]) -> "SectionShape":
        """The shape of ``table``'s sections; the single chords of the stations ``body_term`` (S,)
        get the body-load term, with the body load across them ``body_gain`` (4, S) per unit of the
        body-load coefficients (``body_gains``)."""
        solid = (table.area > 0) & (table.second_moment > 0)
        yna = table.neutral_axis
        half = (table.top - table.bottom) / 2
        single = solid & (table.n_chords == 1) & (half > 0)
        inv_inertia = np.where(solid, 1.0 / np.where(solid, table.second_moment, 1.0), 0.0)
        count = table.n_chords[:, None]
        at, k = np.nonzero((solid[:, None] & (count > 1)) & (count > np.arange(table.lower.shape[1])))
        ua, ub = table.lower[at, k] - yna[at], table.upper[at, k] - yna[at]
        c = 2 * table.first_moment(table.upper)[at, k] / table.thickness + ub * ub
        return cls(
            x=table.x,
            inv_area=np.where(solid, 1.0 / np.where(solid, table.area, 1.0), 0.0),
            inv_inertia=inv_inertia,
            # the outer fibres at u = middle +- reach
            middle=(table.top + table.bottom) / 2 - yna,
            reach=half,
            half=np.where(single, half, 0.0),
            corrected_half=np.where(single & body_term, half, 0.0),
            # (8/9) w^2 c^4 per V^2 on single chords (zero elsewhere), for interior_candidates
            shear_gain=np.where(single, (8 / 9) * inv_inertia**2 * half**4, 0.0),
            body_gain=body_gain,
            split=_Chords(at, ua, ub, c),
            hole_ends=_HoleEdges.of(np.flatnonzero(solid & (table.n_chords > 1)), at, k, table.n_chords[at], ua, ub, c),
        )

    def fibre_basis(self, basis: ForceBasis) -> tuple[NDArray[np.float64], ...]:
        """Per unit load coefficient, (Q, S) each: the mean and half the difference of sigma at the
        top and bottom fibres, N / A + M u / I and the body-load term +-0.4 b c (b the body load
        across the section, ``body_gain``); and 0.1925 b c on the single chords that take the term
        (zero elsewhere), for ``interior_candidates``."""
        along = basis.normal * self.inv_area
        mean = along + basis.moment * (self.inv_inertia * self.middle)
        spread = basis.moment * (self.inv_inertia * self.reach)
        # delta_sigma at the top fibre is 0.4 b c (minus it at the bottom)
        spread[BODY] += 0.4 * self.corrected_half * self.body_gain
        body = np.zeros_like(mean)
        body[BODY] = BODY_TERM * self.corrected_half * self.body_gain
        return mean, spread, body

    @property
    def body_columns(self) -> NDArray[np.bool_]:
        """(4,): the body-load coefficients that reach a section taking the body-load term."""
        return (self.body_gain[:, self.corrected_half > 0] != 0).any(axis=1)

    def inverse_square_half(self) -> NDArray[np.float64]:
        """(S,) 1 / c^2 on the single chords that get the body-load term, zero elsewhere: b_y times
        it is the term's beta (``fibre_sigma``)."""
        c = self.corrected_half
        return np.divide(1.0, c * c, out=np.zeros_like(c), where=c > 0)

    def outer_fibres(self, mean, spread, fibres: "Fibres"):
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

    def hole_end_fibres(self, forces: InternalForces, fibres: "Fibres", positions: slice) -> None:
        """Chord ends at holes (these few stations, at ``positions``) that beat ``fibres``: of a
        station's ends, the largest (the first of equals)."""
        ends = self.hole_ends
        if not len(ends.at):
            return
        at = ends.at
        n = forces.normal[positions][:, at] * self.inv_area[at]
        m = forces.moment[positions][:, at] * self.inv_inertia[at]
        w = forces.shear[positions][:, at] * (self.inv_inertia[at] / 2)
        # a last column that never wins, for the -1 of stations with fewer ends
        f = np.column_stack([_von_mises(n, m, w, ends.c, ends.u), np.full(len(n), -np.inf)])
        stations, table = ends.stations, ends.table
        candidates = f[:, table]
        pick = candidates.argmax(axis=1)
        largest = candidates.max(axis=1)
        u = np.append(ends.u, 0.0)[table][pick, np.arange(len(stations))]
        first = np.arange(len(forces.normal))[positions][:, None] * len(self.x)
        fibres.keep_larger((first + stations).ravel(), largest.ravel(), u.ravel())

    def single_interiors(self, forces: InternalForces, coefficients, flat, fibres: "Fibres") -> None:
        """Interior maxima of single chords (with the body-load term) at flat indices ``flat``.

        In s = u / c: sigma = n + (m - 0.6 beta c^2) c s + beta c^3 s^3 with beta c^3 = b_y c, and
        3 tau^2 = 3 w^2 c^4 (1 - s^2)^2 (``single_chord_peak``). Where there is no body load (a crank
        turning steadily about a fixed pivot, without gravity) or the section takes no body-load term
        (near a hole) sigma is linear and the maximum is in closed form, as on split sections
        (``cubic_peak``)."""
        if not len(flat):
            return
        n, m, w, at = self._reduced(forces, flat)
        half = self.half[at]
        c = half * half
        rows = flat // len(self.x)
        body = self.body_load(coefficients[rows], at) * self.corrected_half[at]
        plain = body == 0
        if plain.any():
            k = np.flatnonzero(plain & has_cubic_peak(n, m, w, c))
            u = np.clip(cubic_peak(n[k], m[k], w[k], c[k]), -half[k], half[k])
            fibres.keep_larger(flat[k], _von_mises(n[k], m[k], w[k], c[k], u), u)
            loaded = np.flatnonzero(~plain)
            n, m, w, half, c, body, flat = (v[loaded] for v in (n, m, w, half, c, body, flat))
            if not len(flat):
                return
        reached = fibres.von_mises.reshape(-1)[flat]
        k, s, peak = single_chord_peak(n, m * half - 0.6 * body, body, 3 * (w * c) ** 2, reached * reached)
        fibres.keep_larger(flat[k], np.sqrt(peak), s * half[k])

    def split_interiors(self, forces: InternalForces, flat, chord, fibres: "Fibres") -> None:
        """Interior maxima of the split sections' chords ``chord`` at flat indices ``flat``."""
        if not len(flat):
            return
        n, m, w, _ = self._reduced(forces, flat)
        split = self.split
        c = split.c[chord]
        u = np.clip(cubic_peak(n, m, w, c), split.ua[chord], split.ub[chord])
        fibres.keep_larger(flat, _von_mises(n, m, w, c, u), u, repeated=True)

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

    def body_load(self, coefficients, at) -> NDArray[np.float64]:
        """The body load across the section b [N/m^3] at stations ``at`` (n,), from rows of the load
        coefficients (n, Q) (one per station)."""
        return (coefficients[:, BODY] * self.body_gain[:, at].T).sum(axis=1)


def body_gains(origin: NDArray[np.float64], normal: NDArray[np.float64], density: float) -> NDArray[np.float64]:
    """(4, S): the d'Alembert load across each section, b = rho (g - a_O - alpha k x c + omega^2 c) . n
    [N/m^3] at its axis point c (S, 2) [m, load frame] with unit normal n (S, 2), per unit of
    (g - a_O)_x, (g - a_O)_y, alpha and omega^2 (the last four ``load_coefficients``). On a member
    along the load frame's x (c = (x, 0), n = (0, 1)) it is rho ((g - a_O)_y - alpha x)."""
    cx, cy = origin.T
    nx, ny = normal.T
    return density * np.stack([nx, ny, cy * nx - cx * ny, cx * nx + cy * ny])


def _von_mises(n, m, w, c, u):
    """sqrt(sigma^2 + 3 tau^2) at offset u of a chord without the body-load term: sigma = n + m u and
    Jourawski's tau = w (C - u^2) (single chords with the term take ``fibre_peaks``' g instead)."""
    sigma = n + m * u
    tau = w * (c - u * u)
    return np.sqrt(sigma * sigma + 3 * tau * tau)


def fibre_sigma(n, m, u, beta, half):
    """sigma at offset u from the neutral axis: n + m u and the body-load term beta u (u^2 - 0.6 c^2)
    of a single chord of half-depth c (beta = b_y / c^2; zero on split sections)."""
    return n + m * u + beta * u * (u * u - 0.6 * half * half)


@dataclass
class Fibres:
    """The critical fibre of every (position, station) so far: von Mises and offset u from the
    neutral axis there (views into the result arrays; ``section_stress`` turns u into the fibre's y
    once a block of positions is done)."""

    von_mises: NDArray[np.float64]
    u: NDArray[np.float64]

    def block(self, positions: slice) -> "Fibres":
        return Fibres(self.von_mises[positions], self.u[positions])

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


CURVED_SAMPLES = 17
"""Fibres per chord at which a curved-beam section's von Mises is evaluated, ends included."""


@dataclass(frozen=True)
class CurvedFibres:
    """The stations ``at`` (C,) of a member that take curved-beam normal stress (Winkler-Bach,
    ``linkstress.geometry.curved_beam``): sigma = N / A + M g(v), with Jourawski's tau = V Q(v) / (I t).

    Their von Mises is not the quartic in v of a straight section, so it is evaluated at
    ``CURVED_SAMPLES`` fibres per chord, ends included: ``v`` (C, F) [m], with ``gain`` (C, F)
    [1/m^3] (g) and ``shear_gain`` (C, F) [1/m^2] (Q / (I t)) there. The chords' ends are exact (free
    edges: tau = 0, where bending puts the largest stress); an interior maximum (where shear matters)
    is the largest of the samples.
    """

    at: NDArray[np.intp]
    sections: CurvedSections
    inv_area: NDArray[np.float64]
    v: NDArray[np.float64]
    gain: NDArray[np.float64]
    shear_gain: NDArray[np.float64]

    @classmethod
    def of(cls, table: SectionTable, curvature: NDArray[np.float64], curved: NDArray[np.bool_]) -> "CurvedFibres | None":
        """Those of ``table``'s stations ``curved`` (S,) with ``curvature`` (S,) [1/m]; None if there are none."""
        at = np.flatnonzero(curved)
        if not len(at):
            return None
        sections = curved_sections(table, np.where(curved, curvature, 0.0))
        fractions = np.linspace(0.0, 1.0, CURVED_SAMPLES)
        present = table.present
        # padding chords repeat the first chord's samples
        lower = np.where(present, table.lower, table.lower[:, :1])[at]
        upper = np.where(present, table.upper, table.upper[:, :1])[at]
        v = (lower[:, :, None] + (upper - lower)[:, :, None] * fractions).reshape(len(at), -1)
        fibres = np.zeros((len(table.x), v.shape[1]))
        fibres[at] = v
        first_moment = table.first_moment(fibres)[at]
        shear_gain = first_moment / (table.second_moment[at, None] * table.thickness)
        return cls(at, sections, 1.0 / table.area[at], v, sections.gain(v, at), shear_gain)

    def sigma(self, normal, moment, fibre_y) -> NDArray[np.float64]:
        """(P, C) [Pa]: sigma at fibres ``fibre_y`` (P, C) [m] of these stations, from N and M (P, C)."""
        gain = self.sections.gain(fibre_y.T, self.at).T
        return normal * self.inv_area + moment * gain

    def fibres(self, forces: InternalForces, fibres: "Fibres", table: SectionTable) -> None:
        """Put the largest von Mises of these stations, and its offset u from the centroid, into
        ``fibres`` (over whatever the straight-beam search found there): the largest sample, and
        where that is inside a chord, the vertex of the parabola through it and its two neighbours,
        evaluated exactly, if larger."""
        at = self.at
        n = forces.normal[:, at] * self.inv_area
        sigma = n[:, :, None] + forces.moment[:, at, None] * self.gain
        tau = forces.shear[:, at, None] * self.shear_gain
        von_mises = np.sqrt(sigma * sigma + 3 * tau * tau)
        k = von_mises.argmax(axis=2)
        best = np.take_along_axis(von_mises, k[:, :, None], axis=2)[:, :, 0]
        station = np.arange(len(at))[None, :]
        v = self.v[station, k]
        inner = (k % CURVED_SAMPLES > 0) & (k % CURVED_SAMPLES < CURVED_SAMPLES - 1)
        if inner.any():
            below = np.take_along_axis(von_mises, np.where(inner, k - 1, k)[:, :, None], axis=2)[:, :, 0]
            above = np.take_along_axis(von_mises, np.where(inner, k + 1, k)[:, :, None], axis=2)[:, :, 0]
            step = self.v[station, np.where(inner, k + 1, k)] - v
            bend = below - 2 * best + above
            shift = np.where(inner & (bend < 0), 0.5 * step * (below - above) / np.where(bend < 0, bend, -1.0), 0.0)
            vertex = v + shift
            rows, cols = np.nonzero(shift != 0)
            if len(rows):
                y = np.zeros((len(table.x), len(rows)))
                y[at[cols], np.arange(len(rows))] = vertex[rows, cols]
                q = table.first_moment(y)[at[cols], np.arange(len(rows))] / (table.second_moment[at[cols]] * table.thickness)
                g = self.sections.gain(vertex[rows, cols], at[cols])
                sigma = n[rows, cols] + forces.moment[rows, at[cols]] * g
                tau = forces.shear[rows, at[cols]] * q
                refined = np.sqrt(sigma * sigma + 3 * tau * tau)
                wins = refined > best[rows, cols]
                best[rows[wins], cols[wins]] = refined[wins]
                v[rows[wins], cols[wins]] = vertex[rows[wins], cols[wins]]
        fibres.von_mises[:, at] = best
        fibres.u[:, at] = v - table.neutral_axis[at]
