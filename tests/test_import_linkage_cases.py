"""``linkstress import CASE.dxf --scene`` on the seven linkage cases drawn assembled
(validation/cases: each DXF written by its make_sketch.py from its independent truth.py): the
scene written solves the drawn pose and moves every link as the case's hand-written scene.toml does.

Each case's scene.toml was written by hand from its NOTES.md; the import reads only the DXF. Both
are solved over the hand scene's own sweep with its speed and acceleration: every joint of every
link within 1e-9 m, every link's angular velocity and acceleration within 1e-7 relative (the
issue's bounds against a truth). The Watt II six-bar is two four-bar loops chained through the bell
crank's pivot, which the import still writes as loops; the others are written as one linkage.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from linkstress.cli import main
from linkstress.errors import SketchError
from linkstress.importers.assembly import check_pose
from linkstress.kinematics.solve import solve_machine
from linkstress.scene.reader import load_scene, scene_from_text

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
LINKAGES = {
    # case: (the groups the written linkage is solved in, the sliders it writes as (point, on, line, block))
    "stephenson3_press": (["input (crank)", "RRR dyad (coupler, rocker)", "RRR dyad (link, lever)"], []),
    "whitworth_shaper": (["input (crank)", "RPR dyad (lever)", "RRP dyad (rod)"],
                         [("crank:1", "lever", [0, 1], "collar"), ("rod:1", "frame", [0, 3], "ram")]),
    "jansen_leg": (["input (crank)", "RRR dyad (hip, upper_rod)", "RRR dyad (rocker, lower_rod)",
                    "RRR dyad (thigh, shin)"], []),
    "klann_leg": (["input (crank)", "RRR dyad (connecting_rod, lower_rocker)", "RRR dyad (leg, upper_rocker)"], []),
    "triad_sixbar": (["input (crank)", "triad (coupler, ternary, rocker, output)"], []),
    "loader_arm_cylinder": (["group (arm, barrel)"], [("arm:1", "barrel", [0, 1], "rod")]),
}


def imported(case: str, tmp_path: Path, capsys) -> tuple[Path, str]:
    """The scene ``import --scene`` writes for ``case``'s DXF, and what it printed."""
    out = tmp_path / f"{case}.toml"
    assert main(["import", str(CASES / case / f"{case}.dxf"), "--scene", str(out)]) == 0
    return out, capsys.readouterr().out


def same_motion(written: Path, case: str) -> None:
    """Over the hand scene's sweep, every link of the written scene moves as the hand scene's does."""
    hand = load_scene(CASES / case / "scene.toml")
    mine = load_scene(written)
    assert sorted(mine.links) == sorted(hand.links)
    got, want = solve_machine(mine.machine, hand.motion), solve_machine(hand.machine, hand.motion)
    assert got.feasible.all() and want.feasible.all()
    for name, link in hand.links.items():
        assert np.array_equal(mine.links[name].joints, link.joints)  # one drawing, one joint order
        here = got.links[name].point(mine.links[name].to_member(link.joints))[0]
        there = want.links[name].point(link.to_member(link.joints))[0]
        assert np.abs(here - there).max() < 1e-9, name
        for rate in ("omega", "alpha"):
            a, b = getattr(got.links[name], rate), getattr(want.links[name], rate)
            assert np.allclose(a, b, rtol=1e-7, atol=1e-7 * max(np.abs(b).max(), 1e-300)), (name, rate)


@pytest.mark.parametrize("case", sorted(LINKAGES))
def test_a_linkage_case_imports_as_the_linkage_its_hand_written_scene_is(tmp_path, capsys, case):
    out, printed = imported(case, tmp_path, capsys)
    written = tomllib.loads(out.read_text())
    hand = tomllib.loads((CASES / case / "scene.toml").read_text())
    (mechanism,), (hand_mechanism,) = written["mechanisms"].values(), hand["mechanisms"].values()
    assert mechanism["type"] == "linkage" and mechanism["ground"] == hand_mechanism["ground"] == "frame"
    assert mechanism["input"] == hand_mechanism["input"]
    # The same pins, each the same set of joints, in whatever order.
    assert sorted(map(sorted, mechanism["pins"])) == sorted(map(sorted, hand_mechanism["pins"]))
    groups, sliders = LINKAGES[case]
    assert [(s["point"], s["on"], s["line"], s["block"]) for s in mechanism.get("sliders", [])] == sliders
    assert f"  solved as: {', '.join(groups)}" in printed
    same_motion(out, case)


def test_the_watt_ii_case_imports_as_two_loops_chained_through_the_bell_crank(tmp_path, capsys):
    out, printed = imported("watt2_sixbar", tmp_path, capsys)
    written = tomllib.loads(out.read_text())
    assert [m["type"] for m in written["mechanisms"].values()] == ["four-bar", "four-bar"]
    assert "mechanism loop2: four-bar, crank 'bellcrank', coupler 'rod', output 'output'" in printed
    same_motion(out, "watt2_sixbar")


def test_the_drawn_input_of_each_linkage_case_is_its_motion_and_solves_to_the_drawing(tmp_path, capsys):
    # The drawn inputs of NOTES.md: the press at 60 deg, the shaper 30, Jansen's leg 0, Klann's 30,
    # the triad six-bar 70, and the loader's cylinder at a stroke of 1.20 m (its pin-to-pin length).
    drawn = {"stephenson3_press": 60.0, "whitworth_shaper": 30.0, "jansen_leg": 0.0, "klann_leg": 30.0,
             "triad_sixbar": 70.0, "loader_arm_cylinder": 1.2}
    for case, value in drawn.items():
        out, _ = imported(case, tmp_path, capsys)
        motion = tomllib.loads(out.read_text())["motion"]
        assert motion.get("input_angle_deg", motion.get("input_stroke_m")) == pytest.approx(value, abs=1e-9)
        scene = load_scene(out)
        at = solve_machine(scene.machine, scene.motion)
        for name, link in scene.links.items():
            moved = at.links[name].point(link.to_member(link.joints))[0][0]
            assert np.abs(moved - link.joints).max() < 1e-9, (case, name)


def test_a_linkage_scene_solved_off_its_drawn_input_is_refused_naming_a_joint_that_moved(tmp_path, capsys):
    out, _ = imported("stephenson3_press", tmp_path, capsys)
    # The crank a degree past its drawn 60 deg: its pin A (30, 51.96) mm moves by 60 mm x 1 deg = 1.05 mm.
    turned = scene_from_text(out.read_text().replace("input_angle_deg = 60.0 ", "input_angle_deg = 61.0 "), out)
    with pytest.raises(SketchError, match=r"link 'crank', joint 1 drawn at \(0\.03, 0\.0519615\) m: the linkage solved "
                                          r"at the drawn input puts it at \(0\.0290\d*, 0\.0524\d*\) m, 0\.00105 m away"):
        check_pose(turned, 1e-6, "the linkage solved at the drawn input")
