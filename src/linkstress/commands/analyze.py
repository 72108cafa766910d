"""``linkstress analyze SCENE [--json OUT] [--table OUT.npz] [--html OUT] [--stations] [--accuracy F]
[--peaks | --beam-only] [--details] [--explain]``: motion, joint forces and section stresses of a
scene's machine at every input position, and the FEA peaks of the links whose governing stress beam
theory and the Kt tables cannot answer within the accuracy (``linkstress.model_choice``).

stdout: the verdict first (``linkstress.report.verdict``: per link the stress that governs it, where,
its safety factors and how far to trust it), the scene's warnings, each mechanism's class (Grashof,
Barker), toggles, feasible input range, limit positions and driving torque range, each link's
maxima, and the notes and infeasible positions; ``--details`` adds the motion, joint forces and
section stresses position by position. ``--json`` writes docs/design.md's ``analyze`` JSON (see
``linkstress.report.records``), ``--table`` the same per-position numbers as NumPy arrays in an .npz file
(``linkstress.report.table``); ``--explain`` prints what will be computed and stops.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from linkstress.analysis import PEAK_MESH_LEVELS, AnalysisResult, Plan, plan_for, run_analysis
from linkstress.commands import HelpFormatter, examples
from linkstress.commands.fea_options import add_cache_options, fea_choices
from linkstress.errors import InputError
from linkstress.executors import OPTION, SCHEDULER_VARIABLE, Retry, scheduler_choice
from linkstress.model_choice import DEFAULT_ACCURACY, NO_FEA, accuracy_problem
from linkstress.output import check_outputs, json_stream, write_all
from linkstress.report.records import links_record, stream_position_records, summary_record
from linkstress.report.table import check_table_name, table_stream
from linkstress.report.text import report
from linkstress.report.verdict import analysis_verdict
from linkstress.scene import Scene, load_scene

MEMORY_LIMIT = 6e9
"""Bytes a run may take: a workstation's share, leaving room for everything else it runs."""
# Measured on the seed four-bar (4 links, 3 stressed; peak RSS less the 0.1 GB of the loaded tool):
# 1e6 positions took 0.5 GB for kinematics, 1.3 GB with joint forces and 1.36-1.40 GB with section
# stresses at 101 stations, with or without --json: a sweep keeps per-position reductions, and the
# arrays along the links and the JSON records are made and written a block of positions at a time.
BYTES_PER_LINK_POSITION = {"kinematics": 110, "forces": 230}
BYTES_PER_STRESSED_LINK_POSITION = 60
UNIT_CASES_PER_LOAD = 37
"""Unit load cases a pin or point force can take at most: 36 bearing directions and a couple."""
NODES_PER_ELEMENT = {1: 0.5, 2: 2.0}
"""Nodes per triangle of a large mesh: vertices (about half the triangles) and, for P2, edges."""
PEAK_COPIES = 3
"""Arrays of nodes x 3 x unit cases held at once while the unit cases are solved and recovered."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "analyze",
        help="motion, joint forces and section stresses of a scene's machine",
        description=(
            "Read a scene file (TOML) and report, at every input angle, each link's angle, angular "
            "velocity and acceleration and its centre of mass's acceleration, the joint forces and "
            "driving torque, and the largest beam-section von Mises stress of every link with a profile "
            "(ground frame, SI); and, for each link whose governing stress beam theory and the pin-hole Kt "
            "estimates cannot answer within the accuracy (--accuracy, 5 % by default), its FEA peaks and fatigue "
            "over the sweep: the report says which model each link took and why. Without an [analysis] table the "
            "scene gets everything its data allows. "
            "A sweep [motion] input_angle_deg = {start, stop, num} is num angles from start to stop, both "
            "included: {start = 0.0, stop = 350.0, num = 36} is every 10 deg of a turn (stop = 360.0 with "
            "num = 37 repeats the pose at 0 deg)."
        ),
        epilog=examples(
            "linkstress analyze validation/cases/six_bar/scene.toml --html six.html",
            "linkstress analyze validation/cases/seed_ansys_fourbar/scene.toml --accuracy 0.02",
            "linkstress analyze validation/cases/bell_crank/scene.toml --beam-only",
            "linkstress analyze validation/cases/bell_crank/scene.toml --peaks",
            "linkstress analyze validation/cases/bell_crank/scene.toml --peaks --scheduler tcp://10.0.0.5:8786",
        ),
        formatter_class=HelpFormatter,
    )
    parser.add_argument("scene", type=Path, metavar="SCENE", help="scene file (TOML)")
    parser.add_argument("--json", type=Path, metavar="OUT", help="also write the results as JSON to OUT")
    parser.add_argument(
        "--table", type=Path, metavar="OUT.npz",
        help="also write the JSON's per-position numbers as named NumPy arrays to OUT.npz, one per quantity with the "
        "positions along its first axis (np.load(OUT) in a notebook; docs/design.md, \"The table\"): for long sweeps, "
        "a fraction of the JSON's size and time",
    )
    parser.add_argument(
        "--stations", action="store_true",
        help="add N, V, M and von Mises along every link (member frame) to the JSON",
    )
    parser.add_argument("--html", type=Path, metavar="OUT", help="also write a self-contained HTML report to OUT")
    parser.add_argument(
        "--accuracy", type=float, metavar="FRACTION",
        help="the governing stress of every link within this fraction (default: [analysis] accuracy, else "
        f"{DEFAULT_ACCURACY:g}, i.e. {100 * DEFAULT_ACCURACY:g} %%): each link takes beam sections, with the pin-hole "
        "Kt estimates where they answer within it, and the FEA peaks where they do not (a pin hole outside the Kt "
        "tables, a couple through a pin, a junction, a bend, a fillet); the report says which model and why",
    )
    fea = parser.add_mutually_exclusive_group()
    fea.add_argument(
        "--peaks", action="store_true",
        help="the FEA peak stress of every stressed link at every position, whatever its model (unit load cases "
        "superposed, one mesh and factorisation per link) and, where its material gives endurance_limit and "
        "ultimate_strength, its fatigue safety factor over the sweep; as [analysis] peaks = true",
    )
    fea.add_argument(
        "--beam-only", action="store_true",
        help="no FEA at all: beam sections and pin-hole estimates only, fast; the verdict says what they do not cover",
    )
    parser.add_argument(
        "--scheduler", metavar="ADDRESS",
        help="compute the FEA peaks on the Dask cluster whose scheduler is at ADDRESS (tcp://HOST:PORT), a task per "
        f"link; local: a cluster of this machine's cores for this run; default: the {SCHEDULER_VARIABLE} variable "
        "(ignored when no peaks are computed). Not with --beam-only; needs "
        'pip install "linkstress[cluster]" (docs/cluster.md)',
    )
    add_cache_options(parser)
    parser.add_argument(
        "--details", action="store_true",
        help="also print the motion, joint forces and section stresses position by position, and the FEA peak details "
        "(the JSON and HTML carry them either way)",
    )
    parser.add_argument("--explain", action="store_true", help="print what would be computed, and stop")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    outputs = {"--json": args.json, "--html": args.html, "--table": args.table}
    check_outputs(outputs, [args.scene])
    check_table_name(args.table)
    scene = load_scene(args.scene)
    check_outputs(outputs, scene_sketches(scene))
    plan = command_plan(scene, args)
    if plan.peaks or args.peaks:
        check_peaks(scene, plan)
    if args.scheduler is not None and (plan.beam_only or not plan.stresses):
        raise InputError(
            f"{OPTION}: only the FEA peaks run on a cluster and this run computes none"
            + (" (--beam-only): leave out one of them" if plan.beam_only else
               ": add --peaks (or [analysis] peaks = true), or leave out --scheduler")
        )
    check_work(scene, plan)
    if args.explain:
        print(plan.describe())
        return 0
    retried: list[Retry] = []
    # Overflow is reported by refuse_non_finite, naming the keys, rather than as numpy warnings.
    with np.errstate(all="ignore"):
        result = run_analysis(scene, plan, peaks=False)
        links = plan.fea_links(result.models) if result.forces is not None else ()
        scheduler = None
        if links:
            from linkstress.validation.peaks_scene import stored_links

            cache = fea_choices(args)
            links = fea_ready(result, links, stored_links(scene, replace(plan, peaks=links), result.forces, cache))
        if links:
            # The variable alone is ignored without peaks: set for a shell, it must not stop a plain analyze.
            scheduler, source = scheduler_choice(args.scheduler)
            result, retried = analysis_with_peaks(result, links, scheduler, source, cache)
    refuse_non_finite(result)
    # Every output is staged before any is renamed into place, so a failure leaves none half-done; the
    # JSON is encoded into its staged file as its records are made, a block of positions at a time.
    files = []
    verdict = analysis_verdict(result)
    if args.json is not None:
        records = stream_position_records(result, stations=args.stations)
        cluster = {} if scheduler is None else {"scheduler": scheduler, "retried": [r.record() for r in retried]}

        def after() -> dict[str, object]:
            links = {"links": links_record(result)} if result.stresses else {}
            return {**links, **summary_record(result, verdict), **cluster}

        files.append((args.json, json_stream("positions", records, "--json", after)))
    if args.table is not None:
        files.append((args.table, table_stream(result)))
    if args.html is not None:
        from linkstress.report.html import analysis_html  # matplotlib: half a second to import

        files.append((args.html, analysis_html(result, verdict).encode("utf-8")))
    print(report(result, args.details, verdict) + "".join(f"\nretried: {r.task} ({r.reason})" for r in retried))
    write_all(files)
    return 0


def command_plan(scene: Scene, args: argparse.Namespace) -> Plan:
    """The scene's plan with the command line's --accuracy, --peaks and --beam-only."""
    plan = plan_for(scene)
    if args.accuracy is not None:
        if (problem := accuracy_problem(args.accuracy)) is not None:
            raise InputError(f"--accuracy: {problem}")
        plan = replace(plan, accuracy=args.accuracy)
    if args.peaks:
        plan = plan.with_peaks()
    if args.beam_only:
        plan = replace(plan, peaks=(), beam_only=True)
    return plan


def fea_ready(result: AnalysisResult, links: tuple[str, ...], stored: set[str]) -> tuple[str, ...]:
    """Of ``links`` (``Plan.fea_links``), those whose FEA peaks this run computes: those asked for
    (checked before the run), those whose result the cache holds (``stored``: checked when first
    computed), and those whose model is "fea-peaks" and that the FEA can take (elastic constants, a
    mesh this machine can carry). Where it cannot, the link's model reason says why and the link
    keeps its beam values (the verdict says what they do not cover)."""
    if result.plan.peaks:
        return links
    ready = []
    for name in links:
        try:
            if name not in stored:
                check_peaks(result.scene, replace(result.plan, peaks=(name,)))
        except InputError as error:
            chosen = result.models[name]
            result.models[name] = replace(chosen, reason=f"{chosen.reason}{NO_FEA}{error}")
            continue
        ready.append(name)
    return tuple(ready)


def analysis_with_peaks(
    result: AnalysisResult, links: tuple[str, ...], scheduler: str | None, source: str, cache=None
) -> tuple[AnalysisResult, list[Retry]]:
    """``result`` with the FEA peaks of ``links`` computed as tasks on this machine (``scheduler``
    None: in a process per core, at most one per link, since the links are independent and each
    runs on one thread) or on the Dask cluster at ``scheduler`` (named by ``source`` in messages),
    each using the disk ``cache`` (``CacheSettings``; None: none); the tasks it ran again."""
    import time

    from linkstress.executors import executor
    from linkstress.validation.peaks_scene import scene_peaks

    from linkstress.threads import cores

    plan = replace(result.plan, peaks=links)
    with executor(scheduler, source, min(cores(), len(links))) as where:
        start = time.perf_counter()
        peaks = scene_peaks(result.scene, plan, result.forces, where, cache)
        seconds = {**result.seconds, "peaks": time.perf_counter() - start}
    return replace(result, plan=plan, peaks=peaks, seconds=seconds), where.retried


def check_peaks(scene: Scene, plan: Plan) -> None:
    """FEA peaks need stressed links, each with elastic constants and a mesh this machine can carry."""
    from linkstress.commands.validate import check_materials, check_meshes, finest_mesh

    if not plan.peaks:
        raise InputError(
            f"{scene.path.name}: --peaks / [analysis] peaks: no link has section stresses; the FEA peaks need links "
            "drawn in a sketch with a thickness and a material, and joint forces (mass data for every moving link)"
        )
    check_materials(scene, plan.peaks)
    size = scene.analysis.mesh_size if scene.analysis is not None else None
    check_meshes(scene, plan.peaks, size, PEAK_MESH_LEVELS)
    order = scene.analysis.element_order if scene.analysis is not None else 2
    for name in plan.peaks:
        elements = finest_mesh(scene, name, size, PEAK_MESH_LEVELS).elements
        link = scene.links[name]
        cases = UNIT_CASES_PER_LOAD * (len(link.profile.joints) + len(scene.loads.forces)) + 4
        estimate = NODES_PER_ELEMENT[order] * elements * 3 * cases * 8 * PEAK_COPIES
        if estimate > MEMORY_LIMIT:
            raise InputError(
                f"{scene.path.name}: --peaks: link {name!r} would need about {estimate / 1e9:.3g} GB for its unit load "
                f"cases ({elements:.2g} elements, up to {cases} cases), more than the {MEMORY_LIMIT / 1e9:g} GB limit: "
                "give a coarser [analysis] mesh_size_m"
            )


def scene_sketches(scene: Scene) -> list[Path]:
    """The sketch files a scene reads (outputs must not overwrite them)."""
    return [link.sketch for link in scene.links.values() if link.sketch is not None]


# What feeds each computed quantity, for the message when one overflows.
KINEMATIC_KEYS = "the joints and motion.input_angle_deg / input_speed_rad_s / input_acceleration_rad_s2"
FORCE_KEYS = f"{KINEMATIC_KEYS}, the links' mass data or thickness and material density, and [loads]"
STRESS_KEYS = f"{FORCE_KEYS}, and the links' sketches"


def refuse_non_finite(result: AnalysisResult) -> None:
    """The last guard: a non-finite number at a feasible position is an ``InputError`` naming the
    quantity, the first such input angle and the keys that feed it (never a nan cell in a table)."""
    feasible = result.feasible
    for what, values, keys in _computed(result):
        bad = ~np.isfinite(values[feasible].reshape(int(feasible.sum()), -1)).all(axis=1)
        if bad.any():
            angle = result.scene.motion.angle_deg[feasible][bad.argmax()]
            raise InputError(
                f"{result.scene.path.name}: {what} overflowed (not a finite number) at input angle {angle:g} deg; "
                f"it comes from {keys}: bring them to the size of a real machine"
            )


def _computed(result: AnalysisResult):
    """(what, (P, ...) array, keys that feed it) for every computed per-position quantity."""
    for name, motion in result.kinematics.links.items():
        for label, values in (("angle", motion.angle), ("angular speed", motion.omega),
                              ("angular acceleration", motion.alpha), ("acceleration", motion.origin_acceleration)):
            yield f"the {label} of link {name!r}", values, KINEMATIC_KEYS
    if result.forces is not None:
        for name, mech in result.forces.mechanisms.items():
            for force, values in mech.forces.items():
                yield f"joint force {force} of mechanism {name!r}", values, FORCE_KEYS
            for label, values in (("driving torque", mech.driving_torque), ("driving force", mech.driving_force)):
                if values is not None:
                    yield f"the {label} of mechanism {name!r}", values, FORCE_KEYS
    for name, stress in result.stresses.items():
        yield f"the section von Mises stress of link {name!r}", stress.max_von_mises, STRESS_KEYS
    for name, peaks in result.peaks.items():
        yield f"the FEA peak von Mises stress of link {name!r}", peaks.peak, STRESS_KEYS


def check_work(scene: Scene, plan: Plan) -> None:
    """Refuse, before computing, a run whose arrays would not fit in MEMORY_LIMIT, stating the
    estimate and the limit."""
    estimate = memory_estimate(scene, plan)
    if estimate > MEMORY_LIMIT:
        positions, links = scene.motion.n_positions, len(scene.links)
        raise InputError(
            f"{scene.path.name}: {positions} positions of {links} links"
            + (f" with section stresses at {plan.stations} stations" if plan.stresses else "")
            + f" need about {estimate / 1e9:.3g} GB of memory, more than the {MEMORY_LIMIT / 1e9:g} GB limit: give fewer "
            "input angles (motion.input_angle_deg num) or [analysis] stations, ask for less in [analysis], "
            "or split the sweep"
        )


def memory_estimate(scene: Scene, plan: Plan) -> float:
    """Peak memory [bytes] of analysing ``scene`` by ``plan``, per link and position (the arrays
    along the links and the output records take a block of positions at a time, whatever the sweep)."""
    positions = scene.motion.n_positions
    per_link = BYTES_PER_LINK_POSITION["kinematics"] + (BYTES_PER_LINK_POSITION["forces"] if plan.forces else 0)
    return float(positions * (len(scene.links) * per_link + len(plan.stresses) * BYTES_PER_STRESSED_LINK_POSITION))
