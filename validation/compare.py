"""Beam sections against plane-stress FEA of the same link under the same loads.

Three comparisons per link and position (docs/design.md, "FEA cross-check"), along each member of
the link (the arms between its joints, ``linkstress.geometry.members``), each sectioned on its own axis:

- section resultants: N, V, M integrated over FEA cuts, the beam's section segments normal to the
  member's axis at the comparison stations, against the beam's free-body values; error = largest
  difference over the stations, relative to the largest section force (N, V) of the member at that
  position, or for M to the larger of the largest moment and that force times a sixth of the depth
  (which stresses the outer fibre alike);
- nominal von Mises: at stations at least one section depth from every pin hole's centre (and, on
  a member, from every other member's axis), the FEA von Mises at the beam's critical fibre against
  the beam's; error = largest difference over those stations relative to the largest beam value
  among them;
- peak von Mises: the FEA's largest anywhere against the beam's largest (which is nominal near
  holes); their difference is the stress concentration beam theory does not see;
- pin holes: each hole's Kt x nominal estimate against the FEA's largest within HOLE_NEIGHBOURHOOD
  hole radii of that hole's centre, at the same position.

A link's errors are the worst over its members. Where the stations lie, and the default mesh:
``stations``. A member with no station (every cut passes through a hole:
``ComparisonStations.skipped``) is not compared, and the link's ``skipped`` notes say so; with no
member compared the link has no resultant or nominal error (None), while its FEA peak and pin holes
are compared as ever. A link's positions may be solved in blocks (``solve_compared`` on each, joined
by ``join_link_fea``): what one solve of them all gives, to the bit.

With a refinement study, ``LinkComparison.convergence`` says how much each compared quantity
(resultants, nominal, peak) changed between the two finest meshes, against its own limit.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.pin_holes import PinHoleEstimate
from linkstress.dynamics.section_stress import SectionStresses, section_stresses
from linkstress.loads import LinkLoadCase
from linkstress.geometry.members import Member, MemberCuts, frame_member
from linkstress.geometry.profile import LinkProfile
from linkstress.stress_state import von_mises
from linkstress.validation.fea.cache import DiskCache
from linkstress.validation.fea.convergence import (
    CONVERGED_CHANGE,
    PEAK_CONVERGED_CHANGE,
    RESULTANT_CONVERGED_CHANGE,
    ConvergenceStudy,
    convergence_study,
    join_studies,
)
from linkstress.validation.fea.link import CutResultants, LinkFEAResult, join_cut_resultants, join_results, solve_link
from linkstress.validation.fea.mesh import MeshSettings
from linkstress.validation.stations import ComparisonStations, choose_stations, default_mesh, member_stations

HOLE_NEIGHBOURHOOD = 2.0
"""The FEA peak at a pin hole: the largest von Mises within this many hole radii of its centre (the
rim and one radius of material around it), where the Kt x nominal estimate places its peak."""


@dataclass(frozen=True)
class Convergence:
    """How much one compared quantity changed between the two finest meshes of a refinement study:
    ``change`` (Pc,) [-] per compared position, relative (see each quantity), and its ``limit`` [-];
    ``previous`` (Pc,) [-] the change over the refinement before, where it is judged too (the peak)."""

    change: NDArray[np.float64]
    limit: float
    previous: NDArray[np.float64] | None = None

    @property
    def converged(self) -> bool:
        within = bool((self.change <= self.limit).all())
        return within and (self.previous is None or bool((self.previous <= self.limit).all()))

    def words(self) -> str:
        """The change(s) against the limit, in percent."""
        text = f"changed {100 * self.change.max():.3g} % over the last refinement"
        if self.previous is not None:
            text += f" and {100 * self.previous.max():.3g} % over the one before"
        return f"{text}, limit {100 * self.limit:g} %"


@dataclass(frozen=True)
class HolePeak:
    """The FEA against the Kt x nominal ``estimate`` (Pc,) [Pa] at the pin hole of joint ``joint``
    (diameter ``diameter`` [m], centre ``centre`` (2,) [m, member frame]): ``fea`` (Pc,) [Pa] the
    largest von Mises within HOLE_NEIGHBOURHOOD radii of that centre, at ``fea_at`` (Pc, 2) [m,
    member frame], at each compared position; ``inside`` (Pc,) where the estimate's geometry is
    inside the Kt tables (elsewhere it is no estimate), ``reasons`` why not."""

    joint: int
    diameter: float
    centre: NDArray[np.float64]
    estimate: NDArray[np.float64]
    fea: NDArray[np.float64]
    fea_at: NDArray[np.float64]
    inside: NDArray[np.bool_]
    reasons: tuple[str | None, ...]

    @property
    def error(self) -> NDArray[np.float64]:
        """(Pc,) [-]: estimate / FEA - 1 at each position (0 where the FEA is unloaded)."""
        return relative(self.estimate - self.fea, self.fea)


@dataclass(frozen=True)
class Skipped:
    """A member of a link (between ``joints``) that is not compared with the FEA, and ``note``: why
    (``ComparisonStations.skipped``: every cut passes through a hole)."""

    joints: tuple[int, int]
    note: str


@dataclass(frozen=True)
class NominalDifference:
    """The worst nominal comparison of a link: at compared position ``position`` (index into the
    compared positions), on the member between ``joints``, at arc length ``s`` [m] from its first
    joint (axis point ``at`` (2,) [m, member frame]): the beam's von Mises ``beam`` [Pa] at its
    critical fibre against the FEA's ``fea`` [Pa] there; ``error`` [-] the link's nominal error at
    that position (the largest difference over the member's nominal stations over its largest beam
    value)."""

    position: int
    joints: tuple[int, int]
    s: float
    at: NDArray[np.float64]
    beam: float
    fea: float
    error: float


@dataclass(frozen=True)
class LinkComparison:
    """One link compared over the positions ``positions`` (indices into the sweep).

    ``beam`` holds the beam stresses at ``stations`` (along the member of the frame joints: the
    frame's x on a straight one) for those positions; ``fea`` the finest FEA; ``fea_resultants`` its
    resultants over the beam's cut segments there; ``fea_von_mises`` (Pc, S) the FEA von Mises at the
    beam's critical fibre of each station; ``away`` (S,) the stations used for the nominal
    comparison; ``study`` the mesh refinement study (None with a single mesh level); ``station_note``
    why the stations are not the usual ones ("" when they are); ``members`` each member of the link
    compared along its own axis (none: along the frame's member only). With members, the link's
    errors are the worst over them. ``skipped``: for each member (the frame's included) with no
    station to compare at, why (``ComparisonStations.skipped``); when the frame's member is one,
    ``stations`` is empty, ``fea_resultants`` None and ``beam`` is its section at its midpoint alone
    (its pin-hole estimates and theory), compared with nothing.
    """

    name: str
    positions: NDArray[np.intp]
    stations: NDArray[np.float64]
    away: NDArray[np.bool_]
    beam: SectionStresses
    fea: LinkFEAResult
    fea_resultants: CutResultants | None
    fea_von_mises: NDArray[np.float64]
    beam_seconds: float
    fea_seconds: float
    study: ConvergenceStudy | None
    station_note: str = ""
    members: tuple[MemberComparison, ...] = ()
    skipped: tuple[Skipped, ...] = ()

    @property
    def frame_compared(self) -> bool:
        """Whether the frame's member is compared (has stations)."""
        return self.fea_resultants is not None

    @property
    def convergence(self) -> dict[str, Convergence | None] | None:
        """Change over the last refinement of ``resultants`` (the measure of ``resultant_error``),
        ``nominal`` (over the largest nominal value; None without a nominal station) and ``peak``
        (over the finer peak, judged over the refinement before too), each against its limit; None
        with a single mesh (nothing checked). ``resultants`` is None where no cut is compared."""
        if self.study is None:
            return None
        s = self.study
        change = self._resultant_change()
        resultants = None if change is None else Convergence(change, RESULTANT_CONVERGED_CHANGE)
        compared = any(m.beam.away.any() for m in self.members) if self.members else self.away.any()
        nominal = Convergence(s.change, CONVERGED_CHANGE) if compared else None
        peak = Convergence(s.peak_change, PEAK_CONVERGED_CHANGE, s.peak_changes[-2])
        return {"resultants": resultants, "nominal": nominal, "peak": peak}

    def _resultant_change(self) -> NDArray[np.float64] | None:
        """(Pc,) [-]: the resultants' change between the two finest meshes, measured as
        ``resultant_error`` is: over the stations, or the worst over the members' cuts; None where
        no cut is compared."""
        finer, coarser = self.study.resultants[-1], self.study.resultants[-2]
        if not self.members:
            if not self.frame_compared:
                return None
            depth = float((self.beam.sections.top - self.beam.sections.bottom).max())
            return resultant_error(finer, coarser, depth)
        counts = [len(m.beam.cuts.ends) for m in self.members]
        stops = len(self.stations) + np.cumsum(counts)
        return np.max([
            resultant_error(finer[..., stop - count:stop], coarser[..., stop - count:stop], m.beam.depth)
            for m, count, stop in zip(self.members, counts, stops)
        ], axis=0)

    @property
    def converged(self) -> bool | None:
        """Whether every compared quantity (resultants, nominal where compared, peak) converged;
        None with a single mesh."""
        convergence = self.convergence
        if convergence is None:
            return None
        return all(q.converged for q in convergence.values() if q is not None)

    @property
    def hole_peaks(self) -> tuple[HolePeak, ...]:
        """Each pin hole's Kt x nominal estimate beside the FEA's peak at that hole (an estimate
        counts only at the positions where its geometry is inside the Kt tables)."""
        return tuple(_hole_peak(self.fea, h) for h in self.beam.pin_holes)

    @property
    def resultant_error(self) -> NDArray[np.float64] | None:
        """(Pc,) [-]: largest N, V, M difference over the stations, relative to the link's largest;
        with members, the worst over them (each relative to its own largest); None where no cut is
        compared (``skipped``)."""
        if self.members:
            return np.max([m.resultant_error for m in self.members], axis=0)
        if not self.frame_compared:
            return None
        b, f = self.beam.forces, self.fea_resultants
        depth = float((self.beam.sections.top - self.beam.sections.bottom).max())
        return resultant_error(
            np.stack([f.normal, f.shear, f.moment]), np.stack([b.normal, b.shear, b.moment]), depth,
        )

    @property
    def nominal_error(self) -> NDArray[np.float64] | None:
        """(Pc,) [-] over the stations away from holes; None when every station is near one; with
        members, the worst over those that have a nominal station."""
        if self.members:
            errors = [e for e in (m.nominal_error for m in self.members) if e is not None]
            return np.max(errors, axis=0) if errors else None
        if not self.away.any():
            return None
        beam = self.beam.von_mises[:, self.away]
        fea = self.fea_von_mises[:, self.away]
        return relative(np.abs(fea - beam).max(axis=1), beam.max(axis=1))

    def worst_nominal(self) -> NominalDifference | None:
        """Where the nominal comparison differs most (the position and station behind the largest
        ``nominal_error``), None when there is no nominal station."""
        error = self.nominal_error
        if error is None:
            return None
        k = int(np.argmax(error))
        if self.members:
            m = max((m for m in self.members if m.nominal_error is not None), key=lambda m: m.nominal_error[k])
            away, joints = m.beam.away, m.joints
            beam, fea, cuts = m.beam.von_mises[k, away], m.fea_von_mises[k, away], m.beam.cuts
        else:
            away, joints = self.away, tuple(self.beam.cuts.joints)
            beam, fea, cuts = self.beam.von_mises[k, away], self.fea_von_mises[k, away], self.beam.cuts
        s = int(np.argmax(np.abs(fea - beam)))
        return NominalDifference(
            k, joints, float(cuts.s[away][s]), cuts.origin[away][s], float(beam[s]), float(fea[s]), float(error[k]),
        )

    @property
    def beam_max(self) -> NDArray[np.float64]:
        """(Pc,) [Pa]: the beam's largest von Mises at the compared stations, over every member
        (with none compared, at the frame member's midpoint section)."""
        frame = [self.beam.max_von_mises] if self.frame_compared or not self.members else []
        return np.max([*frame, *(m.beam_max for m in self.members)], axis=0)

    @property
    def fea_peak(self) -> NDArray[np.float64]:
        return self.fea.von_mises_peak

    @property
    def peak_error(self) -> NDArray[np.float64]:
        """(Pc,) [-]: (FEA peak - beam largest) / FEA peak: what the beam misses near holes."""
        return relative(self.fea_peak - self.beam_max, self.fea_peak)

    @property
    def discretisation_error(self) -> NDArray[np.float64] | None:
        """(Pc,) [-]: Richardson estimate of the finest mesh's error at the nominal points."""
        return None if self.study is None else self.study.relative_error


@dataclass(frozen=True)
class MemberBeam:
    """The beam's values along one member of a link (the arm between its ``joints``) at S compared
    stations and Pc compared positions; load frame, SI units.

    ``cuts``: the member's sections there (their segments ``cuts.ends`` are the FEA's cuts);
    ``forces`` (3, Pc, S): N [N], V [N], M [N m];
    ``von_mises`` (Pc, S) [Pa] at the critical fibre ``fibre_v`` (Pc, S) [m, along ``normal`` from
    ``origin``]; ``note``: why the stations are not the usual ones ("" when they are).
    """

    joints: tuple[int, int]
    cuts: MemberCuts
    forces: NDArray[np.float64]
    von_mises: NDArray[np.float64]
    fibre_v: NDArray[np.float64]
    note: str = ""

    @property
    def away(self) -> NDArray[np.bool_]:
        """(S,): the nominal stations, a section depth from pins, junctions and sharp bends."""
        return ~(np.asarray(self.cuts.near_hole, bool) | np.asarray(self.cuts.junction, bool) | np.asarray(self.cuts.bend, bool))

    @property
    def depth(self) -> float:
        """The member's largest section depth [m] (outer fibre to outer fibre) at the stations."""
        table = self.cuts.table
        return float((table.top - table.bottom).max())

    @property
    def axes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The tangents (S, 2) and the section centroids (S, 2) [m]: the axes across which, and the
        points about which, the cut resultants are taken."""
        cuts = self.cuts
        return np.asarray(cuts.tangent, float), cuts.origin + cuts.table.neutral_axis[:, None] * cuts.normal

    @property
    def fibres(self) -> NDArray[np.float64]:
        """Points (Pc, S, 2) [m] of the critical fibres."""
        return self.cuts.origin[None] + self.fibre_v[..., None] * self.cuts.normal[None]

    def at(self, rows: NDArray[np.intp]) -> "MemberBeam":
        """The same member at the positions ``rows`` (indices into the Pc)."""
        return replace(self, forces=self.forces[:, rows], von_mises=self.von_mises[rows], fibre_v=self.fibre_v[rows])


@dataclass(frozen=True)
class MemberComparison:
    """One member's ``beam`` values against the FEA: ``fea_resultants`` over the same cut segments
    about each section's centroid, ``fea_von_mises`` (Pc, S) [Pa] at the beam's critical fibres."""

    beam: MemberBeam
    fea_resultants: CutResultants
    fea_von_mises: NDArray[np.float64]

    @property
    def joints(self) -> tuple[int, int]:
        return self.beam.joints

    @property
    def resultant_error(self) -> NDArray[np.float64]:
        """(Pc,) [-]: largest N, V, M difference over the stations, relative to the member's largest."""
        f = self.fea_resultants
        return resultant_error(np.stack([f.normal, f.shear, f.moment]), self.beam.forces, self.beam.depth)

    @property
    def nominal_error(self) -> NDArray[np.float64] | None:
        """(Pc,) [-] over the stations away from pins and junctions; None when there is none."""
        away = self.beam.away
        if not away.any():
            return None
        beam, fea = self.beam.von_mises[:, away], self.fea_von_mises[:, away]
        return relative(np.abs(fea - beam).max(axis=1), beam.max(axis=1))

    @property
    def beam_max(self) -> NDArray[np.float64]:
        """(Pc,) [Pa]: the beam's largest von Mises over the member's compared stations."""
        return self.beam.von_mises.max(axis=1)


def compare_member(fea: LinkFEAResult, beam: MemberBeam) -> MemberComparison:
    """One member's ``beam`` values against ``fea`` (solved at the same Pc positions, with the
    member's cut segments ``beam.cuts.ends`` meshed)."""
    resultants = fea.cut_resultants(beam.cuts.ends, *beam.axes)
    n_pos, count = beam.fibre_v.shape
    sampled = von_mises(fea.stress_at(beam.fibres.reshape(-1, 2)))  # every position's fibres at every position
    rows = np.arange(n_pos)
    return MemberComparison(beam, resultants, sampled.reshape(n_pos, n_pos, count)[rows, rows])


def relative(difference: NDArray[np.float64], scale: NDArray[np.float64]) -> NDArray[np.float64]:
    """difference / scale, 0 where nothing is loaded (scale 0)."""
    return np.divide(difference, scale, out=np.zeros_like(difference), where=scale > 0)


def resultant_error(values: NDArray[np.float64], reference: NDArray[np.float64], depth: float) -> NDArray[np.float64]:
    """(P,) [-]: largest difference of N, V, M stacks (3, P, S) from the ``reference`` ones, N and V
    relative to the reference's largest section force, M to the larger of its largest moment and
    that force times a sixth of the ``depth`` [m]: a moment is small only next to what the forces do
    over the depth (N h / 6 stresses the outer fibre as much as N / A; near a change point M is
    0.02 N m beside 8,100 N)."""
    force_scale = np.abs(reference[:2]).max(axis=(0, 2))
    moment_scale = np.maximum(np.abs(reference[2]).max(axis=1), force_scale * depth / 6)
    d_force = np.abs(values[:2] - reference[:2]).max(axis=(0, 2))
    d_moment = np.abs(values[2] - reference[2]).max(axis=1)
    return np.maximum(relative(d_force, force_scale), relative(d_moment, moment_scale))


def _hole_peak(fea: LinkFEAResult, hole: PinHoleEstimate) -> HolePeak:
    """The FEA's largest von Mises within HOLE_NEIGHBOURHOOD radii of ``hole``'s centre."""
    centre = fea.link.frame(*fea.frame_joints).to_local(fea.link.joints[hole.joint])
    near = np.flatnonzero(np.hypot(*(fea.nodes - centre).T) <= HOLE_NEIGHBOURHOOD * hole.diameter / 2)
    values = fea.nodal_von_mises[:, near]
    k = values.argmax(axis=1)
    return HolePeak(
        hole.joint, hole.diameter, centre, hole.estimate, values.max(axis=1), fea.nodes[near[k]], ~hole.outside,
        hole.reasons,
    )


def member_beam(link: LinkProfile, loads: LinkLoadCase, member: Member, body_load_near_holes: bool = False,
                chosen: ComparisonStations | None = None) -> MemberBeam:
    """The beam along ``member`` at its comparison stations (``chosen``, default ``member_stations``;
    at least one) for every position of ``loads``."""
    chosen = chosen or member_stations(member)
    beam = section_stresses(link, loads, chosen.x, body_load_near_holes, member=member)
    forces = np.stack([beam.forces.normal, beam.forces.shear, beam.forces.moment])
    return MemberBeam(member.joints, beam.cuts, forces, beam.von_mises, beam.fibre_y, chosen.note)


@dataclass(frozen=True)
class LinkBeams:
    """The beam side of a link's comparison at Pc positions: ``sections`` at ``stations`` (S,) [m]
    along the member of its frame joints, the same as ``along``, and ``members`` each along its own
    axis; ``note``: why the stations are not the usual ones ("" when they are); ``seconds`` to make them.
    ``skipped``: why each member without a station (``ComparisonStations.skipped``) is not compared;
    such members are not in ``members``, and when the frame's is one, ``along`` is None, ``stations``
    empty and ``sections`` the frame member's section at its midpoint (its pin holes, its theory)."""

    stations: NDArray[np.float64]
    sections: SectionStresses
    along: MemberBeam | None
    members: tuple[MemberBeam, ...]
    note: str
    seconds: float
    skipped: tuple[Skipped, ...] = ()

    @property
    def away(self) -> NDArray[np.bool_]:
        """(S,): the frame member's stations compared as nominal, a section depth from the holes."""
        return np.zeros(0, bool) if self.along is None else ~self.sections.near_hole

    @property
    def compared(self) -> tuple[MemberBeam, ...]:
        """The frame's member (when compared), then each member: what the FEA is compared along."""
        return (*([] if self.along is None else [self.along]), *self.members)

    def nominal_points(self) -> NDArray[np.float64]:
        """(Q, 2) [m, member frame]: the critical fibres of the nominal stations at every position,
        each once: the points a refinement study follows."""
        frame = [] if self.along is None else [self.along.fibres[:, self.away].reshape(-1, 2)]
        return np.unique(np.concatenate([
            np.zeros((0, 2)), *frame, *(b.fibres[:, b.away].reshape(-1, 2) for b in self.members)
        ]), axis=0)

    def at(self, rows: NDArray[np.intp]) -> tuple[MemberBeam, ...]:
        """``compared`` at the positions ``rows`` (indices into the Pc)."""
        return tuple(b.at(rows) for b in self.compared)


def link_beams(
    link: LinkProfile,
    loads: LinkLoadCase,
    stations: NDArray[np.float64] | None = None,
    body_load_near_holes: bool = False,
    station_note: str = "",
    members: Sequence[Member] = (),
) -> LinkBeams:
    """The beam along the link's frame member at ``stations`` (default ``choose_stations``) and along
    each of ``members`` at its own (``member_beam``), for every position of ``loads``. No
    ``stations`` (a frame member whose every cut passes through a hole; ``station_note`` says why)
    leaves the frame's member out of the comparison; a member without stations is left out with its
    note in ``skipped``."""
    start = time.perf_counter()
    if stations is None:
        chosen = choose_stations(link, loads.frame_joints)
        stations, station_note = chosen.x, chosen.note
    stations = np.asarray(stations, float)
    on_frame = [m for m in members if m.joints == tuple(loads.frame_joints)]
    frame = on_frame[0] if on_frame else frame_member(link, loads.frame_joints)
    sectioned = stations if len(stations) else np.array([frame.length / 2])
    beam = section_stresses(link, loads, sectioned, body_load_near_holes, member=frame)
    forces = np.stack([beam.forces.normal, beam.forces.shear, beam.forces.moment])
    # The stations are on the frame's member (its sections normal to its axis, vertical when straight).
    along = MemberBeam(beam.cuts.joints, beam.cuts, forces, beam.von_mises, beam.fibre_y) if len(stations) else None
    chosen_members = [(m, member_stations(m)) for m in members]
    beams = tuple(member_beam(link, loads, m, body_load_near_holes, c) for m, c in chosen_members if not c.skipped)
    # The frame's pair is named only when it is what is compared (no members given).
    skipped = tuple([Skipped(frame.joints, station_note)] if not len(stations) and not members else []) + tuple(
        Skipped(m.joints, c.note) for m, c in chosen_members if c.skipped
    )
    return LinkBeams(stations, beam, along, beams, station_note, time.perf_counter() - start, skipped)


def comparison_mesh(link: LinkProfile, loads: LinkLoadCase, beams: LinkBeams, mesh: MeshSettings | None = None,
                    members: Sequence[Member] = ()) -> MeshSettings:
    """``mesh`` (default ``default_mesh``) with the cut segments of every compared member meshed."""
    mesh = mesh or default_mesh(link, loads.frame_joints, beams.stations, members=members)
    segments = np.concatenate([np.zeros((0, 2, 2)), *(b.cuts.ends for b in beams.compared)])
    return replace(mesh, stations=(), cuts=segments.tolist())


@dataclass(frozen=True)
class LinkFEA:
    """The FEA side of a link's comparison at Pc positions: the finest ``fea``, the refinement
    ``study`` (None with one mesh) and, along each compared member (``LinkBeams.compared``), the
    ``resultants`` over its cuts and the ``von_mises`` (Pc, S) [Pa] at its beam's critical fibres;
    ``seconds`` spent."""

    fea: LinkFEAResult
    study: ConvergenceStudy | None
    resultants: tuple[CutResultants, ...]
    von_mises: tuple[NDArray[np.float64], ...]
    seconds: float


def solve_compared(
    link: LinkProfile,
    loads: LinkLoadCase,
    mesh: MeshSettings,
    beams: Sequence[MemberBeam],
    points: NDArray[np.float64],
    levels: int = 3,
    cache: DiskCache | None = None,
) -> LinkFEA:
    """The FEA of ``link`` under ``loads`` on ``mesh`` (``comparison_mesh``), a refinement study of
    ``levels`` >= 3 following the nominal ``points`` (Q, 2) [m], or one mesh with 1, sampled along
    the compared ``beams`` (``LinkBeams.compared``, at the same positions as ``loads``); the meshes
    from and into ``cache`` when given."""
    start = time.perf_counter()
    study = None
    if levels >= 3:
        axes = [np.concatenate(parts) for parts in zip(*(b.axes for b in beams))]
        study = convergence_study(link, loads, mesh, points, levels=levels, cut_axes=axes, cache=cache)
        fea = study.finest
    else:
        fea = solve_link(link, loads, mesh, cache)
    compared = [compare_member(fea, b) for b in beams]
    return LinkFEA(
        fea, study, tuple(c.fea_resultants for c in compared), tuple(c.fea_von_mises for c in compared),
        time.perf_counter() - start,
    )


def join_link_fea(parts: Sequence[LinkFEA]) -> LinkFEA:
    """One link's FEA side over the positions of ``parts`` in their order, each solved at a block
    of positions on the same meshes: what one solve of them all gives; times add up."""
    if len(parts) == 1:
        return parts[0]
    return LinkFEA(
        join_results([p.fea for p in parts]),
        None if parts[0].study is None else join_studies([p.study for p in parts]),
        tuple(join_cut_resultants(r) for r in zip(*(p.resultants for p in parts))),
        tuple(np.concatenate(v) for v in zip(*(p.von_mises for p in parts))),
        sum(p.seconds for p in parts),
    )


def link_comparison(name: str, positions: NDArray[np.intp], beams: LinkBeams, fea: LinkFEA) -> LinkComparison:
    """Link ``name``'s ``beams`` against its ``fea`` at the sweep ``positions``."""
    first = 0 if beams.along is None else 1
    members = tuple(
        MemberComparison(b, r, v) for b, r, v in zip(beams.members, fea.resultants[first:], fea.von_mises[first:])
    )
    frame_resultants = None if beams.along is None else fea.resultants[0]
    frame_von_mises = np.zeros((len(positions), 0)) if beams.along is None else fea.von_mises[0]
    return LinkComparison(
        name, np.asarray(positions), beams.stations, beams.away, beams.sections, fea.fea, frame_resultants,
        frame_von_mises, beams.seconds, fea.seconds, fea.study, beams.note, members, beams.skipped,
    )


def compare_link(
    name: str,
    link: LinkProfile,
    loads: LinkLoadCase,
    positions: NDArray[np.intp],
    mesh: MeshSettings | None = None,
    levels: int = 3,
    stations: NDArray[np.float64] | None = None,
    body_load_near_holes: bool = False,
    station_note: str = "",
    members: Sequence[Member] = (),
) -> LinkComparison:
    """Compare link ``name`` at sweep ``positions``; ``levels`` >= 3 runs a refinement study and
    compares with its finest mesh, 1 compares with ``mesh`` alone; the beam's sections take the
    body-load term near holes too with ``body_load_near_holes``; ``station_note`` says why the
    ``stations`` are not the usual ones (``choose_stations``). ``members`` (``link_members``): each is
    compared along its own axis too, over its cut segments (``member_stations``, meshed as cuts) and
    at its beam's critical fibres; the link's errors are then the worst over them."""
    selected = loads.at(positions)
    beams = link_beams(link, selected, stations, body_load_near_holes, station_note, members)
    mesh = comparison_mesh(link, selected, beams, mesh, members)
    fea = solve_compared(link, selected, mesh, beams.compared, beams.nominal_points(), levels)
    return link_comparison(name, positions, beams, fea)
