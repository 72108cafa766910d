"""FEA peaks and fatigue of every link a plan names, over the scene's whole sweep.

For each link of ``plan.peaks``: its unit load cases on the peak mesh (``peaks.peak_mesh``), their
superposition over every feasible position (``peaks.sweep_peaks``) or, for a link a slider's block
slides along, a direct solve of each (``direct_peaks``), the peak's check over the last
refinement at the worst position (``peaks.coarser_peak``), and, where the material gives
``endurance_limit`` and ``ultimate_strength``, the fatigue safety factor of every node from the
extremes of its signed equivalent stress over the sweep (``linkstress.fatigue``).

A link's whole result (the superposed peaks, the node extremes fatigue reads, the check) is a
function of its task's data and the code alone: the disk cache keeps it under a key of exactly
those (``sweep_key``), so that running the same scene again reads it without loading gmsh or
scikit-fem, meshing, solving or superposing anything.

A fatigue factor is the cycle's only when the sweep is one: a whole turn of the input, every
position feasible. Otherwise it is still given, with a note that says what it covers. A peak that
moved more than the limit over the last refinement gives no safety factor, yield or fatigue: the
note says so and why.
"""

from __future__ import annotations

import importlib.util
import os
import time
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import Plan, used_joints
from linkstress.dynamics.machine_forces import MachineForces
from linkstress.executors import DaskExecutor, LocalExecutor
from linkstress.fatigue import NodeFatigue, criteria_available, node_fatigue
from linkstress.loads import LinkLoadCase
from linkstress.scene import Scene, SceneLink
from linkstress.threads import blas_alone
from linkstress.validation.fea.cache import CacheSettings, DiskCache, key_of, open_cache
from linkstress.validation.peak_results import MeshSizes, PeakCheck, StoredCases, SweepPeaks

FULL_TURN_DEG = 360.0


@dataclass(frozen=True)
class LinkPeaks:
    """One link's FEA peaks over a sweep of P positions and, where its material allows, its fatigue.

    ``sweep``: the superposed peaks at the feasible positions ``sweep.positions``; ``check``: the
    peak's change over the last refinement at the worst position; ``mesh``: the peak mesh's
    settings (``fea.mesh.MeshSettings``; read from the cache, its ``MeshSizes``); ``fatigue``: per node factors and the critical node (None without fatigue data, then
    ``fatigue_note`` says why); ``fatigue_note``: what the factor covers when not one whole cycle,
    or why there is none.
    """

    name: str
    n_positions: int
    sweep: SweepPeaks
    check: PeakCheck
    mesh: object
    fatigue: NodeFatigue | None
    fatigue_criterion: str
    fatigue_note: str
    check_seconds: float = 0.0

    @property
    def peak(self) -> NDArray[np.float64]:
        """(P,) [Pa]: the peak at every position of the sweep, nan where infeasible."""
        return self._spread(self.sweep.peak)

    @property
    def peak_at(self) -> NDArray[np.float64]:
        """(P, 2) [m, member frame]: where each position's peak is, nan where infeasible."""
        return self._spread(self.sweep.peak_at)

    @property
    def worst_position(self) -> int:
        """Index into the sweep of the largest peak."""
        return int(self.sweep.positions[self.sweep.worst])

    @property
    def peak_max(self) -> float:
        """[Pa]: the largest peak over the sweep."""
        return float(self.sweep.peak[self.sweep.worst])

    @property
    def trusted(self) -> bool:
        """Whether the peak settled on its mesh (and safety factors may be taken from it)."""
        return self.check.converged

    @property
    def untrusted_reason(self) -> str:
        """Why no safety factor is taken from the peak ("" when one is)."""
        if self.trusted:
            return ""
        return (
            f"the FEA peak is NOT converged: it changed {100 * self.check.change:.3g} % over the last mesh refinement "
            f"and {100 * self.check.previous_change:.3g} % over the one before at its worst position (limit "
            f"{100 * self.check.limit:g} % each): a sharp corner or a steep stress the mesh does not resolve; round "
            "the corner in the drawing or give a finer [analysis] mesh_size_m"
        )

    def _spread(self, values: NDArray[np.float64]) -> NDArray[np.float64]:
        out = np.full((self.n_positions, *values.shape[1:]), np.nan)
        out[self.sweep.positions] = values
        return out


def scene_peaks(
    scene: Scene,
    plan: Plan,
    forces: MachineForces,
    executor: LocalExecutor | DaskExecutor | None = None,
    cache: CacheSettings | None = None,
) -> dict[str, LinkPeaks]:
    """The peaks (and fatigue) of every link of ``plan.peaks`` over the sweep's feasible positions;
    none where no position is feasible. Each link is a task of ``executor`` (default: here, one
    after another), its unit-load solutions, meshes and peak check from and into the disk cache of
    ``cache`` when given (the settings travel with the task). Raises FEAError (an InputError) naming
    a link that cannot be meshed or solved."""
    tasks = peaks_tasks(scene, plan, forces, cache)
    if not tasks:
        return {}
    where = executor or LocalExecutor()
    here = isinstance(where, LocalExecutor) and (where.jobs == 1 or len(tasks) == 1)
    work = link_peaks if here else portable_link_peaks
    return dict(zip(plan.peaks, where.map(work, tasks, [f"link {name}" for name in plan.peaks])))


def stored_links(scene: Scene, plan: Plan, forces: MachineForces, cache: CacheSettings | None) -> set[str]:
    """The links of ``plan.peaks`` whose very result the disk cache holds (``sweep_key``): they need
    neither the mesh checks nor the FEA stack."""
    store = open_cache(cache)
    if store is None:
        return set()
    return {task.name for task in peaks_tasks(scene, plan, forces, cache)
            if store.path(SWEEP_PEAKS, sweep_key(task)).exists()}


def peaks_tasks(scene: Scene, plan: Plan, forces: MachineForces, cache: CacheSettings | None) -> list["PeaksTask"]:
    """A task per link of ``plan.peaks``; none where no position is feasible."""
    feasible = np.flatnonzero(forces.feasible)
    if not len(feasible):
        return []
    size = scene.analysis.mesh_size if scene.analysis is not None else None
    order = scene.analysis.element_order if scene.analysis is not None else 2
    note = cycle_note(scene.motion.angle_deg, forces.feasible)
    return [
        PeaksTask(name, scene.links[name], forces.link_loads[name], feasible, len(forces.feasible), size, order, note,
                  plan.fatigue_criterion, used_joints(scene, name), cache)
        for name in plan.peaks
    ]


@dataclass(frozen=True)
class PeaksTask:
    """What one link's peaks need, all of it data: the ``link``, its ``loads`` over the sweep of
    ``n_positions``, the ``feasible`` positions (indices), the mesh ``size`` [m] (None: default)
    and element ``order``, the sweep's ``cycle_note``, the fatigue ``criterion``, the joints the
    scene uses (``linkstress.analysis.used_joints``: the link's members join those alone) and the
    disk ``cache`` (None: none)."""

    name: str
    link: SceneLink
    loads: LinkLoadCase
    feasible: NDArray[np.intp]
    n_positions: int
    size: float | None
    order: int
    cycle_note: str
    criterion: str
    used_joints: tuple[int, ...] | None = None
    cache: CacheSettings | None = None


def link_peaks(task: PeaksTask) -> LinkPeaks:
    """One link's peaks over the sweep and its fatigue (a task: runs wherever the executor sends it,
    with BLAS on one thread as in ``run_analysis``): from the disk cache when it holds this very
    task's result, else computed (and kept there)."""
    link = task.link
    with blas_alone():
        cache = open_cache(task.cache)
        key = sweep_key(task) if cache is not None else ""
        stored = cache.load(SWEEP_PEAKS, key) if cache is not None else None
        if stored is not None:
            sweep, check, mesh, check_seconds = _from_stored(stored, time.perf_counter())
        else:
            sweep, check, mesh, check_seconds = _computed(task, cache)
            if cache is not None:
                cache.store(SWEEP_PEAKS, key, _to_store(sweep, check, mesh))
    fatigue, fatigue_note = None, task.cycle_note
    strength = link.material.fatigue_strength
    if strength is None:
        fatigue_note = f"no fatigue check: materials.{link.material.name} gives no endurance_limit and ultimate_strength"
    elif task.criterion not in criteria_available(strength):
        fatigue_note = f"no fatigue check: the {task.criterion} criterion needs materials.{link.material.name}.yield_strength"
    else:
        fatigue = node_fatigue(sweep.largest, sweep.smallest, strength, task.criterion)
    return LinkPeaks(task.name, task.n_positions, sweep, check, mesh, fatigue, task.criterion, fatigue_note, check_seconds)


def portable_link_peaks(task: PeaksTask) -> LinkPeaks:
    """``link_peaks`` for a task run in another process: its unit cases travel back as what the
    reports read of them (``StoredCases``), a few MB, not their solved fields and model (35 MB for
    the README tutorial's coupler, pickled, piped and read again in the parent)."""
    peaks = link_peaks(task)
    cases = peaks.sweep.cases
    if not isinstance(cases, StoredCases):
        cases = StoredCases(cases.nodes, cases.element_dofs, cases.dofs, cases.count, cases.directions,
                            tuple(cases.frame_joints), dict(cases.seconds))
    return replace(peaks, sweep=replace(peaks.sweep, cases=cases))


def _computed(task: PeaksTask, cache: DiskCache | None) -> tuple[SweepPeaks, PeakCheck, object, float]:
    """Mesh, solve the unit cases, superpose and check (the FEA stack loads here, and only here); the
    peak mesh's ``MeshSettings``."""
    from linkstress.geometry.members import link_members
    from linkstress.validation.fea.unit_loads import DIRECTION_STEP_DEG, unit_load_cases
    from linkstress.validation.peaks import coarser_peak, peak_mesh, sweep_peaks

    link, loads, feasible = task.link, task.loads, task.feasible
    profile = link.profile
    members = link_members(profile, loads.frame_joints, link.members, task.used_joints)
    mesh = peak_mesh(profile, loads.frame_joints, members, task.size, task.order)
    if loads.contacts:
        from linkstress.validation.direct_peaks import direct_sweep_peaks

        sweep = direct_sweep_peaks(profile, loads, feasible, mesh, cache)
    else:
        cases = unit_load_cases(profile, loads.at(feasible), mesh, DIRECTION_STEP_DEG, cache)
        sweep = sweep_peaks(cases, loads, feasible)
    start = time.perf_counter()
    check = coarser_peak(sweep, loads, mesh, cache, profile)
    return sweep, check, mesh, time.perf_counter() - start


SWEEP_PEAKS = "sweep-peaks"
"""The cache's kind for a link's whole peaks result over one sweep (``link_peaks``)."""


def sweep_key(task: PeaksTask) -> str:
    """The cache key of ``task``'s result: everything it is computed from (the link's outline and
    holes, joints, thickness, material, members and the joints the scene uses, its loads at every
    feasible position, the sweep's length, the mesh size and order) and, as every key, the code and
    library versions and the sparse solver (named without loading it: ``LINKSTRESS_SOLVER``, else
    CHOLMOD where scikit-sparse is installed)."""
    link, loads = task.link, task.loads.at(task.feasible)
    profile = link.profile
    material = profile.material
    parts = {
        "outline": [np.asarray(profile.outline.exterior.coords)] + [np.asarray(r.coords) for r in profile.outline.interiors],
        "joints": np.asarray(profile.joints, float),
        "thickness": profile.thickness, "density": profile.density,
        "youngs_modulus": material.youngs_modulus, "poisson_ratio": material.poisson_ratio,
        "members": [list(pair) for pair in link.members or ()],
        "used_joints": None if task.used_joints is None else list(task.used_joints),
        "frame_joints": list(loads.frame_joints),
        "pin_forces": loads.pin_forces, "joint_couples": loads.joint_couples, "omega": loads.omega,
        "alpha": loads.alpha, "origin_acceleration": loads.origin_acceleration, "gravity": loads.gravity,
        "point_forces": [{"at": np.asarray(p.at, float), "force": np.asarray(p.force, float)} for p in loads.point_forces],
        "contacts": [c.record() for c in loads.contacts],
        "feasible": np.asarray(task.feasible, np.int64), "n_positions": task.n_positions,
        "size": task.size, "order": task.order,
    }
    solver = os.environ.get("LINKSTRESS_SOLVER", "").strip().lower() or (
        "cholmod" if importlib.util.find_spec("sksparse") is not None else "superlu")
    return key_of(SWEEP_PEAKS, parts, solver)


def _to_store(sweep: SweepPeaks, check: PeakCheck, mesh: MeshSizes) -> dict[str, NDArray]:
    cases = sweep.cases
    return {
        "positions": sweep.positions, "peak": sweep.peak, "peak_node": sweep.peak_node, "envelope": sweep.envelope,
        "largest": sweep.largest, "smallest": sweep.smallest, "reaction_ratio": sweep.reaction_ratio,
        "worst": np.array([sweep.worst]), "worst_stress": sweep.worst_stress,
        "nodes": cases.nodes, "element_dofs": cases.element_dofs, "directions": cases.directions,
        "counts": np.array([cases.dofs, cases.count]), "frame_joints": np.array(cases.frame_joints),
        "check": np.array([check.finer, check.coarser, check.coarsest, check.limit]),
        "mesh": np.array([mesh.size, mesh.hole_size, mesh.order]),
    }


def _from_stored(stored: dict[str, NDArray], start: float) -> tuple[SweepPeaks, PeakCheck, MeshSizes, float]:
    dofs, count = (int(v) for v in stored["counts"])
    cases = StoredCases(stored["nodes"], stored["element_dofs"], dofs, count, stored["directions"],
                        tuple(int(j) for j in stored["frame_joints"]),
                        {"mesh": 0.0, "solve": 0.0, "cache": time.perf_counter() - start})
    sweep = SweepPeaks(cases, stored["positions"], stored["peak"], stored["peak_node"], stored["envelope"],
                       stored["largest"], stored["smallest"], stored["reaction_ratio"], int(stored["worst"][0]),
                       stored["worst_stress"], 0.0)
    check = PeakCheck(*(float(v) for v in stored["check"]))
    size, hole_size, order = stored["mesh"]
    return sweep, check, MeshSizes(float(size), float(hole_size), int(order)), 0.0


def cycle_note(angles_deg: NDArray[np.float64], feasible: NDArray[np.bool_]) -> str:
    """"" when the sweep is one whole cycle (a full turn of the input, every position feasible),
    else what the stress history covers."""
    angles = np.asarray(angles_deg, float)
    if len(angles) < 2:
        return "over one position only, not a cycle: sweep motion.input_angle_deg over a whole turn"
    step = float(np.median(np.abs(np.diff(angles))))
    span = float(np.ptp(angles)) + step
    if not feasible.all():
        return (
            f"over the {int(feasible.sum())} feasible positions of {len(feasible)} only: the linkage cannot reach the "
            "others, so the stress history is not a whole cycle"
        )
    if span < FULL_TURN_DEG - 1e-6 * step:
        return (
            f"over the swept {span:.4g} deg of input only, not a whole turn: sweep motion.input_angle_deg over "
            "360 deg for the cycle's alternating and mean stress"
        )
    return ""
