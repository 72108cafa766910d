"""Speed against error of every stress method on one case, all against one FEA reference.

Methods, each timed the same way (wall time after imports, from the link profiles and their kinetic
loads to the stresses; where a run is cheap, the best of as many runs as fill a window of a second
in the full run; the joint-force solve they all share is timed apart):

- the beam engine (``section_stresses``) at several station counts, the exact mass properties
  recomputed each run;
- the original program's strip sums at several strip widths (``strip_sections``);
- plane-stress FEA, P2 and P1, on the validate default mesh refined by RATIO**k for several k
  (mesh, assembly, factorisation, solve, stress recovery and sampling).

The quantity is the nominal von Mises stress at validate's comparison stations (those one section
depth or more from every hole), at the beam's critical fibre of each; a method with other stations
is interpolated linearly along the link, as a reader of its station table would. Error: the
largest difference over those points relative to the largest reference value, per position, worst
over positions and links. The reference is the Richardson extrapolation (``convergence.richardson``)
of the three finest P2 meshes (the finest where the observed order is below MIN_ORDER); its own
error estimate is reported beside it. The peak von Mises (anywhere, pins included) is compared the same way, and the beam's section
resultants against the finest FEA's cut resultants.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult, plan_for, run_analysis
from linkstress.dynamics.section_stress import default_stations, near_holes, section_stresses
from linkstress.loads import LinkLoadCase
from linkstress.mass_properties import area_properties
from linkstress.profile import LinkProfile
from linkstress.scene import Scene, load_scene
from linkstress.validation.compare import comparison_stations, default_mesh, relative, resultant_error
from linkstress.validation.convergence import richardson
from linkstress.validation.errors import FEAError
from linkstress.validation.link_fea import solve_link
from linkstress.validation.mesh import MeshSettings
from linkstress.validation.recovery import von_mises
from linkstress.validation.report import is_curved as curved_sections
from linkstress.validation.strip_sections import strip_baseline
from linkstress.validation.timing import best_run
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
    """One compared link: its loads at the compared positions, validate's comparison ``stations``
    (S,), which of them are ``away`` from holes, the critical ``fibre`` heights (P, S) and mesh."""

    name: str
    link: LinkProfile
    loads: LinkLoadCase
    stations: NDArray[np.float64]
    away: NDArray[np.bool_]
    fibre: NDArray[np.float64]
    mesh: MeshSettings

    @property
    def depth(self) -> float:
        """The deepest compared section [m] (scales the moment differences, as validate does)."""
        table = self.link.sections(self.stations, *self.loads.frame_joints)
        return float((table.top - table.bottom).max())

    @property
    def points(self) -> NDArray[np.float64]:
        """Every position's critical fibres (P * S, 2) [m, member frame]."""
        return np.column_stack([np.broadcast_to(self.stations, self.fibre.shape).ravel(), self.fibre.ravel()])


@dataclass(frozen=True)
class Answer:
    """One method's answer for one link: ``nominal`` von Mises (P, S) [Pa] at the comparison points,
    ``peak`` (P,) [Pa] or None, section ``resultants`` (3, P, S) N [N], V [N], M [N m] or None,
    ``seconds`` [s] and ``size`` (stations, strips or dofs)."""

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
    link (nominal, peak, resultants)."""

    method: str
    setting: str
    size: int
    seconds: float
    nominal_error: float
    peak_error: float | None
    resultant_error: float | None
    link_errors: dict[str, tuple[float, float | None, float | None]]
    mass_errors: dict[str, tuple[float, float, float]] | None = None
    """Strip sums only: per link, area, centroid and polar moment errors against the exact values."""


@dataclass(frozen=True)
class CaseStudy:
    """Every method measured on one case; ``reference_error`` [-] per link: Richardson's estimate
    of the reference's own error; ``kinetics_seconds``: the shared joint-force solve."""

    name: str
    title: str
    links: tuple[str, ...]
    positions: int
    methods: tuple[MethodResult, ...]
    reference_error: dict[str, float]
    reference_dofs: dict[str, int]
    kinetics_seconds: float
    curved: tuple[str, ...]
    failures: tuple[str, ...]

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


def setup_links(scene: Scene, analysis: AnalysisResult, chosen: NDArray[np.intp]) -> list[LinkSetup]:
    """validate's comparison of every link it checks, at the sweep positions ``chosen``."""
    setups = []
    for name in analysis.plan.validate:
        link = scene.links[name].profile
        loads = analysis.forces.link_loads[name].at(chosen)
        stations = comparison_stations(link, loads.frame_joints)
        beam = section_stresses(link, loads, stations)
        away = ~beam.near_hole if (~beam.near_hole).any() else np.ones(len(stations), bool)
        mesh = default_mesh(link, loads.frame_joints, stations)
        setups.append(LinkSetup(name, link, loads, stations, away, beam.fibre_y, mesh))
    return setups


def is_curved(setup: LinkSetup) -> bool:
    """validate's curved-link test on the compared stations."""
    table = setup.link.sections(setup.stations, *setup.loads.frame_joints)
    return curved_sections(table, near_holes(setup.link, setup.loads.frame_joints, table))


def fea_answer(setup: LinkSetup, mesh: MeshSettings, settings: StudySettings) -> Answer:
    """FEA on ``mesh``: nominal von Mises at the comparison points, peak and cut resultants."""
    points = setup.points
    count, n_pos = len(setup.stations), setup.loads.n_positions
    rows = np.arange(n_pos)

    def solve():
        result = solve_link(setup.link, setup.loads, mesh)
        sampled = von_mises(result.stress_at(points)).reshape(n_pos, n_pos, count)[rows, rows]
        return result, sampled, result.von_mises_peak

    seconds, (result, nominal, peak) = _timed(solve, settings)
    cuts = result.section_resultants(setup.stations)
    return Answer(nominal, peak, np.stack([cuts.normal, cuts.shear, cuts.moment]), seconds, result.dofs, result.n_elements)


def beam_answer(setup: LinkSetup, count: int, settings: StudySettings) -> Answer:
    """The beam engine at ``count`` stations over the link, read at the comparison stations; its
    time includes the exact (Green) mass properties, recomputed each run."""
    link = setup.link

    def solve():
        area_properties(link.outline)
        return section_stresses(link, setup.loads, default_stations(link, setup.loads.frame_joints, count))

    seconds, stresses = _timed(solve, settings)
    f = stresses.forces
    along = [stresses.von_mises, f.normal, f.shear, f.moment]
    nominal, *resultants = (_along(stresses.x, v, setup.stations) for v in along)
    return Answer(nominal, stresses.max_von_mises, np.stack(resultants), seconds, count)


def _along(x, values, stations) -> NDArray[np.float64]:
    """Values (P, S') at stations x (S',) read at ``stations`` by linear interpolation, (P, S)."""
    return np.stack([np.interp(stations, x, row) for row in values])


def _timed(work, settings: StudySettings):
    """Best wall time of ``work`` and its value: one run, or where that is cheap, the best of as many
    runs as fill ``settings.cheap`` seconds (at least ``settings.repeat``), so that a burst of load on
    a shared machine does not decide a few-millisecond figure."""
    seconds, value = best_run(work, 1)
    if seconds < settings.cheap and settings.repeat > 1:
        again, value = best_run(work, max(settings.repeat - 1, int(settings.cheap / max(seconds, 1e-6))))
        seconds = min(seconds, again)
    return seconds, value


def _error(values, reference, away) -> float:
    """Largest |values - reference| over the away points relative to the largest reference, worst position."""
    diff = np.abs(values[:, away] - reference[:, away]).max(axis=1)
    return float(np.max(relative(diff, np.abs(reference[:, away]).max(axis=1))))


def case_study(scene_path, settings: StudySettings) -> CaseStudy:
    """Measure every method of ``settings`` on the scene at ``scene_path``."""
    scene = load_scene(scene_path)
    analysis = run_analysis(scene, plan_for(scene))
    kinetics_seconds = analysis.seconds["kinematics"] + analysis.seconds["forces"]
    chosen = compared_positions(analysis.feasible, settings.positions)
    setups = setup_links(scene, analysis, chosen)
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
    mass = {}
    for dx in settings.strip_steps:
        key = ("strip sums", f"dx = {dx:g} m")
        answers[key], mass[key] = _strip_answers(scene, analysis, chosen, setups, dx, settings)
    methods = [_method(key, by_link, setups, reference, mass.get(key)) for key, by_link in answers.items()]
    reference_error = {s.name: _error(r.nominal + r.nominal_error, r.nominal, s.away) for s, r in zip(setups, reference.values())}
    title = scene.title if scene.title != scene_path.stem else scene_path.parent.name.replace("_", " ")
    return CaseStudy(
        scene_path.parent.name, title, tuple(s.name for s in setups), len(chosen), tuple(methods),
        reference_error, {s.name: finest[-1][s.name].size for s in setups}, kinetics_seconds,
        tuple(s.name for s in setups if is_curved(s)), tuple(failures),
    )


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
    names = tuple(s.name for s in setups)
    seconds, baseline = _timed(lambda: strip_baseline(scene, analysis.kinematics, names, chosen, dx), settings)
    answers = {}
    for s in setups:
        st = baseline.stresses[s.name]
        x = st.sections.x
        nominal = _along(x, st.von_mises, s.stations)
        resultants = np.stack([_along(x, v, s.stations) for v in (st.normal, st.shear, st.moment)])
        answers[s.name] = Answer(nominal, st.von_mises.max(axis=1), resultants, baseline.seconds / len(setups), len(x))
    return answers, baseline.mass_errors


def _method(key, by_link: dict[str, Answer], setups, reference, mass_errors=None) -> MethodResult:
    method, setting = key
    errors = {}
    for s in setups:
        answer = by_link[s.name]
        ref = reference[s.name]
        peak = None if answer.peak is None else float(np.max(relative(np.abs(answer.peak - ref.peak), ref.peak)))
        resultants = None if method.startswith("FEA") else float(
            resultant_error(answer.resultants, ref.resultants, s.depth).max()
        )
        errors[s.name] = (_error(answer.nominal, ref.nominal, s.away), peak, resultants)
    worst = [max((e[i] for e in errors.values() if e[i] is not None), default=None) for i in range(3)]
    seconds = sum(a.seconds for a in by_link.values())
    size = sum(a.size for a in by_link.values())
    return MethodResult(method, setting, size, seconds, worst[0], worst[1], worst[2], errors, mass_errors)
