"""Beam-section stresses along a link: normal, Jourawski shear and von Mises at every fibre.

At station x with N, V, M (see ``internal_forces``) and the section's A, I, y_na and first moment
Q(y) (``linkstress.geometry.sections``), at fibre y of the plate of thickness t, with u = y - y_na:

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
single-chord section a section depth from every hole, with b_y = rho (g - a_O - alpha k x r)_y at
the station (the part of the d'Alembert load uniform through the depth); sigma is then a cubic in u
and the chord's interior maxima are found by ``fibre_peaks.single_chord_peak``. On the stubby seed
bars the term is 2-4 % of the nominal stress and takes the beam-versus-FEA difference there from up
to 3.8 % to under 0.6 %.

Near a hole (and at a junction of members or a bend sharper than the curved-beam range,
``linkstress.geometry.members``) the values are nominal: elementary beam theory, the stress a Kt
multiplies. The correction refines beam theory where it holds, so there it is left out, as on
sections split by holes, unless asked for (``body_load_near_holes``). It is also where it costs
most: the near-hole stations of an inertia-loaded link (its rounded ends, where N and M fade and
the body load makes most of the stress) are nearly all the chord searches of a sweep. Measured on
the seed: the 3,600-position sweep takes 1.3-1.7 times as long with it; against FEA (12
positions, one mesh) the median near-hole difference is 1.4 % (output) and 7.6 % (coupler) with it,
2.7 % and 7.7 % without, and the largest 21 % and 62 % either way (pin bearing stress, which no beam
value carries).

Every stress is linear in the load coefficients, so N, V, M and the outer fibres' sigma over a
sweep are products of the (P, Q) coefficients with (Q, S) bases made once per link, evaluated in
blocks of positions; only the (position, station) pairs where a bound says a chord's interior can
beat its outer fibres are searched further. A sweep keeps each block's per-position reductions
(``StressSummary``: the largest von Mises and where, and the equilibrium check), not its (P, S)
arrays, which took 12 kB per position over three links of 101 stations; the arrays of a block of
positions are evaluated again where they are asked for (``StressSummary.at``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from linkstress.geometry.curved_beam import theory_of
from linkstress.dynamics.fibre_candidates import CurvedFibres, Fibres, SectionShape, body_gains, fibre_sigma
from linkstress.dynamics.internal_forces import (
    BODY, ForceBasis, InternalForces, contact_terms, load_coefficients, member_force_basis,
)
from linkstress.dynamics.pin_holes import PinHoleEstimate, pin_hole_estimates
from linkstress.loads import LinkLoadCase
from linkstress.geometry.members import Member, MemberCuts, frame_member
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.sections import SectionTable
from linkstress.threads import blas_alone, cores, even_blocks, in_parallel


@dataclass(frozen=True)
class SectionStresses:
    """Stresses along one link over P positions and S stations, member frame.

    ``forces``: N, V, M. ``von_mises`` (P, S) [Pa]: the largest von Mises over the section's fibres,
    reached at ``fibre_y`` (P, S) [m]; ``sigma``/``tau`` (P, S) [Pa] at that fibre (made when asked
    for, from the section forces). ``near_hole`` (S,): the
    stations whose values are nominal (``MemberCuts.nominal``: within a section depth of a hole's
    centre, a junction or a sharp bend); ``pin_holes``: the
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
    shape: SectionShape
    body_load: NDArray[np.float64]
    """(P, 4): the load coefficients of the body load (g - a_O [m/s^2], alpha [rad/s^2], omega^2
    [rad^2/s^2]), for sigma's body-load term."""
    cuts: MemberCuts
    """The member's sections: where each station is (``cuts.points``), and its flags."""
    curved: CurvedFibres | None = None
    """The stations that take curved-beam normal stress (Winkler-Bach), if any."""

    @property
    def sigma(self) -> NDArray[np.float64]:
        """(P, S) [Pa]: sigma at the critical fibre, N / A + M u / I and, on the single chords that
        take it, the body-load term."""
        shape, forces = self.shape, self.forces
        u = self.fibre_y - self.sections.neutral_axis
        beta = (self.body_load @ shape.body_gain) * shape.inverse_square_half()
        sigma = fibre_sigma(forces.normal * shape.inv_area, forces.moment * shape.inv_inertia, u, beta, shape.half)
        if self.curved is not None:
            at = self.curved.at
            sigma[:, at] = self.curved.sigma(forces.normal[:, at], forces.moment[:, at], self.fibre_y[:, at])
        return sigma

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
        """(P, 2) [m, load frame]: where each position's largest von Mises is."""
        k = self.von_mises.argmax(axis=1)
        rows = np.arange(len(k))
        return self.cuts.origin[k] + self.fibre_y[rows, k][:, None] * self.cuts.normal[k]

    @property
    def max_away_from_holes(self) -> NDArray[np.float64] | None:
        """(P,) largest von Mises over the stations not near a hole; None when every station is."""
        away = self.von_mises[:, ~self.near_hole]
        return away.max(axis=1) if away.shape[1] else None

    @property
    def mismatch(self) -> NDArray[np.float64]:
        """(P,) the equilibrium check of ``forces`` (as ``StressSummary.mismatch``)."""
        return self.forces.mismatch


def section_stresses(
    link: LinkProfile,
    loads: LinkLoadCase,
    stations: NDArray[np.float64],
    body_load_near_holes: bool = False,
    member: Member | None = None,
) -> SectionStresses:
    """Stresses at ``stations`` [m] along ``member`` (default: the member along ``loads.frame_joints``,
    whose stations are the member frame's x on a straight member) for every position, evaluated
    together; with ``body_load_near_holes``, the body-load term on the single-chord sections near
    holes too.

    Candidates for the largest von Mises of a section (``fibre_candidates``): its outer fibres (free
    edges, tau = 0), the ends of chords at holes, and each chord's interior maximum where shear
    matters. Every stress is linear in the load coefficients (``load_coefficients``), so N, V, M
    and the outer fibres' sigma are each one product of those with a basis made once per member.
    A long sweep takes ``links_section_stresses``: it holds only per-position reductions.
    """
    member = member or frame_member(link, loads.frame_joints)
    holes = pin_hole_estimates(link, loads, member_depths((member,)))
    return _Sweep.of(link, loads, member, stations, body_load_near_holes, holes).stresses(slice(None))


@dataclass(frozen=True)
class MemberSummary:
    """One member's section stresses over P positions, reduced per position: what a sweep keeps, 40
    bytes per position instead of (P, S) arrays of each quantity.

    ``max_von_mises`` (P,) [Pa] and ``max_at`` (P, 2) [m, load frame]: the largest von Mises over all
    stations and where; ``max_away_from_holes`` (P,) [Pa] likewise over the stations that are not
    nominal (near a hole, a junction or a sharp bend; None where every station is); ``mismatch`` (P,): the
    equilibrium check of ``InternalForces``. ``at(positions)`` recomputes the full station arrays of
    a block of positions; on the blocks of ``blocks`` (those the sweep was evaluated in) they are
    exactly those the reductions came from.
    """

    sweep: "_Sweep"
    blocks: tuple[slice, ...]
    max_von_mises: NDArray[np.float64]
    max_at: NDArray[np.float64]
    max_away_from_holes: NDArray[np.float64] | None
    mismatch: NDArray[np.float64]

    @property
    def joints(self) -> tuple[int, int]:
        return self.sweep.cuts.joints

    @property
    def member(self) -> Member:
        return self.sweep.member

    @property
    def theory(self) -> str:
        """"curved" where some station takes curved-beam (Winkler-Bach) normal stress, else "straight"."""
        return "curved" if self.sweep.curved is not None else "straight"

    @property
    def x(self) -> NDArray[np.float64]:
        return self.sweep.table.x

    @property
    def near_hole(self) -> NDArray[np.bool_]:
        return self.sweep.near_hole

    def at(self, positions: slice) -> SectionStresses:
        """The full arrays (``SectionStresses``) at the consecutive ``positions``, evaluated as one block."""
        return self.sweep.stresses(positions)


@dataclass(frozen=True)
class StressSummary:
    """One link's section stresses over P positions: each member's (``members``, the first along the
    link's frame joints when that pair is a member) and, over them, the largest von Mises per position
    ``max_von_mises`` (P,) [Pa] and where ``max_at`` (P, 2) [m, load frame], ``max_away_from_holes``
    (P,) [Pa] (None where every station of every member is nominal), the worst equilibrium check
    ``mismatch`` (P,); ``pin_holes``: the Kt x nominal estimates (``pin_holes.py``). ``x``,
    ``near_hole`` and ``at`` are the first member's."""

    members: tuple[MemberSummary, ...]
    pin_holes: tuple[PinHoleEstimate, ...]

    @property
    def blocks(self) -> tuple[slice, ...]:
        return self.members[0].blocks

    @cached_property
    def max_von_mises(self) -> NDArray[np.float64]:
        return self._largest("max_von_mises")

    @cached_property
    def max_at(self) -> NDArray[np.float64]:
        if len(self.members) == 1:
            return self.members[0].max_at
        k = np.argmax([m.max_von_mises for m in self.members], axis=0)
        places = np.stack([m.max_at for m in self.members])
        return places[k, np.arange(len(k))]

    @cached_property
    def max_away_from_holes(self) -> NDArray[np.float64] | None:
        away = [m.max_away_from_holes for m in self.members if m.max_away_from_holes is not None]
        return np.max(away, axis=0) if len(away) > 1 else (away[0] if away else None)

    @cached_property
    def mismatch(self) -> NDArray[np.float64]:
        return self._largest("mismatch")

    def _largest(self, name: str) -> NDArray[np.float64]:
        """The largest of the members' per-position ``name`` (a single member's own array)."""
        values = [getattr(m, name) for m in self.members]
        return values[0] if len(values) == 1 else np.max(values, axis=0)

    @property
    def x(self) -> NDArray[np.float64]:
        return self.members[0].x

    @property
    def near_hole(self) -> NDArray[np.bool_]:
        return self.members[0].near_hole

    def at(self, positions: slice) -> SectionStresses:
        """The first member's full arrays at the consecutive ``positions`` (``MemberSummary.at``)."""
        return self.members[0].at(positions)


def links_section_stresses(
    jobs: Sequence[tuple[LinkProfile, LinkLoadCase, tuple[Member, ...], int]],
    body_load_near_holes: bool = False,
) -> list[StressSummary]:
    """Each job's (link, loads, members, stations per member) section stresses along every member,
    reduced per position as they are made: blocks of positions are evaluated and reduced one at a
    time, so that a sweep never holds its (P, S) arrays. The blocks of every member share the cores
    (BLAS on one thread, ``linkstress.threads``), so that no core waits at the end of one member's
    blocks."""
    sweeps = []
    for link, loads, members, count in jobs:
        holes = pin_hole_estimates(link, loads, member_depths(members))
        sweeps.append([
            _Sweep.of(link, loads, member, member.stations(count), body_load_near_holes, holes) for member in members
        ])
    every = [sweep for link_sweeps in sweeps for sweep in link_sweeps]
    threaded = cores() > 1 and sum(sweep.pairs for sweep in every) >= THREADED_PAIRS
    summaries = {id(sweep): (_Reductions.of(sweep), tuple(sweep.blocks(threaded))) for sweep in every}
    blocks = [(sweep, summaries[id(sweep)][0], block) for sweep in every for block in summaries[id(sweep)][1]]
    if not threaded:
        in_parallel(_reduce, blocks, threads=False)
    else:
        with blas_alone():
            in_parallel(_reduce, blocks)
    return [
        StressSummary(
            tuple(summaries[id(sweep)][0].summary(sweep, summaries[id(sweep)][1]) for sweep in link_sweeps),
            link_sweeps[0].pin_holes,
        )
        for link_sweeps in sweeps
    ]


def member_depths(members: Sequence[Member]) -> dict[int, float]:
    """Per joint, the section depth [m] of the member it sits on, the depth a pin-hole estimate
    reports: through a joint that ends the tree, the cut across its member there; at a joint where
    members meet, whose cuts run along the other arms, the smallest depth of those members between
    their joints."""
    ends = [end for member in members for end in member.joints]
    depths: dict[int, float] = {}
    for member in members:
        for end, depth in zip(member.joints, member.end_depths):
            depth = float(depth) if ends.count(end) == 1 else member.depth
            depths[end] = min(depths.get(end, np.inf), depth)
    return depths


def _reduce(item: tuple["_Sweep", "_Reductions", slice]) -> None:
    sweep, reductions, positions = item
    reductions.take(sweep, positions)


@dataclass(frozen=True)
class _Reductions:
    """A member's per-position reductions, filled block by block (each block writes only its rows)."""

    max_von_mises: NDArray[np.float64]
    max_at: NDArray[np.float64]
    max_away_from_holes: NDArray[np.float64] | None
    mismatch: NDArray[np.float64]

    @classmethod
    def of(cls, sweep: "_Sweep") -> "_Reductions":
        count = len(sweep.coefficients)
        away = np.empty(count) if not sweep.near_hole.all() else None
        return cls(np.empty(count), np.empty((count, 2)), away, np.empty(count))

    def take(self, sweep: "_Sweep", p: slice) -> None:
        """Evaluate the block ``p`` and keep its reductions."""
        forces, fibres = sweep.evaluate(p)
        k = fibres.von_mises.argmax(axis=1)
        rows = np.arange(len(k))
        self.max_von_mises[p] = fibres.von_mises[rows, k]
        self.max_at[p] = sweep.cuts.origin[k] + fibres.u[rows, k][:, None] * sweep.cuts.normal[k]
        if self.max_away_from_holes is not None:
            self.max_away_from_holes[p] = fibres.von_mises[:, ~sweep.near_hole].max(axis=1)
        self.mismatch[p] = forces.mismatch

    def summary(self, sweep: "_Sweep", blocks: tuple[slice, ...]) -> MemberSummary:
        return MemberSummary(sweep, blocks, self.max_von_mises, self.max_at, self.max_away_from_holes, self.mismatch)


@dataclass(frozen=True)
class _Sweep:
    """One member's section stresses over the sweep: what every block of positions is evaluated from."""

    link: LinkProfile
    loads: LinkLoadCase
    member: Member
    cuts: MemberCuts
    near_hole: NDArray[np.bool_]
    basis: ForceBasis
    shape: SectionShape
    fibre_bases: tuple[NDArray[np.float64], ...]
    coefficients: NDArray[np.float64]
    pin_holes: tuple[PinHoleEstimate, ...]
    curved: CurvedFibres | None

    @classmethod
    def of(
        cls, link: LinkProfile, loads: LinkLoadCase, member: Member, stations: NDArray[np.float64],
        body_load_near_holes: bool = False, pin_holes: tuple[PinHoleEstimate, ...] = (),
    ) -> "_Sweep":
        cuts = member.cuts(stations)
        near_hole = cuts.nominal
        table = cuts.table
        curved = (theory_of(cuts.curvature, table.top - table.bottom) == "curved") & ~cuts.tight
        # the body-load term refines the straight beam; a curved section takes Winkler-Bach without it
        body_term = (np.ones_like(near_hole) if body_load_near_holes else ~near_hole) & ~curved
        shape = SectionShape.of(table, body_gains(cuts.origin, cuts.normal, link.density), body_term)
        basis = member_force_basis(link, loads, cuts)
        return cls(
            link, loads, member, cuts, near_hole, basis, shape, shape.fibre_basis(basis),
            load_coefficients(loads, link.frame(*loads.frame_joints).to_local(link.joints)),
            pin_holes, CurvedFibres.of(table, cuts.curvature, curved),
        )

    @property
    def table(self) -> SectionTable:
        return self.cuts.table

    @property
    def pairs(self) -> int:
        """(Position, station) pairs of the sweep."""
        return len(self.coefficients) * len(self.table.x)

    def blocks(self, threaded: bool = False) -> list[slice]:
        """Near-equal blocks of positions: of at most ``POSITION_BLOCK`` on one thread; on threads,
        of at most ``THREADED_BLOCK`` and at least one per core, so that each core takes a block
        of every member."""
        count = len(self.coefficients)
        pieces = -(-count // (THREADED_BLOCK if threaded else POSITION_BLOCK))
        if threaded:
            pieces = min(max(pieces, cores()), count)
        return even_blocks(count, pieces)

    def evaluate(self, p: slice) -> tuple[InternalForces, Fibres]:
        """N, V, M and the critical fibre of every station at the consecutive positions ``p``, in
        arrays of the block's own (rows are the block's positions)."""
        basis, shape = self.basis, self.shape
        to_mean, to_spread, body = self.fibre_bases
        c = self.coefficients[p]
        normal, shear, moment = (np.matmul(c, b) for b in (basis.normal, basis.shear, basis.moment))
        mean, spread = c @ to_mean, c @ to_spread
        if self.loads.contacts:
            d_n, d_v, d_m = self.contact_terms(p)
            normal, shear, moment = normal + d_n, shear + d_v, moment + d_m
            mean += d_n * shape.inv_area + d_m * (shape.inv_inertia * shape.middle)
            spread += d_m * (shape.inv_inertia * shape.reach)
        forces = InternalForces(self.table.x, normal, shear, moment, basis.mismatch(c))
        fibres = Fibres(np.empty_like(normal), np.empty_like(normal))
        size_n, size_m = shape.outer_fibres(mean, spread, fibres)
        # a crank turning steadily about a fixed pivot, without gravity, has no body load
        loaded = ((c[:, BODY] != 0).any(axis=0) & shape.body_columns).any()
        at_single, at_split, chord = shape.interior_candidates(
            size_n, size_m, fibres.von_mises, np.abs(c @ body) if loaded else None, normal, shear, moment
        )
        shape.single_interiors(forces, c, at_single, fibres)
        shape.hole_end_fibres(forces, fibres, slice(None))
        shape.split_interiors(forces, at_split, chord, fibres)
        if self.curved is not None:
            self.curved.fibres(forces, fibres, self.table)
        fibres.u += self.table.neutral_axis  # now the fibre's y
        return forces, fibres

    def contact_terms(self, p: slice) -> tuple[NDArray[np.float64], ...]:
        """(dN, dV, dM) of the sliding contacts at the positions ``p`` (``internal_forces.contact_terms``)."""
        joints = self.link.frame(*self.loads.frame_joints).to_local(self.link.joints)
        cuts = self.cuts
        return contact_terms(self.loads.at(np.arange(len(self.coefficients))[p]), joints, cuts.on_left,
                             cuts.cut_points, cuts.tangent, cuts.normal)

    def stresses(self, p: slice) -> SectionStresses:
        """``SectionStresses`` of the consecutive positions ``p``, evaluated as one block."""
        forces, fibres = self.evaluate(p)
        return SectionStresses(
            self.table, forces, fibres.von_mises, fibres.u, self.near_hole, tuple(h.at(p) for h in self.pin_holes), self.shape,
            self.coefficients[p][:, BODY], self.cuts, self.curved,
        )


THREADED_PAIRS = 50_000
"""(Position, station) pairs from which the blocks run on threads: below it, about one block of
positions, handing work to threads costs more than it saves."""

POSITION_BLOCK = 512
"""Most positions evaluated together on one thread: (block x stations) arrays stay in cache, faster
than whole-sweep arrays on a long sweep (this is blocking, not a loop over positions). On one
core, over the seed's 3,600-position sweep at 200 stations (best of five rounds alternated in one
process): 298 ms with blocks of 512, 346 ms with 1,800 and 331 ms with one block per link.
Re-checked once the sections near holes went nominal (stresses alone, eight rounds): best 184 ms
with 512, 187 with 256, 172 with 1,024, 206 with 1,800; medians 201, 198, 208 and 252."""

THREADED_BLOCK = 2048
"""Most positions evaluated together when the blocks run on threads. There a block's fixed cost
counts more than the cache: each block makes about 600 numpy calls, and threads take turns at the
interpreter between them. So as few blocks as give every core one of each link (``blocks``): on
two cores, over the same sweep, blocks of 1,800 (two per link) took 187 ms at best against 209 ms
for blocks of 512 (eight rounds alternated in one process; processor time 344 and 364 ms), and
one block per link 216 ms (three blocks for two cores). The price is memory for the blocks' working
arrays: the process's peak over that sweep was 288 MB against 213 MB with blocks of 512 (its
results then took 86 MB, since reduced per block). Re-checked once the sections near holes went nominal (stresses alone on two
cores, six rounds): 133-153 ms with 2,048, 134-174 ms with 1,024, 145-185 ms with 512."""
