"""``linkstress analyze SCENE [--json OUT] [--html OUT] [--stations] [--explain]``: motion, joint forces and
section stresses of a scene's machine at every input position.

stdout: each mechanism's class (Grashof, Barker), toggles, feasible input range and limit
positions; the motion of every link; joint forces and the driving torque; the largest section
stress per link; the infeasible positions and why. ``--json`` writes DESIGN.md's ``analyze`` JSON
(see ``linkstress.report.records``); ``--explain`` prints what will be computed and stops.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from linkstress.analysis import plan_for, run_analysis
from linkstress.output import check_folder, write_json_stream, write_text
from linkstress.report.records import stream_position_records
from linkstress.report.text import report
from linkstress.scene import load_scene


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "analyze",
        help="motion, joint forces and section stresses of a scene's machine",
        description=(
            "Read a scene file (TOML) and report, at every input angle, each link's angle, angular "
            "velocity and acceleration and its centre of mass's acceleration, the joint forces and "
            "driving torque, and the largest beam-section von Mises stress of every link with a profile "
            "(ground frame, SI). Without an [analysis] table the scene gets everything its data allows."
        ),
    )
    parser.add_argument("scene", type=Path, metavar="SCENE", help="scene file (TOML)")
    parser.add_argument("--json", type=Path, metavar="OUT", help="also write the results as JSON to OUT")
    parser.add_argument(
        "--stations", action="store_true",
        help="add N, V, M and von Mises along every link (member frame) to the JSON",
    )
    parser.add_argument("--html", type=Path, metavar="OUT", help="also write a self-contained HTML report to OUT")
    parser.add_argument("--explain", action="store_true", help="print what would be computed, and stop")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_folder(args.json, "--json")
    check_folder(args.html, "--html")
    scene = load_scene(args.scene)
    plan = plan_for(scene)
    if args.explain:
        print(plan.describe())
        return 0
    result = run_analysis(scene, plan)
    print(report(result))
    # The HTML is made before any output is written and the JSON is written to a temporary file
    # renamed when complete, so a failure leaves no output half-done.
    document = None
    if args.html is not None:
        from linkstress.report.html import analysis_html  # matplotlib: half a second to import

        document = analysis_html(result)
    if args.json is not None:
        write_json_stream(args.json, "positions", stream_position_records(result, stations=args.stations))
    if document is not None:
        write_text(args.html, document)
    return 0
