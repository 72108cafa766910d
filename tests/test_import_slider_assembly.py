"""A slider-crank drawn assembled becomes a scene: crank pivoted on the ground, a rod, and a slider
block with one pin, which slides along its longer side through that pin.

The drawings are made here: bars as rectangles around their pins with a hole at each, a block
centred on the rod's far pin, for slider lines at any angle and offset and either branch; the
written scene must put every drawn pin back where it is drawn (the import checks that itself, and
the tests check the slider's line, offset and branch against the drawing's).
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from shapely.geometry import MultiPoint

from linkstress.cli import main
from linkstress.kinematics.motion import angle_motion
from linkstress.kinematics.solve import solve_machine
from linkstress.scene.reader import load_scene

O2 = np.array([0.05, 0.02])
HOLE = 0.004
"""Pin hole diameter [m]."""


def rectangle(p: np.ndarray, q: np.ndarray, width: float, overhang: float) -> list[tuple[float, float]]:
    """The corners of a bar ``width`` wide from ``p`` to ``q`` [m], ``overhang`` past each."""
    u = (q - p) / np.hypot(*(q - p))
    n = np.array([-u[1], u[0]])
    a, b = p - overhang * u, q + overhang * u
    return [tuple(c) for c in (a - n * width / 2, b - n * width / 2, b + n * width / 2, a + n * width / 2)]


def slider_crank_pins(crank: float, rod: float, offset: float, line_deg: float, theta_deg: float,
                      branch: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pins O2, A, B [m] of a slider-crank whose slider line runs at ``line_deg`` with its signed
    distance ``offset`` [m] to the left of O2 (kinematics.slider_crank's convention), crank at
    ``theta_deg``; ``open`` puts B ahead of A along the line."""
    u = np.array([math.cos(math.radians(line_deg)), math.sin(math.radians(line_deg))])
    n = np.array([-u[1], u[0]])
    a = O2 + crank * np.array([math.cos(math.radians(theta_deg)), math.sin(math.radians(theta_deg))])
    across = offset - (a - O2) @ n
    along = math.sqrt(rod**2 - across**2) * (1 if branch == "open" else -1)
    b = O2 + offset * n + ((a - O2) @ u + along) * u
    return O2, a, b


def draw_slider_crank(path: Path, pins, line_deg: float, block: tuple[float, float] = (0.04, 0.02),
                      ground: bool = False) -> Path:
    """The crank O2 -> A and rod A -> B as 12 mm bars, a block ``block`` (along, across) [m] centred on B
    with its long side at ``line_deg``; with ``ground``, a ground plate around O2 with a second hole."""
    o2, a, b = pins
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    u = np.array([math.cos(math.radians(line_deg)), math.sin(math.radians(line_deg))])
    parts = {
        "crank": (rectangle(o2, a, 0.012, 0.008), [o2, a]),
        "rod": (rectangle(a, b, 0.012, 0.008), [a, b]),
        "slider": (rectangle(b - u * block[0] / 2, b + u * block[0] / 2, block[1], 0.0), [b]),
    }
    if ground:
        parts["ground"] = (rectangle(o2 - [0.03, 0.0], o2 + [0.03, 0.0], 0.02, 0.01), [o2, o2 - [0.03, 0.0]])
    for layer, (corners, holes) in parts.items():
        msp.add_lwpolyline(corners, close=True, dxfattribs={"layer": layer})
        for centre in holes:
            msp.add_circle(tuple(centre), HOLE / 2, dxfattribs={"layer": layer})
    doc.saveas(path)
    return path


def turn(degrees: float) -> float:
    """``degrees`` brought into [-180, 180)."""
    return (degrees + 180.0) % 360.0 - 180.0


@pytest.mark.parametrize("offset, line_deg, theta_deg, branch", [
    (0.0, 0.0, 45.0, "open"),
    (0.012, 0.0, 130.0, "open"),
    (-0.01, 30.0, 250.0, "open"),
    (0.008, -70.0, 10.0, "crossed"),
], ids=["in line", "offset", "inclined, negative offset", "steep, crossed"])
def test_a_slider_crank_drawn_assembled_becomes_a_scene_with_the_drawn_line_offset_and_branch(
    tmp_path, capsys, offset, line_deg, theta_deg, branch,
):
    pins = slider_crank_pins(0.03, 0.11, offset, line_deg, theta_deg, branch)
    sketch = draw_slider_crank(tmp_path / "engine.dxf", pins, line_deg)
    assert main(["import", str(sketch), "--scene", str(tmp_path / "scene.toml")]) == 0
    assert "mechanism main: slider-crank, crank 'crank', coupler 'rod', slider 'slider', ground 'ground'" in capsys.readouterr().out
    written = tomllib.loads((tmp_path / "scene.toml").read_text())
    mechanism = written["mechanisms"]["main"]
    assert (mechanism["type"], mechanism["slider"]) == ("slider-crank", "slider")
    # the line is written pointing from the crank's pivot toward the slider; drawn the other way, the
    # same mechanism is the reversed line, its offset negated, on the other branch
    u = np.array([math.cos(math.radians(line_deg)), math.sin(math.radians(line_deg))])
    if (pins[2] - pins[0]) @ u < 0:
        line_deg, offset, branch = line_deg - 180.0, -offset, {"open": "crossed", "crossed": "open"}[branch]
    assert mechanism["branch"] == branch
    assert turn(mechanism["slider_angle_deg"] - line_deg) == pytest.approx(0.0, abs=1e-9)
    assert mechanism["offset_m"] == pytest.approx(offset, abs=1e-12)
    assert turn(written["motion"]["input_angle_deg"] - theta_deg) == pytest.approx(0.0, abs=1e-9)
    scene = load_scene(tmp_path / "scene.toml")
    motion = solve_machine(scene.machine, angle_motion(np.array([theta_deg]), 0.0, 0.0))
    assert motion.feasible[0]
    slider_pin = motion.links["slider"].point(np.zeros((1, 2)))[0][0, 0]
    np.testing.assert_allclose(slider_pin, pins[2], atol=1e-9)


def test_a_drawn_ground_with_a_second_joint_carries_the_slider_line_apart(tmp_path):
    pins = slider_crank_pins(0.03, 0.11, 0.005, 15.0, 60.0, "open")
    sketch = draw_slider_crank(tmp_path / "engine.dxf", pins, 15.0, ground=True)
    assert main(["import", str(sketch), "--scene", str(tmp_path / "scene.toml")]) == 0
    written = tomllib.loads((tmp_path / "scene.toml").read_text())
    assert written["mechanisms"]["main"]["ground"] == {"link": "ground", "joints": [1, 0]}
    assert written["mechanisms"]["main"]["slider_angle_deg"] == pytest.approx(15.0, abs=1e-9)
    assert "joints" not in written["links"]["ground"]  # the drawn ground, read from its layer


def test_a_square_slider_block_gives_no_line_and_is_refused_naming_it(tmp_path, capsys):
    pins = slider_crank_pins(0.03, 0.11, 0.0, 0.0, 45.0, "open")
    sketch = draw_slider_crank(tmp_path / "engine.dxf", pins, 0.0, block=(0.02, 0.019))
    assert main(["import", str(sketch), "--scene", str(tmp_path / "scene.toml")]) == 2
    err = capsys.readouterr().err
    assert "link 'slider' is taken for a slider" in err and "about as long as it is wide (0.02 x 0.019 m)" in err
    assert not (tmp_path / "scene.toml").exists()


def test_a_slider_crank_drawn_at_its_toggle_is_refused(tmp_path, capsys):
    # the rod square to the slider line: B right under A
    pins = (O2, O2 + [0.03, 0.0], O2 + [0.03, -0.11])
    sketch = draw_slider_crank(tmp_path / "engine.dxf", pins, 0.0, block=(0.04, 0.02))
    assert main(["import", str(sketch), "--scene", str(tmp_path / "scene.toml")]) == 2
    assert "the drawing is at a toggle (rod 'rod' square to the slider line" in capsys.readouterr().err


def test_a_drawn_slider_block_gets_no_section_stresses_and_the_others_do(tmp_path, capsys):
    pins = slider_crank_pins(0.03, 0.11, 0.0, 0.0, 45.0, "open")
    sketch = draw_slider_crank(tmp_path / "engine.dxf", pins, 0.0)
    scene = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--scene", str(scene)]) == 0
    scene.write_text(scene.read_text().replace("input_speed_rad_s = 1.0", "input_speed_rad_s = 300.0"))
    capsys.readouterr()
    assert main(["analyze", str(scene), "--explain"]) == 0
    assert "no section stresses for slider: a slider, with one joint, has no member between two to section" in capsys.readouterr().out
    assert main(["analyze", str(scene), "--peaks", "--json", str(tmp_path / "a.json")]) == 0
    links = json.loads((tmp_path / "a.json").read_text())["positions"][0]["links"]
    assert "max_von_mises_pa" in links["crank"] and "max_von_mises_pa" in links["rod"]
    assert "max_von_mises_pa" not in links["slider"]
    scene.write_text(scene.read_text() + '\n[analysis]\nvalidate = ["slider"]\n')
    assert main(["validate", str(scene)]) == 2
    assert "analysis.validate: link 'slider' is a slider, with one joint" in capsys.readouterr().err


def test_a_slider_crank_driven_by_a_four_bars_rocker_is_chained_to_it(tmp_path, capsys):
    # a crank-rocker O2 (0, 0), O4 (0.1, 0): crank 0.03, coupler 0.1, rocker 0.08 (O4 -> B) with a third
    # pin C 0.05 from O4, 100 deg round from B; a rod C -> D of 0.12 to a slider on the line y = -0.07
    o2, o4 = np.array([0.0, 0.0]), np.array([0.1, 0.0])
    a = o2 + 0.03 * np.array([math.cos(1.0), math.sin(1.0)])
    d_ao4 = np.hypot(*(o4 - a))
    along = (0.1**2 - 0.08**2 + d_ao4**2) / (2 * d_ao4)
    unit = (o4 - a) / d_ao4
    b = a + along * unit + math.sqrt(0.1**2 - along**2) * np.array([-unit[1], unit[0]])
    turn_c = math.atan2(*(b - o4)[::-1]) + math.radians(100.0)
    c = o4 + 0.05 * np.array([math.cos(turn_c), math.sin(turn_c)])
    d = np.array([c[0] + math.sqrt(0.12**2 - (c[1] + 0.07) ** 2), -0.07])
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    bars = {"crank": (o2, a), "coupler": (a, b), "rod": (c, d)}
    for layer, (p, q) in bars.items():
        msp.add_lwpolyline(rectangle(p, q, 0.012, 0.008), close=True, dxfattribs={"layer": layer})
        for centre in (p, q):
            msp.add_circle(tuple(centre), HOLE / 2, dxfattribs={"layer": layer})
    rocker = MultiPoint([tuple(o4), tuple(b), tuple(c)]).convex_hull.buffer(0.008)
    msp.add_lwpolyline(list(rocker.exterior.coords)[:-1], close=True, dxfattribs={"layer": "rocker"})
    for centre in (o4, b, c):
        msp.add_circle(tuple(centre), HOLE / 2, dxfattribs={"layer": "rocker"})
    msp.add_lwpolyline(rectangle(d - [0.02, 0.0], d + [0.02, 0.0], 0.02, 0.0), close=True, dxfattribs={"layer": "slider"})
    msp.add_circle(tuple(d), HOLE / 2, dxfattribs={"layer": "slider"})
    doc.saveas(tmp_path / "press.dxf")

    assert main(["import", str(tmp_path / "press.dxf"), "--scene", str(tmp_path / "scene.toml")]) == 0
    out = capsys.readouterr().out
    assert "mechanism main: four-bar, crank 'crank', coupler 'coupler', output 'rocker'" in out
    assert "mechanism loop2: slider-crank, crank 'rocker', coupler 'rod', slider 'slider'" in out
    second = tomllib.loads((tmp_path / "scene.toml").read_text())["mechanisms"]["loop2"]
    assert (second["type"], second["driven_by"], second["slider_angle_deg"]) == ("slider-crank", "main.output", 0.0)
    assert second["offset_m"] == pytest.approx(-0.07, abs=1e-12)
    scene = load_scene(tmp_path / "scene.toml")
    motion = solve_machine(scene.machine, angle_motion(np.array([math.degrees(1.0)]), 0.0, 0.0))
    np.testing.assert_allclose(motion.links["slider"].point(np.zeros((1, 2)))[0][0, 0], d, atol=1e-9)


def keyed_crank(path: Path, point: bool) -> Path:
    """A crank disc (radius 40 mm) whose 12 mm bore has a 4 mm keyway, and a pin hole A 30 mm out at
    45 deg; with ``point``, POINTs at the bore's axis and at A."""
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    attrs = {"layer": "crank"}
    msp.add_circle((0, 0), 40, dxfattribs=attrs)
    r, half = 6.0, 2.0
    y0 = math.sqrt(r * r - half * half)
    msp.add_arc((0, 0), r, math.degrees(math.atan2(y0, -half)), math.degrees(math.atan2(y0, half)) + 360, dxfattribs=attrs)
    for p, q in (((half, y0), (half, r + 2)), ((half, r + 2), (-half, r + 2)), ((-half, r + 2), (-half, y0))):
        msp.add_line(p, q, dxfattribs=attrs)
    a = (30 * math.cos(math.pi / 4), 30 * math.sin(math.pi / 4))
    msp.add_circle(a, 4, dxfattribs=attrs)
    if point:
        msp.add_point((0, 0), dxfattribs=attrs)
        msp.add_point(a, dxfattribs=attrs)
    doc.saveas(path)
    return path


def test_a_point_in_a_keyed_bore_is_refused_as_a_hole_that_is_not_round(tmp_path, capsys):
    # bore pi 6^2 = 113.1 mm^2, keyway 4 x (8 - 5.657) = 9.37 mm^2 less the bore's cap under it 0.92:
    # the largest inscribed circle (the bore) fills 113.1 / 121.55 = 93 %
    sketch = keyed_crank(tmp_path / "crank.dxf", point=True)
    assert main(["import", str(sketch)]) == 2
    err = capsys.readouterr().err
    assert "lies in a hole of link 'crank' that is not round (its largest inscribed circle fills 93 % of it" in err
    assert "draw the bore round to analyse the link" in err and "not at its centre" not in err


def test_a_drawing_that_closes_no_mechanism_names_the_links_with_fewer_than_two_joints(tmp_path, capsys):
    sketch = keyed_crank(tmp_path / "crank.dxf", point=False)
    assert main(["import", str(sketch), "--scene", str(tmp_path / "scene.toml")]) == 2
    assert "links with fewer than two joints: 'crank' (1) (joints are POINTs, else the centres of round holes" in capsys.readouterr().err
