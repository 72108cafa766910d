"""Start-up cost of ``linkstress analyze`` of the seed against a bare ``import numpy``.

Runs the two commands alternately, ``--repeat`` times each, and prints the best wall time [s] of
each, their ratio and whether it meets the target (at most 3), then where analyze's time goes:
the interpreter, numpy, linkstress's other imports, reading the scene and its sketches, the
analysis and the report. Best of N because the noise of a shared machine only ever adds time;
alternated so that a slow spell of the machine falls on both.

Both are timed twice: as this environment runs them, and with bytecode cached (in a temporary
folder, warmed by one run) as an installed package has it. They differ where bytecode is not
written (``PYTHONDONTWRITEBYTECODE``, a read-only checkout): then every run compiles linkstress's
sources again (about 0.1 s), unless ``python -m compileall src importers validation`` wrote it once.

    python -m linkstress.validation.bench.startup [--repeat 10]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SEED = Path(__file__).resolve().parents[1] / "cases" / "seed_ansys_fourbar" / "scene.toml"
ANALYZE = [sys.executable, "-m", "linkstress", "analyze", str(SEED)]
NUMPY = [sys.executable, "-c", "import numpy"]
TARGET_RATIO = 3.0
PHASES = """
import time
start = time.perf_counter()
import json, sys
import numpy
numpy_done = time.perf_counter()
from linkstress.analysis import plan_for, run_analysis
from linkstress.report.text import report
from linkstress.scene import load_scene
imports_done = time.perf_counter()
scene = load_scene(sys.argv[1])
read_done = time.perf_counter()
result = run_analysis(scene, plan_for(scene))
analysis_done = time.perf_counter()
report(result)
report_done = time.perf_counter()
print(json.dumps({"numpy": numpy_done - start, "imports": imports_done - numpy_done, "read": read_done - imports_done,
                  "analysis": analysis_done - read_done, "report": report_done - analysis_done}))
"""
"""analyze's steps, each timed in the process: numpy, the other imports, the scene and its sketches,
the analysis, the text report."""


def wall_time(command: list[str], env: dict[str, str]) -> float:
    """Wall time [s] of one run of ``command``, its output discarded; a failure stops the benchmark."""
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, env=env)
    return time.perf_counter() - start


def best_times(repeat: int, env: dict[str, str]) -> tuple[float, float]:
    """Best wall times [s] of analyze and of ``import numpy`` over ``repeat`` alternated runs each."""
    analyze, numpy = [], []
    for _ in range(repeat):
        analyze.append(wall_time(ANALYZE, env))
        numpy.append(wall_time(NUMPY, env))
    return min(analyze), min(numpy)


def phases(repeat: int, env: dict[str, str]) -> tuple[float, dict[str, float]]:
    """The best wall time [s] of a bare interpreter (``python -c pass``), and analyze's steps [s] in
    the run where they sum least."""
    bare = min(wall_time([sys.executable, "-c", "pass"], env) for _ in range(repeat))
    runs = [json.loads(subprocess.run([sys.executable, "-c", PHASES, str(SEED)], check=True, capture_output=True,
                                      text=True, env=env).stdout) for _ in range(repeat)]
    return bare, min(runs, key=lambda run: sum(run.values()))


def bytecode_written() -> bool:
    """Whether linkstress's modules have bytecode beside their sources (else each run compiles them)."""
    source = importlib.util.find_spec("linkstress.analysis").origin
    return Path(importlib.util.cache_from_source(source)).exists()


def cached_bytecode(folder: str) -> dict[str, str]:
    """An environment whose bytecode lives in ``folder``, warmed by one run of each command."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPYCACHEPREFIX"] = folder
    for command in (ANALYZE, NUMPY, [sys.executable, "-c", PHASES, str(SEED)]):
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL, env=env)
    return env


def print_times(label: str, repeat: int, env: dict[str, str]) -> None:
    analyze, numpy = best_times(repeat, env)
    ratio = analyze / numpy
    print(label)
    print(f"  linkstress analyze (seed): {analyze:.3f} s  (best of {repeat})")
    print(f"  python -c 'import numpy':  {numpy:.3f} s  (best of {repeat})")
    print(f"  ratio: {ratio:.2f}, target <= {TARGET_RATIO:g}: {'met' if ratio <= TARGET_RATIO else 'NOT met'}")
    bare, steps = phases(repeat, env)
    print(f"  where analyze's time goes (steps timed inside the process, best run): interpreter {bare:.3f} s "
          f"(python -c pass), numpy {steps['numpy']:.3f} s, other imports {steps['imports']:.3f} s, "
          f"scene and sketches {steps['read']:.3f} s, analysis {steps['analysis']:.3f} s, "
          f"report {steps['report']:.3f} s")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=10, help="runs of each command (default 10)")
    args = parser.parse_args()
    if args.repeat < 1:
        parser.error(f"--repeat: give at least 1 run, got {args.repeat}")
    compiled = "PYTHONDONTWRITEBYTECODE" in os.environ and not bytecode_written()
    print_times("as this environment runs it" + (" (PYTHONDONTWRITEBYTECODE set, no bytecode beside the sources: "
                                                 "linkstress compiles them every run)" if compiled else ""),
                args.repeat, dict(os.environ))
    with tempfile.TemporaryDirectory(prefix="linkstress-bytecode-") as folder:
        print_times("with bytecode cached, as an installed package runs it", args.repeat, cached_bytecode(folder))
    return 0


if __name__ == "__main__":
    sys.exit(main())
