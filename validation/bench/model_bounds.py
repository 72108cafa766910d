"""The bounds of modelling only what a scene needs (issue 30), as figures; no check fails on a time.

- The README tutorial's ``analyze`` (a whole turn, the default accuracy, FEA where the model choice
  puts it): the first run (an empty disk cache) against ``analyze --peaks`` of the same scene by
  another installation (``--before PYTHON``: the interpreter of a virtual environment holding the
  earlier commit; the target is at most 0.5 x), and a second run with the cache warm (target under
  1.5 s as a whole process).
- The seed four-bar at its one position: the crank's governing stress from ``analyze`` with the
  default accuracy against ``validate``'s converged FEA peak (target within 5 %).
- The straight four-bar, whose links the beam and the Kt tables answer: ``analyze`` imports no FEA
  and its start-up against a bare ``import numpy`` (target at most 3 x).

Whole processes, alternated in one process tree (a slow spell of the shared machine falls on every
command alike), the best of ``--repeat`` runs each (noise only ever adds time). Bytecode is
compiled first and written to a temporary folder (``PYTHONPYCACHEPREFIX``), as an installed package
has it, for every interpreter timed.

    python -m linkstress.validation.bench.model_bounds [--before PYTHON] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from linkstress.validation.bench.tutorial import checkout, tutorial_scene

CASES = Path(__file__).resolve().parents[1] / "cases"
SEED = CASES / "seed_ansys_fourbar" / "scene.toml"
STRAIGHT = CASES / "straight_fourbar" / "scene.toml"
FIRST_RUN_TARGET = 0.5
"""The tutorial's first run over the earlier commit's ``analyze --peaks``."""
WARM_RUN_TARGET = 1.5
"""[s]: the tutorial's second run, cache warm, as a whole process."""
SEED_TARGET = 0.05
STARTUP_TARGET = 3.0


def _environment(prefix: str) -> dict[str, str]:
    env = {key: value for key, value in os.environ.items() if key not in ("PYTHONDONTWRITEBYTECODE", "LINKSTRESS_CACHE")}
    env["PYTHONPYCACHEPREFIX"] = prefix
    return env


def timed(command: list[str], env: dict[str, str], cwd: Path) -> float:
    """[s] wall time of ``command``, which must succeed."""
    start = time.perf_counter()
    subprocess.run(command, env=env, cwd=cwd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    return time.perf_counter() - start


@dataclass(frozen=True)
class TutorialTimes:
    """Best wall times [s]: ``first`` (empty cache), ``warm`` (its second run), ``before`` (the
    earlier installation's ``analyze --peaks``, None without one); ``models`` per link."""

    first: float
    warm: float
    before: float | None
    models: dict[str, str]


def tutorial_times(folder: Path, python: str, before: str | None, repeat: int) -> TutorialTimes:
    """Alternate the earlier ``analyze --peaks``, the first run and the warm run ``repeat`` times."""
    scene = tutorial_scene(folder / "tutorial")
    env = _environment(str(folder / "pycache"))
    subprocess.run([python, "-m", "compileall", "-q", str(Path(__file__).resolve().parents[2])], env=env,
                   stdout=subprocess.DEVNULL, check=False)
    firsts, warms, befores = [], [], []
    for k in range(repeat):
        if before is not None:
            befores.append(timed([before, "-m", "linkstress", "analyze", str(scene), "--peaks"], env, scene.parent))
        cache = folder / f"cache-{k}"
        analyze = [python, "-m", "linkstress", "analyze", str(scene), "--cache", str(cache)]
        firsts.append(timed(analyze, env, scene.parent))
        warms.append(timed(analyze, env, scene.parent))
        shutil.rmtree(cache, ignore_errors=True)
    out = folder / "tutorial.json"
    subprocess.run([python, "-m", "linkstress", "analyze", str(scene), "--cache", str(folder / "cache-models"),
                    "--json", str(out)], env=env, check=True, stdout=subprocess.DEVNULL)
    models = {name: link["model"] for name, link in json.loads(out.read_text())["links"].items()}
    return TutorialTimes(min(firsts), min(warms), min(befores) if befores else None, models)


@dataclass(frozen=True)
class AnalyzeRun:
    """``analyze`` of one scene as a whole process: its ``first`` run (an empty disk cache) and its
    ``cached`` second run [s], best of ``repeat``; the ``models`` it chose per stressed link."""

    case: str
    positions: int
    first: float
    cached: float
    repeat: int
    models: dict[str, str]

    def record(self) -> dict[str, object]:
        return {"case": self.case, "positions": self.positions, "first_seconds": self.first,
                "cached_seconds": self.cached, "repeat": self.repeat, "models": self.models}


def analyze_run(case: str, scene: Path, folder: Path, python: str, repeat: int) -> AnalyzeRun:
    """Time ``analyze`` of ``scene``: a first run on an empty cache and a second on the same cache,
    alternated ``repeat`` times (bytecode compiled first)."""
    env = _environment(str(folder / "pycache"))
    subprocess.run([python, "-m", "compileall", "-q", str(Path(__file__).resolve().parents[2])], env=env,
                   stdout=subprocess.DEVNULL, check=False)
    firsts, cached = [], []
    for k in range(repeat):
        cache = folder / f"cache-{case}-{k}"
        analyze = [python, "-m", "linkstress", "analyze", str(scene), "--cache", str(cache)]
        firsts.append(timed(analyze, env, scene.parent))
        cached.append(timed(analyze, env, scene.parent))
        if k < repeat - 1:
            shutil.rmtree(cache, ignore_errors=True)
    out = folder / f"{case}.json"
    subprocess.run([python, "-m", "linkstress", "analyze", str(scene), "--cache", str(cache), "--json", str(out)],
                   env=env, check=True, stdout=subprocess.DEVNULL)
    shutil.rmtree(cache, ignore_errors=True)
    data = json.loads(out.read_text())
    models = {name: link["model"] for name, link in data.get("links", {}).items()}
    return AnalyzeRun(case, len(data["positions"]), min(firsts), min(cached), repeat, models)


def analyze_runs(repeat: int) -> list[AnalyzeRun]:
    """The README tutorial's scene (in a source checkout) and the seed: ``analyze``'s first and cached
    runs (``linkstress bench``)."""
    with tempfile.TemporaryDirectory(prefix="linkstress-bench-") as name:
        folder = Path(name)
        seed = analyze_run("seed_ansys_fourbar", SEED, folder, sys.executable, repeat)
        if checkout() is None:
            return [seed]
        return [analyze_run("tutorial", tutorial_scene(folder / "tutorial"), folder, sys.executable, repeat), seed]


def seed_crank(folder: Path, python: str) -> tuple[float, float, str]:
    """[Pa]: the seed crank's governing stress from ``analyze`` and validate's converged FEA peak; its model."""
    env = _environment(str(folder / "pycache"))
    analysis, check = folder / "seed-analyze.json", folder / "seed-validate.json"
    subprocess.run([python, "-m", "linkstress", "analyze", str(SEED), "--no-cache", "--json", str(analysis)], env=env,
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run([python, "-m", "linkstress", "validate", str(SEED), "--no-cache", "--json", str(check)], env=env,
                   check=True, stdout=subprocess.DEVNULL)
    data = json.loads(analysis.read_text())
    row = next(r for r in data["verdict"]["rows"] if r["link"] == "crank")
    fea = json.loads(check.read_text())["links"]["crank"]["fea_max_von_mises_pa"]
    return row["stress_pa"], fea, data["links"]["crank"]["model"]


PROBE = (
    "import json, sys, contextlib, io; from linkstress.cli import main\n"
    "with contextlib.redirect_stdout(io.StringIO()): code = main(['analyze', sys.argv[1]])\n"
    "print(json.dumps({'code': code, 'fea': sorted(m for m in ('skfem', 'gmsh') if m in sys.modules)}))"
)


def straight_startup(folder: Path, python: str, repeat: int) -> tuple[float, float, list[str]]:
    """Best wall times [s] of ``analyze`` of the straight four-bar and of ``import numpy``,
    alternated; the FEA modules that analyze imported (none expected)."""
    env = _environment(str(folder / "pycache"))
    probe = subprocess.run([python, "-c", PROBE, str(STRAIGHT)], env=env, check=True, capture_output=True, text=True)
    fea = json.loads(probe.stdout.strip().splitlines()[-1])["fea"]
    analyze, numpy = [], []
    for _ in range(repeat):
        analyze.append(timed([python, "-m", "linkstress", "analyze", str(STRAIGHT)], env, folder))
        numpy.append(timed([python, "-c", "import numpy"], env, folder))
    return min(analyze), min(numpy), fea


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", metavar="PYTHON", help="the interpreter of an installation of the earlier commit")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    python = sys.executable
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        times = tutorial_times(folder, python, args.before, args.repeat)
        print(f"tutorial analyze, models {times.models}:")
        print(f"  first run (empty cache) {times.first:.2f} s; second run (cache warm) {times.warm:.2f} s "
              f"(target under {WARM_RUN_TARGET:g} s: {'met' if times.warm < WARM_RUN_TARGET else 'NOT met'})")
        if times.before is not None:
            ratio = times.first / times.before
            print(f"  earlier analyze --peaks {times.before:.2f} s; first run / earlier = {ratio:.2f} "
                  f"(target at most {FIRST_RUN_TARGET:g}: {'met' if ratio <= FIRST_RUN_TARGET else 'NOT met'})")
        governing, fea, model = seed_crank(folder, python)
        off = governing / fea - 1
        print(f"seed crank ({model}): analyze {governing / 1e6:.4g} MPa, validate's converged FEA peak {fea / 1e6:.4g} MPa, "
              f"{100 * off:+.2f} % (target within {100 * SEED_TARGET:g} %: {'met' if abs(off) <= SEED_TARGET else 'NOT met'})")
        analyze, numpy, modules = straight_startup(folder, python, max(args.repeat, 5))
        ratio = analyze / numpy
        print(f"straight four-bar analyze {analyze:.3f} s, import numpy {numpy:.3f} s: {ratio:.2f} x "
              f"(target at most {STARTUP_TARGET:g}: {'met' if ratio <= STARTUP_TARGET else 'NOT met'}); FEA modules "
              f"imported: {', '.join(modules) or 'none'}")


if __name__ == "__main__":
    main()
