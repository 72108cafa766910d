"""FEA peaks by superposition of unit loads against direct FEA, for ``linkstress bench``.

- ``peaks_study``: every link whose peaks a scene's sweep computes (``Plan.with_peaks``: every
  stressed link), analysed as ``analyze --peaks`` does (``peaks_scene``): its unit load cases'
  count and cost (mesh, unit solves, superposition over every feasible position of the sweep), and
  the superposed field against the direct FEA (``solve_link``) of the same loads on the same mesh
  at validate's compared positions: the error of the peak von Mises and the rms error of the nodal
  von Mises field, worst over those positions.
- ``peaks_speed``: the seed four-bar over a whole turn in 360 positions (written beside a copy of its
  sketch, as a user would sweep it), analysed with peaks for its three links, against one
  ``validate`` of the seed's own one-position scene (validate's three mesh levels), timed in one
  run: gmsh and the assembly warmed once untimed, the two alternated, the best of each kept. The
  target: the whole sweep with its FEA peaks in less time than one validate at one position, the
  superposition itself at most SUPERPOSITION_TARGET per link and position. Times are reported as
  a must-show (met or not), never checked in a test: machines are shared and noisy.

Peak error: |superposed peak / direct peak - 1| per position [-]; field error: ``peaks.field_error``.
"""

from __future__ import annotations

import re
import shutil
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from linkstress.analysis import AnalysisResult, Plan, plan_for, run_analysis
from linkstress.scene import Scene, load_scene
from linkstress.stress_state import von_mises
from linkstress.validation.fea.link import solve_link
from linkstress.validation.peaks import field_error, peak_mesh, superposed_stress
from linkstress.validation.bench.speed_error import VALIDATE_LEVELS
from linkstress.validation.fea.unit_loads import DIRECTION_STEP_DEG
from linkstress.validation.validate_scene import MAX_POSITIONS, compared_positions, validate_scene

PEAK_BOUND = 0.01
"""Largest error [-] of a superposed peak against the direct FEA's on the same mesh."""
FIELD_BOUND = 0.005
"""Largest rms error [-] of a superposed von Mises field against the direct FEA's."""
RATIO_TARGET = 1.0
"""The seed's 360-position sweep with peaks must take less than this times one validate at one position."""
SUPERPOSITION_TARGET = 1e-3
"""Largest superposition time [s] per link and position over the seed's sweep."""
FULL_TURN = 360
"""Positions of the timed sweep: one per degree, 0 to 359 deg."""
SETTING = f"bearing directions every {DIRECTION_STEP_DEG:g} deg, validate's converged mesh"
"""The superposition's setting, in words."""


@dataclass(frozen=True)
class LinkPeakStudy:
    """One link's superposed FEA over a sweep against direct FEA on the same (peak) mesh.

    ``unit_cases`` solved on ``dofs`` dofs; ``mesh_seconds``, ``unit_solve_seconds`` (factorisation,
    unit solves, stress recovery) and ``superposition_seconds`` (every one of the ``sweep_positions``
    feasible positions) [s]; ``peak_error`` and ``field_error`` [-]: worst over the ``compared``
    positions; ``direct_seconds`` [s]: the direct FEA of those positions (mesh, one factorisation,
    the solves, stress recovery).
    """

    name: str
    unit_cases: int
    dofs: int
    sweep_positions: int
    mesh_seconds: float
    unit_solve_seconds: float
    superposition_seconds: float
    compared: int
    peak_error: float
    field_error: float
    direct_seconds: float

    @property
    def superposition_per_position(self) -> float:
        """[s] per position of the sweep."""
        return self.superposition_seconds / self.sweep_positions

    @property
    def sweep_seconds(self) -> float:
        """[s]: the whole sweep's peaks, mesh and unit solves included."""
        return self.mesh_seconds + self.unit_solve_seconds + self.superposition_seconds

    @property
    def direct_per_position(self) -> float:
        """[s] per compared position of the direct FEA (its mesh and factorisation shared by them)."""
        return self.direct_seconds / self.compared


@dataclass(frozen=True)
class PeaksStudy:
    """Every link of a case's sweep (``positions`` input angles): superposed against direct FEA."""

    name: str
    title: str
    positions: int
    links: tuple[LinkPeakStudy, ...]

    @property
    def peak_error(self) -> float:
        return max(link.peak_error for link in self.links)

    @property
    def field_error(self) -> float:
        return max(link.field_error for link in self.links)

    @property
    def superposition_per_link_position(self) -> float:
        """[s]: the slowest link's superposition per position."""
        return max(link.superposition_per_position for link in self.links)


@dataclass(frozen=True)
class PeaksSpeed:
    """The seed's sweep of ``sweep_positions`` input angles with peaks for its ``links``, best of
    ``repeat`` runs ``sweep_seconds`` [s], against one validate at one position, best
    ``validate_seconds`` [s]; ``study``: the best sweep's peaks against direct FEA."""

    sweep_positions: int
    links: tuple[str, ...]
    repeat: int
    sweep_seconds: float
    validate_seconds: float
    study: PeaksStudy

    @property
    def ratio(self) -> float:
        """Sweep with peaks over one validate at one position [-]."""
        return self.sweep_seconds / self.validate_seconds

    @property
    def superposition_per_link_position(self) -> float:
        """[s], the slowest link's, in the best sweep."""
        return self.study.superposition_per_link_position

    @property
    def met(self) -> bool:
        return self.ratio < RATIO_TARGET and self.superposition_per_link_position <= SUPERPOSITION_TARGET


def peaks_study(scene_path: Path, positions: int = MAX_POSITIONS) -> PeaksStudy:
    """The scene at ``scene_path`` analysed with peaks for every stressed link, each compared with
    direct FEA at up to ``positions`` of its feasible positions (validate's choice)."""
    scene = load_scene(scene_path)
    analysis = run_analysis(scene, plan_for(scene).with_peaks())
    return _study(scene_path.parent.name, _title(scene, scene_path), analysis, positions)


def peaks_speed(scene_path: Path, positions: int = MAX_POSITIONS, repeat: int = 3, sweep: int = FULL_TURN) -> PeaksSpeed:
    """The scene at ``scene_path`` (one position, as the seed's) over a whole turn of ``sweep``
    positions with peaks, against one validate of the scene itself; best of ``repeat`` runs of each,
    alternated. The best sweep's peaks are compared with direct FEA at up to ``positions``."""
    one = load_scene(scene_path)
    one_plan = plan_for(one)
    with tempfile.TemporaryDirectory(prefix="linkstress-bench-") as folder:
        swept = load_scene(full_turn_scene(scene_path, Path(folder), sweep))
    swept_plan = plan_for(swept).with_peaks()
    _warm_up(one, one_plan)
    best, sweep_seconds, validate_seconds = None, np.inf, np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        analysis = run_analysis(swept, swept_plan)
        elapsed = time.perf_counter() - start
        if elapsed < sweep_seconds:
            best, sweep_seconds = analysis, elapsed
        start = time.perf_counter()
        validate_scene(one, one_plan, positions=1, levels=len(VALIDATE_LEVELS))
        validate_seconds = min(validate_seconds, time.perf_counter() - start)
    study = _study(scene_path.parent.name, _title(one, scene_path), best, positions)
    return PeaksSpeed(sweep, swept_plan.peaks, repeat, sweep_seconds, validate_seconds, study)


def full_turn_scene(scene_path: Path, folder: Path, positions: int) -> Path:
    """The scene at ``scene_path`` over a whole turn in ``positions`` input angles (0 deg to one step
    short of 360 deg: the turn's first position is not repeated), written to ``folder`` beside a copy
    of its sketches."""
    motion = f"input_angle_deg = {{ start = 0.0, stop = {360.0 * (positions - 1) / positions!r}, num = {positions} }}"
    text, count = re.subn(r"^input_angle_deg = .*$", motion, scene_path.read_text(), flags=re.MULTILINE)
    if count != 1:
        raise RuntimeError(f"{scene_path}: expected one input_angle_deg line, found {count}")
    for sketch in scene_path.parent.glob("*.dxf"):
        shutil.copy(sketch, folder / sketch.name)
    out = folder / scene_path.name
    out.write_text(text)
    return out


def _warm_up(scene: Scene, plan: Plan) -> None:
    """gmsh's and the assembly's first use costs more than the next: one solve, untimed."""
    analysis = run_analysis(scene, plan)
    name = plan.stresses[0]
    profile, loads = scene.links[name].profile, analysis.forces.link_loads[name]
    solve_link(profile, loads, peak_mesh(profile, loads.frame_joints))


def _study(name: str, title: str, analysis: AnalysisResult, positions: int) -> PeaksStudy:
    """Each link of ``analysis.peaks`` against its direct FEA at up to ``positions`` feasible positions."""
    chosen = compared_positions(analysis, positions)
    links = []
    for link, peaks in analysis.peaks.items():
        cases = peaks.sweep.cases
        loads = analysis.forces.link_loads[link].at(chosen)
        start = time.perf_counter()
        direct = solve_link(cases.link, loads, peaks.mesh)
        direct_seconds = time.perf_counter() - start
        superposed = superposed_stress(cases, cases.weights(loads))
        peak = np.abs(von_mises(superposed).max(axis=1) / direct.von_mises_peak - 1.0)
        field = field_error(superposed, direct.nodal_stress)
        links.append(LinkPeakStudy(
            link, cases.count, cases.dofs, len(peaks.sweep.positions), cases.seconds["mesh"], cases.seconds["solve"],
            peaks.sweep.seconds, len(chosen), float(peak.max()), float(field.max()), direct_seconds,
        ))
    return PeaksStudy(name, title, len(analysis.feasible), tuple(links))


def _title(scene: Scene, path: Path) -> str:
    return scene.title if scene.title != path.stem else path.parent.name.replace("_", " ")
