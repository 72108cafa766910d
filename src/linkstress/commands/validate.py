"""``linkstress validate SCENE [--json OUT] [--html OUT] [--vtu DIR] [--details]``: beam sections
against plane-stress FEA of every profiled link of a scene, under the same loads; the verdict first
(``linkstress.validation.verdict``), then a compact comparison per link (``--details``: in full).

Exit 0 when the check passes, 1 when it fails (a link's FEA could not run, its support reactions are
not ~0, or its section resultants or nominal stresses disagree with the beam's beyond their bounds),
2 on bad input. Convergence is reported
beside the check, not judged by it: a peak that moved more than 5 % over either of the last two
refinements is named NOT converged and gives no safety factor; with ``--mesh-levels 1`` convergence is "not
checked" and no safety factor is given either.
"""

from __future__ import annotations

import argparse
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from linkstress.analysis import plan_for
from linkstress.commands import HelpFormatter, examples
from linkstress.commands.fea_options import add_cache_options, fea_choices
from linkstress.commands.analyze import check_work, refuse_non_finite, scene_sketches
from linkstress.errors import InputError
from linkstress.executors import SCHEDULER_VARIABLE, executor, scheduler_choice
from linkstress.output import check_outputs, json_bytes, write_all
from linkstress.scene import Scene, load_scene

MAX_MESH_LEVELS = 6
MAX_COMPARED_POSITIONS = 3600
MAX_ELEMENTS = 1_000_000
"""Triangles on a link's finest mesh: quadratic ones give about 4 million unknowns, some GB to factorise."""
JOBS_PER_PROCESSOR = 4


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "validate",
        help="check the beam-section stresses against plane-stress FEA of the same links",
        description=(
            "Analyse a scene, then mesh every link with a profile (or those its [analysis] validate list "
            "names) with gmsh, solve plane stress with scikit-fem under the same loads, and compare section "
            "resultants, nominal and peak von Mises. Each link is a three-level mesh refinement study unless "
            "--mesh-levels 1; each quantity's change over the last refinement is reported, and a safety factor "
            "is taken only from a peak that converged (within 5 %)."
        ),
        epilog=examples(
            "linkstress validate validation/cases/banana_coupler/scene.toml --positions 4",
            "linkstress validate validation/cases/seed_ansys_fourbar/scene.toml --json seed.json --vtu seed_fields",
            "linkstress validate validation/cases/six_bar/scene.toml --scheduler tcp://10.0.0.5:8786",
        ),
        formatter_class=HelpFormatter,
    )
    parser.add_argument("scene", type=Path, metavar="SCENE", help="scene file (TOML)")
    parser.add_argument("--json", type=Path, metavar="OUT", help="write docs/design.md's validate JSON to OUT")
    parser.add_argument("--html", type=Path, metavar="OUT", help="write a self-contained HTML report to OUT")
    parser.add_argument("--vtu", type=Path, metavar="DIR", help="write the FEA fields (VTU + PVD per link) into DIR")
    parser.add_argument("--positions", type=int, default=None, metavar="N",
                        help="compare at most N feasible positions of a sweep, evenly spread, first and last "
                        "included; a pose the sweep repeats (0 and 360 deg of a one-turn machine) counts once "
                        "(default 36)")
    parser.add_argument("--mesh-levels", type=int, default=3, metavar="L",
                        help="mesh refinement levels per link: 3 or more for a convergence study, 1 for one mesh")
    parser.add_argument("--mesh-size", type=float, default=None, metavar="M",
                        help="element size away from holes and cuts [m] (default: from the link's depth)")
    parser.add_argument("--jobs", type=int, default=1, metavar="N", help="run N FEA tasks at once in parallel processes")
    parser.add_argument(
        "--positions-per-task", type=int, default=None, metavar="N",
        help="solve each link's compared positions in tasks of N (rounded up to a multiple of 8), each meshing and "
        "factorising the link once; the results are the same as one task's. Default: a task per link, or, with more "
        "workers (--jobs, --scheduler) than links, blocks of at least 64 positions that fill them",
    )
    parser.add_argument(
        "--scheduler", metavar="ADDRESS",
        help="solve on the Dask cluster whose scheduler is at ADDRESS (tcp://HOST:PORT), a task per link or block of "
        "positions (--positions-per-task); "
        f"local: a cluster of this machine's cores for this run; default: the {SCHEDULER_VARIABLE} variable, else "
        'this machine (--jobs). Needs pip install "linkstress[cluster]" (docs/cluster.md)',
    )
    add_cache_options(parser)
    parser.add_argument(
        "--details", action="store_true",
        help="also print each link's comparison in full: every pin hole's estimate against the FEA, each member, "
        "the convergence of every quantity",
    )
    parser.add_argument("--explain", action="store_true", help="print what would be computed, and stop")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    outputs = {"--json": args.json, "--html": args.html}
    check_outputs(outputs, [args.scene])
    if args.vtu is not None and args.vtu.exists() and not args.vtu.is_dir():
        raise InputError(f"--vtu: {str(args.vtu)!r} exists and is not a folder")
    check_flags(args)
    # The FEA stack (gmsh, scikit-fem) loads only when a validation runs.
    from linkstress.validation.report import validation_html, validation_json, validation_text
    from linkstress.validation.validate_scene import MAX_POSITIONS, validate_scene
    from linkstress.validation.verdict import validation_verdict

    scene = load_scene(args.scene)
    check_outputs(outputs, scene_sketches(scene))
    plan = plan_for(scene)
    if args.explain:
        print(plan.describe())
        return 0
    if not plan.validate:
        raise InputError(
            f"{args.scene.name}: no link to validate: the FEA needs links drawn in a sketch with a thickness and "
            "a material (density, youngs_modulus, poisson_ratio), and joint forces (mass data for every moving link)"
        )
    check_materials(scene, plan.validate)
    check_meshes(scene, plan.validate, args.mesh_size, args.mesh_levels)
    check_work(scene, plan)
    scheduler, source = scheduler_choice(args.scheduler)
    cache = fea_choices(args)
    with executor(scheduler, source, args.jobs) as where, np.errstate(all="ignore"):
        result = validate_scene(
            scene, plan, args.positions or MAX_POSITIONS, args.mesh_levels, args.mesh_size, executor=where,
            block=args.positions_per_task, cache=cache,
        )
    refuse_non_finite(result.analysis)
    cluster = {} if scheduler is None else {"scheduler": scheduler, "retried": [r.record() for r in where.retried]}
    # Every output is made before any is written, so a failure leaves none half-done.
    files = []
    verdict = validation_verdict(result)
    if args.json is not None:
        files.append((args.json, json_bytes({**validation_json(result, verdict), **cluster}, "--json")))
    if args.html is not None:
        files.append((args.html, validation_html(result, verdict).encode("utf-8")))
    print(validation_text(result, args.details, verdict) + "".join(f"\nretried: {r.task} ({r.reason})" for r in where.retried))
    write_all(files)
    if args.vtu is not None:
        args.vtu.mkdir(parents=True, exist_ok=True)
        for name, comparison in result.comparisons.items():
            comparison.fea.write_vtu(args.vtu / name)
    return 1 if result.failures() else 0


def check_flags(args: argparse.Namespace) -> None:
    """The numeric flags, each within the limit this machine can carry out."""
    if args.mesh_levels != 1 and not 3 <= args.mesh_levels <= MAX_MESH_LEVELS:
        raise InputError(
            f"--mesh-levels: use 1 (one mesh) or 3 to {MAX_MESH_LEVELS} (a refinement study, each level finer than "
            f"the last), got {args.mesh_levels}"
        )
    if args.positions is not None and not 1 <= args.positions <= MAX_COMPARED_POSITIONS:
        raise InputError(f"--positions: must be 1 to {MAX_COMPARED_POSITIONS} (each is an FEA load case), got {args.positions}")
    if args.positions_per_task is not None and not 1 <= args.positions_per_task <= MAX_COMPARED_POSITIONS:
        raise InputError(
            f"--positions-per-task: must be 1 to {MAX_COMPARED_POSITIONS} (positions of a link solved as one task), "
            f"got {args.positions_per_task}"
        )
    if args.mesh_size is not None and not (math.isfinite(args.mesh_size) and args.mesh_size > 0):
        raise InputError(f"--mesh-size: must be a finite size > 0 m, got {args.mesh_size!r}")
    check_jobs(args.jobs, scheduler_choice(args.scheduler)[1])


def check_jobs(jobs: int, scheduler: str = "") -> None:
    """``--jobs``: 1 to JOBS_PER_PROCESSOR per processor (more processes only compete for them, and
    each holds its own FEA stack in memory); 1 when a scheduler is given (``scheduler``: the option or
    variable that gave it): the cluster's workers are the parallel processes then."""
    if scheduler and jobs != 1:
        raise InputError(f"--jobs: not with {scheduler} (the cluster's workers run the tasks in parallel); give one of them")
    most = JOBS_PER_PROCESSOR * (os.cpu_count() or 1)
    if not 1 <= jobs <= most:
        raise InputError(f"--jobs: must be 1 to {most} ({JOBS_PER_PROCESSOR} per processor of this machine), got {jobs}")


def check_materials(scene: Scene, names: tuple[str, ...]) -> None:
    """The FEA needs each link's elastic constants: missing ones are bad input, not a failed check."""
    for name in names:
        material = scene.links[name].material
        for key in ("youngs_modulus", "poisson_ratio"):
            if getattr(material, key) is None:
                raise InputError(
                    f"{scene.path.name}: materials.{material.name}.{key}: missing; the FEA of link {name!r} needs it "
                    "(e.g. youngs_modulus = 200e9 and poisson_ratio = 0.3 for steel)"
                )


def check_meshes(scene: Scene, names: tuple[str, ...], size: float | None, levels: int) -> None:
    """Refuse, before meshing, an element size coarser than a link's depth or one whose finest mesh
    would hold more than MAX_ELEMENTS triangles (estimated from the link's area)."""
    size = size or (scene.analysis.mesh_size if scene.analysis is not None else None)
    flag = "--mesh-size" if size is not None else "the default mesh size"
    for name in names:
        link = scene.links[name]
        mesh = finest_mesh(scene, name, size, levels)
        if size is not None and size > mesh.depth:
            raise InputError(
                f"{flag} (or [analysis] mesh_size_m): {size:g} m is larger than the depth of link {name!r}, {mesh.depth:.3g} m; "
                f"give at most that (the default is {mesh.default:.3g} m)"
            )
        if mesh.elements > MAX_ELEMENTS:
            raise InputError(
                f"--mesh-size / --mesh-levels: link {name!r} ({link.profile.area:.3g} m^2) would need about "
                f"{mesh.elements:.2g} elements of {mesh.finest:.3g} m on its finest mesh, more than the {MAX_ELEMENTS:.0e} "
                f"this tool meshes; give a size of at least {mesh.coarsest * math.sqrt(mesh.elements / MAX_ELEMENTS):.3g} m or fewer levels"
            )


@dataclass(frozen=True)
class FinestMesh:
    """A link's meshes estimated before meshing: its ``depth`` [m] (slenderest compared section),
    the ``default`` and ``coarsest`` element sizes [m], the ``finest`` after the study's refinements,
    and about how many ``elements`` that one holds (from the link's area)."""

    depth: float
    default: float
    coarsest: float
    finest: float
    elements: float


def finest_mesh(scene: Scene, name: str, size: float | None, levels: int) -> FinestMesh:
    """The estimate of link ``name``'s meshes for an element ``size`` [m] (None: the default) over a
    study of ``levels`` (the finest is REFINEMENT_RATIO^(levels - 1) finer)."""
    from linkstress.validation.stations import ELEMENTS_PER_DEPTH, comparison_stations, default_mesh
    from linkstress.validation.fea.convergence import REFINEMENT_RATIO
    from linkstress.validation.validate_scene import LINEAR_REFINEMENT

    order = scene.analysis.element_order if scene.analysis is not None else 2
    link = scene.links[name]
    stations = comparison_stations(link.profile, link.frame_joints)
    default = default_mesh(link.profile, link.frame_joints, stations).size
    coarsest = size or default
    if size is None and order == 1:
        coarsest /= LINEAR_REFINEMENT
    finest = coarsest / REFINEMENT_RATIO ** (levels - 1)
    elements = link.profile.area / (math.sqrt(3) / 4 * finest**2)
    return FinestMesh(default * ELEMENTS_PER_DEPTH, default, coarsest, finest, elements)
