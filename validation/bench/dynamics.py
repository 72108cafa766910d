"""Benchmark: joint forces and section stresses of the seed four-bar, one position and a sweep.

Run ``python -m linkstress.validation.bench.dynamics``. Prints figures (best of several runs); asserts
nothing about time. Targets: the seed case at one position, mass properties included,
under 5 ms, the work the original program takes 31.8 s for (mass properties at 1e-4 m strips plus
one solve; ``bench_profile --full`` measures its strip sums here); forces and section stresses for
3,600 positions x 3 links x 200 stations under 0.2 s. The one position with section stresses as
well is shown beside them, without a target. The sweep's blocks of positions run on every core the
process may use (``linkstress.threads``); the figures say how many, and the sweep is timed on one
of them as well: on a shared machine their ratio, measured in the same run, shows how much of the
second core the other tenants left (near 2 on a quiet two-core machine, near 1 when another process
keeps a core busy). The sweep with the body-load term on the sections near holes as well
(``[analysis] body_load_near_holes``) is timed beside it: what that setting costs.
"""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np

from linkstress.analysis import Plan, run_analysis
from linkstress.kinematics.motion import angle_motion
from linkstress.geometry.profile import LinkProfile
from linkstress.scene import load_scene
from linkstress.tables import format_table
from linkstress.threads import cores
from linkstress.validation.bench.timing import best_time

SEED = Path(__file__).resolve().parents[1] / "cases" / "seed_ansys_fourbar" / "scene.toml"



def fresh_mass_properties(scene) -> None:
    """Mass and inertia of every profiled link from its outline, without any cached value."""
    for link in scene.links.values():
        if link.profile is not None:
            p = link.profile
            fresh = LinkProfile(p.outline, p.joints, p.thickness, p.material, p.name)
            fresh.mass, fresh.mass_moment_of_inertia, fresh.center_of_mass


def on_one_core(timing):
    """``timing()`` with the process held to one of its cores (so ``linkstress.threads`` runs the
    blocks on the calling thread), or None where there is only one or the system cannot say."""
    if cores() == 1 or not hasattr(os, "sched_setaffinity"):
        return None
    allowed = os.sched_getaffinity(0)
    os.sched_setaffinity(0, {min(allowed)})
    try:
        return timing()
    finally:
        os.sched_setaffinity(0, allowed)


def main() -> None:
    scene = load_scene(SEED)
    links = ("crank", "coupler", "output")
    one = Plan(forces=True, stresses=links, stations=101, validate=(), notes=())
    forces_only = Plan(forces=True, stresses=(), stations=101, validate=(), notes=())
    t_mass = best_time(lambda: fresh_mass_properties(scene))
    t_forces = best_time(lambda: run_analysis(scene, forces_only))
    t_solve = best_time(lambda: (fresh_mass_properties(scene), run_analysis(scene, forces_only)))
    t_one = best_time(lambda: (fresh_mass_properties(scene), run_analysis(scene, one)))
    sweep_scene = replace(scene, motion=angle_motion(np.linspace(0.0, 360.0, 3600, endpoint=False), -1.0, 0.0))
    sweep = Plan(forces=True, stresses=links, stations=200, validate=(), notes=())
    result = run_analysis(sweep_scene, sweep)
    t_sweep = best_time(lambda: run_analysis(sweep_scene, sweep), repeat=5)
    t_one_core = on_one_core(lambda: best_time(lambda: run_analysis(sweep_scene, sweep), repeat=5))
    with_term = replace(sweep, body_load_near_holes=True)
    t_with_term = best_time(lambda: run_analysis(sweep_scene, with_term), repeat=5)
    stages = {k: 1e3 * v for k, v in result.seconds.items()}
    rows = [
        ("seed, 1 position: mass properties of 4 links", 1e3 * t_mass, ""),
        ("seed, 1 position: kinematics + forces", 1e3 * t_forces, ""),
        ("seed, 1 position: mass properties + kinematics + forces", 1e3 * t_solve, 5.0),
        ("seed, 1 position: mass properties + forces + stresses (3 links x 101 stations)", 1e3 * t_one, ""),
        ("sweep: 3,600 positions x 3 links x 200 stations, kinematics + forces + stresses", 1e3 * t_sweep, 200.0),
    ]
    print(format_table(("task", "time [ms]", "target [ms]"), rows))
    print(
        f"\nsweep stages (one run) [ms]: kinematics {stages['kinematics']:.1f}, forces {stages['forces']:.1f}, "
        f"stresses {stages['stresses']:.1f}; {int(result.feasible.sum())} of 3600 positions feasible "
        "(the seed linkage is a change point: 180 deg is a toggle)"
    )
    print(f"positions per second, whole pipeline: {3600 / t_sweep:,.0f} (on {cores()} cores)")
    if t_one_core is not None:
        print(
            f"sweep on one core: {1e3 * t_one_core:.1f} ms; on {cores()} cores {1e3 * t_sweep:.1f} ms, "
            f"{t_one_core / t_sweep:.2f} x faster in this run"
        )
    print(
        f"sweep with the body-load term near holes too (body_load_near_holes): {1e3 * t_with_term:.1f} ms, "
        f"{t_with_term / t_sweep:.2f} x the default's time"
    )
    print(
        f"original program, 1 position: 31.8 s (measured by the project); here {31.8 / t_solve:,.0f} x faster, "
        f"{31.8 / t_one:,.0f} x with the section stresses of 3 links as well"
    )


if __name__ == "__main__":
    main()
