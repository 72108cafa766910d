"""``linkstress regress [CASES_DIR] [--update] [--jobs N] [--scheduler ADDRESS] [--json OUT]``: re-run
every regression case and compare it with its stored reference: kinematics, forces and stresses
within their tolerances, beam-against-FEA errors no larger than stored and within the case's limits.
Exit 1 on any regression; 2 when a case cannot be read (its reference, its scene or a sketch the
scene names), naming the case, before any case runs. With a scheduler each case is a task on that Dask cluster, carried by
content (its scene, sketches and reference)."""

from __future__ import annotations

import argparse
import math
from functools import partial
from pathlib import Path

from linkstress.commands import HelpFormatter, examples
from linkstress.commands.fea_options import add_cache_options, fea_choices
from linkstress.commands.validate import check_jobs
from linkstress.errors import InputError
from linkstress.executors import LOCAL, SCHEDULER_VARIABLE, Retry, executor, scheduler_choice
from linkstress.output import check_outputs, json_bytes, write_all
from linkstress.validation.regression import (
    REFERENCE_FILE,
    CaseResult,
    check_case,
    find_cases,
    packed_case,
    read_reference,
    run_case,
    run_packed_case,
)
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
        epilog=examples(
            "linkstress regress",
            "linkstress regress validation/cases/six_bar --verbose",
            "linkstress regress --scheduler tcp://10.0.0.5:8786 --json regress.json",
        ),
        formatter_class=HelpFormatter,
    )
    parser.add_argument("cases", nargs="?", type=Path, metavar="CASES_DIR",
                        help="folder of cases, or one case folder (default: the shipped validation/cases)")
    parser.add_argument("--update", action="store_true", help="rewrite each case's reference from this run (stored numbers it reproduces to rounding are kept)")
    parser.add_argument("--jobs", type=int, default=1, metavar="N", help="run N cases in parallel processes")
    parser.add_argument("--verbose", action="store_true", help="list every check, not only each case's closest call")
    parser.add_argument(
        "--scheduler", metavar="ADDRESS",
        help="run each case as a task on the Dask cluster whose scheduler is at ADDRESS (tcp://HOST:PORT), sent by "
        f"content; {LOCAL}: a cluster of this machine's cores for this run; default: the {SCHEDULER_VARIABLE} "
        'variable, else this machine (--jobs). Needs pip install "linkstress[cluster]" (docs/cluster.md)',
    )
    parser.add_argument("--json", type=Path, metavar="OUT",
                        help="also write every case's checks (and any case a cluster ran again) as JSON to OUT; not with --update")
    add_cache_options(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    scheduler, source = scheduler_choice(args.scheduler)
    check_jobs(args.jobs, source)
    check_outputs({"--json": args.json}, [])
    if args.update and args.json is not None:
        raise InputError("--json: not with --update (which rewrites the references and checks nothing); run regress again after it")
    cases = find_cases(args.cases or default_cases())
    for case in cases:
        # a broken reference.json or a scene that cannot be read stops the run before any case runs
        read_reference(case)
        check_case(case)
    cache = fea_choices(args)
    with executor(scheduler, source, args.jobs) as where:
        if scheduler is None:
            results = list(progress(where.map(partial(run_case, update=args.update, cache=cache), cases), len(cases)))
        else:
            # A worker sees none of this machine's files: each case travels by content, and with
            # --update its new reference comes back to be written here.
            packed = [packed_case(case) for case in cases]
            work = partial(run_packed_case, update=args.update, cache=cache)
            outcomes = list(progress(where.map(work, packed, [c.name for c in cases]), len(cases)))
            results = [result for result, _ in outcomes]
            write_all([(case / REFERENCE_FILE, reference) for case, (_, reference) in zip(cases, outcomes) if reference is not None])
    if args.update:
        for r in results:
            print(f"{r.name}: {'reference rewritten' if not r.error else 'NOT updated: ' + r.error}")
        if where.retried:
            print(retried_lines(where.retried).lstrip("\n"))
        return 0 if all(not r.error for r in results) else 1
    print(report(results, args.verbose) + retried_lines(where.retried))
    if args.json is not None:
        write_all([(args.json, json_bytes(regress_json(results, scheduler, where.retried), "--json"))])
    return 0 if all(r.passed for r in results) else 1


def retried_lines(retried: list[Retry]) -> str:
    """One line per task a cluster ran again, and why ("" when none was)."""
    return "".join(f"\nretried: {r.task} ({r.reason})" for r in retried)


def regress_json(results: list[CaseResult], scheduler: str | None, retried: list[Retry]) -> dict:
    """docs/design.md's regress JSON: every case's verdict and checks, the scheduler that ran them
    (null: this machine) and the cases it ran again. A check's ``worst`` is null where it is not a
    number (a value the run no longer gives counts as infinitely far off)."""
    cases = [
        {
            "case": r.name, "passed": r.passed, "error": r.error,
            "checks": [
                {"what": c.what, "worst": _finite(c.worst), "allowed": float(c.allowed), "passed": c.passed, "detail": c.detail}
                for c in r.checks
            ],
        }
        for r in results
    ]
    return {"cases": cases, "scheduler": scheduler, "retried": [r.record() for r in retried]}


def _finite(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


def progress(items, total: int):
    """A progress bar on a terminal (tqdm), the plain items otherwise."""
    import sys

    from tqdm import tqdm

    return tqdm(items, total=total, desc="cases", unit="case", disable=not sys.stderr.isatty())


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

