"""``linkstress regress [CASES_DIR] [--update] [--jobs N]``: re-run every regression case and compare
it with its stored reference: kinematics, forces and stresses within their tolerances, beam-against-FEA
errors no larger than stored and within the case's limits. Exit 1 on any regression."""

from __future__ import annotations

import argparse
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from linkstress.commands import HelpFormatter, examples
from linkstress.commands.validate import check_jobs
from linkstress.validation.regression import CaseResult, find_cases, read_reference, run_case
from linkstress.tables import format_table

def default_cases() -> Path:
    """The shipped cases: in the source tree, or inside the installed package."""
    from linkstress import validation

    return Path(validation.__file__).resolve().parent / "cases"


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "regress",
        help="re-run the regression cases and compare with their stored references",
        description=(
            "Re-run every case (a folder with scene.toml, its sketches and reference.json) and compare "
            "with the stored reference; exit 1 on any regression. Point it at your own cases folder."
        ),
        epilog=examples("linkstress regress", "linkstress regress validation/cases/six_bar --verbose"),
        formatter_class=HelpFormatter,
    )
    parser.add_argument("cases", nargs="?", type=Path, metavar="CASES_DIR",
                        help="folder of cases, or one case folder (default: the shipped validation/cases)")
    parser.add_argument("--update", action="store_true", help="rewrite each case's reference from this run (stored numbers it reproduces to rounding are kept)")
    parser.add_argument("--jobs", type=int, default=1, metavar="N", help="run N cases in parallel processes")
    parser.add_argument("--verbose", action="store_true", help="list every check, not only each case's closest call")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_jobs(args.jobs)
    cases = find_cases(args.cases or default_cases())
    for case in cases:
        read_reference(case)  # a broken reference.json stops the run before any case runs
    if args.jobs > 1 and len(cases) > 1:
        with ProcessPoolExecutor(max_workers=args.jobs) as pool:
            results = list(pool.map(run_case, cases, [args.update] * len(cases)))
    else:
        results = [run_case(case, args.update) for case in progress(cases)]
    if args.update:
        for r in results:
            print(f"{r.name}: {'reference rewritten' if not r.error else 'NOT updated: ' + r.error}")
        return 0 if all(not r.error for r in results) else 1
    print(report(results, args.verbose))
    return 0 if all(r.passed for r in results) else 1


def progress(items):
    """A progress bar on a terminal (tqdm), the plain items otherwise."""
    import sys

    from tqdm import tqdm

    return tqdm(items, desc="cases", unit="case", disable=not sys.stderr.isatty())


def report(results: list[CaseResult], verbose: bool = False) -> str:
    """Every regression, and per case its closest call (worst / allowed); with ``verbose`` every check."""
    rows = []
    for r in results:
        if r.error:
            rows.append((r.name, "run", "", "", "ERROR", r.error))
            continue
        shown = r.checks if verbose else [c for c in r.checks if not c.passed] or [max(r.checks, key=lambda c: c.closeness)]
        for c in shown:
            rows.append((c.case, c.what, float(c.worst), float(c.allowed), "ok" if c.passed else "REGRESSION", c.detail))
    failed = [r.name for r in results if not r.passed]
    checks = sum(len(r.checks) for r in results)
    summary = f"{len(results) - len(failed)} of {len(results)} cases passed ({checks} checks)" + (
        f"; regressions in {', '.join(failed)}" if failed else ""
    )
    heading = "every check" if verbose else "regressions, else each case's closest call"
    return heading + "\n" + format_table(("case", "check", "worst", "allowed", "status", "detail"), rows) + "\n\n" + summary

