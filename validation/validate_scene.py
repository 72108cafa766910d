"""Validate a scene: every link the plan names is solved by FEA under its kinetic loads and compared
with the beam sections (``compare``), along each of its members. A link that cannot be meshed or solved gets an error entry
with the reason; the others still finish.

A link fails the check when its FEA support reactions are not ~0 (the kinetics' loads are not in
equilibrium) or its section resultants differ from the beam's by more than RESULTANT_LIMIT (the
two engines disagree on the loads). Stress differences are reported, not judged: they measure
beam theory, and the report says where it falls short. Nor does convergence fail the check: a
peak that has not converged is named beside the check's verdict (``unconverged``) and gives no
safety factor.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray
from tqdm import tqdm

from linkstress.analysis import AnalysisResult, Plan, run_analysis
from linkstress.errors import GeometryError
from linkstress.executors import DaskExecutor, LocalExecutor
from linkstress.members import link_members
from linkstress.scene import Scene
from linkstress.validation.compare import LinkComparison, choose_stations, compare_link, default_mesh
from linkstress.validation.fea.errors import FEAError

REACTION_LIMIT = 1e-4
"""Largest support reaction, relative to the applied load, for loads in equilibrium. Not zero: the
mesh follows exact arcs and splines where the kinetics used the drawing's flattened outline, so the
body forces differ by the relative area between the two (about 1e-5 on curved links); a wrong load
in the kinetics leaves a reaction of order 1."""
RESULTANT_LIMIT = 0.01
"""Largest section-resultant difference between beam and FEA (relative) before the check fails."""
LINEAR_REFINEMENT = 2.25
"""Linear (P1) elements get meshes this much finer than the default sizes (two of the study's
refinement steps) unless the scene gives a mesh size. Measured by ``linkstress bench`` (docs/benchmarks.md,
"Speed against error"): on the default meshes P1's nominal error is several times P2's and its cut
resultants miss the RESULTANT_LIMIT check on the seed case."""
MAX_POSITIONS = 36
"""Positions of a sweep compared by default (evenly spread over the feasible ones)."""
POSE_RESOLUTION = 1e-9
"""Two positions whose state (cosines and sines of angles, origins [m], input speed [rad/s] and
acceleration [rad/s^2]) agrees to this are one pose: far above the rounding of a sweep's arithmetic
(the cosine of 360 deg is 1 to 1e-16), far below the step of any sweep worth comparing."""


@dataclass(frozen=True)
class ValidationResult:
    """The analysis, the compared positions (indices into the sweep), one comparison per link that
    could be solved and an error message per link that could not."""

    analysis: AnalysisResult
    positions: NDArray[np.intp]
    comparisons: dict[str, LinkComparison]
    errors: dict[str, str]
    seconds: dict[str, float] = field(default_factory=dict)

    def failures(self) -> list[str]:
        """What fails the check, one line each (empty when everything passes)."""
        lines = [f"{name}: FEA failed: {message}" for name, message in self.errors.items()]
        for name, c in self.comparisons.items():
            if (c.fea.reaction_ratio > REACTION_LIMIT).any():
                lines.append(
                    f"{name}: FEA support reactions reach {c.fea.reaction_ratio.max():.3g} of the applied "
                    "load: the kinetic loads on this link are not in equilibrium"
                )
            if (c.resultant_error > RESULTANT_LIMIT).any():
                lines.append(
                    f"{name}: section resultants differ by {100 * c.resultant_error.max():.3g} % between beam "
                    f"and FEA (limit {100 * RESULTANT_LIMIT:g} %)"
                )
        return lines

    def unconverged(self) -> list[str]:
        """The quantities of each link that did not converge over its refinement study, one line
        each (empty with one mesh level, where nothing was checked)."""
        lines = []
        for name, c in self.comparisons.items():
            for quantity, q in (c.convergence or {}).items():
                if q is not None and not q.converged:
                    lines.append(f"{name}: {quantity} NOT converged ({q.words()})")
        return lines


def distinct_poses(analysis: AnalysisResult) -> NDArray[np.intp]:
    """The feasible positions of ``analysis`` less each that repeats an earlier one's pose: the same
    input angle modulo 360 deg, input speed and acceleration, and every link at the same angle modulo
    2 pi and with its frame origin at the same point (ground frame), so the same loads. A sweep over
    0..360 deg (both ends included) ends on the pose it starts from on a machine that closes in one
    turn; where the links come back elsewhere, or the speed is reversed, both positions are kept."""
    ok = np.flatnonzero(analysis.feasible)
    motion = analysis.scene.motion
    columns = [np.cos(motion.angle), np.sin(motion.angle), motion.speed, motion.acceleration]
    for link in analysis.kinematics.links.values():
        columns += [np.cos(link.angle), np.sin(link.angle), link.origin[:, 0], link.origin[:, 1]]
    # Rounded to the resolution; adding 0.0 makes a rounded -0.0 equal to 0.0 for np.unique.
    state = np.round(np.column_stack(columns)[ok] / POSE_RESOLUTION) + 0.0
    _, first = np.unique(state, axis=0, return_index=True)
    return ok[np.sort(first)]


def compared_positions(analysis: AnalysisResult, limit: int) -> NDArray[np.intp]:
    """Up to ``limit`` distinct poses of ``analysis``'s feasible positions (``distinct_poses``), evenly
    spread, first and last included (indices into the sweep)."""
    ok = distinct_poses(analysis)
    if len(ok) <= limit:
        return ok
    return np.unique(ok[np.linspace(0, len(ok) - 1, limit).round().astype(int)])


def validate_scene(
    scene: Scene,
    plan: Plan,
    positions: int = MAX_POSITIONS,
    levels: int = 3,
    mesh_size: float | None = None,
    jobs: int = 1,
    executor: LocalExecutor | DaskExecutor | None = None,
) -> ValidationResult:
    """Analyse ``scene`` and compare every link of ``plan.validate`` with its FEA at up to
    ``positions`` feasible positions, with the elements of the scene's ``[analysis] element_order``
    (default 2); ``levels`` >= 3 makes each a mesh refinement study; each link is a task of
    ``executor`` (default: ``jobs`` local processes when > 1, else here). A progress bar shows on a
    terminal."""
    analysis = run_analysis(scene, plan)
    chosen = compared_positions(analysis, positions)
    size = mesh_size or (scene.analysis.mesh_size if scene.analysis is not None else None)
    order = scene.analysis.element_order if scene.analysis is not None else 2
    tasks = [
        (name, scene.links[name].profile, analysis.forces.link_loads[name], chosen, levels, size, order,
         plan.body_load_near_holes, scene.links[name].members)
        for name in plan.validate
    ]
    where = executor or LocalExecutor(jobs)
    outcomes = list(_progress(where.map(_compare, tasks, [f"link {name}" for name in plan.validate]), len(tasks)))
    comparisons = {name: result for name, result, _, _ in outcomes if result is not None}
    errors = {name: error for name, _, error, _ in outcomes if error}
    seconds = {name: elapsed for name, _, _, elapsed in outcomes}
    return ValidationResult(analysis, chosen, comparisons, errors, seconds)


def _compare(task) -> tuple[str, LinkComparison | None, str, float]:
    """One link's comparison, or the reason it could not run (top level: runs in a worker process)."""
    name, link, loads, chosen, levels, size, order, body_load_near_holes, member_pairs = task
    start = time.perf_counter()
    if not len(chosen):
        return name, None, "no feasible position to compare", 0.0
    try:
        stations = choose_stations(link, loads.frame_joints, members=member_pairs)
        members = link_members(link, loads.frame_joints, member_pairs)
        mesh = replace(default_mesh(link, loads.frame_joints, stations.x, size, members), order=order)
        if order == 1 and size is None:
            mesh = mesh.refined(LINEAR_REFINEMENT)
        comparison = compare_link(
            name, link, loads, chosen, mesh, levels, stations.x, body_load_near_holes, stations.note, members,
        )
        return name, comparison, "", time.perf_counter() - start
    except (FEAError, GeometryError) as error:
        return name, None, str(error), time.perf_counter() - start


def _progress(items, total: int):
    """A progress bar over the links on a terminal (tqdm); silent otherwise."""
    return tqdm(items, total=total, desc="FEA", unit="link", disable=not sys.stderr.isatty())
