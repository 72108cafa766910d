"""What ``linkstress analyze`` imports: only what the scene needs (its start-up is held to at most 3 x
a bare ``import numpy``). Each scene runs in a fresh interpreter, which prints ``sorted(sys.modules)``
after the command; the lists below are the packages measured to dominate start-up
(``python -X importtime``; validation/bench/startup.py times the whole process)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"

NEVER_FOR_ANALYZE = ("matplotlib", "skfem", "gmsh", "meshio", "tqdm", "scipy", "ezdxf", "multiprocessing",
                     "linkstress.validation", "linkstress.commands.regress", "linkstress.commands.validate",
                     "linkstress.importers.ilogic_csv", "linkstress.importers.dxf_document", "numpy.ma")
"""Plots only with --html, FEA only where a link's model needs it (not with --beam-only), with --peaks or
validate, progress bars only in validate, numpy's
masked arrays never (10 ms, which np.median would import). SciPy
(0.25 s: k-d trees, sparse graphs, B-splines) only for a sketch of more than 1500 curve ends or a
SPLINE, ezdxf (0.2 s) only for a DXF that is not plain (blocks, ELLIPSE, SPLINE, POLYLINE, binary,
encodings, damage), the process pool and the other commands' modules only for those commands, the
CSV reader only for a CSV sketch."""
SKETCH_READING = ("linkstress.importers", "linkstress.importers.dxf_plain", "shapely")
"""Reading a DXF sketch: the importers, with the plain DXF reader for the header and tables."""
ANALYSIS = ("numpy", "shapely", "threadpoolctl", "tomllib")
"""What every analysis needs: arrays, link outlines, BLAS kept to one thread, the scene file."""

PROGRAM = """
import json, sys
from linkstress.cli import main
code = main(["analyze", *sys.argv[1:]])
print(json.dumps({"code": code, "modules": sorted(sys.modules)}))
"""


def modules_of_analyze(scene: Path, *options: str) -> set[str]:
    """The modules loaded in a fresh interpreter that ran ``linkstress analyze scene [options]``."""
    done = subprocess.run([sys.executable, "-c", PROGRAM, str(scene), *options], capture_output=True, text=True,
                          check=True)
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["code"] == 0
    return set(result["modules"])


def loaded(modules: set[str], package: str) -> bool:
    return any(name == package or name.startswith(package + ".") for name in modules)


def test_analyze_of_the_seed_reads_its_dxf_sketches_without_ezdxf_scipy_plots_fea_or_other_commands():
    # --beam-only: the seed's crank carries its driving torque through its pivot, which takes the FEA
    modules = modules_of_analyze(CASES / "seed_ansys_fourbar" / "scene.toml", "--beam-only")
    assert [p for p in NEVER_FOR_ANALYZE if loaded(modules, p)] == []
    assert [p for p in SKETCH_READING if loaded(modules, p)] == list(SKETCH_READING)
    assert [p for p in ANALYSIS if loaded(modules, p)] == list(ANALYSIS)


def test_analyze_of_a_scene_of_bare_joints_imports_no_sketch_reader():
    modules = modules_of_analyze(CASES / "textbook_fourbar" / "scene.toml")
    assert [p for p in (*NEVER_FOR_ANALYZE, "linkstress.importers") if loaded(modules, p)] == []
    needed = ("numpy", "threadpoolctl", "tomllib")
    assert [p for p in needed if loaded(modules, p)] == list(needed)
