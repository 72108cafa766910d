"""Validate a scene: every link the plan names is solved by FEA under its kinetic loads and compared
with the beam sections (``compare``), along each of its members. A link that cannot be meshed or solved gets an error entry
with the reason; the others still finish.

A link fails the check when its FEA support reactions are not ~0 (the kinetics' loads are not in
equilibrium), its section resultants differ from the beam's by more than RESULTANT_LIMIT (the
two engines disagree on the loads), or its nominal von Mises (a section depth from pins and
junctions, where beam theory is meant to hold) differs from the FEA's by more than NOMINAL_LIMIT
(the beam's stress is wrong where it claims to be right). The peak is reported, not judged: beam
theory does not see the stress raisers it measures. Nor does convergence fail the check: a peak
that has not converged is named beside the check's verdict (``unconverged``) and gives no safety
factor. A comparison that cannot be made (a member whose every cut passes through a hole) is not
checked and is listed as such (``not_compared``); it never stops the rest.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray
from tqdm import tqdm

from linkstress.analysis import AnalysisResult, Plan, run_analysis, scene_link_members, used_joints
from linkstress.errors import GeometryError
from linkstress.executors import DaskExecutor, LocalExecutor
from linkstress.scene import Scene
from linkstress.validation.compare import (
    LinkBeams,
    LinkComparison,
    LinkFEA,
    comparison_mesh,
    join_link_fea,
    link_beams,
    link_comparison,
    solve_compared,
)
from linkstress.validation.fea.cache import CacheSettings, open_cache
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.mesh import MeshSettings
from linkstress.validation.fea.plane_stress import SOLVE_COLUMNS
from linkstress.validation.stations import choose_stations, default_mesh

REACTION_LIMIT = 1e-4
"""Largest support reaction, relative to the applied load, for loads in equilibrium. Not zero: the
mesh follows exact arcs and splines where the kinetics used the drawing's flattened outline, so the
body forces differ by the relative area between the two (about 1e-5 on curved links); a wrong load
in the kinetics leaves a reaction of order 1."""
RESULTANT_LIMIT = 0.01
"""Largest section-resultant difference between beam and FEA (relative) before the check fails."""
NOMINAL_LIMIT = 0.05
"""Largest nominal von Mises difference between beam and FEA, relative to the largest beam value at
the member's nominal stations, before the check fails. Nominal stations start one section depth
from a pin, where the bearing pressure's disturbance has not quite died out: measured on a straight
bar 20 mm deep (tests/test_validate_checks.py), a station exactly one depth from an 8 mm pin hole
is 4.2 % off, those 1.67 depths away within 0.3 % (beside 4 mm holes 0.9 % at one depth); the
shipped cases' stored references are within 1.7 %. Where the beam is wrong where it claims to hold
the difference is well beyond: 29 % at the midpoint of a 40 mm crank, one depth from both of its
12 mm pins, whose fields overlap there (tests/test_validate_story.py)."""
LINEAR_REFINEMENT = 2.25
"""Linear (P1) elements get meshes this much finer than the default sizes (two of the study's
refinement steps) unless the scene gives a mesh size. Measured by ``linkstress bench`` (docs/benchmarks.md,
"Speed against error"): on the default meshes P1's nominal error is several times P2's and its cut
resultants miss the RESULTANT_LIMIT check on the seed case."""
MAX_POSITIONS = 36
MIN_BLOCK = 64
"""Fewest positions in a block when a link's positions are split to fill idle workers: each block
meshes and factorises its link anew, which cost as much as about 110 positions' solves on the
six_bar coupler (1.7 s for its three meshes against 0.0155 s per position)."""
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
    skipped: dict[str, str] = field(default_factory=dict)
    """Links of the default plan left out, and why (a guide whose block does not run in a closed slot)."""

    def failures(self) -> list[str]:
        """What fails the check, one line each (empty when everything passes)."""
        lines = [f"{name}: FEA failed: {message}" for name, message in self.errors.items()]
        angles = np.asarray(self.analysis.scene.motion.angle_deg, float)[self.positions]
        for name, c in self.comparisons.items():
            if (c.fea.reaction_ratio > REACTION_LIMIT).any():
                lines.append(
                    f"{name}: FEA support reactions reach {c.fea.reaction_ratio.max():.3g} of the applied "
                    "load: the kinetic loads on this link are not in equilibrium"
                )
            if c.resultant_error is not None and (c.resultant_error > RESULTANT_LIMIT).any():
                lines.append(
                    f"{name}: section resultants differ by {100 * c.resultant_error.max():.3g} % between beam "
                    f"and FEA (limit {100 * RESULTANT_LIMIT:g} %)"
                )
            worst = c.worst_nominal()
            if worst is not None and worst.error > NOMINAL_LIMIT:
                lines.append(
                    f"{name}: nominal von Mises differs by {100 * worst.error:.3g} % between beam and FEA (limit "
                    f"{100 * NOMINAL_LIMIT:g} %), worst at input angle {angles[worst.position]:.6g} deg on member joints "
                    f"{worst.joints[0]}-{worst.joints[1]}, s = {worst.s:.4g} m: beam {worst.beam / 1e6:.4g} MPa, FEA "
                    f"{worst.fea / 1e6:.4g} MPa; beam theory is off where it is meant to hold"
                )
        return lines

    def checked(self) -> str:
        """What the check judges, with its limits, in one phrase."""
        return (
            f"FEA support reactions below {REACTION_LIMIT:g} of the load, section resultants within "
            f"{100 * RESULTANT_LIMIT:g} % and nominal von Mises within {100 * NOMINAL_LIMIT:g} % of the beam's"
        )

    def not_compared(self) -> list[str]:
        """The comparisons that could not be made and were not checked, one line each, per link
        and member (a member whose every cut passes through a hole), saying why."""
        return [s.note for c in self.comparisons.values() for s in c.skipped]

    def not_compared_names(self) -> list[str]:
        """The members of ``not_compared``, named short ("coupler member 0-1")."""
        return [f"{name} member {s.joints[0]}-{s.joints[1]}" for name, c in self.comparisons.items() for s in c.skipped]

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


def position_blocks(count: int, links: int, workers: int, size: int | None = None) -> list[NDArray[np.intp]]:
    """Blocks (indices into a link's ``count`` compared positions, in order) to solve as separate
    tasks: of ``size`` positions if given, else one block when the ``links`` fill the ``workers``,
    else as many as give each link its share of the idle workers, of at least MIN_BLOCK positions.
    A size is rounded up to a multiple of SOLVE_COLUMNS, so the blocks' results join into those of
    one solve bit for bit."""
    if size is None:
        size = count if links >= workers else max(MIN_BLOCK, math.ceil(count / (workers // links)))
    size = max(SOLVE_COLUMNS, math.ceil(size / SOLVE_COLUMNS) * SOLVE_COLUMNS)
    return [np.arange(k, min(k + size, count)) for k in range(0, count, size)] or [np.arange(0)]


@dataclass(frozen=True)
class LinkWork:
    """One link's side of a validation made here: its ``beams`` and its ``mesh`` (cuts included) at
    the compared positions; ``seconds`` spent on them."""

    beams: LinkBeams
    mesh: MeshSettings
    seconds: float


def validate_scene(
    scene: Scene,
    plan: Plan,
    positions: int = MAX_POSITIONS,
    levels: int = 3,
    mesh_size: float | None = None,
    jobs: int = 1,
    executor: LocalExecutor | DaskExecutor | None = None,
    block: int | None = None,
    cache: CacheSettings | None = None,
) -> ValidationResult:
    """Analyse ``scene`` and compare every link of ``plan.validate`` with its FEA at up to
    ``positions`` feasible positions, with the elements of the scene's ``[analysis] element_order``
    (default 2); ``levels`` >= 3 makes each a mesh refinement study. The beams are sectioned here;
    each link's FEA runs as tasks of ``executor`` (default: ``jobs`` local processes when > 1, else
    here), one per block of its positions (``position_blocks``: ``block`` positions each, or as the
    executor's workers call for), and the blocks are joined into what one solve gives; each task
    takes its meshes from and into the disk cache of ``cache`` when given. A progress bar shows on
    a terminal."""
    analysis = run_analysis(scene, plan)
    chosen = compared_positions(analysis, positions)
    skipped = {} if scene.analysis is not None and scene.analysis.validate else _without_fea(analysis, chosen)
    if skipped:
        plan = replace(plan, validate=tuple(n for n in plan.validate if n not in skipped))
        analysis = replace(analysis, plan=plan)
    size = mesh_size or (scene.analysis.mesh_size if scene.analysis is not None else None)
    order = scene.analysis.element_order if scene.analysis is not None else 2
    where = executor or LocalExecutor(jobs)
    errors: dict[str, str] = {}
    work: dict[str, LinkWork] = {}
    for name in plan.validate:
        try:
            work[name] = _link_work(scene, plan, analysis, name, chosen, size, order)
        except (FEAError, GeometryError) as error:
            errors[name] = str(error)
    blocks = position_blocks(len(chosen), len(work), where.workers, block)
    tasks, labels, owners = [], [], []
    for name, w in work.items():
        loads, points = analysis.forces.link_loads[name].at(chosen), w.beams.nominal_points()
        for rows in blocks:
            tasks.append((scene.links[name].profile, loads.at(rows), w.mesh, w.beams.at(rows), points, levels, cache))
            labels.append(f"link {name}" if len(blocks) == 1 else f"link {name}, positions {chosen[rows[0]]}-{chosen[rows[-1]]}")
            owners.append(name)
    outcomes: dict[str, list] = {name: [] for name in work}
    for name, outcome in zip(owners, _progress(where.map(_solve_block, tasks, labels), len(tasks))):
        outcomes[name].append(outcome)
    comparisons, seconds = {}, {}
    for name, w in work.items():
        failed = [message for _, message, _ in outcomes[name] if message]
        seconds[name] = w.seconds + sum(elapsed for _, _, elapsed in outcomes[name])
        if failed:
            errors[name] = failed[0]
            continue
        try:
            fea = join_link_fea([part for part, _, _ in outcomes[name]])
        except FEAError as error:
            errors[name] = str(error)
            continue
        comparisons[name] = link_comparison(name, chosen, w.beams, fea)
    ordered = {name: errors[name] for name in plan.validate if name in errors}
    return ValidationResult(analysis, chosen, comparisons, ordered, {name: seconds.get(name, 0.0) for name in plan.validate},
                            skipped)


def _without_fea(analysis: AnalysisResult, chosen: NDArray[np.intp]) -> dict[str, str]:
    """The guides of ``analysis.plan.validate`` whose block does not stay inside a closed slot of
    theirs at the positions ``chosen``: the FEA has no wall to bear it on (``fea.loads``)."""
    from linkstress.loads import contacts_in_slots

    out = {}
    for name in analysis.plan.validate:
        if name not in analysis.plan.guides or analysis.forces is None:
            continue
        loads = analysis.forces.link_loads[name]
        outline = analysis.scene.links[name].profile.local_outline(*loads.frame_joints)
        if not contacts_in_slots(outline, loads.at(chosen)):
            out[name] = "a slider's block slides along it outside a closed slot of it: no FEA bears it"
    return out


def _link_work(scene: Scene, plan: Plan, analysis: AnalysisResult, name: str, chosen: NDArray[np.intp],
               size: float | None, order: int) -> LinkWork:
    """Link ``name``'s beams at the ``chosen`` positions and its mesh settings (elements of ``order``,
    ``size`` [m] or the default); FEAError or GeometryError when it has nothing to compare."""
    start = time.perf_counter()
    if not len(chosen):
        raise FEAError("no feasible position to compare")
    link, loads = scene.links[name].profile, analysis.forces.link_loads[name]
    stations = choose_stations(link, loads.frame_joints, members=scene.links[name].members,
                               used_joints=used_joints(scene, name))
    members = scene_link_members(scene, name, loads.frame_joints)
    mesh = replace(default_mesh(link, loads.frame_joints, stations.x, size, members), order=order)
    if order == 1 and size is None:
        mesh = mesh.refined(LINEAR_REFINEMENT)
    selected = loads.at(chosen)
    beams = link_beams(link, selected, stations.x, plan.body_load_near_holes, stations.note, members)
    mesh = comparison_mesh(link, selected, beams, mesh, members)
    return LinkWork(beams, mesh, time.perf_counter() - start)


def _solve_block(task) -> tuple[LinkFEA | None, str, float]:
    """One block of a link's FEA, or why it could not run, and its time (top level: runs in a worker)."""
    link, loads, mesh, beams, points, levels, cache = task
    start = time.perf_counter()
    try:
        return solve_compared(link, loads, mesh, beams, points, levels, open_cache(cache)), "", time.perf_counter() - start
    except (FEAError, GeometryError) as error:
        return None, str(error), time.perf_counter() - start


def _progress(items, total: int):
    """A progress bar over the tasks on a terminal (tqdm); silent otherwise."""
    return tqdm(items, total=total, desc="FEA", unit="task", disable=not sys.stderr.isatty())
