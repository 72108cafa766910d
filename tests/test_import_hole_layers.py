"""Holes and slots drawn on a layer of their own: reported as such without --hole-layers (the link would
import solid), taken as the holes of the links they lie in with it (round ones pin holes, their centres
joints), refused where one crosses its link's edge; the scene key hole_layers does the same.

Every drawing is generated here with ezdxf, in mm.
"""

from __future__ import annotations

import json
import math
import textwrap

import ezdxf
import numpy as np
import pytest

from linkstress.cli import main
from linkstress.errors import SketchError
from linkstress.importers import SketchRefused, read_sketch
from linkstress.scene.reader import load_scene
from test_import_dxf import save


def plate(msp, x0: float, y0: float, width: float, height: float, layer: str, holes: str = "holes",
          radius: float = 5.0, slot: bool = True) -> float:
    """A ``width`` x ``height`` plate on ``layer`` with, on layer ``holes``, a round hole of ``radius`` 20 mm in
    from each end and (``slot``) a rounded slot 40 x 10 mm in the middle; the plate's net area [mm^2]."""
    msp.add_lwpolyline([(x0, y0), (x0 + width, y0), (x0 + width, y0 + height), (x0, y0 + height)], close=True,
                       dxfattribs={"layer": layer})
    cy = y0 + height / 2
    for x in (x0 + 20, x0 + width - 20):
        msp.add_circle((x, cy), radius, dxfattribs={"layer": holes})
    area = width * height - 2 * math.pi * radius**2
    if slot:
        cx = x0 + width / 2
        msp.add_lwpolyline([(cx - 15, cy - 5, 0), (cx + 15, cy - 5, 1), (cx + 15, cy + 5, 0), (cx - 15, cy + 5, 1)],
                           format="xyb", close=True, dxfattribs={"layer": holes})
        area -= 30 * 10 + math.pi * 25  # the slot: a 30 x 10 rectangle and two half discs of 5 mm
    return area


@pytest.mark.parametrize("width, height, slot", [(200.0, 60.0, True), (120.0, 40.0, False), (400.0, 90.0, True)])
def test_without_hole_layers_a_plate_with_holes_on_their_own_layer_is_refused_naming_the_fix(tmp_path, capsys,
                                                                                             width, height, slot):
    # Before: a solid plate (no joints) plus a disc and a slot-shaped "link" on top of it, exit 0.
    doc = ezdxf.new("R2013", units=4)
    plate(doc.modelspace(), 0, 0, width, height, "plate", slot=slot)
    path = save(doc, tmp_path)
    out = tmp_path / "links.json"
    assert main(["import", str(path), "--json", str(out)]) == 2
    err = capsys.readouterr().err
    n = 3 if slot else 2
    assert f"sketch.dxf: {n} outline(s) on layer(s) 'holes' lie wholly inside the link through LWPOLYLINE" in err
    assert "likely holes or slots drawn on their own layer" in err
    assert 'give --hole-layers holes (a scene link: hole_layers = ["holes"])' in err and err.count("\n") == 1
    (problem,) = json.loads(out.read_text())["problems"]
    assert problem["kind"] == "hole_on_own_layer" and problem["layer"] == "plate"


@pytest.mark.parametrize("width, height, slot", [(200.0, 60.0, True), (120.0, 40.0, False), (400.0, 90.0, True)])
def test_hole_layers_make_them_the_plates_holes_and_its_round_ones_pin_holes_and_joints(tmp_path, width, height, slot):
    doc = ezdxf.new("R2013", units=4)
    area = plate(doc.modelspace(), 0, 0, width, height, "plate", slot=slot)
    sketch = read_sketch(save(doc, tmp_path), hole_layers=["holes"])
    (link,) = sketch.links
    assert link.name == "plate" and sketch.problems == () and sketch.hole_layers == ("holes",)
    # Flattened keeping each arc's area (docs/importing.md): the net area to rounding.
    assert link.outline.area == pytest.approx(area * 1e-6, rel=1e-9)
    assert link.joints.tolist() == [[0.02, height / 2e3], [(width - 20) / 1e3, height / 2e3]]
    assert link.joint_rules == ("hole centre", "hole centre")
    round_holes = sorted(d for d in link.hole_diameters_m if d is not None)
    assert round_holes == pytest.approx([0.01, 0.01], rel=1e-12)
    assert len(link.hole_diameters_m) == (3 if slot else 2)


def test_a_hole_layer_shared_by_several_links_gives_each_its_own_holes(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    areas = [plate(msp, 0, 0, 200, 60, "left"), plate(msp, 0, 100, 120, 40, "right", radius=3, slot=False),
             plate(msp, 300, 0, 150, 50, "third", radius=4)]
    sketch = read_sketch(save(doc, tmp_path), hole_layers=["holes"])
    assert [link.name for link in sketch.links] == ["left", "right", "third"]
    assert [link.outline.area for link in sketch.links] == pytest.approx([a * 1e-6 for a in areas], rel=1e-9)
    assert [len(link.outline.interiors) for link in sketch.links] == [3, 2, 3]
    assert sketch.link("right").joints.tolist() == [[0.02, 0.12], [0.1, 0.12]]


def test_a_pin_hole_on_a_shared_hole_layer_where_two_links_overlap_is_a_hole_of_both(tmp_path):
    # Two bars drawn assembled, overlapping at the pin at x = 100: its hole is drawn once, on "holes".
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for layer, x0, x1 in (("crank", 0.0, 100.0), ("coupler", 100.0, 250.0)):
        msp.add_lwpolyline([(x0, -10, 0.0), (x1, -10, 1.0), (x1, 10, 0.0), (x0, 10, 1.0)], format="xyb", close=True,
                           dxfattribs={"layer": layer})
    for x in (0.0, 100.0, 250.0):
        msp.add_circle((x, 0.0), 3.0, dxfattribs={"layer": "holes"})
    sketch = read_sketch(save(doc, tmp_path), hole_layers=["holes"])
    assert sketch.link("crank").joints.tolist() == [[0.0, 0.0], [0.1, 0.0]]
    assert sketch.link("coupler").joints.tolist() == [[0.1, 0.0], [0.25, 0.0]]


def test_points_on_the_hole_layer_are_the_joints_and_one_off_a_holes_centre_is_a_problem(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    plate(msp, 0, 0, 200, 60, "plate")
    for x in (20.0, 180.0):
        msp.add_point((x, 30.0), dxfattribs={"layer": "holes"})
    path = save(doc, tmp_path)
    link = read_sketch(path, hole_layers=["holes"]).link("plate")
    assert link.joints.tolist() == [[0.02, 0.03], [0.18, 0.03]] and link.joint_rules == ("point", "point")
    msp.add_point((182.0, 30.0), dxfattribs={"layer": "holes"})
    doc.saveas(path)
    with pytest.raises(SketchError, match=r"POINT \(handle .*, layer 'holes'\) at \(182, 30\) mm lies in a hole of link "
                                          r"'plate' but not at its centre \(180, 30\) mm"):
        read_sketch(path, hole_layers=["holes"])


@pytest.mark.parametrize("centre", [(199.0, 30.0), (60.0, 30.0)], ids=["across the plate's edge", "across its own hole"])
def test_a_hole_crossing_its_links_edge_or_another_hole_leaves_that_link_out_named(tmp_path, centre):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    plate(msp, 0, 0, 200, 60, "plate")
    msp.add_circle((65.0, 30.0), 4.0, dxfattribs={"layer": "plate"})  # a hole drawn on the plate's own layer
    plate(msp, 0, 100, 120, 40, "other", slot=False)
    circle = msp.add_circle(centre, 6.0, dxfattribs={"layer": "holes"})
    sketch = read_sketch(save(doc, tmp_path), hole_layers=["holes"])
    assert [link.name for link in sketch.links] == ["other"]
    (problem,) = sketch.problems
    assert problem.kind == "hole_crossing_link_edge" and problem.layer == "plate"
    assert problem.problem.startswith(f"the outline through CIRCLE (handle {circle.dxf.handle}, layer 'holes') on hole "
                                      "layer 'holes' crosses or touches the edge or a hole of the link through LWPOLYLINE")
    assert problem.problem.endswith("that link is left out")


def test_a_problem_on_the_hole_layer_inside_a_link_leaves_the_link_out_rather_than_solid(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    plate(msp, 0, 0, 200, 60, "plate")
    plate(msp, 0, 100, 120, 40, "other", slot=False)
    msp.add_circle((110.0, 30.0), 6.0, dxfattribs={"layer": "holes"})  # crosses the slot, on the same layer
    msp.add_line((40.0, 120.0), (50.0, 125.0), dxfattribs={"layer": "holes"})  # a slot of "other" left open
    with pytest.raises(SketchRefused) as refused:
        read_sketch(save(doc, tmp_path), hole_layers=["holes"])
    problems = refused.value.sketch.problems
    assert sorted(p.kind for p in problems) == ["crossing", "left_out_with_another", "left_out_with_another", "open_chain"]
    spoilt = sorted(p.layer for p in problems if p.kind == "left_out_with_another")
    assert spoilt == ["other", "plate"]
    assert all("its hole layer 'holes' has a problem inside it" in p.problem for p in problems if p.layer in spoilt)


def test_a_hole_layer_outline_in_no_link_is_a_problem_and_an_island_in_a_hole_no_hole(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    area = plate(msp, 0, 0, 200, 60, "plate", slot=False)
    msp.add_circle((300.0, 30.0), 5.0, dxfattribs={"layer": "holes"})
    msp.add_circle((20.0, 30.0), 2.0, dxfattribs={"layer": "holes"})  # inside the round hole at x = 20
    sketch = read_sketch(save(doc, tmp_path), hole_layers=["holes"])
    assert sketch.link("plate").outline.area == pytest.approx(area * 1e-6, rel=1e-9)
    (problem,) = sketch.problems
    assert problem.kind == "hole_in_no_link" and "on hole layer 'holes' lies in no link" in problem.problem
    assert any("lie inside another hole's outline" in fix for fix in sketch.fixes)


def test_hole_layers_must_be_layers_of_the_drawing_and_not_excluded(tmp_path, capsys):
    doc = ezdxf.new("R2013", units=4)
    plate(doc.modelspace(), 0, 0, 200, 60, "plate")
    path = save(doc, tmp_path)
    assert main(["import", str(path), "--hole-layers", "HOLES"]) == 2
    assert "no layer 'HOLES' in the drawing (its layers are 'holes', 'plate')" in capsys.readouterr().err
    assert main(["import", str(path), "--hole-layers", "holes", "--exclude-layers", "holes"]) == 2
    assert "layer(s) 'holes' given both as hole layers and in --exclude-layers" in capsys.readouterr().err
    # --layers need not name them: hole layers are read.
    assert main(["import", str(path), "--hole-layers", "holes", "--layers", "plate"]) == 0
    assert "1 link(s)" in capsys.readouterr().out


# -- scenes -----------------------------------------------------------------------------------------

SCENE = """
[materials.steel]
density = 7850.0

[links.plate]
sketch = "plate.dxf"
layer = "plate"
thickness = 0.01
material = "steel"
{hole_layers}

[links.coupler]
joints = [[0.0, 0.0], [0.2, 0.0]]

[links.output]
joints = [[0.0, 0.0], [0.16, 0.0]]

[links.ground]
joints = [[0.0, 0.0], [0.22, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "plate"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = 60.0
input_speed_rad_s = 1.0
"""


def test_a_scene_link_reads_its_holes_from_hole_layers(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    area = plate(doc.modelspace(), 0, 0, 200, 60, "plate")
    save(doc, tmp_path, "plate.dxf")
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(SCENE.format(hole_layers='hole_layers = ["holes"]')))
    link = load_scene(path).links["plate"]
    assert link.profile.area == pytest.approx(area * 1e-6, rel=1e-9)
    assert np.allclose(link.profile.joints, [[0.02, 0.03], [0.18, 0.03]], rtol=0, atol=1e-15)


def test_a_scene_link_with_holes_on_their_own_layer_is_refused_with_the_key_to_give(tmp_path, capsys):
    doc = ezdxf.new("R2013", units=4)
    plate(doc.modelspace(), 0, 0, 200, 60, "plate")
    save(doc, tmp_path, "plate.dxf")
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(SCENE.format(hole_layers="")))
    assert main(["analyze", str(path)]) == 2
    err = capsys.readouterr().err
    assert "links.plate.sketch: plate.dxf: 3 outline(s) on layer(s) 'holes' lie wholly inside" in err
    assert 'hole_layers = ["holes"]' in err


@pytest.mark.parametrize("value, message", [
    ('"holes"', "must be a list of layer names"), ("[]", "must be a list of layer names"),
    ('["nope"]', "no layer 'nope' in the drawing"),
])
def test_a_bad_hole_layers_key_is_refused_by_its_path(tmp_path, capsys, value, message):
    doc = ezdxf.new("R2013", units=4)
    plate(doc.modelspace(), 0, 0, 200, 60, "plate")
    save(doc, tmp_path, "plate.dxf")
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(SCENE.format(hole_layers=f"hole_layers = {value}")))
    assert main(["analyze", str(path)]) == 2
    err = capsys.readouterr().err
    assert "links.plate." in err and message in err


def test_import_scene_with_hole_layers_writes_them_into_each_sketch_link(tmp_path, capsys):
    from test_import_layers import assembled_four_bar

    def holes_apart(msp):
        # The pin holes the layout draws on each link's layer, moved to a layer of their own.
        for circle in list(msp.query("CIRCLE")):
            circle.dxf.layer = "holes"

    sketch = tmp_path / "assembled.dxf"
    assembled_four_bar(sketch, extra=holes_apart)
    scene = tmp_path / "scene.toml"
    assert main(["import", str(sketch), "--scene", str(scene)]) == 2
    assert "--hole-layers holes" in capsys.readouterr().err
    assert main(["import", str(sketch), "--hole-layers", "holes", "--scene", str(scene)]) == 0
    text = scene.read_text()
    assert text.count('hole_layers = ["holes"]') == 3
    assert main(["analyze", str(scene)]) == 0


@pytest.mark.parametrize("seed", range(12))
def test_random_plates_with_random_holes_import_exactly_or_are_refused_naming_the_crossing_hole(tmp_path, seed):
    """Plates of random size with 1-6 random round holes and slots on the hole layer: a plate all of whose
    holes lie clear inside it imports with its area less theirs (each kept to rounding, docs/importing.md);
    one with a hole crossing its edge is left out with that hole named."""
    rng = np.random.default_rng(seed)
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    expected: dict[str, float | None] = {}
    for k in range(3):
        width, height = rng.uniform(60, 400), rng.uniform(30, 120)
        x0, y0, layer = 0.0, 200.0 * k, f"plate{k}"
        msp.add_lwpolyline([(x0, y0), (x0 + width, y0), (x0 + width, y0 + height), (x0, y0 + height)], close=True,
                           dxfattribs={"layer": layer})
        area, clear = width * height, True
        # Holes in columns, so that they never meet each other (a slot reaches 1.5 r sideways, r up and down).
        columns = int(rng.integers(1, 7))
        for c in range(columns):
            cx = x0 + (c + 0.5) * width / columns
            r = rng.uniform(0.05, 0.3) * min(height, width / columns)
            cy = y0 + rng.uniform(-0.4, 0.4) * height + height / 2
            if rng.random() < 0.5:
                msp.add_circle((cx, cy), r, dxfattribs={"layer": "holes"})
                hole_area, reach = math.pi * r * r, r
            else:  # a slot: a rectangle r wide, 2r tall, with half discs of r on its left and right
                h = r / 2
                msp.add_lwpolyline([(cx - h, cy - r, 0), (cx + h, cy - r, 1), (cx + h, cy + r, 0), (cx - h, cy + r, 1)],
                                   format="xyb", close=True, dxfattribs={"layer": "holes"})
                hole_area, reach = 2 * h * 2 * r + math.pi * r * r, r
            clear &= y0 < cy - reach and cy + reach < y0 + height
            area -= hole_area
        expected[layer] = area * 1e-6 if clear else None
    path = save(doc, tmp_path)
    try:
        sketch = read_sketch(path, hole_layers=["holes"])
    except SketchRefused as refused:  # every plate has a hole across its edge
        sketch = refused.sketch
    assert sorted(link.name for link in sketch.links) == sorted(k for k, v in expected.items() if v is not None)
    for link in sketch.links:
        assert link.outline.area == pytest.approx(expected[link.name], rel=1e-9)
    refused = sorted(p.layer for p in sketch.problems)
    assert refused == sorted(k for k, v in expected.items() if v is None)
    assert all(p.kind == "hole_crossing_link_edge" for p in sketch.problems)
