"""``linkstress bench [--json OUT] [--html OUT] [--markdown OUT] [--quick]``: speed against error of every stress
method, throughput, FEA memory, the hard cases and the FEA peaks by superposition of unit loads, in
one run (``linkstress.validation.bench.suite``).

Exit 0 when every error stays under its bound, 1 when one does not; times are reported, never
checked. ``--quick`` measures fewer settings (seconds, for CI); the full run takes minutes.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from linkstress.commands import HelpFormatter, examples
from linkstress.output import check_outputs, json_bytes, write_all


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "bench",
        help="speed against error of the beam engine, the original strip sums and P1/P2 FEA",
        description=(
            "Time the beam engine at several station counts, the original program's strip sums at dx = 1e-2, "
            "1e-3, 1e-4 m and plane-stress FEA (P1 and P2) at several mesh sizes on the seed's ANSYS four-bar "
            "and a curved-link four-bar; compare each with the Richardson-extrapolated finest FEA; mark the "
            "Pareto front. Also: positions per second of kinematics, joint forces and section stresses over "
            "sweeps, the FEA's peak memory, and the beam against FEA on hard cases (near toggle, change point, "
            "slender, stubby, hole close to the edge), and FEA peaks by superposition of unit loads against direct "
            "FEA on the same mesh, with the seed's 360-position sweep with peaks timed against one validate at one "
            "position. Checks errors against their bounds, never times."
        ),
        epilog=examples("linkstress bench --quick", "linkstress bench --json bench.json --html bench.html",
                        "linkstress bench --markdown docs/benchmarks.md --json docs/benchmarks.json"),
        formatter_class=HelpFormatter,
    )
    parser.add_argument("--json", type=Path, metavar="OUT", help="write the figures as JSON to OUT")
    parser.add_argument("--html", type=Path, metavar="OUT", help="write a self-contained HTML report to OUT")
    parser.add_argument("--markdown", type=Path, metavar="OUT",
                        help="write the figures as a Markdown page to OUT (docs/benchmarks.md is written this way)")
    parser.add_argument("--quick", action="store_true", help="fewer settings, for CI (well under a minute)")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_outputs({"--json": args.json, "--html": args.html, "--markdown": args.markdown})
    # The FEA stack (gmsh, scikit-fem) loads only when the bench runs.
    from linkstress.validation.bench.markdown import bench_markdown
    from linkstress.validation.bench.report import bench_html, bench_json, bench_text
    from linkstress.validation.bench.suite import FULL, QUICK, run_bench

    result = run_bench(QUICK if args.quick else FULL, progress=lambda message: print(f"bench: {message}", file=sys.stderr))
    print(bench_text(result))
    # Every output is made before any is written, so a failure leaves none half-done.
    figures = json_bytes(bench_json(result), "--json")
    files = []
    if args.json is not None:
        files.append((args.json, figures))
    if args.html is not None:
        files.append((args.html, bench_html(result).encode("utf-8")))
    if args.markdown is not None:
        # From the JSON as written, so that a page can be checked against the figures it came from.
        files.append((args.markdown, bench_markdown(json.loads(figures)).encode("utf-8")))
    write_all(files)
    return 1 if result.failures() else 0
