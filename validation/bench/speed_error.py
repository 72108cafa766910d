"""Speed against error of every stress method on one case, all against one FEA reference.

Methods, each timed the same way (wall time after imports, from the link profiles and their kinetic
loads to the stresses; where a run is cheap, the best of as many runs as fill a window of a second
in the full run; the joint-force solve they all share is timed apart):

- the beam engine (``section_stresses``) along every member of each link at several station counts
  per member, the link's members (``link_members``) and exact mass properties recomputed each run;
- the original program's strip sums at several strip widths (``strip_sections``), on the links that
  are one straight member only: its strips are vertical cuts along the frame axis, which can
  section neither a curved member nor the other arms of a bell crank;
- plane-stress FEA, P2 and P1, on the validate default mesh refined by RATIO**k for several k
  (mesh, assembly, factorisation, solve, stress recovery and sampling).

The quantity is the nominal von Mises stress along every member of each link (``linkstress.geometry.members``:
sections square to the member's axis) at validate's comparison stations of that member
(``member_stations``), at the beam's critical fibre of each, over the stations that are not nominal
(a section depth from every hole and junction; a member whose every station is nominal, a crank
short for its holes, has no nominal error); a method with other stations is interpolated linearly
along the member's arc length s, as a reader of its station table would. Error: per member, the largest difference over those points relative
to the largest reference value, per position, worst over positions; a link's is the worst over its
members, a method's the worst over links. The reference is the Richardson extrapolation
(``convergence.richardson``) of the three finest P2 meshes (the finest where the observed order is
below MIN_ORDER); its own error estimate is reported beside it. The peak von Mises (anywhere, pins
included) is compared the same way, and the beam's section resultants against the finest FEA's
resultants over the same cut segments (``LinkFEAResult.cut_resultants``: across each member's axis,
about each section's centroid).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult, plan_for, run_analysis
from linkstress.dynamics.section_stress import section_stresses
from linkstress.loads import LinkLoadCase
from linkstress.geometry.mass_properties import area_properties
from linkstress.geometry.members import Member, MemberCuts, link_members
from linkstress.geometry.profile import LinkProfile
from linkstress.scene import Scene, load_scene
from linkstress.stress_state import von_mises
from linkstress.validation.compare import relative, resultant_error
from linkstress.validation.stations import choose_stations, default_mesh, member_stations
from linkstress.validation.fea.convergence import richardson
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.link import solve_link
from linkstress.validation.fea.mesh import MeshSettings
from linkstress.validation.bench.strip_sections import strip_baseline
from linkstress.validation.bench.timing import best_run
from linkstress.validation.validate_scene import compared_positions

RATIO = 1.5
"""Refinement ratio between FEA levels, as validate's refinement study."""
VALIDATE_LEVELS = (0, 1, 2)
"""The levels validate's default three-level study solves; the last is the mesh it compares with."""
MIN_ORDER = 0.5
"""Richardson extrapolates only where the observed order is at least this. P2 stresses converge at
order about 2; an order near 0 means values creeping rather than converging (as at a fibre on a
concave curved edge, which the drawing's flattening puts just outside the exact arc), and the
extrapolation would land far past every mesh."""


@dataclass(frozen=True)
class StudySettings:
    """What to measure: ``positions`` compared per case, beam ``station_counts``, strip widths
    ``strip_steps`` [m], FEA levels k (mesh refined by RATIO**k) per element order (the last three
    of ``p2_levels`` make the reference); runs shorter than ``cheap`` [s] are repeated for about
    ``cheap`` seconds (``repeat`` times at least) and the best is kept."""

    positions: int
    station_counts: tuple[int, ...]
    strip_steps: tuple[float, ...]
    p2_levels: tuple[int, ...]
    p1_levels: tuple[int, ...]
    repeat: int
    cheap: float = 1.0


@dataclass(frozen=True)
class LinkSetup:
    """One compared link: its loads at the compared positions and its ``members`` (the scene's
    ``member_pairs``, else the tree of its joints), each member's sections ``cuts`` at validate's
    comparison stations of that member, which of them are ``away`` (S,) from holes and junctions (not
    nominal), the critical fibres' offsets ``fibre`` (P, S) [m, along each cut's normal] and the
    ``mesh``, with every cut segment meshed. S counts every member's stations, member by member (``blocks``); load
    frame throughout."""

    name: str
    link: LinkProfile
    loads: LinkLoadCase
    member_pairs: tuple[tuple[int, int], ...] | None
    members: tuple[Member, ...]
    cuts: tuple[MemberCuts, ...]
    away: NDArray[np.bool_]
    fibre: NDArray[np.float64]
    mesh: MeshSettings

    @property
    def blocks(self) -> tuple[slice, ...]:
        """Each member's columns among the S stations."""
        stops = np.cumsum([len(c.s) for c in self.cuts])
        return tuple(slice(stop - len(c.s), stop) for c, stop in zip(self.cuts, stops))

    @property
    def labels(self) -> tuple[str, ...]:
        """Each member named by its joints, "[i, j]", as validate names it."""
        return tuple(member_label(m) for m in self.members)

    @property
    def depths(self) -> tuple[float, ...]:
        """Each member's deepest compared section [m] (scales its moment differences, as validate does)."""
        return tuple(float((c.table.top - c.table.bottom).max()) for c in self.cuts)

    @property
    def curved(self) -> bool:
        """Whether a member is sectioned normal to a curved centreline (``Member.curved``)."""
        return any(m.curved for m in self.members)

    @property
    def points(self) -> NDArray[np.float64]:
        """Every position's critical fibres (P * S, 2) [m, load frame], position by position."""
        per_member = [c.points(self.fibre[:, b]) for c, b in zip(self.cuts, self.blocks)]
        return np.concatenate(per_member, axis=1).reshape(-1, 2)

    @property
    def segments(self) -> NDArray[np.float64]:
        """Every section's cut segment (S, 2, 2) [m], as meshed."""
        return np.concatenate([c.ends for c in self.cuts])


def member_label(member: Member) -> str:
    """A member named by its joints, "[i, j]"."""
    return str(list(member.joints))


def setup_links(
    scene: Scene, analysis: AnalysisResult, chosen: NDArray[np.intp], names: tuple[str, ...] | None = None,
) -> list[LinkSetup]:
    """validate's comparison along every member of the links ``names`` (default: every link the
    plan validates) at the sweep positions ``chosen``: each member's comparison stations, the beam's
    critical fibres there and validate's default mesh with the members' cut segments."""
    setups = []
    for name in names or analysis.plan.validate:
        link, pairs = scene.links[name].profile, scene.links[name].members
        loads = analysis.forces.link_loads[name].at(chosen)
        members = link_members(link, loads.frame_joints, pairs)
        beams = [section_stresses(link, loads, member_stations(m).x, member=m) for m in members]
        away = np.concatenate([~b.near_hole for b in beams])
        cuts = tuple(b.cuts for b in beams)
        frame = choose_stations(link, loads.frame_joints, members=pairs).x
        mesh = default_mesh(link, loads.frame_joints, frame, members=members)
        mesh = replace(mesh, stations=(), cuts=np.concatenate([c.ends for c in cuts]).tolist())
        fibre = np.concatenate([b.fibre_y for b in beams], axis=1)
        setups.append(LinkSetup(name, link, loads, pairs, members, cuts, away, fibre, mesh))
    return setups


def strip_links(setups: list[LinkSetup]) -> tuple[str, ...]:
    """The links the strip sums can section: one straight member (the frame's), cut vertically."""
    return tuple(s.name for s in setups if len(s.members) == 1 and not s.curved)


@dataclass(frozen=True)
class Answer:
    """One method's answer for one link: ``nominal`` von Mises (P, S) [Pa] at the comparison points of
    every member, ``peak`` (P,) [Pa] or None, section ``resultants`` (3, P, S) N [N], V [N], M [N m]
    or None, ``seconds`` [s] and ``size`` (stations, strips or dofs)."""

    nominal: NDArray[np.float64]
    peak: NDArray[np.float64] | None
    resultants: NDArray[np.float64] | None
    seconds: float
    size: int
    elements: int = 0


@dataclass(frozen=True)
class MethodResult:
    """One method and setting over a case's links: ``seconds`` summed, errors [-] the worst over
    links and positions (None where the method does not give that quantity), ``link_errors`` per
    link (nominal, peak, resultants; the worst over its members), ``member_errors`` per link and
    member ("[i, j]") (nominal, resultants); a nominal error is None on a member whose every compared
    station is nominal, and on a link all of whose members are; ``note``: the links the method leaves
    out, and why."""

    method: str
    setting: str
    size: int
    seconds: float
    nominal_error: float
    peak_error: float | None
    resultant_error: float | None
    link_errors: dict[str, tuple[float | None, float | None, float | None]]
    mass_errors: dict[str, tuple[float, float, float]] | None = None
    """Strip sums only: per link, area, centroid and polar moment errors against the exact values."""
    member_errors: dict[str, dict[str, tuple[float | None, float | None]]] = field(default_factory=dict)
    note: str = ""


@dataclass(frozen=True)
class CaseStudy:
    """Every method measured on one case; ``reference_error`` [-] per link: Richardson's estimate
    of the reference's own error (worst over its members; None where no station is away from the
    holes); ``kinetics_seconds``: the shared joint-force solve; ``curved``: the links with a curved
    member; ``members``: each link's members; ``note``: a method the case could not run, and why."""

    name: str
    title: str
    links: tuple[str, ...]
    positions: int
    methods: tuple[MethodResult, ...]
    reference_error: dict[str, float | None]
    reference_dofs: dict[str, int]
    kinetics_seconds: float
    curved: tuple[str, ...]
    failures: tuple[str, ...]
    members: dict[str, tuple[str, ...]] = field(default_factory=dict)
    note: str = ""

    def pareto(self) -> list[int]:
        """Indices of the methods no other method beats in both time and nominal error."""
        order = sorted(range(len(self.methods)), key=lambda k: (self.methods[k].seconds, self.methods[k].nominal_error))
        front, best = [], math.inf
        for k in order:
            if self.methods[k].nominal_error < best:
                front.append(k)
                best = self.methods[k].nominal_error
        return front

    def find(self, method: str, setting: str) -> MethodResult | None:
        return next((m for m in self.methods if m.method == method and m.setting == setting), None)


def fea_answer(setup: LinkSetup, mesh: MeshSettings, settings: StudySettings) -> Answer:
    """FEA on ``mesh``: nominal von Mises at the comparison points, peak and the resultants over
    every member's cut segments."""
    points = setup.points
    n_pos, count = setup.fibre.shape
    rows = np.arange(n_pos)

    def solve():
        result = solve_link(setup.link, setup.loads, mesh)
        sampled = von_mises(result.stress_at(points)).reshape(n_pos, n_pos, count)[rows, rows]
        return result, sampled, result.von_mises_peak

    seconds, (result, nominal, peak) = _timed(solve, settings)
    tangents = np.concatenate([c.tangent for c in setup.cuts])
    centroids = np.concatenate([c.cut_points for c in setup.cuts])
    cuts = result.cut_resultants(setup.segments, tangents, centroids)
    return Answer(nominal, peak, np.stack([cuts.normal, cuts.shear, cuts.moment]), seconds, result.dofs, result.n_elements)


def beam_answer(setup: LinkSetup, count: int, settings: StudySettings) -> Answer:
    """The beam engine at ``count`` stations over each member, read at the member's comparison
    stations; its time includes finding the members and the exact (Green) mass properties,
    recomputed each run."""
    link, loads = setup.link, setup.loads

    def solve():
        area_properties(link.outline)
        members = link_members(link, loads.frame_joints, setup.member_pairs)
        return [section_stresses(link, loads, m.stations(count), member=m) for m in members]

    seconds, stresses = _timed(solve, settings)
    along = [
        [_along(st.x, v, cuts.s) for v in (st.von_mises, st.forces.normal, st.forces.shear, st.forces.moment)]
        for st, cuts in zip(stresses, setup.cuts)
    ]
    nominal, *resultants = (np.concatenate(values, axis=1) for values in zip(*along))
    peak = np.max([st.max_von_mises for st in stresses], axis=0)
    return Answer(nominal, peak, np.stack(resultants), seconds, count * len(stresses))


def _along(s, values, stations) -> NDArray[np.float64]:
    """Values (P, S') at stations s (S',) [m along a member] read at ``stations`` by linear interpolation, (P, S)."""
    return np.stack([np.interp(stations, s, row) for row in values])


def _timed(work, settings: StudySettings):
    """Best wall time of ``work`` and its value: one run, or where that is cheap, the best of as many
    runs as fill ``settings.cheap`` seconds (at least ``settings.repeat``), so that a burst of load on
    a shared machine does not decide a few-millisecond figure."""
    seconds, value = best_run(work, 1)
    if seconds < settings.cheap and settings.repeat > 1:
        again, value = best_run(work, max(settings.repeat - 1, int(settings.cheap / max(seconds, 1e-6))))
        seconds = min(seconds, again)
    return seconds, value


def _error(values, reference, away) -> float | None:
    """Largest |values - reference| over the away points relative to the largest reference, worst
    position; None without an away point."""
    if not away.any():
        return None
    diff = np.abs(values[:, away] - reference[:, away]).max(axis=1)
    return float(np.max(relative(diff, np.abs(reference[:, away]).max(axis=1))))


def member_nominal_errors(setup: LinkSetup, values: NDArray[np.float64], reference: NDArray[np.float64]) -> list[float | None]:
    """Each member's nominal error (``_error``) of ``values`` (P, S) against ``reference`` (P, S); None
    on a member whose every compared station is nominal (a crank short for its holes)."""
    return [_error(values[:, b], reference[:, b], setup.away[b]) for b in setup.blocks]


def case_study(scene_path, settings: StudySettings, links: tuple[str, ...] | None = None) -> CaseStudy:
    """Measure every method of ``settings`` on the scene at ``scene_path``, on its ``links``
    (default: every link its plan validates)."""
    scene = load_scene(scene_path)
    analysis = run_analysis(scene, plan_for(scene))
    kinetics_seconds = analysis.seconds["kinematics"] + analysis.seconds["forces"]
    chosen = compared_positions(analysis, settings.positions)
    setups = setup_links(scene, analysis, chosen, links)
    solve_link(setups[0].link, setups[0].loads, setups[0].mesh)  # gmsh and the assembly warm up untimed
    answers: dict[tuple[str, str], dict[str, Answer]] = {}
    failures = []
    for order, levels in ((2, settings.p2_levels), (1, settings.p1_levels)):
        for k in levels:
            key = (f"FEA P{order}", f"k = {k}")
            try:
                answers[key] = {s.name: fea_answer(s, replace(s.mesh.refined(RATIO**k), order=order), settings) for s in setups}
            except FEAError as error:
                failures.append(f"FEA P{order} at k = {k}: {error}")
    finest = [answers[("FEA P2", f"k = {k}")] for k in settings.p2_levels[-3:]]
    reference = {s.name: _reference(s, [a[s.name] for a in finest]) for s in setups}
    for count in settings.station_counts:
        answers[("beam", f"{count} stations")] = {s.name: beam_answer(s, count, settings) for s in setups}
    mass, notes = {}, {}
    stripped = strip_links(setups)
    for dx in settings.strip_steps:
        key = ("strip sums", f"dx = {dx:g} m")
        if stripped:
            straight = [s for s in setups if s.name in stripped]
            answers[key], mass[key] = _strip_answers(scene, analysis, chosen, straight, dx, settings)
            notes[key] = strip_note(setups)
    methods = [_method(key, by_link, setups, reference, mass.get(key), notes.get(key, "")) for key, by_link in answers.items()]
    reference_error = {
        s.name: _worst(member_nominal_errors(s, r.nominal + r.nominal_error, r.nominal))
        for s, r in zip(setups, reference.values())
    }
    title = scene.title if scene.title != scene_path.stem else scene_path.parent.name.replace("_", " ")
    return CaseStudy(
        scene_path.parent.name, title, tuple(s.name for s in setups), len(chosen), tuple(methods),
        reference_error, {s.name: finest[-1][s.name].size for s in setups}, kinetics_seconds,
        tuple(s.name for s in setups if s.curved), tuple(failures), {s.name: s.labels for s in setups},
        "" if stripped or not settings.strip_steps else f"strip sums {strip_note(setups)}",
    )


def strip_note(setups: list[LinkSetup]) -> str:
    """Which links the strip sums leave out, and why ("" when none)."""
    straight = strip_links(setups)
    left = [f"{s.name} ({'curved' if s.curved else f'{len(s.members)} members'})" for s in setups if s.name not in straight]
    if not left:
        return ""
    return f"not on {', '.join(left)}: the strips are vertical cuts along the frame axis"


@dataclass(frozen=True)
class Reference:
    """One link's reference: ``nominal`` (P, S) [Pa] with its estimated ``nominal_error`` (P, S) [Pa],
    ``peak`` (P,) [Pa], and the finest mesh's cut ``resultants`` (3, P, S)."""

    nominal: NDArray[np.float64]
    nominal_error: NDArray[np.float64]
    peak: NDArray[np.float64]
    resultants: NDArray[np.float64]


def extrapolate(values: NDArray[np.float64], spacing: list[float]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Richardson's value and error estimate from three meshes (coarsest first), where the observed
    order is at least MIN_ORDER; elsewhere the finest value, its error the last change."""
    estimate = richardson(values, spacing)
    trusted = estimate.determined & (estimate.order >= MIN_ORDER)
    change = np.abs(values[-1] - values[-2])
    return np.where(trusted, estimate.extrapolated, values[-1]), np.where(trusted, estimate.error, change)


def _reference(setup: LinkSetup, finest: list[Answer]) -> Reference:
    spacing = [math.sqrt(setup.link.area / a.elements) for a in finest]
    nominal, error = extrapolate(np.array([a.nominal for a in finest]), spacing)
    peak, _ = extrapolate(np.array([a.peak for a in finest]), spacing)
    return Reference(nominal, error, peak, finest[-1].resultants)


def _strip_answers(scene, analysis, chosen, setups, dx, settings) -> tuple[dict[str, Answer], dict]:
    """The strip sums on ``setups`` (each one straight member along the frame, whose stations s are the frame's x)."""
    names = tuple(s.name for s in setups)
    seconds, baseline = _timed(lambda: strip_baseline(scene, analysis.kinematics, names, chosen, dx), settings)
    answers = {}
    for s in setups:
        st = baseline.stresses[s.name]
        x, stations = st.sections.x, s.cuts[0].s
        nominal = _along(x, st.von_mises, stations)
        resultants = np.stack([_along(x, v, stations) for v in (st.normal, st.shear, st.moment)])
        answers[s.name] = Answer(nominal, st.von_mises.max(axis=1), resultants, baseline.seconds / len(setups), len(x))
    return answers, baseline.mass_errors


def _method(key, by_link: dict[str, Answer], setups, reference, mass_errors=None, note="") -> MethodResult:
    method, setting = key
    errors, members = {}, {}
    for s in (s for s in setups if s.name in by_link):
        answer, ref = by_link[s.name], reference[s.name]
        peak = None if answer.peak is None else float(np.max(relative(np.abs(answer.peak - ref.peak), ref.peak)))
        nominal = member_nominal_errors(s, answer.nominal, ref.nominal)
        resultants = [None] * len(s.members) if method.startswith("FEA") else [
            float(resultant_error(answer.resultants[..., b], ref.resultants[..., b], depth).max())
            for b, depth in zip(s.blocks, s.depths)
        ]
        members[s.name] = dict(zip(s.labels, zip(nominal, resultants)))
        errors[s.name] = (_worst(nominal), peak, _worst(resultants))
    worst = [_worst([e[i] for e in errors.values()]) for i in range(3)]
    seconds = sum(a.seconds for a in by_link.values())
    size = sum(a.size for a in by_link.values())
    return MethodResult(method, setting, size, seconds, worst[0], worst[1], worst[2], errors, mass_errors, members, note)


def _worst(errors: list[float | None]) -> float | None:
    """The largest of ``errors`` that are measured (None where none is)."""
    return max((e for e in errors if e is not None), default=None)
