"""Start-up cost of ``linkstress analyze`` of the seed against a bare ``import numpy``.

Runs the two commands alternately, ``--repeat`` times each, and prints the best wall time [s] of each
and their ratio. Best of N because the noise of a shared machine only ever adds time; alternated so
that a slow spell of the machine falls on both. The target of issue 20 is a ratio of at most 3.

    python -m linkstress.validation.bench.startup [--repeat 10]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

SEED = Path(__file__).resolve().parents[1] / "cases" / "seed_ansys_fourbar" / "scene.toml"
ANALYZE = [sys.executable, "-m", "linkstress", "analyze", str(SEED)]
NUMPY = [sys.executable, "-c", "import numpy"]
TARGET_RATIO = 3.0


def wall_time(command: list[str]) -> float:
    """Wall time [s] of one run of ``command``, its output discarded; a failure stops the benchmark."""
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def best_times(repeat: int) -> tuple[float, float]:
    """Best wall times [s] of analyze and of ``import numpy`` over ``repeat`` alternated runs each."""
    analyze, numpy = [], []
    for _ in range(repeat):
        analyze.append(wall_time(ANALYZE))
        numpy.append(wall_time(NUMPY))
    return min(analyze), min(numpy)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=10, help="runs of each command (default 10)")
    args = parser.parse_args()
    analyze, numpy = best_times(args.repeat)
    ratio = analyze / numpy
    print(f"linkstress analyze (seed): {analyze:.3f} s  (best of {args.repeat})")
    print(f"python -c 'import numpy':  {numpy:.3f} s  (best of {args.repeat})")
    print(f"ratio: {ratio:.2f} (target <= {TARGET_RATIO:g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
