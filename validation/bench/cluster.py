"""Regression cases on a Dask cluster of 1 and 2 local workers: scaling, per-task cost and overhead.

The cases are ``--cases`` copies of the shipped ones, cycled in name order (arc_coupler,
banana_coupler, bell_crank, seed_ansys_fourbar, six_bar, slider_crank_curved_rod,
textbook_fourbar, arc_coupler, ...), each copy in its own folder of a temporary directory and
named ``NAME_K``: the same work as the shipped case, checked against its own reference. Each run
goes through ``DaskExecutor`` as ``regress --scheduler`` does: every case packed by content and
unpacked on its worker.

Measured: the cases one after another in this process (no cluster); on a LocalCluster of 1 and of
2 worker processes (``linkstress.executors.local_cluster``: one thread each, glibc's own malloc
thresholds, warmed up: each worker has imported the FEA stack before the
clock starts); the round trip of an empty task, submitted and awaited one at a time; and the
scheduler's cost per task when ``--empty`` empty tasks are submitted at once. Printed as a table
with the projection for 10,000 cases on N workers:

    T(N) = n c / N + n o

with n the cases, c the per-case cost on one worker (the 1-worker wall time over the cases) and o
the per-task overhead of a batch of empty tasks (the scheduler handles tasks one at a time, so that
part does not shrink with N). It assumes every worker as fast as this machine's and the cases as
these.

    python -m linkstress.validation.bench.cluster [--cases 20] [--empty 1000]
"""

from __future__ import annotations

import argparse
import os
import pickle
import shutil
import sys
import tempfile
import time
from pathlib import Path

CASES = Path(__file__).resolve().parents[1] / "cases"
PROJECTED_CASES = 10_000
PROJECTED_WORKERS = (1, 10, 100)


def copied_cases(folder: Path, count: int) -> list[Path]:
    """``count`` copies of the shipped cases, cycled in name order, as ``folder/NAME_K``."""
    from linkstress.validation.regression import find_cases

    shipped = find_cases(CASES)
    copies = []
    for k in range(count):
        case = shipped[k % len(shipped)]
        copy = folder / f"{case.name}_{k // len(shipped)}"
        shutil.copytree(case, copy)
        copies.append(copy)
    return copies


def timed_case(packed) -> tuple[bool, float, float]:
    """A packed case run where it is sent: whether it passed, its wall and CPU time [s] there."""
    from linkstress.validation.regression import run_packed_case

    wall, cpu = time.perf_counter(), time.process_time()
    result, _ = run_packed_case(packed)
    return result.passed, time.perf_counter() - wall, time.process_time() - cpu


def nothing(value: int) -> int:
    """An empty task."""
    return value


def warm_up() -> None:
    """Import, on a worker, what a regression case uses (the FEA stack above all)."""
    import linkstress.validation.regression  # noqa: F401
    import linkstress.validation.validate_scene  # noqa: F401


def serial_seconds(cases: list[Path]) -> float:
    """Wall time [s] of the cases one after another in this process."""
    from linkstress.validation.regression import run_case

    warm_up()
    start = time.perf_counter()
    for case in cases:
        run_case(case)
    return time.perf_counter() - start


def cluster_seconds(cases: list[Path], workers: int, empty: int) -> dict[str, float]:
    """On a LocalCluster of ``workers`` processes: the cases' wall time [s] (``cases``), the sums of
    their wall and CPU times [s] inside the tasks (``task_wall``, ``task_cpu``), an empty task's
    round trip [s] one at a time (``round_trip``), and the time per task [s] of ``empty`` empty
    tasks submitted at once (``overhead``)."""
    from distributed import Client

    from linkstress.executors import DaskExecutor, local_cluster
    from linkstress.validation.regression import packed_case

    with local_cluster(workers) as cluster, Client(cluster) as client:
        client.run(warm_up)
        where = DaskExecutor(client, cluster.scheduler_address)
        start = time.perf_counter()
        results = list(where.map(timed_case, [packed_case(c) for c in cases], [c.name for c in cases]))
        seconds = time.perf_counter() - start
        failed = [c.name for c, (passed, _, _) in zip(cases, results) if not passed]
        if failed:
            raise SystemExit(f"cases failed on the cluster: {', '.join(failed)}")
        trips = 50
        start = time.perf_counter()
        for k in range(trips):
            client.submit(nothing, k, pure=False).result()
        round_trip = (time.perf_counter() - start) / trips
        start = time.perf_counter()
        client.gather(client.map(nothing, range(empty), pure=False))
        overhead = (time.perf_counter() - start) / empty
    return {
        "cases": seconds, "task_wall": sum(r[1] for r in results), "task_cpu": sum(r[2] for r in results),
        "round_trip": round_trip, "overhead": overhead,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=20, help="copies of the shipped cases to run (default 20)")
    parser.add_argument("--empty", type=int, default=1000, help="empty tasks for the per-task overhead (default 1000)")
    args = parser.parse_args()
    from linkstress.threads import cores
    from linkstress.validation.regression import packed_case

    # The machine's load before and after each run: on a shared machine, what the runs competed with.
    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory(prefix="linkstress-cluster-bench-") as folder:
        cases = copied_cases(Path(folder), args.cases)
        payload = sum(len(pickle.dumps(packed_case(c))) for c in cases) / len(cases)
        serial = serial_seconds(cases)
        loads.append(os.getloadavg()[0])
        one = cluster_seconds(cases, 1, args.empty)
        loads.append(os.getloadavg()[0])
        two = cluster_seconds(cases, 2, args.empty)
        loads.append(os.getloadavg()[0])
    n = len(cases)
    cost = one["cases"] / n
    overhead = max(one["overhead"], two["overhead"])
    print(f"{n} regression cases (copies of the shipped {', '.join(sorted({c.name.rsplit('_', 1)[0] for c in cases}))})")
    print(f"mean task payload (a case packed by content, pickled): {payload / 1e3:.0f} kB")
    print(f"cores: {cores()}; 1-minute load average before and after each run: {', '.join(f'{v:.1f}' for v in loads)}")
    print()
    print("| run | wall time [s] | per case [s] | speed-up over 1 worker | in the tasks: wall, CPU per case [s] |")
    print("|---|---:|---:|---:|---:|")
    print(f"| this process, one after another | {serial:.1f} | {serial / n:.2f} | | |")
    for label, run in (("1 worker", one), ("2 workers", two)):
        print(f"| LocalCluster, {label} | {run['cases']:.1f} | {run['cases'] / n:.2f} | {one['cases'] / run['cases']:.2f} | "
              f"{run['task_wall'] / n:.2f}, {run['task_cpu'] / n:.2f} |")
    print()
    print(f"empty task, one at a time (round trip): {1e3 * one['round_trip']:.2f} ms (1 worker), "
          f"{1e3 * two['round_trip']:.2f} ms (2 workers)")
    print(f"empty tasks, {args.empty} at once: {1e3 * one['overhead']:.2f} ms per task (1 worker), "
          f"{1e3 * two['overhead']:.2f} ms (2 workers)")
    print()
    print(f"projection for {PROJECTED_CASES} cases: T(N) = n c / N + n o, c = {cost:.2f} s, o = {1e3 * overhead:.2f} ms")
    print("| workers N | projected wall time |")
    print("|---:|---:|")
    for workers in PROJECTED_WORKERS:
        total = PROJECTED_CASES * cost / workers + PROJECTED_CASES * overhead
        print(f"| {workers} | {total:.0f} s ({total / 3600:.2f} h) |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
