"""Benchmark: four-bar sweeps against pylinkage and two plain reference loops, measured in one run.

Run ``python -m linkstress.validation.bench.kinematics``. Every figure is the best of ``--repeat``
rounds in this one process, each round running every sweep once, so that their ratios compare like
with like; wall time and CPU time (every thread: the work done, whatever else loads the machine).
It prints figures and asserts nothing about time (machines are shared and noisy).

- linkstress ``solve_fourbar``: angles, angular velocities and accelerations of every link and the
  joints' positions, velocities and accelerations.
- pylinkage (not a dependency: ``pip install 'pylinkage[numba]'``): its compiled
  ``Linkage.step_fast`` over the same four-bar, joint positions only. The target is linkstress at
  least twice its rate.
- Two references that never change, so that a ratio to them can be quoted across machines: the
  same four-bar's joint positions in a plain Python loop (``math`` module) and in one vectorised
  numpy pass.
- A machine of four chained loops over 3,600 positions (target: under 50 ms).
- Theo Jansen's leg as a ``type = "linkage"`` (``kinematics.linkage.examples``): every link's
  angle, angular velocity and acceleration over ``--positions`` crank angles, against pylinkage's
  compiled positions-only sweep of the same leg (a crank and five RRR dyads): the target is
  linkstress at least as fast. Also on one thread (``LINKSTRESS_THREADS=1``): pylinkage runs on
  one, and on a machine whose other cores are busy a second thread only waits for the first. And
  the textbook four-bar written as a linkage against the dedicated four-bar path: the target is
  within 2 x.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import time
from collections.abc import Callable
from importlib import metadata

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics import Drive, FourBar, Loop, Machine, Role, angle_motion, solve_fourbar, solve_machine
from linkstress.kinematics.linkage import Input, Joint, LinkageGraph, solve_linkage
from linkstress.kinematics.linkage.examples import JANSEN_CM, jansen_leg, jansen_pose
from linkstress.tables import format_table
from linkstress.threads import THREADS_VARIABLE, cores
from linkstress.validation.bench.timing import best_time

TARGET_RATIO = 2.0
"""linkstress with rates against pylinkage's positions only."""

MACHINE_TARGET_S = 0.05
JANSEN_TARGET_RATIO = 1.0
"""linkstress's Jansen leg with rates against pylinkage's positions only."""
LINKAGE_FOURBAR_TARGET = 2.0
"""A four-bar written as a linkage against the dedicated four-bar path: at most this many times slower."""

TEXTBOOK = FourBar((0.0, 0.0), (0.06, 0.0), 0.08, 0.08, 0.09, "open")
"""Norton, Design of Machinery, problem 4-1 row g: ground 6, crank 8, coupler 8, output 9 cm."""


def python_positions(linkage: FourBar, theta2: list[float]) -> list[tuple[float, float, float, float]]:
    """Joints A and B (ax, ay, bx, by) [m] per crank angle [rad], a plain Python loop: B is where the
    circles (A, b) and (O4, c) meet, on ``linkage``'s branch. A fixed reference: never optimise it."""
    a, b, c = linkage.crank, linkage.coupler, linkage.output
    (o2x, o2y), (o4x, o4y) = linkage.o2, linkage.o4
    sigma = linkage.sigma
    joints = []
    for theta in theta2:
        ax, ay = o2x + a * math.cos(theta), o2y + a * math.sin(theta)
        dx, dy = o4x - ax, o4y - ay
        s2 = dx * dx + dy * dy
        along = (b * b - c * c + s2) / (2.0 * s2)
        height = sigma * math.sqrt(max(b * b / s2 - along * along, 0.0))
        joints.append((ax, ay, ax + along * dx - height * dy, ay + along * dy + height * dx))
    return joints


def numpy_positions(linkage: FourBar, theta2: NDArray[np.float64]) -> NDArray[np.float64]:
    """``python_positions`` as one vectorised numpy pass: (P, 4) [m]. A fixed reference: never
    optimise it."""
    a, b, c = linkage.crank, linkage.coupler, linkage.output
    (o2x, o2y), (o4x, o4y) = linkage.o2, linkage.o4
    ax, ay = o2x + a * np.cos(theta2), o2y + a * np.sin(theta2)
    dx, dy = o4x - ax, o4y - ay
    s2 = dx * dx + dy * dy
    along = (b * b - c * c + s2) / (2.0 * s2)
    height = linkage.sigma * np.sqrt(np.maximum(b * b / s2 - along * along, 0.0))
    return np.column_stack([ax, ay, ax + along * dx - height * dy, ay + along * dy + height * dx])


def pylinkage_sweep(linkage: FourBar, n: int) -> Callable[[], NDArray[np.float64]]:
    """pylinkage's compiled sweep of ``linkage`` over ``n`` crank steps of 2 pi / n: it returns
    (n, 4, 2) joint positions O2, O4, A, B [m]. B starts on ``linkage``'s branch (pylinkage then
    follows the root nearest the previous position)."""
    from pylinkage import Crank, Ground, RRRDyad
    from pylinkage.simulation import Linkage

    start = solve_fourbar(linkage, [0.0]).joints["B"].position[0]
    o2, o4 = Ground(*linkage.o2, name="O2"), Ground(*linkage.o4, name="O4")
    crank = Crank(anchor=o2, radius=linkage.crank, angular_velocity=2 * math.pi / n)
    rocker = RRRDyad(crank.output, o4, linkage.coupler, linkage.output, x=start[0], y=start[1], name="B")
    sweep = Linkage([o2, o4, crank, rocker], name="four-bar")
    sweep.step_fast(iterations=1)  # compiles
    return lambda: sweep.step_fast(iterations=n)


def pylinkage_agreement(linkage: FourBar, joints: NDArray[np.float64]) -> float:
    """Largest distance [m] between pylinkage's B and linkstress's at pylinkage's crank angles."""
    a = joints[:, 2] - np.asarray(linkage.o2)
    theta = np.arctan2(a[:, 1], a[:, 0])
    return float(np.abs(joints[:, 3] - solve_fourbar(linkage, theta).joints["B"].position).max())


def pylinkage_status() -> str:
    """"" when pylinkage and numba are importable, else what to install."""
    if importlib.util.find_spec("pylinkage") is None:
        return "pylinkage not installed: pip install 'pylinkage[numba]' to measure it"
    if importlib.util.find_spec("numba") is None:
        return "pylinkage installed without numba (its uncompiled path): pip install numba to measure it"
    return ""


def pylinkage_jansen(n: int) -> Callable[[], NDArray[np.float64]]:
    """pylinkage's compiled sweep of Jansen's leg over ``n`` crank steps of 2 pi / n from 0: a
    crank and five RRR dyads (the rigid triangles' third points are dyads on two of their corners),
    each starting at its drawn position. Returns (n, 8, 2) joint positions [m]."""
    from pylinkage import Crank, Ground, RRRDyad
    from pylinkage.simulation import Linkage

    p = jansen_pose(0.0)
    L = {k: v * 0.01 for k, v in JANSEN_CM.items()}
    o, b = Ground(*p["O"], name="O"), Ground(*p["B"], name="B")
    crank = Crank(anchor=o, radius=L["m"], angular_velocity=2 * math.pi / n, name="A")
    c = RRRDyad(crank.output, b, L["j"], L["b"], x=p["C"][0], y=p["C"][1], name="C")
    d = RRRDyad(crank.output, b, L["k"], L["c"], x=p["D"][0], y=p["D"][1], name="D")
    e = RRRDyad(b, c, L["d"], L["e"], x=p["E"][0], y=p["E"][1], name="E")
    f = RRRDyad(e, d, L["f"], L["g"], x=p["F"][0], y=p["F"][1], name="F")
    g = RRRDyad(f, d, L["h"], L["i"], x=p["G"][0], y=p["G"][1], name="G")
    leg = Linkage([o, b, crank, c, d, e, f, g], name="jansen")
    leg.step_fast(iterations=1)  # compiles
    return lambda: leg.step_fast(iterations=n)


def jansen_agreement(trajectory: NDArray[np.float64], n: int) -> float:
    """Largest distance [m] between pylinkage's foot and linkstress's, over the first 1,000 steps
    (pylinkage's row k is the crank turned k + 2 steps from its start: compared so)."""
    count = min(n, 1000)
    theta = np.arange(2, count + 2) * 360.0 / n
    ours = solve_linkage(jansen_leg(0.0), angle_motion(theta)).linkage.joints["leg:2"].position
    feet = trajectory[:count, -1]
    return float(np.nanmax(np.abs(feet - ours)))


def linkage_fourbar(linkage: FourBar) -> LinkageGraph:
    """``linkage`` written as a ``type = "linkage"``, drawn at crank angle 0 on its branch."""
    pose = solve_fourbar(linkage, [0.0]).joints
    a, b = pose["A"].position[0], pose["B"].position[0]
    links = {"ground": [linkage.o2, linkage.o4], "crank": [linkage.o2, a], "coupler": [a, b], "output": [linkage.o4, b]}
    pins = [("ground", 0, "crank", 0), ("crank", 1, "coupler", 0), ("coupler", 1, "output", 1), ("ground", 1, "output", 0)]
    return LinkageGraph("main", links, "ground", tuple((Joint(a, i), Joint(b, j)) for a, i, b, j in pins), (),
                        Input("crank", 0, 1))


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


def one_thread(work: Callable[[], object]) -> Callable[[], object]:
    """``work`` run with ``LINKSTRESS_THREADS=1``: linkstress's blocks on the calling thread alone."""
    def run() -> object:
        saved = os.environ.get(THREADS_VARIABLE)
        os.environ[THREADS_VARIABLE] = "1"
        try:
            return work()
        finally:
            if saved is None:
                del os.environ[THREADS_VARIABLE]
            else:
                os.environ[THREADS_VARIABLE] = saved
    return run


def best_times(works: dict[str, Callable[[], object]], repeat: int) -> dict[str, tuple[float, float]]:
    """Best wall time and best CPU time [s] (every thread of the process) of each work over
    ``repeat`` rounds, each round running every work once: on a shared machine all of them then
    see the same spells of load, and the CPU times show the work done whatever the load."""
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in works}
    for _ in range(repeat):
        for name, work in works.items():
            wall, cpu = time.perf_counter(), time.process_time()
            work()
            times[name].append((time.perf_counter() - wall, time.process_time() - cpu))
    return {name: (min(t[0] for t in runs), min(t[1] for t in runs)) for name, runs in times.items()}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="rounds; the best of each is shown (default 7)")
    parser.add_argument("--positions", type=int, default=1_000_000,
                        help="crank angles per four-bar sweep (default 1,000,000)")
    parser.add_argument("--python-positions", type=int, default=100_000,
                        help="crank angles for the plain Python loop (default 100,000)")
    args = parser.parse_args(argv)

    n = args.positions
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    omega, alpha = np.full(n, 100.0), np.full(n, 18.0)
    sweep = solve_fourbar(TEXTBOOK, theta, omega, alpha)
    assert sweep.feasible.all() and np.isfinite(sweep.alpha4).all()
    python_theta = theta[:: max(n // args.python_positions, 1)][: args.python_positions].tolist()
    works = {
        "linkstress": lambda: solve_fourbar(TEXTBOOK, theta, omega, alpha),
        "python": lambda: python_positions(TEXTBOOK, python_theta),
        "numpy": lambda: numpy_positions(TEXTBOOK, theta),
    }
    names = {
        "linkstress": f"linkstress solve_fourbar ({cores()} threads): angles, omega, alpha of every link, "
                      "joints' p, v, a",
        "python": "reference: plain Python loop (math), joint positions only",
        "numpy": "reference: one plain numpy pass, joint positions only",
    }
    missing = pylinkage_status()
    if not missing:
        works["pylinkage"] = pylinkage_sweep(TEXTBOOK, n)
        drift = pylinkage_agreement(TEXTBOOK, works["pylinkage"]())
        names["pylinkage"] = f"pylinkage {metadata.version('pylinkage')} Linkage.step_fast (numba): joint positions only"
    times = best_times(works, args.repeat)
    counts = {"linkstress": n, "pylinkage": n, "python": len(python_theta), "numpy": n}
    rate = n / times["linkstress"][0]
    table = [
        (names[key], f"{counts[key]:,}", f"{times[key][0] * 1e3:.1f}", f"{times[key][1] * 1e3:.1f}",
         f"{counts[key] / times[key][0] / 1e6:.3g}", f"{rate * times[key][0] / counts[key]:.3g}")
        for key in ("linkstress", "pylinkage", "python", "numpy") if key in times
    ]
    print(f"{cores()} cores, load average {os.getloadavg()[0]:.2f} (1 min); best of {args.repeat} interleaved "
          "rounds; CPU: every thread of the process")
    print(format_table(("four-bar sweep", "positions", "best [ms]", "CPU [ms]", "M positions/s", "linkstress / this"),
                       table))
    if missing:
        print(missing)
    else:
        by_wall = times["pylinkage"][0] / times["linkstress"][0]
        by_cpu = times["pylinkage"][1] / times["linkstress"][1]
        print(f"linkstress / pylinkage: {by_wall:.2f} by wall time, target {TARGET_RATIO:g}: "
              f"{'met' if by_wall >= TARGET_RATIO else 'NOT met'}; {by_cpu:.2f} by CPU time (what one free "
              f"core would show); pylinkage's B within {drift:.1e} m of linkstress's")

    leg = jansen_leg(0.0)
    motion = angle_motion(np.degrees(theta), omega, alpha)
    works = {"jansen": lambda: solve_linkage(leg, motion), "jansen, one thread": one_thread(lambda: solve_linkage(leg, motion))}
    names = {"jansen": f"linkstress linkage ({cores()} threads): angle, omega, alpha of every link",
             "jansen, one thread": "the same on one thread"}
    if not missing:
        works["pylinkage"] = pylinkage_jansen(n)
        drift = jansen_agreement(works["pylinkage"](), n)
        names["pylinkage"] = f"pylinkage {metadata.version('pylinkage')} Linkage.step_fast (numba): joint positions only"
    as_linkage = linkage_fourbar(TEXTBOOK)
    as_loop = Machine({"ground": [TEXTBOOK.o2, TEXTBOOK.o4], "crank": [[0, 0], [TEXTBOOK.crank, 0]],
                       "coupler": [[0, 0], [TEXTBOOK.coupler, 0]], "output": [[0, 0], [TEXTBOOK.output, 0]]},
                      (Loop("main", "four-bar", Role("crank"), Role("coupler"), Role("ground"), output=Role("output")),))
    works["four-bar"] = lambda: solve_machine(as_loop, motion)
    works["four-bar linkage"] = lambda: solve_linkage(as_linkage, motion)
    names["four-bar"] = "the same four-bar by the dedicated path (solve_machine of a four-bar loop)"
    names["four-bar linkage"] = "the same four-bar written as a linkage (solve_linkage)"
    times = best_times(works, args.repeat)
    table = [
        (names[key], f"{n:,}", f"{times[key][0] * 1e3:.1f}", f"{times[key][1] * 1e3:.1f}", f"{n / times[key][0] / 1e6:.3g}")
        for key in works
    ]
    print()
    print(format_table(("Jansen's leg and a four-bar as linkages", "positions", "best [ms]", "CPU [ms]", "M positions/s"),
                       table))
    if missing:
        print(missing)
    else:
        by_wall = times["pylinkage"][0] / times["jansen"][0]
        by_cpu = times["pylinkage"][1] / times["jansen"][1]
        alone = times["pylinkage"][0] / times["jansen, one thread"][0]
        print(f"Jansen leg, linkstress / pylinkage: {by_wall:.2f} by wall time, target {JANSEN_TARGET_RATIO:g}: "
              f"{'met' if by_wall >= JANSEN_TARGET_RATIO else 'NOT met'}; {by_cpu:.2f} by CPU time; {alone:.2f} on one "
              f"thread; pylinkage's foot within {drift:.1e} m of linkstress's")
    slower = times["four-bar linkage"][0] / times["four-bar"][0]
    print(f"four-bar as a linkage / dedicated four-bar path: {slower:.2f} x by wall time, "
          f"{times['four-bar linkage'][1] / times['four-bar'][1]:.2f} x by CPU time, target at most "
          f"{LINKAGE_FOURBAR_TARGET:g} x: {'met' if slower <= LINKAGE_FOURBAR_TARGET else 'NOT met'}")

    machine = four_loop_machine()
    motion = angle_motion(np.arange(3600) / 10.0, 100.0, 18.0)
    t_machine = best_time(lambda: solve_machine(machine, motion), max(args.repeat, 20))
    feasible = int(solve_machine(machine, motion).feasible.sum())
    print(f"\nmachine of {len(machine.loops)} chained loops, 3,600 positions: {t_machine * 1e3:.1f} ms "
          f"(target {MACHINE_TARGET_S * 1e3:.0f} ms), {feasible} of 3600 feasible")


if __name__ == "__main__":
    main()
