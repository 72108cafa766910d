"""``linkstress import SKETCH --scene OUT``: a mechanism drawn assembled, each link on its own layer,
becomes a scene that runs at the drawn crank angle and reproduces the drawing.

The drawings are made here: a validation case's links, read from its DXF, moved into their pose at
one input angle by the case's own kinematics, and drawn on their own layers with their hole circles
and a POINT at each joint.
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from linkstress.cli import main
from linkstress.errors import InputError, SketchError
from linkstress.importers import read_sketch
from linkstress.importers.scene_writer import toml_key, toml_string
from linkstress.kinematics.motion import angle_motion
from linkstress.kinematics.solve import solve_machine
from linkstress.importers.assembly import check_pose
from linkstress.scene.model import Scene
from linkstress.scene.reader import load_scene, scene_from_text

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
SEED = CASES / "seed_ansys_fourbar" / "scene.toml"
SIX_BAR = CASES / "six_bar" / "scene.toml"


def posed(scene: Path | Scene, angle_deg: float) -> dict[str, tuple[np.ndarray, np.ndarray, list]]:
    """Each sketch link of the scene at input ``angle_deg``: its outline's shell (m, 2) [m], its joints
    (n, 2) [m] and its holes' diameters [m], moved from where its DXF draws it into that pose."""
    scene = load_scene(scene) if isinstance(scene, Path) else scene
    motion = solve_machine(scene.machine, angle_motion(np.array([angle_deg]), 0.0, 0.0))
    assert motion.feasible[0]
    links = {}
    for name, link in scene.links.items():
        if link.sketch is None:
            continue
        drawn = read_sketch(link.sketch, units=scene.units).link(link.layer)
        move = motion.links[name]

        def place(points, move=move, link=link):
            return move.point(link.to_member(points))[0][0]

        links[name] = (place(np.asarray(drawn.outline.exterior.coords)[:-1]), place(drawn.joints),
                       list(drawn.hole_diameters_m))
    return links


def draw(path: Path, links: dict, layers: dict[str, str] | None = None, points: bool = True) -> Path:
    """A DXF in metres: each link on its own layer (renamed by ``layers``), its shell a closed
    LWPOLYLINE, a CIRCLE of its hole diameter and (with ``points``) a POINT at each joint."""
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    for name, (shell, joints, holes) in links.items():
        layer = (layers or {}).get(name, name)
        doc.layers.add(layer)
        attrs = {"layer": layer}
        msp.add_lwpolyline([tuple(p) for p in shell], close=True, dxfattribs=attrs)
        for p, d in zip(joints, holes):
            msp.add_circle(tuple(p), d / 2, dxfattribs=attrs)
            if points:
                msp.add_point(tuple(p), dxfattribs=attrs)
    doc.saveas(path)
    return path


def analyze_json(scene: Path, out: Path) -> dict:
    assert main(["analyze", str(scene), "--json", str(out)]) == 0
    return json.loads(out.read_text())


@pytest.mark.parametrize("points", [True, False], ids=["joints at POINTs", "joints at hole centres"])
def test_the_seed_drawn_assembled_at_60_deg_gives_the_seed_scenes_forces(tmp_path, capsys, points):
    sketch = draw(tmp_path / "seed_at_60.dxf", posed(SEED, 60.0), points=points)
    scene = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--scene", str(scene)]) == 0
    text = scene.read_text()
    assert 'crank = "crank"' in text and 'ground = "ground"' in text and 'branch = "open"' in text
    # The output's joints sort by x as B (1.86, 4.49) then O4 (2, 3): its axis O4 -> B is [1, 0].
    assert 'output = {link = "output", joints = [1, 0]}' in text
    assert "input_angle_deg = 60.0 " in text
    # The seed's plates, motion and load (validation/cases/seed_ansys_fourbar/scene.toml); steel is the default.
    text = text.replace("thickness = 0.005", "thickness = 0.1")
    text = text.replace("input_speed_rad_s = 1.0", "input_speed_rad_s = -1.0")
    scene.write_text(text + "\n[loads.couples]\noutput = 2.0\n")
    got = analyze_json(scene, tmp_path / "got.json")["positions"][0]
    want = analyze_json(SEED, tmp_path / "want.json")["positions"][0]
    forces, expected = got["mechanisms"]["main"], want["mechanisms"]["main"]
    assert set(forces["forces_n"]) == set(expected["forces_n"]) == {"F12", "F32", "F43", "F14"}
    for key, value in expected["forces_n"].items():
        assert np.allclose(forces["forces_n"][key], value, rtol=1e-9, atol=1e-9 * np.hypot(*value))
    assert forces["driving_torque_nm"] == pytest.approx(expected["driving_torque_nm"], rel=1e-9)


def test_a_six_bar_drawn_assembled_becomes_two_chained_loops_at_the_drawn_angle(tmp_path, capsys):
    # The six_bar case at 30 deg; its ground is bare joints, so it is not drawn (posed draws sketch links only).
    sketch = draw(tmp_path / "six_bar_at_30.dxf", posed(SIX_BAR, 30.0))
    out = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--scene", str(out)]) == 0
    assert ("mechanism loop2: four-bar, crank 'rocker', coupler 'rod2', output 'out2', ground 'ground'; open branch; "
            "driven by main's output") in capsys.readouterr().out
    data = tomllib.loads(out.read_text())
    # Ground pivots in the order the loops use them: the crank's O2 (0, 0), the rocker's (0.1, 0), out2's (0.1, -0.15).
    assert np.allclose(data["links"]["ground"]["joints"], [[0, 0], [0.1, 0], [0.1, -0.15]], atol=1e-12)
    main_loop, second = data["mechanisms"]["main"], data["mechanisms"]["loop2"]
    # The rocker is ternary: joints by x then y at 30 deg are its second crank pin, its pivot and B.
    assert main_loop["crank"] == "crank" and main_loop["coupler"] == "coupler"
    assert main_loop["output"] == {"link": "rocker", "joints": [1, 2]}
    assert main_loop["ground"] == {"link": "ground", "joints": [0, 1]}
    assert second["driven_by"] == "main.output"
    assert second["crank"] == {"link": "rocker", "joints": [1, 0]}
    assert (second["coupler"], second["output"]) == ("rod2", "out2")
    assert second["ground"] == {"link": "ground", "joints": [1, 2]}
    assert data["motion"]["input_angle_deg"] == 30.0
    same_joints_as_the_case(out)
    assert main(["analyze", str(out)]) == 0
    report = capsys.readouterr().out
    assert "1 position (input 30 deg), 1 feasible" in report and "mechanism loop2: four-bar" in report


def test_a_six_bar_with_its_ternary_ground_drawn_on_layer_Base_names_the_grounds_joints(tmp_path):
    links = posed(SIX_BAR, 30.0)
    # A plate around the case's three fixed pivots (0, 0), (0.1, 0) and (0.1, -0.15) m, 6 mm pin holes.
    plate = np.array([[-0.02, -0.02], [0.08, -0.17], [0.12, -0.17], [0.12, 0.02], [-0.02, 0.02]])
    links["Base"] = (plate, np.array([[0.0, 0.0], [0.1, 0.0], [0.1, -0.15]]), [0.006] * 3)
    out = tmp_path / "scene.toml"
    assert main(["import", str(draw(tmp_path / "six_bar.dxf", links)), "--scene", str(out)]) == 0
    data = tomllib.loads(out.read_text())
    assert data["links"]["Base"]["layer"] == "Base" and "ground" not in data["links"]
    # The plate's joints by x then y: 0 (0, 0), 1 (0.1, -0.15), 2 (0.1, 0).
    assert data["mechanisms"]["main"]["ground"] == {"link": "Base", "joints": [0, 2]}
    assert data["mechanisms"]["loop2"]["ground"] == {"link": "Base", "joints": [2, 1]}
    same_joints_as_the_case(out)


def same_joints_as_the_case(scene: Path) -> None:
    """Solved at 30 deg, every joint of every moving link of ``scene`` lands where the six_bar case puts it."""
    imported, case = load_scene(scene), load_scene(SIX_BAR)
    at_30 = angle_motion(np.array([30.0]), 0.0, 0.0)
    got, want = solve_machine(imported.machine, at_30), solve_machine(case.machine, at_30)
    for name in ("crank", "coupler", "rocker", "rod2", "out2"):
        a, b = imported.links[name], case.links[name]
        assert len(a.joints) == len(b.joints)
        here = got.links[name].point(a.to_member(a.joints))[0][0]
        there = want.links[name].point(b.to_member(b.joints))[0][0]
        # The same joints, perhaps in another order (they sort by x as drawn): each meets one of the case's.
        apart = np.hypot(*(here[:, None, :] - there[None, :, :]).transpose(2, 0, 1))
        assert (apart.min(axis=1) < 1e-12).all() and (apart.min(axis=0) < 1e-12).all()


def seed_on_branch(branch: str) -> Scene:
    """The seed scene on ``branch``."""
    return scene_from_text(SEED.read_text().replace('branch = "open"', f'branch = "{branch}"'), SEED)


def test_a_ground_on_layer_Frame_is_the_ground_and_a_crossed_pose_is_written_crossed(tmp_path):
    layers = {"ground": "Frame", "crank": "Input"}
    sketch = draw(tmp_path / "crossed.dxf", posed(seed_on_branch("crossed"), 60.0), layers)
    out = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--scene", str(out)]) == 0
    data = tomllib.loads(out.read_text())
    # The drawn frame is a link of the scene, read from the sketch, not bare joints.
    assert data["links"]["Frame"] == {"sketch": "crossed.dxf", "layer": "Frame", "thickness": 0.005, "material": "steel"}
    mechanism = data["mechanisms"]["main"]
    assert (mechanism["crank"], mechanism["ground"], mechanism["branch"]) == ("Input", "Frame", "crossed")
    assert data["motion"]["input_angle_deg"] == 60.0


def test_a_scene_on_the_other_branch_than_drawn_is_refused_naming_the_joint(tmp_path):
    sketch = draw(tmp_path / "open.dxf", posed(SEED, 60.0))
    out = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--scene", str(out)]) == 0
    flipped = scene_from_text(out.read_text().replace('branch = "open"', 'branch = "crossed"'), out)
    with pytest.raises(SketchError, match=r"link 'coupler', joint 1 drawn at \(1\.86237, 4\.49367\) m: the loop solved"):
        check_pose(flipped, 1e-6)


def test_links_that_close_no_loop_exit_2_naming_the_joint_they_share(tmp_path, capsys):
    links = posed(SEED, 60.0)
    sketch = draw(tmp_path / "two.dxf", {name: links[name] for name in ("crank", "coupler")})
    out = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--scene", str(out)]) == 2
    err = capsys.readouterr().err
    # The crank's pin A at 60 deg: (cos 60, 3 + sin 60) m.
    assert err.startswith("linkstress: error: two.dxf: --scene: no mechanism found: links 'crank', 'coupler' share "
                          "the joint at (0.5, 3.86603) m; no closed loop of four links") and err.count("\n") == 1
    assert not out.exists()


@pytest.mark.parametrize("target", ["sketch", "folder"])
def test_the_scene_output_is_refused_like_other_outputs(tmp_path, capsys, target):
    sketch = draw(tmp_path / "seed.dxf", posed(SEED, 60.0))
    out = sketch if target == "sketch" else tmp_path
    before = sketch.read_bytes()
    assert main(["import", str(sketch), "--scene", str(out)]) == 2
    assert capsys.readouterr().err.startswith("linkstress: error: --scene: ")
    assert sketch.read_bytes() == before


def test_layer_names_with_quotes_backslashes_and_unicode_round_trip_through_the_scene(tmp_path):
    # ezdxf refuses such layer names, other CAD writes them: rename the layers in the DXF text.
    names = {"crank": 'Kurbel "A" \\ ü', "coupler": "Koppel's arm", "output": "Schwinge ☃", "ground": "ground"}
    sketch = draw(tmp_path / "names.dxf", posed(SEED, 60.0), {k: f"LAYER{i}X" for i, k in enumerate(names)})
    text = sketch.read_text()
    for i, name in enumerate(names.values()):
        text = text.replace(f"LAYER{i}X", name)
    sketch.write_text(text, encoding="utf-8")
    out = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--scene", str(out)]) == 0
    data = tomllib.loads(out.read_text(encoding="utf-8"))
    assert sorted(data["links"]) == sorted(names.values())
    assert all(data["links"][name]["layer"] == name for name in names.values())
    # No layer is named crank: the crank is the shortest link pivoted on the ground, the seed's 1 m crank.
    assert data["mechanisms"]["main"]["crank"] == 'Kurbel "A" \\ ü'
    assert load_scene(out).machine.main.coupler.link == "Koppel's arm"


def test_toml_strings_and_keys_escape_what_toml_needs():
    for text in ['plain', 'a "quoted" name', "back\\slash", "tab\tand\nnewline", "bell\x07 del\x7f", "ü ☃ 𝄞", ""]:
        assert tomllib.loads(f"{toml_key(text)} = {toml_string(text)}") == {text: text}
    assert toml_key("crank_2-b") == "crank_2-b" and toml_key("a b") == '"a b"'
    with pytest.raises(InputError, match="lone surrogate"):
        toml_string("broken \ud800 name")


def bar_drawing(path: Path, pins: dict[str, tuple], per_metre: float = 1.0) -> Path:
    """A DXF of straight bars 0.05 m wide, each from its first pin to its second on its own layer, with
    0.01 m pin holes and POINTs; in metres, or unitless at ``per_metre`` drawing units per metre."""
    doc = ezdxf.new("R2013", units=6 if per_metre == 1.0 else 0)
    msp = doc.modelspace()
    for layer, (p, q) in pins.items():
        doc.layers.add(layer)
        p, q = np.asarray(p, float) * per_metre, np.asarray(q, float) * per_metre
        u = (q - p) / np.hypot(*(q - p))
        n = 0.025 * per_metre * np.array([-u[1], u[0]])
        ends = (p - 0.025 * per_metre * u, q + 0.025 * per_metre * u)
        corners = [ends[0] - n, ends[1] - n, ends[1] + n, ends[0] + n]
        msp.add_lwpolyline([tuple(c) for c in corners], close=True, dxfattribs={"layer": layer})
        for pin in (p, q):
            msp.add_circle(tuple(pin), 0.005 * per_metre, dxfattribs={"layer": layer})
            msp.add_point(tuple(pin), dxfattribs={"layer": layer})
    doc.saveas(path)
    return path


def double_rocker(ground_layer: str | None) -> dict[str, tuple]:
    """Crank 0.8 m at 45 deg from O2 (0, 0), coupler 0.4 m, output 0.7 m, ground 1 m to O4 (1, 0), open
    branch: Grashof with the coupler shortest, so the crank rocks. ``ground_layer``: None leaves the
    ground undrawn."""
    o2, o4 = np.array([0.0, 0.0]), np.array([1.0, 0.0])
    a = 0.8 * np.array([math.cos(math.radians(45)), math.sin(math.radians(45))])
    d = o4 - a
    s = np.hypot(*d)
    along = (0.4**2 - 0.7**2 + s**2) / (2 * s)
    across = math.sqrt(0.4**2 - along**2)
    b = a + along * d / s + across * np.array([-d[1], d[0]]) / s  # left of A -> O4: the open branch
    pins = {"crank": (o2, a), "link_b": (a, b), "rocker_c": (o4, b)}
    if ground_layer is not None:
        pins[ground_layer] = (o2, o4)
    return pins


def test_a_crank_that_rocks_gets_a_sweep_between_its_toggles_and_an_undrawn_ground(tmp_path):
    out = tmp_path / "scene.toml"
    assert main(["import", str(bar_drawing(tmp_path / "rocker.dxf", double_rocker(None))), "--scene", str(out)]) == 0
    text = out.read_text()
    data = tomllib.loads(text)
    assert np.allclose(data["links"]["ground"]["joints"], [[0, 0], [1, 0]], atol=1e-12)
    assert (data["mechanisms"]["main"]["crank"], data["mechanisms"]["main"]["branch"]) == ("crank", "open")
    # |A O4|^2 = a^2 + d^2 - 2 a d cos(phi) reaches b + c = 1.1 m and |b - c| = 0.3 m at
    # cos(phi) = (0.64 + 1 - 1.21) / 1.6 and (0.64 + 1 - 0.09) / 1.6: 74.4101 and 14.3615 deg.
    low, high = math.degrees(math.acos(1.55 / 1.6)), math.degrees(math.acos(0.43 / 1.6))
    # The sweep's ends are rounded inward to 1e-6 deg, so that every position assembles.
    assert "# input_angle_deg = {start = 14.361512, stop = 74.410101, num = 201}" in text
    assert (low, high) == pytest.approx((14.3615116, 74.4101019), abs=1e-7)
    assert data["motion"]["input_angle_deg"] == 45.0


def test_a_unitless_drawing_imported_with_units_mm_writes_the_unit_into_the_scene(tmp_path):
    sketch = bar_drawing(tmp_path / "mm.dxf", double_rocker(None), per_metre=1000.0)
    out = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--units", "mm", "--scene", str(out)]) == 0
    data = tomllib.loads(out.read_text())
    assert data["units"] == "mm"
    # Bare joints are always metres: O2 (0, 0) and O4 (1, 0) m, drawn at (0, 0) and (1000, 0) mm.
    assert np.allclose(data["links"]["ground"]["joints"], [[0, 0], [1, 0]], atol=1e-12)
    assert load_scene(out).links["crank"].profile.joints[1] == pytest.approx([0.8 / math.sqrt(2)] * 2, abs=1e-12)


def test_an_unnamed_drawn_ground_is_the_largest_link_in_every_loop(tmp_path):
    out = tmp_path / "scene.toml"
    assert main(["import", str(bar_drawing(tmp_path / "plate.dxf", double_rocker("plate"))), "--scene", str(out)]) == 0
    text = out.read_text()
    # All four bars are in the one loop with two joints each: the 1.05 m plate is the largest.
    assert 'ground = "plate"  # no layer is named ground, frame, base:' in text
    assert tomllib.loads(text)["links"]["plate"]["layer"] == "plate"


def test_links_drawn_apart_exit_2_saying_no_two_share_a_joint(tmp_path, capsys):
    # The seed's own DXF draws its bars one above the other, 1 m apart: a parts sheet, not an assembly.
    sketch = CASES / "seed_ansys_fourbar" / "ansys_four_bars.dxf"
    assert main(["import", str(sketch), "--scene", str(tmp_path / "scene.toml")]) == 2
    assert ("--scene: no mechanism found: no two of the links ('crank', 'coupler', 'output', 'ground') share a joint"
            in capsys.readouterr().err)
    assert list(tmp_path.iterdir()) == []
