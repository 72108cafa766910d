"""Bad sketches: one clear SketchError naming the file, the culprit, where and what to do; and the
repairs that are safe to make (duplicates, tiny curves, damaged files) reported as fixes."""

from __future__ import annotations

import re

import math

import ezdxf
import pytest

from linkstress.errors import SketchError
from linkstress.importers import read_sketch
from test_import_dxf import draw, plate_entities, save
from test_import_exact import assert_matches, combine, disc, rectangle, scaled, stadium_plate


def rectangle_lines(msp, x0, y0, x1, y1, layer="0"):
    for a, b in (((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)), ((x1, y1), (x0, y1)), ((x0, y1), (x0, y0))):
        msp.add_line(a, b, dxfattribs={"layer": layer})


def test_an_open_outline_reports_the_gap_size_and_position(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    recipes = [r for r in plate_entities() if r[0] != "line"]
    draw(msp, recipes)
    msp.add_line((0, 0), (99.5, 0))  # 0.5 mm short of the right end
    with pytest.raises(SketchError) as error:
        read_sketch(save(doc, tmp_path))
    message = str(error.value)
    # Nothing imports: the open outline, and its holes left out with it (else they would be discs).
    assert message.startswith("sketch.dxf: no link imports, 2 problems (1 open chain, 1 outline left out with another's "
                              "problem): (1) open outline: the end of LINE (handle ")
    assert "at (99.5, 0) mm is 0.5 mm from the nearest curve end (ARC (handle" in message
    # The drawing spans 150 x 50 mm: size 158.1 mm, gap tolerance 1e-4 of it; 0.5 mm is 0.00316 of it,
    # a quarter more is 0.00395, rounded up to two digits 0.004.
    assert "at (100, 0) mm), more than the gap tolerance 0.0158 mm" in message
    assert "raise the gap tolerance to --tolerance 0.004;" in message
    assert "(2) 4 closed curve(s) inside the open chain through LINE (handle " in message


def test_a_gap_within_a_raised_tolerance_is_closed_and_reported(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    draw(msp, [r for r in plate_entities() if r[0] != "line"])
    msp.add_line((0, 0), (99.5, 0))
    sketch = read_sketch(save(doc, tmp_path), tolerance=0.01)
    assert sketch.link().largest_gap_m == pytest.approx(0.5e-3, rel=1e-9)
    assert "the largest 0.5 mm at (99.75, 0) mm" in " ".join(sketch.fixes)


def test_crossing_outlines_are_refused_with_where_they_meet(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    rectangle_lines(msp, 0, 0, 2, 1)
    msp.add_lwpolyline([(1, 0.5), (3, 0.5), (3, 2), (1, 2)], close=True)
    with pytest.raises(SketchError, match=r"sketch.dxf: outlines cross or touch at \((1|2), (0.5|1)\) m: the one through"):
        read_sketch(save(doc, tmp_path))


def test_a_self_crossing_outline_is_refused(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    doc.modelspace().add_lwpolyline([(0, 0), (2, 0), (0, 1), (2, 1)], close=True)
    with pytest.raises(SketchError, match=r"the outline through LWPOLYLINE \(handle \w+, layer '0'\) crosses itself at \(1, 0.5\) m"):
        read_sketch(save(doc, tmp_path))


def test_a_line_dividing_a_part_leaves_the_part_out_not_solid(tmp_path):
    # The chain (0, 0)-(1, 0)-(1, 1) hangs off a corner (so the rectangle still closes once it is
    # taken off) and runs from the bottom edge to the top one: it may cut the part in two, so the
    # rectangle is not imported as if solid.
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    rectangle_lines(msp, 0, 0, 2, 1)
    msp.add_line((1, 0), (1, 1))
    msp.add_line((0, 0), (1, 0))  # a second curve along the bottom edge from a corner
    with pytest.raises(SketchError, match=r"no link imports, 2 problems \(.*\): \(1\) open outline: the end of LINE .* at \(1, 1\) m"
                       r".*\(2\) the outline through LINE .* is left out: 1 open chain\(s\) cut into its material"):
        read_sketch(save(doc, tmp_path))


def test_curve_ends_meeting_at_a_corner_of_two_outlines_are_a_branch(tmp_path):
    # Two rectangles of lines sharing a corner: four ends meet there and none dangles.
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    rectangle_lines(msp, 0, 0, 2, 1)
    rectangle_lines(msp, 2, 1, 3, 2)
    with pytest.raises(SketchError, match=r"curve ends meet at \(2, 1\) m .*remove the duplicate or overlapping curve"):
        read_sketch(save(doc, tmp_path))


def test_curves_drawn_twice_and_tiny_curves_are_dropped_and_reported(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    rectangle_lines(msp, 0, 0, 2, 1)
    msp.add_line((0, 1), (2, 1))  # the top edge again, the other way round
    msp.add_circle((0.5, 0.5), 0.2)
    msp.add_circle((0.5, 0.5), 0.2)
    msp.add_line((2, 0), (2, 1e-9))  # a sliver smaller than the gap tolerance
    sketch = read_sketch(save(doc, tmp_path))
    assert_matches(sketch.link().outline, combine(rectangle(0, 0, 2, 1), disc(0.5, 0.5, 0.2).hole()), 1e-6, 2)
    fixes = " ".join(sketch.fixes)
    assert "dropped 1 curve(s) no larger than the gap tolerance" in fixes
    assert fixes.count("drawn twice") == 2  # the circle, then the line


def test_an_empty_drawing_says_what_it_holds(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    doc.modelspace().add_text("nothing to see")
    with pytest.raises(SketchError, match=r"sketch.dxf: no outline: the drawing has no curves it reads \(only 1 TEXT was "
                                          r"found, which is not outline geometry\)$"):
        read_sketch(save(doc, tmp_path))
    doc.modelspace().add_text("nor here")
    with pytest.raises(SketchError, match=r"\(only 2 TEXT were found, which are not outline geometry\)$"):
        read_sketch(save(doc, tmp_path))


def test_a_file_that_is_not_dxf_is_refused(tmp_path):
    path = tmp_path / "photo.dxf"
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)))
    with pytest.raises(SketchError, match=r"photo.dxf: not a DXF file"):
        read_sketch(path)
    with pytest.raises(SketchError, match=r"cannot read the sketch .*missing.dxf.*No such file"):
        read_sketch(tmp_path / "missing.dxf")


def test_a_dxf_truncated_after_its_entities_is_recovered_and_reported(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    draw(doc.modelspace(), plate_entities(), layer="plate")
    data = save(doc, tmp_path).read_bytes()
    cut = data.index(b"\n", data.index(b"OBJECTS") + 200) + 1
    cut = data.index(b"\n", cut) + 1 if data[:cut].count(b"\n") % 2 else cut  # end on a whole code/value pair
    (tmp_path / "cut.dxf").write_bytes(data[:cut])
    sketch = read_sketch(tmp_path / "cut.dxf")
    assert "the file is damaged (the file does not end with the EOF marker (truncated?)); read in ezdxf's recover mode" in sketch.fixes
    assert_matches(sketch.link().outline, scaled(stadium_plate(), 1e-3), 1e-6, 0.15)


def test_a_dxf_truncated_in_its_entities_fails_with_the_damage_noted(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    draw(doc.modelspace(), plate_entities(), layer="plate")
    data = save(doc, tmp_path).read_bytes()
    cut = data.index(b"ENTITIES") + 400
    (tmp_path / "cut.dxf").write_bytes(data[:cut])
    with pytest.raises(SketchError, match=r"^cut.dxf: .*\(note: the file is damaged \(the file does not end with the EOF marker"):
        read_sketch(tmp_path / "cut.dxf")


def test_a_garbled_group_code_is_read_in_recover_mode_and_noted(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    rectangle_lines(doc.modelspace(), 0, 0, 2, 1, layer="bar")
    text = save(doc, tmp_path).read_text()
    second_line = text.index("\nLINE\n", text.index("\nLINE\n") + 1)
    (tmp_path / "garbled.dxf").write_text(text[:second_line] + text[second_line:].replace("\n 10\n", "\n1x0\n", 1))
    # The second line loses its start x, which becomes 0: recovered, a triangle closes and the bottom
    # line dangles from its corner, listed as a problem (a scene on this layer is refused with it).
    sketch = read_sketch(tmp_path / "garbled.dxf")
    assert re.fullmatch(r"the file is damaged \(line \d+: '1x0' is not a group code\); read in ezdxf's recover mode",
                        sketch.fixes[0])
    (problem,) = sketch.problems
    assert problem.problem.startswith("open curve: LINE") and problem.layer == "bar"
    with pytest.raises(SketchError, match=r"garbled.dxf: layer 'bar': open curve: LINE"):
        sketch.link("bar")


def test_the_gap_tolerance_must_be_a_fraction(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    rectangle_lines(doc.modelspace(), 0, 0, 2, 1)
    with pytest.raises(SketchError, match=r"the gap tolerance \(--tolerance\) is a fraction of the drawing size in \[1e-09, 0.5\), got 2"):
        read_sketch(save(doc, tmp_path), tolerance=2)
    with pytest.raises(SketchError, match=r"chord tolerance \(--sagitta\) must be a fraction of the radius in \(0, 0.5\), got 0"):
        read_sketch(save(doc, tmp_path), sagitta=0)


def test_an_entity_outside_the_xy_plane_is_refused(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    rectangle_lines(msp, 0, 0, 2, 1)
    msp.add_circle((0.5, 0.5), 0.1, dxfattribs={"extrusion": (1, 0, 1)})
    with pytest.raises(SketchError, match=r"CIRCLE \(handle \w+, layer '0'\) is not drawn in the XY plane \(extrusion \(1, 0, 1\)\)"):
        read_sketch(save(doc, tmp_path))


def test_unconvertible_insunits_are_refused(tmp_path):
    doc = ezdxf.new("R2013", units=9)  # mils: ezdxf has no factor to metres for it
    rectangle_lines(doc.modelspace(), 0, 0, 2, 1)
    with pytest.raises(SketchError, match=r"\$INSUNITS = 9 \(Mils\) has no conversion to metres"):
        read_sketch(save(doc, tmp_path))


def test_a_link_inside_a_hole_is_a_link_of_its_own(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    rectangle_lines(msp, 0, 0, 4, 4, layer="frame")
    msp.add_circle((2, 2), 1.5, dxfattribs={"layer": "frame"})
    msp.add_circle((2, 2), 1.0, dxfattribs={"layer": "disc"})
    for x in (1.5, 2.5):  # its joints: a disc without any would be a mark drawn in the hole
        msp.add_point((x, 2), dxfattribs={"layer": "disc"})
    sketch = read_sketch(save(doc, tmp_path))
    assert sketch.link("frame").outline.area == pytest.approx(16 - math.pi * 2.25, rel=1e-12)
    assert sketch.link("disc").outline.area == pytest.approx(math.pi, rel=1e-12)


def test_a_sketch_without_a_known_suffix_is_read_by_its_content(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    rectangle_lines(doc.modelspace(), 0, 0, 2, 1)
    doc.saveas(tmp_path / "bar.dat")
    assert read_sketch(tmp_path / "bar.dat").format.startswith("DXF")
    (tmp_path / "bar.txt").write_text("# linkstress-sketch v1 units=m\ncircle, 0, 0, 1\n")
    assert read_sketch(tmp_path / "bar.txt").format == "linkstress-sketch v1 CSV"
