"""``linkstress validate SCENE [--json OUT] [--html OUT] [--vtu DIR]``: beam sections against
plane-stress FEA of every profiled link of a scene, under the same loads.

Exit 0 when the check passes, 1 when it fails (a link's FEA could not run, its support reactions are
not ~0, or its section resultants disagree with the beam's), 2 on bad input. Convergence is reported
beside the check, not judged by it: a peak that moved more than 5 % over either of the last two
refinements is named NOT converged and gives no safety factor; with ``--mesh-levels 1`` convergence is "not
checked" and no safety factor is given either.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from linkstress.analysis import plan_for
from linkstress.errors import InputError
from linkstress.output import check_folder, write_json, write_text
from linkstress.scene import load_scene


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
    )
    parser.add_argument("scene", type=Path, metavar="SCENE", help="scene file (TOML)")
    parser.add_argument("--json", type=Path, metavar="OUT", help="write DESIGN.md's validate JSON to OUT")
    parser.add_argument("--html", type=Path, metavar="OUT", help="write a self-contained HTML report to OUT")
    parser.add_argument("--vtu", type=Path, metavar="DIR", help="write the FEA fields (VTU + PVD per link) into DIR")
    parser.add_argument("--positions", type=int, default=None, metavar="N",
                        help="compare at most N feasible positions of a sweep (default 36)")
    parser.add_argument("--mesh-levels", type=int, default=3, metavar="L",
                        help="mesh refinement levels per link: 3 or more for a convergence study, 1 for one mesh")
    parser.add_argument("--mesh-size", type=float, default=None, metavar="M",
                        help="element size away from holes and cuts [m] (default: from the link's depth)")
    parser.add_argument("--jobs", type=int, default=1, metavar="N", help="solve N links at once in parallel processes")
    parser.add_argument("--explain", action="store_true", help="print what would be computed, and stop")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_folder(args.json, "--json")
    check_folder(args.html, "--html")
    if args.vtu is not None and args.vtu.exists() and not args.vtu.is_dir():
        raise InputError(f"--vtu: {str(args.vtu)!r} exists and is not a folder")
    if args.mesh_levels not in (1,) and args.mesh_levels < 3:
        raise InputError("--mesh-levels: use 1 (one mesh) or 3 and more (a refinement study)")
    if args.positions is not None and args.positions < 1:
        raise InputError("--positions: must be at least 1")
    if args.mesh_size is not None and not args.mesh_size > 0:
        raise InputError("--mesh-size: must be > 0 m")
    if args.jobs < 1:
        raise InputError("--jobs: must be at least 1")
    # The FEA stack (gmsh, scikit-fem) loads only when a validation runs.
    from linkstress.validation.report import validation_html, validation_json, validation_text
    from linkstress.validation.validate_scene import MAX_POSITIONS, validate_scene

    scene = load_scene(args.scene)
    plan = plan_for(scene)
    if args.explain:
        print(plan.describe())
        return 0
    if not plan.validate:
        raise InputError(
            f"{args.scene.name}: no link to validate: the FEA needs links drawn in a sketch with a thickness and "
            "a material (density, youngs_modulus, poisson_ratio), and joint forces (mass data for every moving link)"
        )
    result = validate_scene(scene, plan, args.positions or MAX_POSITIONS, args.mesh_levels, args.mesh_size, args.jobs)
    print(validation_text(result))
    # Every output is made before any is written, so a failure leaves none half-done.
    document = validation_html(result) if args.html is not None else None
    if args.json is not None:
        write_json(args.json, validation_json(result))
    if document is not None:
        write_text(args.html, document)
    if args.vtu is not None:
        args.vtu.mkdir(parents=True, exist_ok=True)
        for name, comparison in result.comparisons.items():
            comparison.fea.write_vtu(args.vtu / name)
    return 1 if result.failures() else 0
