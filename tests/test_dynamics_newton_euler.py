"""Newton-Euler joint forces and driving torques against closed-form and reference values."""

from __future__ import annotations

import numpy as np
import pytest

from linkstress.geometry.builders import straight_bar
from linkstress.dynamics.newton_euler import (
    GROUND, Actuator, AppliedCouple, Assembly, Body, Pin, Slide, solve_forces,
)
from linkstress.kinematics.fourbar import FourBar, solve_fourbar
from linkstress.kinematics.slider_crank import SliderCrank, solve_slider_crank
from linkstress.materials import Material

STEEL = Material("steel", 7850.0, 200e9, 0.3)


def test_crank_accelerated_from_rest_needs_i_o_alpha_and_its_pivot_carries_m_a_g():
    # Uniform bar pinned at one end, at rest, angular acceleration alpha: T = I_O alpha, F = m a_G.
    m, length, alpha = 12.0, 0.5, 4.0
    i_g = m * length**2 / 12
    theta = np.array([0.0, 0.7])
    g_pos = 0.25 * np.column_stack([np.cos(theta), np.sin(theta)])
    a_g = alpha * 0.25 * np.column_stack([-np.sin(theta), np.cos(theta)])
    body = Body("crank", m, i_g, g_pos, a_g, np.full(2, alpha))
    assembly = Assembly((body,), (Pin("O2", 0, GROUND, np.zeros((2, 2))),), (Actuator("T", 0),))
    solution = solve_forces(assembly)
    np.testing.assert_allclose(solution.torques["T"], (i_g + m * 0.25**2) * alpha, rtol=1e-12)
    np.testing.assert_allclose(solution.pin_forces["O2"], m * a_g, rtol=1e-12, atol=1e-12)


def test_static_pendulum_under_gravity_holds_m_g_and_the_moment_m_g_r():
    m, r = 3.0, 0.4
    body = Body("arm", m, 0.1, np.array([[r, 0.0]]), np.zeros((1, 2)), np.zeros(1))
    assembly = Assembly(
        (body,), (Pin("O", 0, GROUND, np.zeros((1, 2))),), (Actuator("T", 0),),
        gravity=np.array([0.0, -9.81]),
    )
    solution = solve_forces(assembly)
    assert solution.pin_forces["O"][0] == pytest.approx([0.0, m * 9.81])
    assert solution.torques["T"][0] == pytest.approx(m * 9.81 * r)


def seed_assembly(hole_diameter=None, theta_deg=60.0):
    """The seed's ANSYS four-bar (seed-ansys-fourbar.md): steel bars 0.5 x 0.1 m, joint spacings
    1.0 / 1.5 / 1.5 m on a 2.0 m ground, crank at 60 deg turning at -1 rad/s, +2 N m on the output."""
    loop = solve_fourbar(FourBar((0, 0), (2, 0), 1.0, 1.5, 1.5, "open"), np.radians(np.atleast_1d(theta_deg)), -1.0, 0.0)
    bodies = []
    for name, spacing in (("crank", 1.0), ("coupler", 1.5), ("output", 1.5)):
        bar = straight_bar(spacing, 0.5, 0.1, 0.1, STEEL, hole_diameter=hole_diameter)
        motion = loop.links[name]
        position, _, acceleration = motion.point(bar.frame().to_local(bar.center_of_mass))
        bodies.append(Body(name, bar.mass, bar.mass_moment_of_inertia, position, acceleration, motion.alpha))
    j = loop.joints
    pins = (
        Pin("F12", 0, GROUND, j["O2"].position), Pin("F32", 0, 1, j["A"].position),
        Pin("F43", 1, 2, j["B"].position), Pin("F14", 2, GROUND, j["O4"].position),
    )
    couple = AppliedCouple(2, np.full(len(loop.theta2), 2.0))
    return Assembly(tuple(bodies), pins, (Actuator("T12", 0),), couples=(couple,)), loop


def test_seed_ansys_fourbar_forces_and_torque_match_the_reference_to_0_1_percent():
    # seed-ansys-fourbar.md, "What the original program printed": solid bars as that program modelled them.
    solution = solve_forces(seed_assembly()[0])
    reference = {"F12": (-869.94, -694.86), "F32": (752.19, 490.91), "F43": (246.60, 87.01), "F14": (-92.19, -27.97)}
    for name, value in reference.items():
        np.testing.assert_allclose(solution.pin_forces[name][0], value, rtol=1e-3)
    assert solution.torques["T12"][0] == pytest.approx(405.96, rel=1e-3)


def test_seed_pin_holes_lower_the_masses_and_forces_by_about_a_tenth_of_a_percent():
    solid = solve_forces(seed_assembly()[0])
    holed = solve_forces(seed_assembly(0.02)[0])
    change = abs(holed.torques["T12"][0] / solid.torques["T12"][0] - 1)
    assert 5e-4 < change < 1.5e-3


def test_driving_torque_equals_the_power_balance_over_a_sweep():
    # Virtual power: T omega2 + C omega4 = sum (m a_G . v_G + I_G alpha omega) for every position.
    assembly, loop = seed_assembly(theta_deg=np.linspace(5, 355, 36))  # 180 deg is a toggle
    solution = solve_forces(assembly)
    power = solution.torques["T12"] * loop.omega2 + 2.0 * loop.omega4
    kinetic = np.zeros_like(power)
    for body, name in zip(assembly.bodies, ("crank", "coupler", "output")):
        motion = loop.links[name]
        r_g = body.position_g - motion.origin
        v_g = motion.origin_velocity + motion.omega[:, None] * np.column_stack([-r_g[:, 1], r_g[:, 0]])
        kinetic += body.mass * (body.acc_g * v_g).sum(axis=1) + body.inertia * body.alpha * motion.omega
    assert solution.solved.all()
    np.testing.assert_allclose(power, kinetic, rtol=1e-9, atol=1e-9 * np.abs(kinetic).max())


def test_singular_positions_are_reported_not_solved():
    # The seed four-bar at theta2 = 180 deg: |A - O4| = 3 m = coupler + output, all joints in line
    # (a toggle). Pin forces would be unbounded: the position is flagged, its values are zero filler.
    o2, a, b, o4 = np.array([[0.0, 0.0]]), np.array([[-1.0, 0.0]]), np.array([[0.5, 0.0]]), np.array([[2.0, 0.0]])
    zero = np.zeros((1, 2))
    bodies = (
        Body("crank", 1.0, 0.1, (o2 + a) / 2, zero, np.zeros(1)),
        Body("coupler", 1.0, 0.1, (a + b) / 2, zero, np.zeros(1)),
        Body("output", 1.0, 0.1, (b + o4) / 2, zero, np.zeros(1)),
    )
    pins = (Pin("F12", 0, GROUND, o2), Pin("F32", 0, 1, a), Pin("F43", 1, 2, b), Pin("F14", 2, GROUND, o4))
    solution = solve_forces(Assembly(bodies, pins, (Actuator("T12", 0),), couples=(AppliedCouple(2, np.ones(1)),)))
    assert not solution.solved[0]
    assert np.isfinite(solution.pin_forces["F43"]).all()


def test_assembly_must_be_square():
    body = Body("rod", 1.0, 0.1, np.array([[0.5, 0.0]]), np.zeros((1, 2)), np.zeros(1))
    pins = (Pin("O", 0, GROUND, np.zeros((1, 2))), Pin("A", 0, GROUND, np.array([[1.0, 0.0]])))
    with pytest.raises(ValueError, match="3 equations and 5 unknowns"):
        solve_forces(Assembly((body,), pins, (Actuator("T", 0),)))


def test_slider_crank_friction_opposes_the_slider_velocity_and_costs_its_power():
    # Crank 0.1 m, rod 0.3 m, 0.02 m offset, 2 kg slider on a guide with mu = 0.2, gravity on.
    # Power balance: T omega2 + F_friction . v_B = sum (m a_G . v_G + I_G alpha omega) - m g . v_G.
    mu, g = 0.2, np.array([0.0, -9.81])
    theta = np.radians(np.linspace(10, 350, 35))
    loop = solve_slider_crank(SliderCrank((0, 0), 0.1, 0.3, offset=0.02), theta, 50.0, 0.0)
    masses = {"crank": (1.0, 0.002, 0.05), "coupler": (1.5, 0.012, 0.15)}
    bodies = []
    for name, (m, i_g, half) in masses.items():
        motion = loop.links[name]
        pos, _, acc = motion.point([half, 0.0])
        bodies.append(Body(name, m, i_g, pos, acc, motion.alpha))
    b = loop.joints["B"]
    bodies.append(Body("slider", 2.0, 0.0, b.position, b.acceleration, np.zeros(len(theta))))
    pins = (Pin("F12", 0, GROUND, loop.joints["O2"].position), Pin("F32", 0, 1, loop.joints["A"].position),
            Pin("F43", 1, 2, b.position))
    slide = Slide("F14", 2, np.array([1.0, 0.0]), b.position, loop.slider_velocity, friction=mu)
    solution = solve_forces(Assembly(tuple(bodies), pins, (Actuator("T12", 0),), slides=(slide,), gravity=g))
    assert solution.solved.all()
    f14 = solution.slide_forces["F14"]
    np.testing.assert_allclose(f14[:, 0], -mu * np.abs(f14[:, 1]) * np.sign(loop.slider_velocity), rtol=1e-12)
    power_in = solution.torques["T12"] * loop.omega2 + (f14 * b.velocity).sum(axis=1)
    demand = np.zeros(len(theta))
    for body, name in zip(bodies, ("crank", "coupler", "slider")):
        motion = loop.links[name]
        half = masses[name][2] if name in masses else 0.0  # the slider's G is its joint B
        _, v_g, _ = motion.point([half, 0.0])
        demand += body.mass * ((body.acc_g - g) * v_g).sum(axis=1) + body.inertia * body.alpha * motion.omega
    np.testing.assert_allclose(power_in, demand, rtol=1e-9, atol=1e-9 * np.abs(demand).max())
