"""Sheets as CAD exports them: a page frame with tick marks and a title block around the parts, text
exploded into glyph outlines, drill marks, layers of annotation. Only the parts import; the rest is
listed as skipped, and the headline counts parts.

Every sheet is generated here with ezdxf, in mm.
"""

from __future__ import annotations

import json
import math

import ezdxf
import numpy as np
import pytest

from linkstress.cli import main
from linkstress.errors import SketchError
from linkstress.importers import read_sketch
from linkstress.importers.parts import MARK_FRACTION, annotation_layers
from test_import_dxf import save


def bar(msp, x0: float, y0: float, length: float, depth: float = 20.0, hole: float = 8.0, layer: str = "0",
        points: bool = False) -> float:
    """A bar with round ends and a pin hole at each end (joints x0 and x0 + length on y0); its area [mm^2]."""
    r = depth / 2
    msp.add_lwpolyline([(x0, y0 - r, 0.0), (x0 + length, y0 - r, 1.0), (x0 + length, y0 + r, 0.0), (x0, y0 + r, 1.0)],
                       format="xyb", close=True, dxfattribs={"layer": layer})
    for x in (x0, x0 + length):
        msp.add_circle((x, y0), hole / 2, dxfattribs={"layer": layer})
        if points:
            msp.add_point((x, y0), dxfattribs={"layer": layer})
    return length * depth + math.pi * r**2 - 2 * math.pi * (hole / 2) ** 2


def frame(msp, width: float, height: float, layer: str = "0", margin: float = 10.0, double: bool = True) -> int:
    """A sheet's frame: the trimmed edge and (``double``) the border ``margin`` inside it, tick marks
    across the margin (or, single, inward from the edge) and a title block of lines in the lower right
    corner; the number of LINEs drawn (tick marks and title block)."""
    att = {"layer": layer}
    msp.add_lwpolyline([(0, 0), (width, 0), (width, height), (0, height)], close=True, dxfattribs=att)
    inner = margin if double else 0.0
    if double:
        msp.add_lwpolyline([(margin, margin), (width - margin, margin), (width - margin, height - margin),
                            (margin, height - margin)], close=True, dxfattribs=att)
    lines = 0
    for k in range(1, 8):
        x = width * k / 8
        for y0, y1 in ((0, margin), (height - margin, height)):
            msp.add_line((x, y0), (x, y1), dxfattribs=att)
            lines += 1
    for k in range(1, 6):
        y = height * k / 6
        for x0, x1 in ((0, margin), (width - margin, width)):
            msp.add_line((x0, y), (x1, y), dxfattribs=att)
            lines += 1
    # The title block: its left and top sides end on the border, its rows and a column on them.
    right, bottom = width - inner, inner
    left, top = right - 180, bottom + 40
    for a, b in [((left, bottom), (left, top)), ((left, top), (right, top)), ((left + 90, bottom), (left + 90, top))]:
        msp.add_line(a, b, dxfattribs=att)
    for k in (1, 2, 3):
        msp.add_line((left, bottom + 10 * k), (right, bottom + 10 * k), dxfattribs=att)
    return lines + 6


def glyph(msp, x: float, y: float, size: float = 2.5, layer: str = "0") -> None:
    """An exploded letter "O" of a filled font, ``size`` tall: a closed outline and its counter."""
    w = 0.7 * size
    msp.add_lwpolyline([(x, y), (x + w, y), (x + w, y + size), (x, y + size)], close=True, dxfattribs={"layer": layer})
    msp.add_lwpolyline([(x + 0.25 * w, y + 0.2 * size), (x + 0.75 * w, y + 0.2 * size), (x + 0.75 * w, y + 0.8 * size),
                        (x + 0.25 * w, y + 0.8 * size)], close=True, dxfattribs={"layer": layer})


def drill_mark(msp, x: float, y: float, radius: float = 3.0, layer: str = "DRILL") -> None:
    """A drill mark: a small circle with a cross through it."""
    msp.add_circle((x, y), radius, dxfattribs={"layer": layer})
    msp.add_line((x - 2 * radius, y), (x + 2 * radius, y), dxfattribs={"layer": layer})
    msp.add_line((x, y - 2 * radius), (x, y + 2 * radius), dxfattribs={"layer": layer})


# -- page frames ------------------------------------------------------------------------------------


@pytest.mark.parametrize("width, height", [(297.0, 210.0), (420.0, 297.0), (841.0, 594.0)], ids=["A4", "A3", "A1"])
@pytest.mark.parametrize("layer, double", [("0", True), ("0", False), ("sheet", True)])
def test_a_page_frame_with_tick_marks_and_a_title_block_is_skipped_and_the_parts_inside_it_import(
        tmp_path, width, height, layer, double):
    # Before, on layer 0: the frame was a link whose holes were the parts, its tick marks cut into it,
    # and it was left out with every part inside it ("no link imports", 5 of 185 problems listed).
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    marks = frame(msp, width, height, layer, double=double)
    areas = [bar(msp, 40, height / 2 + 30, 150), bar(msp, 40, height / 2 - 20, 100, depth=16, hole=6)]
    sketch = read_sketch(save(doc, tmp_path))
    links = sorted(sketch.links, key=lambda link: -link.joints[0, 1])
    assert np.allclose(links[0].joints, [[0.04, height / 2e3 + 0.03], [0.19, height / 2e3 + 0.03]], rtol=0, atol=1e-12)
    assert np.allclose(links[1].joints, [[0.04, height / 2e3 - 0.02], [0.14, height / 2e3 - 0.02]], rtol=0, atol=1e-12)
    assert [link.outline.area for link in links] == pytest.approx([a * 1e-6 for a in areas], rel=1e-6)
    assert sketch.problems == ()
    frames = [item for item in sketch.skipped if item.kind == "page_frame"]
    assert len(frames) == (2 if double else 1) and {item.layer for item in frames} == {layer}
    # Every tick mark and title block line is skipped with the frame it touches.
    assert sum(len(item.entities) for item in frames) == len(frames) + marks
    assert "taken for the sheet's frame and skipped" in frames[0].note


def test_import_prints_the_frame_as_skipped_and_counts_only_the_parts(tmp_path, capsys):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    frame(msp, 420, 297)
    bar(msp, 40, 180, 150)
    bar(msp, 40, 130, 100)
    out = tmp_path / "links.json"
    assert main(["import", str(save(doc, tmp_path)), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("sketch.dxf: DXF AC1027, units mm ($INSUNITS), 2 link(s), 2 outline(s) skipped as no part\n")
    assert "skipped, not parts (every one in --json):\n- 2 page frames\n  - the outline through LWPOLYLINE" in text
    data = json.loads(out.read_text())
    assert [item["kind"] for item in data["skipped"]] == ["page_frame", "page_frame"]
    assert len(data["links"]) == 2 and data["problems"] == []


def test_a_ground_plate_drawn_around_the_mechanism_with_its_pivots_is_a_link_not_a_frame(tmp_path):
    # Layer "frame" names a mechanism's ground; this one holds the crank and has its pivot holes.
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(-40, -40), (200, -40), (200, 60), (-40, 60)], close=True, dxfattribs={"layer": "frame"})
    for x in (0.0, 150.0):
        msp.add_circle((x, 0.0), 4.0, dxfattribs={"layer": "frame"})
    bar(msp, 0, 0, 40, layer="crank")
    sketch = read_sketch(save(doc, tmp_path))
    assert [link.name for link in sketch.links] == ["frame", "crank"] and sketch.skipped == ()
    assert sketch.link("frame").joints.tolist() == [[0.0, 0.0], [0.15, 0.0]]


def test_a_ground_plate_with_pivot_points_in_its_material_is_no_frame_either(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(-40, -40), (200, -40), (200, 60), (-40, 60)], close=True, dxfattribs={"layer": "base"})
    for x in (-20.0, 180.0):
        msp.add_point((x, 0.0), dxfattribs={"layer": "base"})
    bar(msp, 0, 0, 40, layer="crank")
    sketch = read_sketch(save(doc, tmp_path))
    assert [link.name for link in sketch.links] == ["base", "crank"] and sketch.skipped == ()


def test_a_plate_with_a_window_and_nothing_in_it_is_a_link_not_a_frame(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (4, 0), (4, 3), (0, 3)], close=True)
    msp.add_lwpolyline([(1, 1), (3, 1), (3, 2), (1, 2)], close=True)
    sketch = read_sketch(save(doc, tmp_path))
    assert len(sketch.links) == 1 and sketch.skipped == ()
    assert sketch.link().outline.area == pytest.approx(10.0, rel=1e-12)


# -- glyphs and drill marks -------------------------------------------------------------------------


@pytest.mark.parametrize("glyphs", [104, 150])
def test_glyph_sized_outlines_and_drill_marks_are_skipped_and_the_two_real_links_import(tmp_path, capsys, glyphs):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    bar(msp, 0, 0, 200)
    bar(msp, 0, 60, 120)
    for k in range(glyphs):  # lettering 2.5 mm tall in rows beside the links
        glyph(msp, 230 + 2.5 * (k % 30), 5 * (k // 30))
    for x, y in ((0, 0), (200, 0), (0, 60), (120, 60)):  # a drill mark on each pin hole
        drill_mark(msp, x, y, radius=3.0)
    path = save(doc, tmp_path)
    sketch = read_sketch(path)
    assert [link.joints.tolist() for link in sketch.links] == [[[0.0, 0.0], [0.2, 0.0]], [[0.0, 0.06], [0.12, 0.06]]]
    by_kind = {item.kind: item for item in sketch.skipped}
    # Each glyph's outline; its counter is its hole. The sheet is ~320 x 70 mm: a glyph is ~0.9 % of it.
    assert by_kind["small_outline"].count == glyphs and by_kind["small_outline"].layer == "0"
    assert by_kind["in_a_hole"].count == 4 and by_kind["in_a_hole"].layer == "DRILL"
    # The crosses' lines are skipped with their circles, not left as open-chain problems.
    assert sketch.problems == () and "with 8 open chain(s) crossing them" in by_kind["in_a_hole"].note
    assert main(["import", str(path)]) == 0
    head = capsys.readouterr().out.splitlines()[0]
    assert head.endswith(f"2 link(s), {glyphs + 4} outline(s) skipped as no part")


def test_a_line_crossing_a_mark_but_much_longer_than_it_stays_a_problem(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    bar(msp, 0, 0, 200)
    msp.add_circle((100.0, 60.0), 1.0, dxfattribs={"layer": "DRILL"})  # a mark: 1.2 % of the sheet
    msp.add_line((90.0, 60.0), (110.0, 60.0), dxfattribs={"layer": "DRILL"})  # 20 mm across it: 7 times its size
    msp.add_line((100.0, 57.0), (100.0, 63.0), dxfattribs={"layer": "DRILL"})  # 6 mm: twice its size, its cross
    sketch = read_sketch(save(doc, tmp_path))
    (problem,) = sketch.problems
    assert problem.kind == "open_chain" and problem.at == (90.0, 60.0)


def test_a_small_outline_with_two_joints_is_a_part(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    bar(msp, 0, 0, 1000, depth=40, hole=10)
    bar(msp, 0, 100, 10, depth=4, hole=1)  # 14 mm of a 1.1 m sheet: 1.3 %, but its two pin holes make it a part
    assert len(read_sketch(save(doc, tmp_path)).links) == 2


@pytest.mark.parametrize("fraction, skipped", [(0.5 * MARK_FRACTION, True), (2 * MARK_FRACTION, False)])
def test_an_outline_without_joints_is_skipped_when_smaller_than_the_mark_fraction_of_the_sheet(tmp_path, fraction, skipped):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    bar(msp, 0, 0, 300)  # the sheet: 320 x 20 mm, 320.6 mm across
    side = fraction * math.hypot(320, 20 + 0) / math.sqrt(2)  # a square whose diagonal is that fraction
    msp.add_lwpolyline([(0, 50), (side, 50), (side, 50 + side), (0, 50 + side)], close=True)
    sketch = read_sketch(save(doc, tmp_path))
    assert (len(sketch.links), len(sketch.skipped)) == ((1, 1) if skipped else (2, 0))


def test_glyphs_beside_a_part_that_is_refused_do_not_import_as_links_in_its_stead(tmp_path, capsys):
    # Before: the part was refused and the 120 glyphs imported as 120 "links", exit 0.
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for k in range(120):
        glyph(msp, 2.5 * (k % 40), 5 * (k // 40))
    msp.add_lwpolyline([(0, 30), (300, 30), (300, 100), (0, 100)])  # a panel whose outline does not close
    out = tmp_path / "links.json"
    assert main(["import", str(save(doc, tmp_path)), "--json", str(out)]) == 2
    assert "sketch.dxf: open curve: LWPOLYLINE" in capsys.readouterr().err
    data = json.loads(out.read_text())
    assert data["links"] == [] and [p["kind"] for p in data["problems"]] == ["open_chain"]
    assert [(item["kind"], item["count"]) for item in data["skipped"]] == [("small_outline", 120)]


def test_a_circle_without_joints_drawn_in_a_pin_hole_on_another_layer_is_skipped_as_a_pin(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (4, 0), (4, 3), (0, 3)], close=True)
    msp.add_circle((2, 1.5), 0.5)
    msp.add_circle((2, 1.5), 0.2, dxfattribs={"layer": "pins"})  # no part: a pin drawn in the hole
    sketch = read_sketch(save(doc, tmp_path))
    assert len(sketch.links) == 1 and [item.kind for item in sketch.skipped] == ["in_a_hole"]


def test_a_sheet_whose_curves_are_all_on_annotation_layers_says_so(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    bar(doc.modelspace(), 0, 0, 100, layer="TEXT")
    with pytest.raises(SketchError, match=r"^sketch.dxf: no outline: every curve read is on a layer named for annotation "
                                          r"\('TEXT'\); name it in --layers to read it$"):
        read_sketch(save(doc, tmp_path))


# -- layers of annotation ---------------------------------------------------------------------------


@pytest.mark.parametrize("name, annotation", [
    ("TEXT", True), ("Dimensions", True), ("title-block", True), ("TitleBlock", True), ("AM_BORDER", True),
    ("anno_labels", True), ("DIM", True), ("frame", False), ("context", False), ("dimple", False),
    ("crank", False), ("0", False),
])
def test_a_layer_is_annotation_when_a_word_of_its_name_says_so(name, annotation):
    assert annotation_layers([name]) == ([name] if annotation else [])


def test_an_annotation_layer_is_not_read_unless_named_in_layers(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    bar(msp, 0, 0, 100, layer="crank")
    msp.add_lwpolyline([(0, 30), (40, 30), (40, 50), (0, 50)], close=True, dxfattribs={"layer": "TEXT"})
    msp.add_line((50, 30), (90, 30), dxfattribs={"layer": "TEXT"})
    path = save(doc, tmp_path)
    sketch = read_sketch(path)
    assert [link.name for link in sketch.links] == ["crank"] and sketch.problems == ()
    (layer,) = sketch.skipped
    assert (layer.kind, layer.layer) == ("annotation_layer", "TEXT") and "its 2 curve(s)" in layer.note
    assert layer.at in ((0.0, 30.0), (50.0, 30.0))  # where a curve of it starts
    assert [link.name for link in read_sketch(path, layers=["crank", "TEXT"]).links] == ["crank", "TEXT"]


def test_a_rectangular_plate_whose_slot_on_another_layer_holds_a_pin_is_no_frame(tmp_path):
    # Its holes and slot on layer "holes", a POINT in the slot: no part inside it has two joints.
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (200, 0), (200, 60), (0, 60)], close=True, dxfattribs={"layer": "plate"})
    for x in (20, 180):
        msp.add_circle((x, 30), 5, dxfattribs={"layer": "holes"})
    msp.add_lwpolyline([(80, 25, 0), (120, 25, 1), (120, 35, 0), (80, 35, 1)], format="xyb", close=True,
                       dxfattribs={"layer": "holes"})
    msp.add_point((100, 30), dxfattribs={"layer": "holes"})
    sketch = read_sketch(save(doc, tmp_path))
    assert sketch.skipped == ()
    (problem,) = sketch.problems  # the plate and its two round holes; the slot holds a joint, so stays
    assert (problem.kind, problem.layer) == ("hole_on_own_layer", "plate")
