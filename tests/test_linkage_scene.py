"""A ``type = "linkage"`` scene: every check before any solve refuses with its key and what to do
(exit code 2 at the command line), and analyze's JSON carries the linkage's joints, pins, sliders
and driving torque or force."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from linkstress.errors import SceneError
from linkstress.kinematics.linkage.examples import loader_arm, whitworth

from linkage_scenes import link_table, linkage_scene, scene_of_graph

FOURBAR = (link_table("ground", [[0, 0], [0.2, 0]]) + link_table("crank", [[0, 0], [0.05, 0]])
           + link_table("coupler", [[0.05, 0], [0.15, 0.1]]) + link_table("output", [[0.2, 0], [0.15, 0.1]]))
PINS = [["ground:0", "crank:0"], ["crank:1", "coupler:0"], ["coupler:1", "output:1"], ["ground:1", "output:0"]]
MOTION = "input_angle_deg = 0.0"


def refused(tmp_path, links=FOURBAR, pins=PINS, **options) -> str:
    with pytest.raises(SceneError) as caught:
        linkage_scene(tmp_path, links, pins, options.pop("motion", MOTION), **options)
    return str(caught.value)


def test_a_drawn_four_bar_reads_as_a_linkage(tmp_path):
    scene = linkage_scene(tmp_path, FOURBAR, PINS, MOTION)
    assert scene.linkage.gruebler() == (1, 4, 4, 0)
    assert [g.kind for g in scene.linkage.groups] == ["crank", "RRR"]
    assert scene.moving_links == ("crank", "coupler", "output") and scene.actuator == "crank"


def test_a_missing_pin_leaves_two_degrees_of_freedom_and_names_the_floating_links(tmp_path):
    """Without the output's pivot: F = 3 (4 - 1) - 2 x 3 = 3; the coupler and output float."""
    message = refused(tmp_path, pins=PINS[:3])
    assert "mechanisms.main: Gruebler: F = 3 (n - 1) - 2 j1 - j2 = 3 (4 - 1) - 2 x 3 - 0 = 3 degrees of freedom" in message
    assert "links coupler, output float" in message


def test_an_extra_link_that_locks_the_loop_is_refused_naming_the_links(tmp_path):
    """A fifth link from the ground to the coupler: F = 3 x 4 - 2 x 6 = 0, a structure."""
    links = FOURBAR + link_table("brace", [[0.0, 0.0], [0.15, 0.1]])
    pins = [["ground:0", "crank:0", "brace:0"], *PINS[1:2], ["coupler:1", "output:1", "brace:1"], PINS[3]]
    message = refused(tmp_path, links, pins)
    assert "= 0 degrees of freedom" in message and "lock" in message and "brace" in message


def test_a_joint_named_twice_is_refused(tmp_path):
    message = refused(tmp_path, pins=PINS + [["crank:1", "output:1"]])
    assert "mechanisms.main.pins[4]: joint crank:1 is named twice (also in pins[1])" in message


def test_a_link_not_connected_to_the_ground_is_named(tmp_path):
    links = FOURBAR + link_table("loose", [[1.0, 1.0], [1.1, 1.0]]) + link_table("other", [[1.1, 1.0], [1.2, 1.0]])
    message = refused(tmp_path, links, PINS + [["loose:1", "other:0"]])
    assert "link(s) loose, other are not connected to the ground 'ground'" in message


def test_a_drawing_that_does_not_close_names_the_pin_and_its_gap(tmp_path):
    links = FOURBAR.replace("[0.15, 0.1]]\n", "[0.15, 0.101]]\n", 1)  # the coupler's B drawn 1 mm off
    message = refused(tmp_path, links)
    assert "pin coupler:1-output:1 does not close as drawn" in message
    assert "are 0.001 m apart (tolerance 2e-05 m)" in message


def test_a_slider_point_drawn_off_its_line_is_refused(tmp_path):
    graph = whitworth()
    links = "".join(link_table(n, j if n != "collar" else j + [0.0, 0.01]) for n, j in graph.links.items())
    pins = [[str(j) for j in pin] for pin in graph.pins]
    sliders = [{"point": str(s.point), "on": s.on, "line": s.line, "block": s.block} for s in graph.sliders]
    message = refused(tmp_path, links, pins, sliders=sliders, ground="frame")
    assert "pin crank:1-collar:0 does not close as drawn" in message


def test_the_input_must_turn_about_a_pivot_on_the_ground(tmp_path):
    message = refused(tmp_path, input_='{link = "coupler", pivot = 0, to = 1}')
    assert "mechanisms.main.input.pivot: joint coupler:0 is not pinned to the ground 'ground'" in message


def test_a_joint_name_must_be_link_colon_index(tmp_path):
    message = refused(tmp_path, pins=[["ground:0", "crank0"], *PINS[1:]])
    assert "mechanisms.main.pins[0]: must name joints as \"LINK:i\"" in message
    message = refused(tmp_path, pins=[["ground:0", "crank:7"], *PINS[1:]])
    assert "link 'crank' has joints 0..1, no joint 7" in message


def test_a_linkage_is_the_scenes_only_mechanism(tmp_path):
    extra = '[mechanisms.other]\ntype = "four-bar"\ncrank = "crank"\ncoupler = "coupler"\noutput = "output"\nground = "ground"\n'
    path = tmp_path / "two.toml"
    linkage_scene(tmp_path, FOURBAR, PINS, MOTION)
    text = (tmp_path / "linkage.toml").read_text().replace("\n[motion]", extra + "\n[motion]")
    path.write_text(text)
    from linkstress.scene import load_scene

    with pytest.raises(SceneError, match="mechanisms.other: a scene with a type = \"linkage\" mechanism"):
        load_scene(path)


def test_the_motion_keys_follow_the_input(tmp_path):
    assert "motion.actuator: a linkage's input is its actuator" in refused(
        tmp_path, motion='input_angle_deg = 0.0\nactuator = "crank"')
    assert "motion.input_stroke_m: for a linkage driven by a slider's stroke" in refused(
        tmp_path, motion="input_angle_deg = 0.0\ninput_stroke_m = 0.1")
    with pytest.raises(SceneError, match="motion.input_angle_deg: unknown key; allowed keys are: input_stroke_m"):
        scene_of_graph(tmp_path, loader_arm(), "input_angle_deg = 0.0")
    with pytest.raises(SceneError, match="motion.input_stroke_m: missing; give the stroke of slider 0"):
        scene_of_graph(tmp_path, loader_arm(), "input_speed_m_s = 0.1")


def test_friction_names_a_linkage_slider_by_its_block_or_point(tmp_path):
    scene = scene_of_graph(tmp_path, whitworth(), MOTION, extra='[loads.friction]\n"crank:1" = 0.2\nram = 0.1\n')
    assert scene.loads.friction == {"main.sliders[0]": 0.2, "main.sliders[1]": 0.1}
    with pytest.raises(SceneError, match="loads.friction.lever: no slider named 'lever'"):
        scene_of_graph(tmp_path, whitworth(), MOTION, extra="[loads.friction]\nlever = 0.2\n")


def test_the_command_line_refuses_a_bad_linkage_with_exit_code_2(tmp_path):
    with pytest.raises(SceneError):
        linkage_scene(tmp_path, FOURBAR, PINS[:3], MOTION)
    done = subprocess.run([sys.executable, "-m", "linkstress", "analyze", str(tmp_path / "linkage.toml")],
                          capture_output=True, text=True)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr and "links coupler, output float" in done.stderr


def test_analyze_json_of_a_linkage(tmp_path):
    """Per link per position ``joints_m`` (ground frame, the link's joint order); per mechanism
    ``pins`` (joints, at_m, the force on each joint's link: summing to zero on every pin),
    ``sliders`` and ``driving_torque_nm``; a stroke input gives ``input_stroke_m`` and
    ``driving_force_n``."""
    scene = scene_of_graph(tmp_path, whitworth(), "input_angle_deg = [30.0, 100.0]\ninput_speed_rad_s = 5.0")
    out = tmp_path / "out.json"
    done = subprocess.run([sys.executable, "-m", "linkstress", "analyze", str(scene.path), "--json", str(out)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    position = json.loads(out.read_text())["positions"][0]
    assert position["input_angle_deg"] == 30.0
    assert np.allclose(position["links"]["lever"]["joints_m"], whitworth().links["lever"], atol=1e-12)
    mechanism = position["mechanisms"]["main"]
    assert [pin["joints"] for pin in mechanism["pins"]] == [
        ["frame:1", "crank:0"], ["frame:0", "lever:0"], ["lever:1", "rod:0"], ["crank:1", "collar:0"], ["rod:1", "ram:0"]]
    for pin in mechanism["pins"]:
        assert np.abs(np.sum(list(pin["forces_n"].values()), axis=0)).max() < 1e-9
    assert set(mechanism["sliders"][0]) == {"point", "on", "stroke_m", "normal_force_n", "couple_nm", "friction_force_n",
                                            "pin_force_n"}
    assert mechanism["sliders"][0]["stroke_m"] == pytest.approx(np.hypot(0.043301, 0.145), abs=2e-6)  # |O4 P|
    assert isinstance(mechanism["driving_torque_nm"], float)
    arm = scene_of_graph(tmp_path, loader_arm(), "input_stroke_m = [0.4, 0.5]", name="arm.toml")
    done = subprocess.run([sys.executable, "-m", "linkstress", "analyze", str(arm.path), "--json", str(out)],
                          capture_output=True, text=True)
    position = json.loads(out.read_text())["positions"][1]
    assert position["input_stroke_m"] == 0.5 and "input_angle_deg" not in position
    assert "driving_force_n" in position["mechanisms"]["main"]
