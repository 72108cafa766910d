"""Machines: loops chained by a power graph, solved in order, with clear errors for bad graphs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkstress.kinematics import Drive, LinkageError, Loop, Machine, Role, angle_motion, solve_machine
from linkstress.kinematics.fourbar import FourBar, solve_fourbar

pytestmark = pytest.mark.filterwarnings("error")

LINKS = {
    "ground": [[0.0, 0.0], [0.06, 0.0], [0.06, 0.1]],  # O2, O4 of the main loop, O4 of "bell"
    "crank": [[0.0, 0.0], [0.08, 0.0]],
    "coupler": [[0.0, 0.0], [0.08, 0.0]],
    # A bell crank: pivot O4, joint B of the main loop, and a second arm at 90 degrees.
    "rocker": [[0.0, 0.0], [0.09, 0.0], [0.0, 0.03]],
    "link2": [[0.0, 0.0], [0.1, 0.0]],
    "out2": [[0.0, 0.0], [0.08, 0.0]],
    "crank3": [[0.0, 0.0], [0.02, 0.0]],
    "rod3": [[0.0, 0.0], [0.07, 0.0]],
    "piston": [[0.0, 0.0]],
    "frame3": [[0.3, 0.0], [0.4, 0.0]],
}


def main_loop(**changes) -> Loop:
    fields = dict(
        name="main", kind="four-bar", crank=Role("crank"), coupler=Role("coupler"), ground=Role("ground"),
        output=Role("rocker"),
    )
    fields.update(changes)
    return Loop(**fields)


def bell_loop(**changes) -> Loop:
    fields = dict(
        name="bell", kind="four-bar", crank=Role("rocker", (0, 2)), coupler=Role("link2"),
        ground=Role("ground", (1, 2)), output=Role("out2"), driven_by=Drive("main", "output"),
    )
    fields.update(changes)
    return Loop(**fields)


def engine_loop(**changes) -> Loop:
    fields = dict(
        name="engine", kind="slider-crank", crank=Role("crank3"), coupler=Role("rod3"),
        ground=Role("frame3"), slider=Role("piston", (0, 0)), offset=0.005,
        driven_by=Drive("main", "crank", phase=math.radians(90.0)),
    )
    fields.update(changes)
    return Loop(**fields)


def machine(*loops: Loop, links=None) -> Machine:
    return Machine(links or LINKS, loops)


def test_loops_are_solved_drivers_first_and_rigidity_comes_from_link_names():
    m = machine(engine_loop(), bell_loop(), main_loop())
    assert [loop.name for loop in m.loops] == ["main", "engine", "bell"]
    assert m.loop("bell").driven_by.rigid and not m.loop("engine").driven_by.rigid
    assert m.link_frames["rocker"] == (0, 1)  # the main loop's output axis O4 -> B


def test_a_bell_crank_carries_its_second_arm_rigidly_and_a_coupling_adds_its_phase():
    m = machine(main_loop(), bell_loop(), engine_loop())
    motion = angle_motion(np.arange(0.0, 360.0, 10.0), 100.0, 18.0)
    result = solve_machine(m, motion)
    main, bell, engine = (result.loops[k] for k in ("main", "bell", "engine"))
    # The bell crank's second arm is drawn 90 degrees from its first.
    assert np.allclose(bell.theta2, main.theta4 + math.pi / 2)
    assert np.array_equal(bell.omega2, main.omega4) and np.array_equal(bell.alpha2, main.alpha4)
    # Joint 2 of the rocker, moved with the main loop's output, is the bell loop's crank pin.
    local = np.array([0.0, 0.03])
    p, v, a = result.links["rocker"].point(local)
    ok = result.feasible
    assert np.allclose(p[ok], bell.joints["A"].position[ok], atol=1e-15)
    assert np.allclose(v[ok], bell.joints["A"].velocity[ok], rtol=1e-12)
    assert np.allclose(a[ok], bell.joints["A"].acceleration[ok], rtol=1e-11, atol=1e-9)
    assert np.allclose(engine.theta2, main.theta2 + math.pi / 2)
    # The main loop alone gives the same answers as inside the machine.
    alone = solve_fourbar(FourBar((0, 0), (0.06, 0), 0.08, 0.08, 0.09), motion.angle, 100.0, 18.0)
    assert np.array_equal(alone.alpha4, main.alpha4)
    assert set(result.links) == set(LINKS)
    assert not np.any(result.links["ground"].omega) and result.links["frame3"].angle[0] == 0.0


def test_a_driven_loops_dead_point_makes_the_machine_position_infeasible_with_its_reason():
    # Make the bell loop non-Grashof so it cannot follow the rocker everywhere.
    links = dict(LINKS, link2=[[0.0, 0.0], [0.12, 0.0]], out2=[[0.0, 0.0], [0.04, 0.0]])
    m = machine(main_loop(), bell_loop(), links=links)
    result = solve_machine(m, angle_motion(np.arange(0.0, 360.0, 1.0), 1.0, 0.0))
    bell = result.loops["bell"]
    assert not bell.feasible.all() and bell.feasible.any()
    assert np.array_equal(result.feasible, bell.feasible & result.loops["main"].feasible)
    bad = int(np.argmin(result.feasible))
    assert result.reasons[bad].startswith("driven loop 'bell' infeasible: unreachable")
    assert all(r == "" for r, ok in zip(result.reasons, result.feasible) if ok)


def test_a_crankshaft_with_two_throws_drives_two_cylinders():
    links = {
        "shaft": [[0.0, 0.0], [0.02, 0.0], [-0.02, 0.0]],  # throws 180 degrees apart
        "rod1": [[0.0, 0.0], [0.08, 0.0]],
        "rod2": [[0.0, 0.0], [0.08, 0.0]],
        "block": [[0.0, 0.0], [1.0, 0.0]],
    }
    loops = (
        Loop("cyl1", "slider-crank", Role("shaft"), Role("rod1"), Role("block")),
        Loop("cyl2", "slider-crank", Role("shaft", (0, 2)), Role("rod2"), Role("block"),
             driven_by=Drive("cyl1", "crank")),
    )
    result = solve_machine(Machine(links, loops), angle_motion([0.0, 90.0], 10.0, 0.0))
    one, two = result.loops["cyl1"], result.loops["cyl2"]
    assert np.allclose(two.theta2, one.theta2 + math.pi)
    assert np.allclose(one.slider_position, [0.1, math.sqrt(0.08**2 - 0.02**2)])
    assert np.allclose(two.slider_position, [0.06, math.sqrt(0.08**2 - 0.02**2)])


@pytest.mark.parametrize(
    "loops, message",
    [
        ((main_loop(driven_by=Drive("bell", "output")), bell_loop()), "the drives form a cycle (main -> bell -> main)"),
        ((main_loop(), bell_loop(driven_by=None)), "main, bell all lack driven_by"),
        ((main_loop(), bell_loop(driven_by=Drive("mian", "output"))), "no mechanism named 'mian'"),
        ((main_loop(), bell_loop(driven_by=Drive("main", "output", phase=0.1))), "mechanisms.bell.phase_deg"),
        ((main_loop(), bell_loop(crank=Role("rocker", (1, 2)))), "the crank must start there: joints = [0, ...]"),
        ((main_loop(), bell_loop(ground=Role("ground", (2, 1)))), "must be the pivot of link 'rocker'"),
        ((main_loop(), bell_loop(coupler=Role("coupler"))), "link 'coupler' is already the coupler of mechanisms.main"),
        ((main_loop(), engine_loop(), bell_loop(driven_by=Drive("engine", "output"))), "engine is a slider-crank"),
        ((main_loop(crank=Role("cranck")),), "mechanisms.main.crank: no link named 'cranck'; links are: coupler, crank"),
        ((main_loop(crank=Role("piston")),), "link 'piston' has 1 joint(s); a crank needs two (O2 -> A)"),
        ((main_loop(coupler=Role("coupler", (0, 2))),), "mechanisms.main.coupler.joints: link 'coupler' has joints 0..1, no joint 2"),
        ((main_loop(output=None),), "mechanisms.main.output: a four-bar needs an output link"),
        ((main_loop(coupler=Role("crank")),), "link 'crank' is both crank and coupler"),
        ((main_loop(), engine_loop(coupler=Role("ground"))), "the ground cannot move"),
    ],
)
def test_bad_machines_are_refused_with_the_key_to_fix(loops, message):
    with pytest.raises(LinkageError) as error:
        machine(*loops)
    assert message in str(error.value)


def test_lengths_that_can_never_assemble_are_refused():
    links = dict(LINKS, crank=[[0, 0], [0.01, 0]], coupler=[[0, 0], [0.01, 0]], rocker=[[0, 0], [0.01, 0]],
                 ground=[[0, 0], [1.0, 0]])
    with pytest.raises(LinkageError, match=r"mechanisms.main: these lengths can never assemble \(crank 0.01 m"):
        machine(main_loop(), links=links)


def test_coincident_joints_are_refused():
    links = dict(LINKS, crank=[[0.1, 0.1], [0.1, 0.1]])
    with pytest.raises(LinkageError, match=r"joints 0 and 1 of link 'crank' coincide at \(0.1, 0.1\) m"):
        machine(main_loop(), links=links)
