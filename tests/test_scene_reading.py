"""Scene files: every part of the schema is read into checked, SI values."""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest

from linkstress.kinematics import solve_machine
from linkstress.scene import load_scene

SEED = """
    # The seed's ANSYS four-bar (docs/reference/seed-ansys-fourbar.md) with explicit masses.
    [materials.steel]
    density = 7850.0
    youngs_modulus = 200e9
    poisson_ratio = 0.3
    yield_strength = 250e6

    [links.crank]
    joints = [[0.0, 0.0], [1.0, 0.0]]
    mass = 471.0
    inertia = 66.33
    center_of_mass = [0.5, 0.0]

    [links.coupler]
    joints = [[0.0, 0.0], [1.5, 0.0]]
    mass = 667.25
    inertia = 171.6
    center_of_mass = [0.75, 0.0]

    [links.output]
    joints = [[0.0, 0.0], [1.5, 0.0]]
    mass = 667.25
    inertia = 171.6
    center_of_mass = [0.75, 0.0]
    material = "steel"
    thickness = 0.1

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


def write(tmp_path, text: str, name: str = "scene.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_the_seed_scene_reproduces_its_published_kinematics(tmp_path):
    scene = load_scene(write(tmp_path, SEED))
    motion = solve_machine(scene.machine, scene.motion)
    assert motion.feasible.tolist() == [True]
    # The seed's table (3 decimals): a_G and alpha of each link at theta2 = 60 deg, omega2 = -1 rad/s.
    expected = {
        "crank": ((-0.250, -0.433), 0.0),
        "coupler": ((-0.758, -0.605), 0.459),
        "output": ((-0.508, -0.172), 0.695),
    }
    for name, (acc_g, alpha) in expected.items():
        got = motion.links[name].point(scene.links[name].center_of_mass)[2][0]
        assert got == pytest.approx(acc_g, abs=5e-4)
        assert motion.links[name].alpha[0] == pytest.approx(alpha, abs=5e-4)
    assert scene.actuator == "crank"
    assert scene.loads.couples[0].link == "output" and scene.loads.couples[0].value == 2.0
    assert scene.loads.couples[0].at_joint == 0  # the output's frame origin, O4
    assert scene.materials["steel"].yield_strength == 250e6
    assert scene.links["output"].material.density == 7850.0
    assert scene.links["output"].mass_data.mass == 667.25
    assert scene.links["ground"].mass_data is None
    assert scene.analysis is None
    assert scene.moving_links == ("crank", "coupler", "output")


def test_every_optional_part_of_the_schema_is_read(tmp_path):
    scene = load_scene(write(tmp_path, """
        units = "mm"

        [links.crank]
        joints = [[0.0, 0.0], [0.02, 0.0], [-0.02, 0.0]]
        [links.rod]
        joints = [[0.0, 0.0], [0.08, 0.0]]
        [links.rod2]
        joints = [[0.0, 0.0], [0.08, 0.0]]
        [links.piston]
        joints = [[0.0, 0.0]]
        mass = 0.3
        inertia = 0.0
        center_of_mass = [0.0, 0.0]
        [links.rod3]
        joints = [[0.08, 0.0], [0.0, 0.0]]
        [links.crank2]
        joints = [[0.0, 0.0], [0.02, 0.0]]
        [links.block]
        joints = [[0.0, 0.0], [1.0, 0.0], [0.0, 0.5], [0.0, 1.5]]

        [mechanisms.cyl1]
        type = "slider-crank"
        crank = {link = "crank", joints = [0, 1]}
        coupler = "rod"
        ground = {link = "block", joints = [0, 1]}
        slider = {link = "piston", joints = [0]}
        offset_m = 0.005
        branch = "crossed"

        [mechanisms.cyl2]
        type = "slider-crank"
        crank = {link = "crank", joints = [0, 2]}
        coupler = "rod2"
        ground = {link = "block", joints = [0, 1]}
        slider_angle_deg = 90.0
        driven_by = "cyl1.crank"

        [mechanisms.cyl3]
        type = "slider-crank"
        crank = "crank2"
        coupler = {link = "rod3", joints = [1, 0]}
        ground = {link = "block", joints = [2, 3]}
        driven_by = "cyl1.crank"
        phase_deg = 120.0

        [motion]
        input_angle_deg = {expression = "90*sin(2*pi*t)", t = {start = 0.0, stop = 1.0, num = 5}}
        actuator = "piston"

        [loads]
        gravity_m_s2 = [0.0, -9.81]
        [loads.couples]
        crank = {value = 2.5, at_joint = 1}
        [[loads.forces]]
        link = "rod2"
        at_m = [0.04, 0.0]
        force_n = [10.0, -5.0]
        [loads.friction]
        piston = 0.1
        cyl2 = 0.2

        [analysis]
        forces = true
        stations = 21
        mesh_size_m = 0.002
        element_order = 1
        body_load_near_holes = true
    """))
    assert scene.units == "mm"
    cyl1, cyl2, cyl3 = (scene.machine.loop(n) for n in ("cyl1", "cyl2", "cyl3"))
    assert cyl1.branch == "crossed" and cyl1.offset == 0.005 and cyl1.slider.joints == (0, 0)
    assert cyl2.driven_by.rigid and cyl2.crank.joints == (0, 2) and cyl2.slider_angle == pytest.approx(math.pi / 2)
    assert not cyl3.driven_by.rigid and cyl3.driven_by.phase == pytest.approx(math.radians(120.0))
    assert cyl3.ground.joints == (2, 3)
    assert scene.motion.time.tolist() == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert scene.motion.speed[0] == pytest.approx(math.radians(180 * math.pi))
    assert scene.actuator == "piston"
    assert scene.loads.gravity.tolist() == [0.0, -9.81]
    assert (scene.loads.couples[0].value, scene.loads.couples[0].at_joint) == (2.5, 1)
    assert scene.loads.forces[0].at.tolist() == [0.04, 0.0] and scene.loads.forces[0].force.tolist() == [10.0, -5.0]
    assert scene.loads.friction == {"cyl1": 0.1, "cyl2": 0.2}
    assert scene.analysis.forces and not scene.analysis.stresses and not scene.analysis.kinematics
    assert (scene.analysis.stations, scene.analysis.mesh_size, scene.analysis.element_order) == (21, 0.002, 1)
    assert scene.analysis.body_load_near_holes
    assert scene.links["piston"].frame_joints == (0, 0)
    result = solve_machine(scene.machine, scene.motion)
    assert np.allclose(result.loops["cyl2"].theta2, result.loops["cyl1"].theta2 + math.pi)


def test_a_centre_of_mass_from_explicit_data_is_in_the_member_frame_of_the_links_role(tmp_path):
    text = SEED.replace(
        "[links.coupler]\n    joints = [[0.0, 0.0], [1.5, 0.0]]",
        "[links.coupler]\n    joints = [[5.0, 5.0], [5.0, 6.5]]",  # drawn vertically, elsewhere
    )
    scene = load_scene(write(tmp_path, text))
    link = scene.links["coupler"]
    assert link.frame_joints == (0, 1)
    assert link.to_member(np.array([5.0, 5.75])) == pytest.approx([0.75, 0.0])
    motion = solve_machine(scene.machine, scene.motion)
    assert motion.links["coupler"].point(link.center_of_mass)[2][0] == pytest.approx((-0.758, -0.605), abs=5e-4)


def test_title_and_notes_are_read_for_the_reports(tmp_path):
    scene = load_scene(write(tmp_path, 'title = "Seed check"\nnotes = ["loads as stated", "no gravity"]\n' + SEED))
    assert scene.title == "Seed check"
    assert scene.notes == ("loads as stated", "no gravity")
    plain = load_scene(write(tmp_path, SEED, name="plain.toml"))
    assert plain.title == "plain" and plain.notes == ()


def test_notes_must_be_text(tmp_path):
    from linkstress.errors import SceneError

    with pytest.raises(SceneError, match="notes: must be a string or a list of strings"):
        load_scene(write(tmp_path, "notes = [1, 2]\n" + SEED))
