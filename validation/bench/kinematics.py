"""Benchmark: kinematic sweeps against their speed targets.

Run ``python -m linkstress.validation.bench.kinematics``. Prints figures; asserts nothing about time
(machines are shared and noisy). Targets (issue 4): angles, speeds and accelerations of every link
of a four-bar for 1,000,000 input angles in under 0.5 s; a machine of four chained loops over 3,600
positions in under 50 ms.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from linkstress.kinematics import Drive, FourBar, Loop, Machine, Role, angle_motion, solve_fourbar, solve_machine
from linkstress.tables import format_table
from linkstress.validation.bench.timing import best_time



def four_loop_machine() -> Machine:
    """Main four-bar; a bell-crank four-bar on its output; a coupled slider-crank on its crank; a
    four-bar on that slider-crank's crank: four loops, three levels, rigid and coupled drives."""
    links = {
        "ground": [[0.0, 0.0], [0.06, 0.0], [0.06, 0.1], [0.3, 0.0], [0.5, 0.0], [0.3, 0.08]],
        "crank": [[0.0, 0.0], [0.08, 0.0]],
        "coupler": [[0.0, 0.0], [0.08, 0.0]],
        "rocker": [[0.0, 0.0], [0.09, 0.0], [0.0, 0.03]],
        "link2": [[0.0, 0.0], [0.1, 0.0]],
        "out2": [[0.0, 0.0], [0.08, 0.0]],
        "crank3": [[0.0, 0.0], [0.02, 0.0], [0.0, 0.015]],
        "rod3": [[0.0, 0.0], [0.07, 0.0]],
        "piston": [[0.0, 0.0]],
        "link4": [[0.0, 0.0], [0.09, 0.0]],
        "out4": [[0.0, 0.0], [0.07, 0.0]],
    }
    loops = (
        Loop("main", "four-bar", Role("crank"), Role("coupler"), Role("ground", (0, 1)), output=Role("rocker")),
        Loop("bell", "four-bar", Role("rocker", (0, 2)), Role("link2"), Role("ground", (1, 2)),
             output=Role("out2"), driven_by=Drive("main", "output")),
        Loop("engine", "slider-crank", Role("crank3"), Role("rod3"), Role("ground", (3, 4)),
             slider=Role("piston", (0, 0)), offset=0.005, driven_by=Drive("main", "crank", math.radians(90.0))),
        Loop("pump", "four-bar", Role("crank3", (0, 2)), Role("link4"), Role("ground", (3, 5)),
             output=Role("out4"), driven_by=Drive("engine", "crank")),
    )
    return Machine(links, loops)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per figure; the best is shown (default 5)")
    args = parser.parse_args()

    linkage = FourBar((0.0, 0.0), (0.06, 0.0), 0.08, 0.08, 0.09, "open")
    theta = np.linspace(0.0, 2 * math.pi, 1_000_000, endpoint=False)
    omega = np.full_like(theta, 100.0)
    alpha = np.full_like(theta, 18.0)
    t_fourbar = best_time(lambda: solve_fourbar(linkage, theta, omega, alpha), args.repeat)
    sweep = solve_fourbar(linkage, theta, omega, alpha)
    assert np.isfinite(sweep.alpha4).all() and sweep.feasible.all()

    machine = four_loop_machine()
    motion = angle_motion(np.arange(3600) / 10.0, 100.0, 18.0)
    t_machine = best_time(lambda: solve_machine(machine, motion), max(args.repeat, 20))
    result = solve_machine(machine, motion)

    rows = [
        ("four-bar, 1,000,000 input angles (all links: angle, omega, alpha, joints)", t_fourbar, 0.5,
         f"{theta.size / t_fourbar / 1e6:.3g} M positions/s"),
        (f"machine of {len(machine.loops)} chained loops, 3,600 positions", t_machine, 0.05,
         f"{int(result.feasible.sum())} of 3600 feasible"),
    ]
    table = [(what, f"{t * 1e3:.1f}", f"{target * 1e3:.0f}", note) for what, t, target, note in rows]
    print(format_table(("sweep", "best [ms]", "target [ms]", "note"), table))


if __name__ == "__main__":
    main()
