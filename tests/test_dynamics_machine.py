"""Machine-level joint forces: the scene's loops as one Newton-Euler system.

Checks: the seed reference, the power balance of whole machines (the actuator's power equals the
rate of change of kinetic energy minus the power of known loads; coupling torques are internal),
and the equilibrium of the load case handed to every link (the beam and FEA engines rely on it).
"""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from linkstress.dynamics.machine_forces import machine_forces
from linkstress.errors import SceneError
from linkstress.kinematics.solve import solve_machine
from linkstress.scene import load_scene

SEED_SOLID = """
    # The seed's ANSYS four-bar as the original program modelled it: solid 0.5 x 0.1 m steel bars.
    [links.crank]
    joints = [[0.0, 0.0], [1.0, 0.0]]
    mass = 471.0
    inertia = 66.3325            # m (1.2^2 + 0.5^2) / 12
    center_of_mass = [0.5, 0.0]
    [links.coupler]
    joints = [[0.0, 0.0], [1.5, 0.0]]
    mass = 667.25
    inertia = 174.5970833333     # m (1.7^2 + 0.5^2) / 12
    center_of_mass = [0.75, 0.0]
    [links.output]
    joints = [[0.0, 0.0], [1.5, 0.0]]
    mass = 667.25
    inertia = 174.5970833333
    center_of_mass = [0.75, 0.0]
    [links.ground]
    joints = [[0.0, 0.0], [2.0, 0.0]]
    [mechanisms.main]
    type = "four-bar"
    crank = "crank"
    coupler = "coupler"
    output = "output"
    ground = "ground"
    branch = "open"
    [motion]
    input_angle_deg = 60.0
    input_speed_rad_s = -1.0
    input_acceleration_rad_s2 = 0.0
    [loads.couples]
    output = 2.0
"""

SIX_BAR = """
    [links.crank]
    joints = [[0.0, 0.0], [0.04, 0.0]]
    mass = 0.3
    inertia = 1e-4
    center_of_mass = [0.02, 0.0]
    [links.coupler]
    joints = [[0.0, 0.0], [0.12, 0.0], [0.06, 0.03]]
    mass = 0.8
    inertia = 1.2e-3
    center_of_mass = [0.06, 0.01]
    [links.rocker]
    joints = [[0.0, 0.0], [0.1, 0.0], [-0.05, 0.0]]
    mass = 0.6
    inertia = 8e-4
    center_of_mass = [0.02, 0.0]
    [links.ground]
    joints = [[0.0, 0.0], [0.1, 0.0], [0.1, -0.15]]
    [links.rod2]
    joints = [[0.0, 0.0], [0.14, 0.0]]
    mass = 0.5
    inertia = 9e-4
    center_of_mass = [0.07, 0.0]
    [links.out2]
    joints = [[0.0, 0.0], [0.09, 0.0]]
    mass = 0.4
    inertia = 3e-4
    center_of_mass = [0.045, 0.005]
    [links.crank3]
    joints = [[0.0, 0.0], [0.03, 0.0]]
    mass = 0.2
    inertia = 5e-5
    center_of_mass = [0.015, 0.0]
    [links.rod3]
    joints = [[0.0, 0.0], [0.11, 0.0]]
    mass = 0.3
    inertia = 3e-4
    center_of_mass = [0.055, 0.0]
    [links.slider3]
    joints = [[0.0, 0.0]]
    mass = 0.7
    inertia = 0.0
    center_of_mass = [0.0, 0.0]
    [links.ground3]
    joints = [[0.0, 0.0], [0.2, 0.0]]
    [mechanisms.main]
    type = "four-bar"
    crank = "crank"
    coupler = {link = "coupler", joints = [0, 1]}
    output = {link = "rocker", joints = [0, 1]}
    ground = {link = "ground", joints = [0, 1]}
    [mechanisms.second]
    type = "four-bar"
    driven_by = "main.output"
    crank = {link = "rocker", joints = [0, 2]}
    coupler = "rod2"
    output = "out2"
    ground = {link = "ground", joints = [1, 2]}
    [mechanisms.third]
    type = "slider-crank"
    driven_by = "main.crank"
    phase_deg = 90.0
    crank = "crank3"
    coupler = "rod3"
    slider = "slider3"
    ground = "ground3"
    offset_m = 0.01
    [motion]
    input_angle_deg = {start = 0.0, stop = 350.0, num = 36}
    input_speed_rad_s = 30.0
    input_acceleration_rad_s2 = 5.0
    [loads]
    gravity_m_s2 = [0.0, -9.81]
    [loads.couples]
    out2 = 0.3
    [loads.friction]
    third = 0.15
    [[loads.forces]]
    link = "rod2"
    at_m = [0.07, 0.0]
    force_n = [1.0, 2.0]
"""


def scene_file(tmp_path, text, **replace):
    text = textwrap.dedent(text)
    for old, new in replace.items():
        text = text.replace(old, new)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return load_scene(path)


def kinetic_power(scene, motion):
    """sum over moving links of m a_G . v_G + I_G alpha omega - m g . v_G [W] (P,)."""
    total = np.zeros(len(motion.input_angle))
    g = np.asarray(scene.loads.gravity, float)
    for name in scene.moving_links:
        data = scene.links[name].mass_data
        link = motion.links[name]
        _, v, a = link.point(data.center_of_mass)
        total += data.mass * ((a - g) * v).sum(axis=1) + data.inertia * link.alpha * link.omega
    return total


def known_load_power(scene, motion):
    total = np.zeros(len(motion.input_angle))
    for c in scene.loads.couples:
        total += c.value * motion.links[c.link].omega
    for f in scene.loads.forces:
        _, v, _ = motion.links[f.link].point(f.at)
        total += (np.asarray(f.force) * v).sum(axis=1)
    return total


def test_seed_scene_gives_the_reference_forces_and_torque(tmp_path):
    scene = scene_file(tmp_path, SEED_SOLID)
    forces = machine_forces(scene, solve_machine(scene.machine, scene.motion))
    main = forces.mechanisms["main"]
    reference = {"F12": (-869.94, -694.86), "F32": (752.19, 490.91), "F43": (246.60, 87.01), "F14": (-92.19, -27.97)}
    for name, value in reference.items():
        np.testing.assert_allclose(main.forces[name][0], value, rtol=1e-3)
    assert main.torque_name == "T12"
    assert main.driving_torque[0] == pytest.approx(405.96, rel=1e-3)


def test_every_link_load_case_is_in_equilibrium(tmp_path):
    scene = scene_file(tmp_path, SIX_BAR)
    motion = solve_machine(scene.machine, scene.motion)
    forces = machine_forces(scene, motion)
    assert forces.feasible.any()
    for name, loads in forces.link_loads.items():
        data, link = scene.links[name].mass_data, scene.links[name]
        force, moment = loads.residual_of(data.mass, data.inertia, data.center_of_mass, link.to_member(link.joints))
        ok = forces.feasible
        scale = np.abs(loads.pin_forces).max() + 1.0
        np.testing.assert_allclose(force[ok], 0, atol=1e-9 * scale, err_msg=name)
        np.testing.assert_allclose(moment[ok], 0, atol=1e-9 * scale * 0.2, err_msg=name)


def test_machine_power_balance_with_coupled_and_rigid_drives_gravity_friction_and_loads(tmp_path):
    # Actuator power + known loads' power + friction power = rate of kinetic energy (+ gravity's).
    scene = scene_file(tmp_path, SIX_BAR)
    motion = solve_machine(scene.machine, scene.motion)
    forces = machine_forces(scene, motion)
    main = forces.mechanisms["main"]
    assert forces.mechanisms["second"].driving_torque is None  # its crank is the rocker itself
    third = forces.mechanisms["third"]
    assert third.torque_name == "Tmain"
    friction = third.forces["F14"] * motion.loops["third"].joints["B"].velocity
    power = main.driving_torque * motion.input_speed + known_load_power(scene, motion) + friction.sum(axis=1)
    ok = forces.feasible
    demand = kinetic_power(scene, motion)
    np.testing.assert_allclose(power[ok], demand[ok], rtol=1e-9, atol=1e-9 * np.abs(demand).max())


def test_actuator_on_the_output_carries_t14_and_the_crank_carries_none(tmp_path):
    text = SEED_SOLID.replace("input_acceleration_rad_s2 = 0.0", 'input_acceleration_rad_s2 = 0.0\n    actuator = "output"')
    scene = scene_file(tmp_path, text)
    motion = solve_machine(scene.machine, scene.motion)
    main = machine_forces(scene, motion).mechanisms["main"]
    assert main.torque_name == "T14"
    power = main.driving_torque * motion.loops["main"].omega4 + known_load_power(scene, motion)
    np.testing.assert_allclose(power, kinetic_power(scene, motion), rtol=1e-9)


def test_slider_actuator_pushes_along_its_line_with_the_power_the_machine_needs(tmp_path):
    text = SIX_BAR.replace('input_acceleration_rad_s2 = 5.0', 'input_acceleration_rad_s2 = 5.0\n    actuator = "slider3"')
    scene = scene_file(tmp_path, text)
    motion = solve_machine(scene.machine, scene.motion)
    forces = machine_forces(scene, motion)
    third = forces.mechanisms["third"]
    assert third.driving_force is not None and forces.mechanisms["main"].driving_torque is None
    v_b = motion.loops["third"].slider_velocity
    friction = (third.forces["F14"] * motion.loops["third"].joints["B"].velocity).sum(axis=1)
    power = third.driving_force * v_b + known_load_power(scene, motion) + friction
    ok = forces.feasible & (np.abs(v_b) > 1e-6)
    demand = kinetic_power(scene, motion)
    np.testing.assert_allclose(power[ok], demand[ok], rtol=1e-9, atol=1e-9 * np.abs(demand).max())


def test_a_link_without_mass_data_is_named_with_the_keys_that_fix_it(tmp_path):
    text = SEED_SOLID.replace("mass = 471.0\n    inertia = 66.3325            # m (1.2^2 + 0.5^2) / 12\n    center_of_mass = [0.5, 0.0]\n", "")
    scene = scene_file(tmp_path, text)
    with pytest.raises(SceneError, match=r"links.crank: joint forces need this link's mass: give mass, inertia and center_of_mass"):
        machine_forces(scene, solve_machine(scene.machine, scene.motion))
