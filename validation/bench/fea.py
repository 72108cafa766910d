"""Benchmark: the link FEA against its speed and memory targets.

Run ``python -m linkstress.validation.bench.fea [--dofs N] [--repeat R]``. Prints figures; asserts
nothing about time (machines are shared and noisy: timed tasks run ``--repeat`` times and the best
time is shown). Three measurements on the seed's ANSYS crank (1.0 m between
20 mm pin holes, 1.2 x 0.5 x 0.1 m steel):

1. one position (the seed's crank at 60 degrees, its published joint forces) to a converged nominal
   stress: a three-level convergence study, and the single solve on its finest mesh (target < 2 s);
2. a 360-position sweep on that mesh, one factorisation (target < 15 s);
3. peak resident memory of a solve at about ``--dofs`` (default 200,000) degrees of freedom, in a
   fresh process (target < 2 GB).
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import subprocess
import sys
import time

import numpy as np

from linkstress.geometry.builders import straight_bar
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.geometry.profile import LinkProfile
from linkstress.tables import format_table
from linkstress.validation.fea.convergence import convergence_study
from linkstress.validation.fea.link import solve_link
from linkstress.validation.fea.mesh import MeshSettings
from linkstress.validation.bench.timing import best_run

STATIONS = (0.25, 0.5, 0.75)
HOLE_SIZE = 0.004
SEED_ANGLE = math.radians(60.0)
SEED_FORCES = {"F12": (-869.94, -694.86), "F32": (752.19, 490.91)}
"""The seed's joint forces on the crank [N], ground frame (reference/seed-ansys-fourbar.md)."""
SEED_T12 = 405.96


def seed_crank() -> LinkProfile:
    return straight_bar(1.0, 0.5, 0.1, 0.1, STRUCTURAL_STEEL, hole_diameter=0.02, name="crank")


def seed_position() -> LinkLoadCase:
    """The seed's crank at 60 degrees, omega = -1 rad/s, alpha = 0, in its member frame (O2 -> A)."""
    c, s = math.cos(SEED_ANGLE), math.sin(SEED_ANGLE)
    to_member = np.array([[c, s], [-s, c]])
    pins = np.array([[to_member @ SEED_FORCES["F12"], to_member @ SEED_FORCES["F32"]]])
    return LinkLoadCase(
        frame_joints=(0, 1),
        pin_forces=pins,
        joint_couples=np.array([[SEED_T12, 0.0]]),
        omega=np.array([-1.0]),
        alpha=np.zeros(1),
        origin_acceleration=np.zeros((1, 2)),
        gravity=np.zeros((1, 2)),
    )


def rotating_sweep(link: LinkProfile, n: int) -> LinkLoadCase:
    """A crank turning at 10 rad/s under a rotating 1 kN pin force at A, balanced at O2 (force and torque)."""
    phi = np.linspace(0, 2 * math.pi, n, endpoint=False)
    omega = np.full(n, 10.0)
    alpha = 2.0 * np.sin(phi)
    pins = np.zeros((n, 2, 2))
    pins[:, 1] = 1000.0 * np.column_stack([np.cos(phi), np.sin(phi)])
    zero = np.zeros((n, 2))
    open_case = LinkLoadCase((0, 1), pins, np.zeros((n, 2)), omega, alpha, zero, zero)
    force, moment = open_case.residual(link)
    pins[:, 0] = -force
    return LinkLoadCase((0, 1), pins, np.column_stack([-moment, np.zeros(n)]), omega, alpha, zero, zero)


def nominal_points() -> np.ndarray:
    """Top and bottom fibres of the three stations, member frame [m]."""
    return np.array([[x, y] for x in STATIONS for y in (-0.25, 0.25)])



def one_position(size: float, repeat: int) -> tuple[list[tuple], MeshSettings]:
    link, loads = seed_crank(), seed_position()
    settings = MeshSettings(size, HOLE_SIZE, STATIONS)
    study_seconds, study = best_run(
        lambda: convergence_study(link, loads, settings, nominal_points(), ratio=1.5), repeat
    )
    finest = study.settings[-1]

    def single_position():
        result = solve_link(link, loads, finest)
        result.stress_at(nominal_points())
        return result

    single, result = best_run(single_position, repeat)
    print(
        f"convergence study: dofs {study.dofs.tolist()}, change between the finest two "
        f"{study.change[0]:.3%} ({'converged' if study.converged else 'NOT converged'}), "
        f"Richardson error estimate {study.relative_error[0]:.3%}, reaction ratio {result.reaction_ratio[0]:.2e}"
    )
    return [
        ("three-level convergence study, one position", study.dofs[-1], study_seconds, "-"),
        ("one position on the converged mesh (mesh + solve + stresses)", result.dofs, single, 2.0),
    ], finest


def sweep(settings: MeshSettings, n: int, repeat: int) -> tuple:
    link = seed_crank()
    loads = rotating_sweep(link, n)

    def whole_sweep():
        result = solve_link(link, loads, settings)
        result.section_resultants(STATIONS)
        result.stress_at(nominal_points())
        return result

    elapsed, result = best_run(whole_sweep, repeat)
    print(
        f"sweep of {n}: mesh {result.mesh_seconds:.2f} s, solve and recovery {result.solve_seconds:.2f} s, "
        f"largest reaction ratio {result.reaction_ratio.max():.2e}"
    )
    return (f"{n}-position sweep, one factorisation", result.dofs, elapsed, 15.0)


def memory_child(dofs: int) -> None:
    """Solve the seed crank at about ``dofs`` dofs; print dofs, seconds and peak RSS [MB] as JSON."""
    link = seed_crank()
    # About 4 dofs per element for P2 vector triangles: elements ~ dofs / 4 ~ area / (0.433 h^2).
    size = math.sqrt(link.area / (0.433 * dofs / 4))
    start = time.perf_counter()
    result = solve_link(link, seed_position(), MeshSettings(size, min(size, HOLE_SIZE), STATIONS))
    result.stress_at(nominal_points())
    seconds = time.perf_counter() - start
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"dofs": result.dofs, "seconds": seconds, "peak_rss_mb": peak}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dofs", type=int, default=200_000, help="size of the memory measurement")
    parser.add_argument("--positions", type=int, default=360)
    parser.add_argument("--repeat", type=int, default=3, help="runs of each timed task; the best is shown")
    parser.add_argument("--memory-child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.memory_child:
        memory_child(args.memory_child)
        return
    rows, finest = one_position(0.12, args.repeat)
    rows.append(sweep(finest, args.positions, args.repeat))
    child = subprocess.run(
        [sys.executable, "-m", "linkstress.validation.bench.fea", "--memory-child", str(args.dofs)],
        capture_output=True,
        text=True,
        check=True,
    )
    memory = json.loads(child.stdout.strip().splitlines()[-1])
    rows.append((f"solve at {memory['dofs']} dofs", memory["dofs"], memory["seconds"], "-"))
    print(format_table(("task", "dofs", "time [s]", "target [s]"), rows))
    print(
        f"\npeak resident memory at {memory['dofs']} dofs: {memory['peak_rss_mb']:.0f} MB (target < 2048 MB)"
    )


if __name__ == "__main__":
    main()
