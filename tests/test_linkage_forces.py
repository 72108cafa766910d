"""Forces of general linkages: the power balance on every mechanism built (input power = rate of
kinetic energy - power of the applied loads and of friction), the virtual work of a quasi-static
load, two-force members, a pin of three links, a slide on a moving guide, a cylinder's force."""

from __future__ import annotations

import numpy as np
import pytest

from linkstress.analysis import run_analysis
from linkstress.dynamics.linkage_forces import power_balance
from linkstress.kinematics.linkage.examples import jansen_leg, loader_arm, slotted_arm, triad_six_bar, whitworth

from linkage_scenes import scene_of_graph

TURN = "input_angle_deg = {start = 0.0, stop = 355.0, num = 72}\ninput_speed_rad_s = 7.0\ninput_acceleration_rad_s2 = 3.0"
CASES = {
    "Jansen's leg": (lambda: jansen_leg(0.0), TURN,
                     "[loads]\ngravity_m_s2 = [0.0, -9.81]\n[[loads.forces]]\nlink = \"leg\"\nat_m = [0.1, -0.3]\nforce_n = [5.0, 40.0]\n"),
    "Whitworth with friction": (whitworth, TURN,
                                "[loads]\ngravity_m_s2 = [0.0, -9.81]\n[loads.friction]\ncollar = 0.2\nram = 0.15\n"
                                "[loads.couples]\nrod = 1.5\n"),
    "slotted coupler with friction": (slotted_arm, TURN,
                                      "[loads]\n[loads.friction]\npad = 0.25\n[loads.couples]\narm = -2.0\n"),
    "triad six-bar": (lambda: triad_six_bar(20.0),
                      "input_angle_deg = {start = 20.0, stop = 36.0, num = 33}\ninput_speed_rad_s = -4.0",
                      "[loads]\ngravity_m_s2 = [0.0, -9.81]\n[loads.couples]\nplate = -0.8\n"),
    "loader arm": (loader_arm, "input_stroke_m = {start = 0.32, stop = 0.58, num = 27}\ninput_speed_m_s = 0.2\n"
                               "input_acceleration_m_s2 = -0.5",
                   "[loads]\ngravity_m_s2 = [0.0, -9.81]\n[[loads.forces]]\nlink = \"arm\"\nat_m = [1.2, 0.0]\n"
                   "force_n = [0.0, -2000.0]\n"),
}


@pytest.mark.parametrize("case", CASES)
def test_the_power_balance_holds_on_every_mechanism(tmp_path, case):
    """Input power (T omega, or the cylinder's P sdot) = sum (m v_G . a_G + I omega alpha) - power
    of gravity, point forces and couples - friction's f v_rel, at every feasible position, within
    1e-9 of the largest input power (the reference's power balance: no second solver)."""
    make, motion, loads = CASES[case]
    scene = scene_of_graph(tmp_path, make(), motion, extra=loads)
    result = run_analysis(scene)
    ok = result.feasible
    assert ok.all()
    power_in, power_out = power_balance(scene, result.kinematics, result.forces)
    assert np.abs(power_in).max() > 0
    assert np.abs(power_in - power_out)[ok].max() <= 1e-9 * np.abs(power_in[ok]).max()


def test_quasi_static_jansen_torque_is_the_virtual_work_of_the_foot_load(tmp_path):
    """No speed, no gravity, a load F on the foot G: T dtheta + F . dG = 0, so T = -F . dG/dtheta,
    dG/dtheta from central differences of the foot's position (1e-7 rad). The binary links
    (upper_j, lower_k, rocker_c, link_f) are two-force members: each pin force lies along the link
    and the two are opposite. The pin of three links (crank:1, upper_j:0, lower_k:0) puts forces
    summing to zero."""
    graph = jansen_leg(0.0)
    load = np.array([30.0, 200.0])
    foot = graph.local["leg"][2]
    angles = np.linspace(0.0, 350.0, 36)
    text = ("input_angle_deg = [" + ", ".join(repr(float(a)) for a in angles) + "]")
    extra = f"[[loads.forces]]\nlink = \"leg\"\nat_m = [{float(foot[0])!r}, {float(foot[1])!r}]\nforce_n = [{load[0]}, {load[1]}]\n"
    scene = scene_of_graph(tmp_path, graph, text, extra=extra)
    result = run_analysis(scene)
    h = 1e-7
    shifted = [scene_of_graph(tmp_path, graph, "input_angle_deg = [" + ", ".join(repr(float(a + np.degrees(d)))
                                                                             for a in angles) + "]",
                              extra=extra, name=f"shift{k}.toml") for k, d in enumerate((h, -h))]
    feet = [run_analysis(s).kinematics.linkage.joints["leg:2"].position for s in shifted]
    torque = -((feet[0] - feet[1]) / (2 * h)) @ load
    mechanism = result.forces.mechanisms["main"]
    assert np.abs(mechanism.driving_torque - torque).max() <= 1e-6 * np.abs(torque).max()
    joints = result.kinematics.linkage.joints
    detail = mechanism.linkage
    forces = {j: f for pin in detail.forces for j, f in pin.items()}
    for link in ("upper_j", "lower_k", "rocker_c", "link_f"):
        axis = joints[f"{link}:1"].position - joints[f"{link}:0"].position
        for end in (0, 1):
            f = forces[f"{link}:{end}"]
            across = np.abs(f[:, 0] * axis[:, 1] - f[:, 1] * axis[:, 0]) / np.hypot(*axis.T)
            assert across.max() <= 1e-9 * np.abs(f).max(), link
        assert np.abs(forces[f"{link}:0"] + forces[f"{link}:1"]).max() <= 1e-9 * np.abs(forces[f"{link}:0"]).max()
    three = next(pin for pin in detail.forces if "crank:1" in pin)
    assert len(three) == 3
    assert np.abs(sum(three.values())).max() <= 1e-9 * max(np.abs(f).max() for f in three.values())


def test_a_slide_on_a_moving_lever_pushes_square_to_it_and_its_couple_is_zero_for_a_pinned_collar(tmp_path):
    """Whitworth, quasi-static with a load on the ram and no friction: the lever pushes the collar
    along the line's normal only (the slider's normal force is the whole of it), the guide takes
    the opposite at the same point (the collar's pin force equals the normal push reversed), and
    a massless-free collar pinned at the point needs no couple from the lever."""
    scene = scene_of_graph(tmp_path, whitworth(), "input_angle_deg = {start = 0.0, stop = 350.0, num = 36}",
                           masses={"collar": (1e-6, 0.0, (0.0, 0.0))},
                           extra="[[loads.forces]]\nlink = \"ram\"\nat_m = [0.0, 0.0]\nforce_n = [-500.0, 0.0]\n")
    result = run_analysis(scene)
    slider = result.forces.mechanisms["main"].linkage.sliders[0]
    assert np.abs(slider.friction).max() == 0.0
    assert np.abs(slider.normal).max() > 100.0
    assert np.abs(slider.couple).max() <= 1e-9 * np.abs(slider.normal).max() * 0.3
    u = np.column_stack([np.cos(result.kinematics.links["lever"].angle), np.sin(result.kinematics.links["lever"].angle)])
    along = np.abs(slider.pin_force[:, 0] * u[:, 0] + slider.pin_force[:, 1] * u[:, 1])
    assert along.max() <= 1e-9 * np.abs(slider.pin_force).max()


def test_the_cylinder_force_is_the_virtual_work_of_the_tip_load(tmp_path):
    """The loader arm quasi-static, a weight W at the arm's tip: the cylinder's push P along its
    line does the work the weight takes, P ds = -W dy_tip: P = -W dy_tip/ds, dy_tip/ds from
    central differences of the tip's height (1e-8 m)."""
    graph = loader_arm()
    strokes = np.linspace(0.32, 0.58, 14)
    extra = "[[loads.forces]]\nlink = \"arm\"\nat_m = [1.2, 0.0]\nforce_n = [0.0, -2000.0]\n"

    def scene(values, name):
        return scene_of_graph(tmp_path, graph, "input_stroke_m = [" + ", ".join(repr(float(v)) for v in values) + "]",
                              extra=extra, name=name)

    result = run_analysis(scene(strokes, "base.toml"))
    h = 1e-8
    tips = [run_analysis(scene(strokes + d, f"s{k}.toml")).kinematics.linkage.joints["arm:2"].position[:, 1]
            for k, d in enumerate((h, -h))]
    push = 2000.0 * (tips[0] - tips[1]) / (2 * h)
    mechanism = result.forces.mechanisms["main"]
    assert mechanism.driving_torque is None
    assert np.abs(mechanism.driving_force - push).max() <= 1e-6 * np.abs(push).max()
