"""Throughput over sweeps (positions per second, stage by stage) and the FEA's peak memory.

- Kinematics (``solve_machine``), joint forces (``machine_forces``) and section stresses
  (``links_section_stresses`` of every profiled link at the analysis' default station count, the
  links sharing the cores and BLAS on one thread, as ``analyze`` runs them) over a full turn of the
  input, each timed alone (best of several runs).
- The FEA over a sweep: one mesh and one factorisation, every position a right-hand side.
- Peak memory of one FEA solve, measured in a fresh process (``python -m
  linkstress.validation.bench.throughput --memory ...``): the resident set after the imports and the
  scene, and its high-water mark after the solve (``getrusage``), so the FEA's own share is their
  difference.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from linkstress.analysis import DEFAULT_STATIONS, plan_for, run_analysis, scene_link_members
from linkstress.dynamics.machine_forces import machine_forces
from linkstress.dynamics.section_stress import links_section_stresses
from linkstress.kinematics import solve_machine
from linkstress.kinematics.motion import angle_motion
from linkstress.scene import load_scene
from linkstress.validation.stations import comparison_stations, default_mesh
from linkstress.validation.fea.link import solve_link
from linkstress.threads import blas_alone
from linkstress.validation.bench.timing import best_run


@dataclass(frozen=True)
class StageRate:
    """``positions`` of ``case`` through ``stage`` in ``seconds`` (best run); ``detail`` says what a
    position includes."""

    case: str
    stage: str
    positions: int
    seconds: float
    detail: str

    @property
    def per_second(self) -> float:
        return self.positions / self.seconds


@dataclass(frozen=True)
class MemoryUse:
    """Peak resident memory [MB] of one FEA solve of ``link`` with ``dofs`` dofs, and before it."""

    case: str
    link: str
    order: int
    dofs: int
    seconds: float
    baseline_mb: float
    peak_mb: float


def swept(scene, positions: int):
    """``scene`` over a full turn of its input in ``positions`` steps, at its first speed and acceleration."""
    motion = scene.motion
    angles = np.linspace(0.0, 360.0, positions, endpoint=False)
    return replace(scene, motion=angle_motion(angles, float(motion.speed[0]), float(motion.acceleration[0])))


def sweep_rates(scene_path: Path, positions: int, repeat: int) -> list[StageRate]:
    """Each stage of the analysis over ``positions`` input angles of the scene at ``scene_path``."""
    scene = swept(load_scene(scene_path), positions)
    plan = plan_for(scene)
    case = scene_path.parent.name
    kinematics_s, motion = best_run(lambda: solve_machine(scene.machine, scene.motion), repeat)
    forces_s, forces = best_run(lambda: machine_forces(scene, motion), repeat)
    profiles = {name: scene.links[name].profile for name in plan.stresses}

    jobs = [
        (link, forces.link_loads[name], scene_link_members(scene, name, forces.link_loads[name].frame_joints),
         DEFAULT_STATIONS)
        for name, link in profiles.items()
    ]

    def stresses():
        with blas_alone():
            links_section_stresses(jobs)

    stresses_s, _ = best_run(stresses, repeat)
    links = len(profiles)
    return [
        StageRate(case, "kinematics", positions, kinematics_s, f"{len(scene.moving_links)} moving links"),
        StageRate(case, "joint forces", positions, forces_s, "Newton-Euler, every joint and the driving torque"),
        StageRate(case, "section stresses", positions, stresses_s, f"{links} links x {DEFAULT_STATIONS} stations per member"),
        StageRate(case, "whole analysis", positions, kinematics_s + forces_s + stresses_s, "the three stages"),
    ]


def fea_sweep_rate(scene_path: Path, link_name: str, positions: int, refinement: float) -> StageRate:
    """One link's FEA over ``positions`` feasible input angles: one mesh, one factorisation."""
    scene = swept(load_scene(scene_path), positions)
    analysis = run_analysis(scene, replace(plan_for(scene), stresses=(), validate=()))
    link = scene.links[link_name].profile
    feasible = np.flatnonzero(analysis.feasible)
    loads = analysis.forces.link_loads[link_name].at(feasible)
    stations = comparison_stations(link, loads.frame_joints)
    mesh = default_mesh(link, loads.frame_joints, stations).refined(refinement)
    start = time.perf_counter()
    result = solve_link(link, loads, mesh)
    result.section_resultants(stations)
    seconds = time.perf_counter() - start
    detail = f"FEA of the {link_name}, {result.dofs} dofs: mesh, one factorisation, solve and stress recovery per position"
    return StageRate(scene_path.parent.name, "FEA (one link)", len(feasible), seconds, detail)


def memory_use(scene_path: Path, link_name: str, refinement: float, order: int) -> MemoryUse:
    """Run ``measure_memory`` in a fresh Python process and read its result."""
    child = subprocess.run(
        [sys.executable, "-m", "linkstress.validation.bench.throughput", "--memory", str(scene_path), link_name,
         repr(refinement), str(order)],
        capture_output=True, text=True, check=True,
    )
    return MemoryUse(**json.loads(child.stdout.strip().splitlines()[-1]))


def measure_memory(scene_path: Path, link_name: str, refinement: float, order: int) -> MemoryUse:
    """In this process: the scene's kinetics, then one FEA solve of ``link_name``; resident set sizes."""
    scene = load_scene(scene_path)
    analysis = run_analysis(scene, replace(plan_for(scene), stresses=(), validate=()))
    link = scene.links[link_name].profile
    loads = analysis.forces.link_loads[link_name].at(np.flatnonzero(analysis.feasible)[:1])
    stations = comparison_stations(link, loads.frame_joints)
    mesh = replace(default_mesh(link, loads.frame_joints, stations).refined(refinement), order=order)
    baseline = _resident_mb()
    start = time.perf_counter()
    result = solve_link(link, loads, mesh)
    result.section_resultants(stations)
    seconds = time.perf_counter() - start
    return MemoryUse(scene_path.parent.name, link_name, order, result.dofs, seconds, baseline, _resident_mb())


def _resident_mb() -> float:
    """High-water mark of this process's resident set [MB].

    From /proc/self/status (VmHWM) where there is one: getrusage's ru_maxrss survives exec, so a
    child started from a large process would report its parent's size.
    """
    status = Path("/proc/self/status")
    if status.is_file():
        for line in status.read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux


def main() -> None:
    parser = argparse.ArgumentParser(description="Peak memory of one link's FEA, in this process (JSON on stdout).")
    parser.add_argument("--memory", nargs=4, metavar=("SCENE", "LINK", "REFINEMENT", "ORDER"), required=True)
    scene, link, refinement, order = parser.parse_args().memory
    result = measure_memory(Path(scene), link, float(refinement), int(order))
    print(json.dumps(result.__dict__))


if __name__ == "__main__":
    main()
