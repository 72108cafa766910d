"""Sweep a whole machine: every loop in solving order, each one call over all positions; a
``type = "linkage"`` mechanism by its groups (``kinematics.linkage``)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from linkstress.kinematics.crossings import describe, wrapped_steps
from linkstress.kinematics.fourbar import FourBar, solve_fourbar
from linkstress.kinematics.linkage.graph import LinkageGraph
from linkstress.kinematics.linkage.sweep import solve_linkage
from linkstress.kinematics.machine import Loop, Machine
from linkstress.kinematics.motion import InputMotion
from linkstress.kinematics.results import LinkMotion, LoopMotion, MachineMotion, fixed_link
from linkstress.kinematics.slider_crank import solve_slider_crank


def solve_machine(machine: Machine | LinkageGraph, motion: InputMotion) -> MachineMotion:
    """Kinematics of every link and loop of ``machine`` over the input ``motion`` of its main crank
    (a linkage: ``linkage.sweep.solve_linkage``).

    A driven loop's crank angle is its driver's axis angle (theta2 or theta4) plus
    ``machine.drive_offset``; its speed and acceleration are the driver's. A position is feasible
    when every loop is; its reason is the first failing loop's, in solving order.

    A step between two positions at which a loop and its drivers assemble, that passes one of the
    loop's toggles or change points, is a crossing (``LoopMotion.crossings``); the row after it
    stays feasible (its values are exact for the assembly mode the closed form takes) and carries
    the crossing's message in ``MachineMotion.warnings``. A driven crank's turn per step is its
    driver's crank's, or its driver's output's taken the short way round.
    """
    if isinstance(machine, LinkageGraph):
        return solve_linkage(machine, motion)
    n = motion.n_positions
    loops: dict[str, LoopMotion] = {}
    links: dict[str, LinkMotion] = {}
    steps: dict[str, np.ndarray] = {}
    assembled: dict[str, np.ndarray] = {}
    crossings: list[tuple[int, str]] = []
    reasons = np.full(n, "", dtype=object)
    feasible = np.ones(n, bool)
    for loop in machine.loops:
        theta2, omega2, alpha2 = _crank_input(machine, loop, loops, motion)
        steps[loop.name] = _crank_steps(loop, loops, steps, motion)
        upstream = np.ones(n, bool) if loop.driven_by is None else assembled[loop.driven_by.loop]
        result = _solve_loop(machine, loop, theta2, omega2, alpha2, steps[loop.name])
        result = replace(result, crossings=tuple(
            c for c in result.crossings if upstream[c.position - 1] and upstream[c.position]
        ))
        assembled[loop.name] = upstream & result.feasible
        crossings += [
            (c.position, describe(
                loop.name, loop.kind, c, float(motion.angle_deg[c.position - 1]),
                float(motion.angle_deg[c.position]), loop.driven_by is None,
            ))
            for c in result.crossings
        ]
        loops[loop.name] = result
        for role_name, role in loop.roles.items():
            if role.link in links:
                continue
            if role_name == "ground":
                p, _ = machine.axis(role)
                links[role.link] = fixed_link(role.joints, machine.axis_angle(role), p, n)
            else:
                links[role.link] = result.links[role_name]
        failing = feasible & (result.status != 0)
        if failing.any():
            texts = np.asarray(result.reason_texts, dtype=object)[result.status[failing]]
            if loop.driven_by is not None:
                texts = np.char.add(f"driven loop '{loop.name}' infeasible: ", texts.astype(str))
            reasons[failing] = texts
            feasible &= result.status == 0
    return MachineMotion(
        motion.angle, motion.speed, motion.acceleration, motion.time, feasible,
        tuple(reasons.tolist()), links, loops, tuple(sorted(crossings, key=lambda c: c[0])),
    )


def _crank_input(machine: Machine, loop: Loop, solved: dict[str, LoopMotion], motion: InputMotion):
    drive = loop.driven_by
    if drive is None:
        return motion.angle, motion.speed, motion.acceleration
    driver = solved[drive.loop]
    if drive.role == "crank":
        angle, speed, acceleration = driver.theta2, driver.omega2, driver.alpha2
    else:
        angle, speed, acceleration = driver.theta4, driver.omega4, driver.alpha4
    return angle + machine.drive_offset(loop), speed, acceleration


def _crank_steps(loop: Loop, solved: dict[str, LoopMotion], steps: dict[str, np.ndarray], motion: InputMotion):
    """The loop's crank turn [rad] from each position to the next."""
    drive = loop.driven_by
    if drive is None:
        return np.diff(motion.angle)
    if drive.role == "crank":
        return steps[drive.loop]
    return wrapped_steps(solved[drive.loop].theta4)


def _solve_loop(machine: Machine, loop: Loop, theta2, omega2, alpha2, steps) -> LoopMotion:
    linkage = machine.geometry(loop)
    frames = {name: role.joints for name, role in loop.roles.items()}
    if isinstance(linkage, FourBar):
        return solve_fourbar(linkage, theta2, omega2, alpha2, frames, steps)
    return solve_slider_crank(linkage, theta2, omega2, alpha2, frames, steps)
