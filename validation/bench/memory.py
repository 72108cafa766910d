"""Benchmark: peak memory and time of ``linkstress analyze`` over long sweeps of the seed four-bar.

Run ``python -m linkstress.validation.bench.memory [--sizes 10000,100000,1000000]``. Prints
figures; asserts nothing. Each run is ``analyze`` on the seed scene (three links with section
stresses, 101 stations each) with ``[motion] input_angle_deg = {start, stop, num}`` of ``num``
positions, with and without ``--json``, in a fresh child process: its peak resident memory
(``resource.getrusage`` in the child, so one run's memory never counts in another's) and the time of
``analyze`` in it (the interpreter's start and imports left out). The analysis keeps per-position
reductions and the JSON is written block by block (``report.records.stream_position_records``), so
the peak grows with the sweep only by the kinematics, the joint forces and those reductions (about
1.3 kB per position); the target is under 2 GB at 1,000,000 positions with ``--json``.
The JSON file is written to a temporary folder and removed; its size is printed.

Measured on a shared two-core machine (load average in the hundreds, so the times are long): 1e4 positions 146 MB (6.5 s), with --json 157 MB (22 s); 1e5 269 MB (11.5 s), with
--json 276 MB (254 s, 521 MB of JSON); 1e6 1,398 MB (168 s), with --json 1,356 MB peak (35 min,
5.2 GB of JSON; ``/usr/bin/time -v``). When the sweep held its arrays along the links, 1e5 took 1,422 MB and 4,819 MB with --json.
Writing the JSON dominates a long sweep: ``json.dumps`` with indentation runs in Python, about
2 ms per position of the seed.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from linkstress.tables import format_table

SEED = Path(__file__).resolve().parents[1] / "cases" / "seed_ansys_fourbar" / "scene.toml"
SIZES = (10_000, 100_000, 1_000_000)

CHILD = """
import json, resource, sys, time
from contextlib import redirect_stdout
from io import StringIO
from linkstress.cli import main
start = time.perf_counter()
with redirect_stdout(StringIO()):
    code = main(sys.argv[1:])
seconds = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(json.dumps({"code": code, "seconds": seconds, "peak_bytes": peak}), file=sys.stderr)
"""
"""The child: ``linkstress analyze`` with its report kept off the terminal; ru_maxrss is in kB on Linux."""


@dataclass(frozen=True)
class Run:
    """One child's ``analyze``: exit code (minus the signal that ended a child killed before it
    could report, e.g. -9 from the system's out-of-memory killer), seconds [s] and peak resident
    memory [bytes] (None for a killed child) and the JSON file's size [bytes] (None without one)."""

    code: int
    seconds: float | None
    peak_bytes: int | None
    json_bytes: int | None


def seed_sweep_scene(folder: Path, positions: int, stop: float = 359.9) -> Path:
    """The seed scene over ``positions`` input angles from 0 to ``stop`` deg, written to ``folder``
    beside a copy of its sketch."""
    text = SEED.read_text()
    motion = f"input_angle_deg = {{ start = 0.0, stop = {stop!r}, num = {positions} }}"
    text, count = re.subn(r"^input_angle_deg = .*$", motion, text, flags=re.MULTILINE)
    if count != 1:
        raise RuntimeError(f"{SEED}: expected one input_angle_deg line, found {count}")
    for sketch in SEED.parent.glob("*.dxf"):
        shutil.copy(sketch, folder / sketch.name)
    scene = folder / f"seed_{positions}.toml"
    scene.write_text(text)
    return scene


def analyze_in_child(scene: Path, json_out: Path | None = None, *extra: str) -> Run:
    """``linkstress analyze scene [--json json_out] extra...`` in a fresh Python process."""
    args = ["analyze", str(scene), *([] if json_out is None else ["--json", str(json_out)]), *extra]
    done = subprocess.run([sys.executable, "-c", CHILD, *args], capture_output=True, text=True, check=False)
    lines = done.stderr.strip().splitlines()
    if done.returncode < 0:
        return Run(done.returncode, None, None, None)
    if not lines or not lines[-1].startswith("{"):
        raise RuntimeError(f"analyze {scene} failed (exit {done.returncode}):\n{done.stderr}")
    figures = json.loads(lines[-1])
    size = json_out.stat().st_size if json_out is not None and json_out.exists() else None
    return Run(figures["code"], figures["seconds"], figures["peak_bytes"], size)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default=",".join(map(str, SIZES)), help="comma-separated position counts")
    sizes = [int(float(s)) for s in parser.parse_args(argv).sizes.split(",")]
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_memory.") as name:
        folder = Path(name)
        for positions in sizes:
            scene = seed_sweep_scene(folder, positions)
            for with_json in (False, True):
                out = folder / "analysis.json" if with_json else None
                run = analyze_in_child(scene, out)
                if out is not None:
                    out.unlink(missing_ok=True)
                rows.append((
                    positions, "yes" if with_json else "no", run.code, _or_dash(run.seconds),
                    _or_dash(run.peak_bytes and run.peak_bytes / 1e6), _or_dash(run.json_bytes and run.json_bytes / 1e6),
                ))
                print(f"{positions:,} positions, --json {rows[-1][1]}: exit {run.code}, {rows[-1][3]} s, peak {rows[-1][4]} MB",
                      flush=True)
    print()
    print(format_table(
        ("positions", "--json", "exit", "analyze [s]", "peak memory [MB]", "JSON [MB]"), rows,
    ))


def _or_dash(value: float | None) -> float | str:
    return "-" if value is None else value


if __name__ == "__main__":
    main()
