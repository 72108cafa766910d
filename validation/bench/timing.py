"""Wall-clock timing for the benchmark scripts: best of several runs (shared machines are noisy;
compare ratios measured in one run, never a time against a bound in a test)."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_run(work: Callable[[], object], repeat: int = 7) -> tuple[float, object]:
    """Best wall time [s] of ``repeat`` runs of ``work()``, and the last run's value."""
    times, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = work()
        times.append(time.perf_counter() - start)
    return min(times), value


def best_time(work: Callable[[], object], repeat: int = 7) -> float:
    """Best wall time [s] of ``repeat`` runs of ``work()``."""
    return best_run(work, repeat)[0]
