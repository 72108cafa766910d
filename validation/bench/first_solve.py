"""Where the time of one link's unit-load set goes, and analyze with peaks cold and with its cache warm.

    python -m linkstress.validation.bench.first_solve [--repeat 3] [--before PYTHON]

1. One link's unit-load set (``unit_load_cases``) phase by phase, for the seed four-bar's crank and
   the README tutorial's coupler: gmsh meshing, the stiffness's assembly, the unit load vectors,
   the factorisation, the unit solves, the stress recovery (projections, mass factorisation,
   recovered nodal stresses). Each phase with SuperLU and, where scikit-sparse is installed,
   CHOLMOD; beside them the assembly by scikit-fem's vector forms that the scalar blocks replaced.
   Best of ``--repeat``, the settings alternated.
2. Importing the FEA stack, in a fresh interpreter.
3. ``linkstress analyze SCENE --peaks`` as whole processes, alternated: with ``--no-cache`` (every
   run a first run), and with a cache filled by one run before (the second run of a user), and,
   with ``--before PYTHON``, that interpreter's linkstress (e.g. a virtual environment of an earlier
   commit) with its own options. The cache's size after.

Prints figures; asserts nothing about time (machines are shared and noisy: compare the ratios
measured in one run).
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from skfem import BilinearForm, asm
from skfem.helpers import sym_grad
from skfem.models.elasticity import linear_elasticity, linear_stress, plane_stress

from linkstress.analysis import plan_for, run_analysis
from linkstress.geometry.members import link_members
from linkstress.scene import load_scene
from linkstress.tables import format_table
from linkstress.threads import blas_alone
from linkstress.validation.bench.tutorial import DRAWING, checkout
from linkstress.validation.fea.cache import DiskCache, CacheSettings
from linkstress.validation.fea.link import link_region
from linkstress.validation.fea.mesh import mesh_region
from linkstress.validation.fea.plane_stress import SOLVER_VARIABLE, factorise, minimal_support, plane_stress_model
from linkstress.validation.fea.recovery import stress_recovery
from linkstress.validation.fea.unit_loads import DIRECTION_STEP_DEG, group_loads, unit_case_layout
from linkstress.validation.peaks import peak_mesh

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT / "validation" / "cases" / "seed_ansys_fourbar"
TUTORIAL_SCENE = """title = "The README tutorial's four-bar"

[materials.steel]
density = 7850.0
youngs_modulus = 200e9
poisson_ratio = 0.3
yield_strength = 250e6
endurance_limit = 200e6
ultimate_strength = 400e6
{links}
[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "rocker"
ground = "ground"
branch = "open"

[motion]
input_angle_deg = {{start = 60.0, stop = 420.0, num = 361}}
input_speed_rad_s = 100.0

[loads.couples]
rocker = 5.0
"""
"""The scene the README tutorial's import and edits give (6 mm steel, a whole turn at 100 rad/s, 5 N m on the rocker)."""
PHASES = ("mesh (gmsh)", "assembly", "unit loads", "factorisation", "unit solves", "recovery")
VECTOR_FORMS = "stiffness + projections by scikit-fem's vector forms (before)"
SCALAR_BLOCKS = "stiffness + projections as scalar blocks (now)"


def tutorial_scene(folder: Path) -> Path | None:
    """The tutorial's scene beside a copy of its drawing, or None outside a source checkout."""
    repository = checkout()
    if repository is None:
        return None
    shutil.copy(repository / DRAWING, folder / "fourbar.dxf")
    links = "".join(
        f'\n[links.{name}]\nsketch = "fourbar.dxf"\nlayer = "{name}"\nthickness = 0.006\nmaterial = "steel"\n'
        for name in ("crank", "ground", "coupler", "rocker")
    )
    scene = folder / "fourbar.toml"
    scene.write_text(TUTORIAL_SCENE.format(links=links))
    return scene


def seed_scene(folder: Path) -> Path:
    """The seed four-bar over a whole turn in 360 positions, beside a copy of its sketch."""
    shutil.copy(SEED / "ansys_four_bars.dxf", folder / "ansys_four_bars.dxf")
    text = re.sub(r"(?m)^input_angle_deg = .*$", "input_angle_deg = {start = 0.0, stop = 359.0, num = 360}",
                  (SEED / "scene.toml").read_text())
    scene = folder / "scene.toml"
    scene.write_text(text)
    return scene


def link_phases(scene_path: Path, name: str, solver: str) -> dict[str, float]:
    """Seconds of each phase of link ``name``'s unit-load set with ``solver``; and its size."""
    scene = load_scene(scene_path)
    forces = run_analysis(scene, plan_for(scene)).forces
    link, loads = scene.links[name], forces.link_loads[name]
    profile = link.profile
    mesh = peak_mesh(profile, loads.frame_joints, link_members(profile, loads.frame_joints, link.members))
    os.environ[SOLVER_VARIABLE] = solver
    seconds = {}
    with blas_alone():
        start = time.perf_counter()
        region, settings, refine = link_region(profile, loads, mesh)
        plane = mesh_region(region, settings, refine)
        mark = _mark(seconds, "mesh (gmsh)", start)
        model = plane_stress_model(plane, profile.material.youngs_modulus, profile.material.poisson_ratio, profile.thickness)
        model.stiffness
        mark = _mark(seconds, "assembly", mark)
        layout = unit_case_layout(profile, loads, DIRECTION_STEP_DEG)
        unit = np.hstack([group_loads(model, g, layout.directions, profile.density, loads.frame_joints, mesh)
                          for g in layout.groups])
        mark = _mark(seconds, "unit loads", mark)
        fixed, _ = minimal_support(model)
        factors = factorise(model, fixed)
        mark = _mark(seconds, "factorisation", mark)
        displacement, _ = factors.solve(unit)
        mark = _mark(seconds, "unit solves", mark)
        stress_recovery(model).nodal_stress(displacement)
        _mark(seconds, "recovery", mark)
        seconds[VECTOR_FORMS] = _vector_forms(model)
        seconds[SCALAR_BLOCKS] = _scalar_blocks(plane, model)
    seconds["dofs"], seconds["unit cases"] = model.n_dofs, unit.shape[1]
    return seconds


def _mark(seconds: dict[str, float], phase: str, since: float) -> float:
    now = time.perf_counter()
    seconds[phase] = now - since
    return now


def _scalar_blocks(plane, model) -> float:
    """Seconds to assemble the stiffness and the three stress projections as scalar blocks (a fresh model)."""
    start = time.perf_counter()
    fresh = plane_stress_model(plane, model.youngs_modulus, model.poisson_ratio, model.thickness)
    fresh.stiffness
    fresh.stress_projections()
    return time.perf_counter() - start


def _vector_forms(model) -> float:
    """Seconds to assemble the stiffness and the three stress projections with scikit-fem's vector
    forms, as before the scalar blocks."""
    start = time.perf_counter()
    asm(linear_elasticity(*plane_stress(model.youngs_modulus, model.poisson_ratio)), model.basis)
    stress = linear_stress(*plane_stress(model.youngs_modulus, model.poisson_ratio))
    for i, j in ((0, 0), (1, 1), (0, 1)):
        asm(BilinearForm(lambda u, v, w, i=i, j=j: stress(sym_grad(u))[i, j] * v), model.basis, model.scalar)
    return time.perf_counter() - start


def solvers() -> list[str]:
    try:
        import sksparse.cholmod  # noqa: F401
    except ImportError:
        return ["superlu"]
    return ["superlu", "cholmod"]


def import_seconds(python: str, repeat: int) -> float:
    """Best time [s] to import the FEA stack (peaks, gmsh, scikit-fem) in a fresh ``python``."""
    probe = "import time; t = time.perf_counter(); import linkstress.validation.peaks_scene; print(time.perf_counter() - t)"
    return min(float(subprocess.check_output([python, "-c", probe], text=True)) for _ in range(repeat))


def process_seconds(command: list[str], environment: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU (user + system) seconds of running ``command`` (CPU time depends less on what
    else the machine runs)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, env=environment)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs of each setting (best kept)")
    parser.add_argument("--before", metavar="PYTHON", help="also time analyze with this interpreter's linkstress (no cache options)")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="linkstress-first-solve-"))
    try:
        (folder / "seed").mkdir()
        (folder / "tutorial").mkdir()
        scenes = {"seed": seed_scene(folder / "seed"), "tutorial": tutorial_scene(folder / "tutorial")}
        links = [("seed", "crank"), ("tutorial", "coupler")] if scenes["tutorial"] else [("seed", "crank")]
        print_phases(scenes, links, args.repeat)
        print(f"\nimporting the FEA stack (fresh interpreter, best of {args.repeat}): "
              f"{import_seconds(sys.executable, args.repeat):.3f} s")
        for case, scene in scenes.items():
            if scene is not None:
                print_processes(case, scene, folder / f"cache-{case}", args.repeat, args.before)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def print_phases(scenes: dict[str, Path], links: list[tuple[str, str]], repeat: int) -> None:
    before = os.environ.get(SOLVER_VARIABLE)
    try:
        for case, name in links:
            best: dict[str, dict[str, float]] = {}
            for _ in range(repeat):
                for solver in solvers():  # alternated
                    run = link_phases(scenes[case], name, solver)
                    best[solver] = {k: min(v, best.get(solver, {}).get(k, np.inf)) for k, v in run.items()}
            first = best["superlu"]
            print(f"\n{case} {name}: {int(first['dofs'])} dofs, {int(first['unit cases'])} unit load cases "
                  f"(best of {repeat} [s])")
            rows = [(phase, *(best[s][phase] for s in best)) for phase in (*PHASES, VECTOR_FORMS, SCALAR_BLOCKS)]
            rows.insert(len(PHASES), ("total", *(sum(best[s][p] for p in PHASES) for s in best)))
            print(format_table(("phase", *best), rows))
    finally:
        if before is None:
            os.environ.pop(SOLVER_VARIABLE, None)
        else:
            os.environ[SOLVER_VARIABLE] = before


def print_processes(case: str, scene: Path, cache: Path, repeat: int, before: str | None) -> None:
    """Whole ``analyze --peaks`` processes, alternated: no cache, warm cache, and the earlier interpreter."""
    environment = {k: v for k, v in os.environ.items() if k != SOLVER_VARIABLE}
    now = [sys.executable, "-m", "linkstress", "analyze", str(scene), "--peaks"]
    settings = {"first run (--no-cache)": now + ["--no-cache"], "second run (cache warm)": now + ["--cache", str(cache)]}
    if before:
        settings["before (--before interpreter)"] = [before, "-m", "linkstress", "analyze", str(scene), "--peaks"]
    process_seconds(settings["second run (cache warm)"], environment)  # fills the cache
    times: dict[str, list[tuple[float, float]]] = {label: [] for label in settings}
    for _ in range(repeat):
        for label, command in settings.items():
            times[label].append(process_seconds(command, environment))
    best = {label: np.min(t, axis=0) for label, t in times.items()}
    first = best["first run (--no-cache)"]
    rows = [(label, wall, float(np.median([w for w, _ in times[label]])), cpu, wall / first[0], cpu / first[1])
            for label, (wall, cpu) in best.items()]
    size = DiskCache(CacheSettings(str(cache))).size()
    print(f"\n{case}: linkstress analyze --peaks, whole processes alternated, {repeat} runs each [s]; "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; cache {size / 1e6:.1f} MB")
    print(format_table(("run", "best wall", "median wall", "best CPU", "wall / first run", "CPU / first run"), rows))


if __name__ == "__main__":
    main()
