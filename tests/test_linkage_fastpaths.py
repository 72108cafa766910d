"""The four-bar and slider-crank closed forms stay as fast paths: the linkage engine agrees with
them to 1e-12 (positions, rates, joint forces and driving torque) on the seed four-bar's lengths, a
slider-crank with offset and friction, and the six-bar case written as one linkage.

The two scenes of each pair describe one machine: the loop form with links drawn apart, the
linkage form with the same links drawn assembled at the loop engine's pose, the same mass data in
the same member frames (each link's joints 0 -> 1, or 1 -> 2 reordered to 0 -> 1)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkstress.analysis import run_analysis
from linkstress.dynamics.linkage_forces import power_balance
from linkstress.kinematics import solve_machine
from linkstress.scene import load_scene

from linkage_scenes import link_table, linkage_scene

MOTION = "input_angle_deg = {start = 0.0, stop = 350.0, num = 36}\ninput_speed_rad_s = 12.0\ninput_acceleration_rad_s2 = -30.0"
MASS = {  # kg, kg m^2, centre of mass in the member frame [m]
    "crank": (0.4, 2e-3, (0.1, 0.01)), "coupler": (1.1, 1.5e-2, (0.2, -0.02)), "output": (0.9, 1.1e-2, (0.15, 0.03)),
    "rod": (0.7, 6e-3, (0.09, 0.0)), "piston": (0.5, 1e-4, (0.01, 0.0)), "rocker": (0.8, 7e-3, (0.05, 0.01)),
    "rod2": (0.6, 4e-3, (0.07, 0.0)), "out2": (0.3, 1e-3, (0.045, 0.0)),
}
LOADS = "\n[loads]\ngravity_m_s2 = [0.0, -9.81]\n[loads.couples]\n{link} = 2.0\n"


def table(name, joints):
    mass, inertia, com = MASS.get(name, (None, 0.0, (0.0, 0.0)))
    return link_table(name, joints, mass, com, inertia)


def close(a, b, scale=None, rows=slice(None)):
    """|a - b| at ``rows`` against 1e-12 of the larger's size (or ``scale``)."""
    a, b = np.asarray(a)[rows], np.asarray(b)[rows]
    size = scale if scale is not None else max(float(np.abs(b).max()), 1e-300)
    return float(np.abs(a - b).max()) <= 1e-12 * size


def loop_scene(tmp_path, links: str, mechanisms: str, output: str, name="loops.toml"):
    path = tmp_path / name
    path.write_text(links + mechanisms + f"\n[motion]\n{MOTION}\n" + LOADS.format(link=output))
    return load_scene(path)


def seed_fourbar(tmp_path):
    """The seed ANSYS case's lengths (crank 1, coupler and output 1.5, ground 2 m: a change-point
    four-bar, at 180 deg all in line), as bare joints."""
    seed = load_scene("validation/cases/seed_ansys_fourbar/scene.toml")
    lengths = {name: float(np.hypot(*np.diff(link.joints[:2], axis=0)[0])) for name, link in seed.links.items()}
    ground = seed.links["ground"].joints
    apart = "".join(
        table(name, [[0.0, 0.0], [lengths[name], 0.0]]) for name in ("crank", "coupler", "output")
    ) + link_table("ground", ground)
    loops = loop_scene(tmp_path, apart, '[mechanisms.main]\ntype = "four-bar"\ncrank = "crank"\ncoupler = "coupler"\n'
                       'output = "output"\nground = "ground"\nbranch = "open"\n', "output")
    pose = solve_machine(loops.machine, loops.motion).loops["main"].joints
    o2, a, b, o4 = (pose[k].position[0] for k in ("O2", "A", "B", "O4"))
    drawn = table("crank", [o2, a]) + table("coupler", [a, b]) + table("output", [o4, b]) + link_table("ground", ground)
    linkage = linkage_scene(
        tmp_path, drawn, [["ground:0", "crank:0"], ["crank:1", "coupler:0"], ["coupler:1", "output:1"], ["ground:1", "output:0"]],
        MOTION, extra=LOADS.format(link="output"),
    )
    return loops, linkage, {"F12": ("pin ground:0-crank:0", 1), "F32": ("pin crank:1-coupler:0", -1),
                            "F43": ("pin coupler:1-output:1", -1), "F14": ("pin ground:1-output:0", 1)}


def offset_slider_crank(tmp_path, friction=0.0):
    """Crank 0.12 m, rod 0.35 m, the slider line 0.04 m off the crank's pivot at 20 deg."""
    angle, offset = math.radians(20.0), 0.04
    u = np.array([math.cos(angle), math.sin(angle)])
    foot = offset * np.array([-u[1], u[0]])
    ground = [[0.0, 0.0], foot, foot + 0.5 * u]
    apart = table("crank", [[0, 0], [0.12, 0]]) + table("rod", [[0, 0], [0.35, 0]]) + table("piston", [[0, 0]])
    apart += link_table("ground", [[0.0, 0.0], [1.0, 0.0]])
    friction_text = f"[loads.friction]\npiston = {friction}\n" if friction else ""
    loops = loop_scene(tmp_path, apart, '[mechanisms.main]\ntype = "slider-crank"\ncrank = "crank"\ncoupler = "rod"\n'
                       f'ground = "ground"\nslider = "piston"\noffset_m = {offset}\nslider_angle_deg = 20.0\n', "rod")
    if friction:
        path = tmp_path / "loops.toml"
        path.write_text(path.read_text() + friction_text)
        loops = load_scene(path)
    pose = solve_machine(loops.machine, loops.motion).loops["main"].joints
    o2, a, b = (pose[k].position[0] for k in ("O2", "A", "B"))
    drawn = table("crank", [o2, a]) + table("rod", [a, b]) + table("piston", [b]) + link_table("ground", ground)
    linkage = linkage_scene(
        tmp_path, drawn, [["ground:0", "crank:0"], ["crank:1", "rod:0"]], MOTION,
        sliders=[{"point": "rod:1", "on": "ground", "line": (1, 2), "block": "piston"}],
        extra=LOADS.format(link="rod") + friction_text,
    )
    return loops, linkage, {"F12": ("pin ground:0-crank:0", 1), "F32": ("pin crank:1-rod:0", -1),
                            "F43": ("pin rod:1-piston:0", -1), "F14": ("slider rod:1 on ground", 1)}


def six_bar(tmp_path):
    """validation/cases/six_bar's lengths: a crank-rocker whose ternary rocker drives a second
    four-bar rigidly; the rocker's joints ordered pivot, B, second crank pin (frame pivot -> B)."""
    rocker = [[0.0, 0.0], [0.1, 0.0], [-0.05, 0.0]]
    ground = [[0.0, 0.0], [0.1, 0.0], [0.1, -0.15]]
    apart = (table("crank", [[0, 0], [0.04, 0]]) + table("coupler", [[0, 0], [0.12, 0]]) + table("rocker", rocker)
             + table("rod2", [[0, 0], [0.14, 0]]) + table("out2", [[0, 0], [0.09, 0]]) + link_table("ground", ground))
    mechanisms = (
        '[mechanisms.main]\ntype = "four-bar"\ncrank = "crank"\ncoupler = "coupler"\n'
        'output = {link = "rocker", joints = [0, 1]}\nground = {link = "ground", joints = [0, 1]}\n'
        '[mechanisms.second]\ntype = "four-bar"\ndriven_by = "main.output"\ncrank = {link = "rocker", joints = [0, 2]}\n'
        'coupler = "rod2"\noutput = "out2"\nground = {link = "ground", joints = [1, 2]}\n'
    )
    loops = loop_scene(tmp_path, apart, mechanisms, "out2")
    motion = solve_machine(loops.machine, loops.motion)
    main, second = motion.loops["main"].joints, motion.loops["second"].joints
    o2, a, b, o4 = (main[k].position[0] for k in ("O2", "A", "B", "O4"))
    c, d, o6 = (second[k].position[0] for k in ("A", "B", "O4"))
    drawn = (table("crank", [o2, a]) + table("coupler", [a, b]) + table("rocker", [o4, b, c]) + table("rod2", [c, d])
             + table("out2", [o6, d]) + link_table("ground", ground))
    pins = [["ground:0", "crank:0"], ["crank:1", "coupler:0"], ["coupler:1", "rocker:1"], ["ground:1", "rocker:0"],
            ["rocker:2", "rod2:0"], ["rod2:1", "out2:1"], ["ground:2", "out2:0"]]
    linkage = linkage_scene(tmp_path, drawn, pins, MOTION, extra=LOADS.format(link="out2"))
    return loops, linkage, {"F12": ("pin ground:0-crank:0", 1), "F32": ("pin crank:1-coupler:0", -1),
                            "F43": ("pin coupler:1-rocker:1", -1), "F14": ("pin ground:1-rocker:0", 1)}


CASES = {"seed four-bar": seed_fourbar, "offset slider-crank": offset_slider_crank, "six-bar": six_bar}


@pytest.mark.parametrize("case", CASES)
def test_the_linkage_engine_agrees_with_the_loop_closed_forms_to_1e_12(tmp_path, case):
    """Every link's angle, omega, alpha, frame origin and its acceleration; every joint force the
    loop form names (Fij of i on j, Norton) against the pin of the linkage form (of the first
    joint's link on the second's: F32 and F43 are the opposite); the driving torque."""
    loops, linkage, names = CASES[case](tmp_path)
    a, b = run_analysis(loops), run_analysis(linkage)
    ok = a.feasible
    assert ok.sum() >= 35 and np.array_equal(b.feasible, ok)
    assert [row for row, _ in b.kinematics.crossings] == [row for row, _ in a.kinematics.crossings]
    for name in loops.moving_links:
        ka, kb = a.kinematics.links[name], b.kinematics.links[name]
        assert close(np.cos(kb.angle), np.cos(ka.angle), 1.0, ok) and close(np.sin(kb.angle), np.sin(ka.angle), 1.0, ok)
        for key in ("omega", "alpha", "origin", "origin_acceleration"):
            assert close(getattr(kb, key), getattr(ka, key), rows=ok), (name, key)
    main = a.forces.mechanisms["main"]
    mechanism = b.forces.mechanisms["main"]
    for label, (pin, sign) in names.items():
        assert close(sign * mechanism.forces[pin], main.forces[label], rows=ok), label
    assert close(mechanism.driving_torque, main.driving_torque, rows=ok)
    power_in, power_out = power_balance(linkage, b.kinematics, b.forces)
    assert np.abs(power_out - power_in)[ok].max() <= 1e-9 * np.abs(power_in[ok]).max()


def test_friction_on_a_slider_agrees_with_the_slider_crank_and_dissipates(tmp_path):
    """Coulomb friction mu = 0.3 on the offset slider-crank's slider (Norton eq. 11.14): the same
    slide force and torque from both engines; the power balance holds with friction's f v."""
    loops, linkage, names = offset_slider_crank(tmp_path, friction=0.3)
    a, b = run_analysis(loops), run_analysis(linkage)
    mechanism = b.forces.mechanisms["main"]
    assert close(mechanism.forces["slider rod:1 on ground"], a.forces.mechanisms["main"].forces["F14"])
    assert close(mechanism.driving_torque, a.forces.mechanisms["main"].driving_torque)
    friction = mechanism.linkage.sliders[0].friction
    assert np.abs(friction).max() > 0.1 * np.abs(mechanism.linkage.sliders[0].normal).max()
    power_in, power_out = power_balance(linkage, b.kinematics, b.forces)
    assert np.abs(power_out - power_in).max() <= 1e-9 * np.abs(power_in).max()
