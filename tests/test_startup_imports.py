"""What ``linkstress analyze`` imports: only what the scene needs (issue 20: start-up at most 3 x a
bare ``import numpy``). Each scene runs in a fresh interpreter, which prints ``sorted(sys.modules)``
after the command; the lists below are the packages measured to dominate start-up
(``python -X importtime``; validation/bench/startup.py times the whole process)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"

NEVER_FOR_ANALYZE = ("matplotlib", "skfem", "gmsh", "meshio", "tqdm", "scipy.interpolate", "scipy.optimize")
"""Plots only with --html, FEA only with --peaks or validate, progress bars only in validate, SciPy's
B-splines only for a SPLINE entity: none of them for a plain analyze (each costs 0.1-0.5 s)."""
SKETCH_READING = ("linkstress.importers", "ezdxf", "scipy.spatial", "scipy.sparse")
"""Reading a DXF sketch: the importers, ezdxf for the header and tables, k-d trees and graph
components to chain the curves. A scene of bare joints needs none of them."""

PROGRAM = """
import json, sys
from linkstress.cli import main
code = main(["analyze", sys.argv[1]])
print(json.dumps({"code": code, "modules": sorted(sys.modules)}))
"""


def modules_of_analyze(scene: Path) -> set[str]:
    """The modules loaded in a fresh interpreter that ran ``linkstress analyze scene``."""
    done = subprocess.run([sys.executable, "-c", PROGRAM, str(scene)], capture_output=True, text=True, check=True)
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["code"] == 0
    return set(result["modules"])


def loaded(modules: set[str], package: str) -> bool:
    return any(name == package or name.startswith(package + ".") for name in modules)


def test_analyze_of_the_seed_reads_its_dxf_sketches_without_plots_fea_or_progress_bars():
    modules = modules_of_analyze(CASES / "seed_ansys_fourbar" / "scene.toml")
    assert [p for p in NEVER_FOR_ANALYZE if loaded(modules, p)] == []
    assert [p for p in SKETCH_READING if loaded(modules, p)] == list(SKETCH_READING)
    assert [p for p in ("numpy", "shapely", "threadpoolctl") if loaded(modules, p)] == ["numpy", "shapely", "threadpoolctl"]


def test_analyze_of_a_scene_of_bare_joints_imports_no_sketch_reader():
    modules = modules_of_analyze(CASES / "textbook_fourbar" / "scene.toml")
    assert [p for p in (*NEVER_FOR_ANALYZE, *SKETCH_READING) if loaded(modules, p)] == []
