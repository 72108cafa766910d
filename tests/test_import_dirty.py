"""Dirty sheets: every clean outline imports, each stray line, engraving or crossing is a listed
problem that leaves out only what it names; --strict, --layers and --exclude-layers; scenes refuse
a link whose layer has a problem and read one on a clean layer of the same sheet."""

from __future__ import annotations

import json
import re
import textwrap

import ezdxf
import pytest

from linkstress.cli import main
from linkstress.errors import SketchError
from linkstress.importers import read_sketch
from test_import_dxf import save
from test_scene_errors import BASE, write_crank_sketch


def dirty_sheet(tmp_path):
    """Three clean parts and three problems, in mm:

    - layer "crank": the scene tests' crank, a 40 x 16 bar with joints (0, 0) and (20, 0) in 6 mm holes;
    - layer "parts": a 40 x 10 bar at (50, 0) and a 30 x 20 plate with a 5 mm hole at (50, 40), and a
      stray LINE from (100, 0) to (100, 30) beside them;
    - layer "engraving": the letters "L" and "T" as open LWPOLYLINEs on the plate.
    """
    write_crank_sketch(tmp_path / "sketch.dxf")
    doc = ezdxf.readfile(tmp_path / "sketch.dxf")
    msp = doc.modelspace()
    on = {"layer": "parts"}
    msp.add_lwpolyline([(50, 0), (90, 0), (90, 10), (50, 10)], close=True, dxfattribs=on)
    msp.add_lwpolyline([(50, 40), (80, 40), (80, 60), (50, 60)], close=True, dxfattribs=on)
    msp.add_circle((70, 50), 2.5, dxfattribs=on)
    msp.add_line((100, 0), (100, 30), dxfattribs=on)
    engraving = {"layer": "engraving"}
    msp.add_lwpolyline([(55, 55), (55, 45), (60, 45)], dxfattribs=engraving)
    msp.add_lwpolyline([(62, 55), (66, 55), (64, 55), (64, 45)], dxfattribs=engraving)
    return save(doc, tmp_path)


def test_a_dirty_sheet_imports_its_three_clean_parts_and_lists_the_three_problems(tmp_path):
    sketch = read_sketch(dirty_sheet(tmp_path))
    assert [link.name for link in sketch.links] == ["crank", "parts-1", "parts-2"]
    bar, plate = sketch.links[1], sketch.links[2]
    assert bar.outline.area == pytest.approx(400e-6, rel=1e-9)  # 40 x 10 mm
    assert len(plate.outline.interiors) == 1 and plate.hole_diameters_m == pytest.approx((5e-3,), rel=1e-9)
    assert sorted(p.layer for p in sketch.problems) == ["engraving", "engraving", "parts"]
    stray = next(p for p in sketch.problems if p.layer == "parts")
    assert stray.problem.startswith("open curve: LINE (handle ")
    assert "from (100, 0) mm to (100, 30) mm does not close (its ends are 30 mm apart)" in stray.problem
    assert stray.entities[0].startswith("LINE (handle") and stray.at == (100.0, 0.0)
    assert "--exclude-layers" in stray.fix


def test_import_prints_the_problems_and_exits_0_while_a_link_imports(tmp_path, capsys):
    path = dirty_sheet(tmp_path)
    out = tmp_path / "links.json"
    assert main(["import", str(path), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("sketch.dxf: DXF AC1027, units mm ($INSUNITS), 3 link(s), 3 problem(s)\n")
    # The problems come first, grouped, before the links.
    assert "problems (3, left out of the links below; every one in --json):\n- 3 open chains\n" in text
    assert text.count("\n  - open ") == 3 and text.index("problems (3") < text.index("link crank")
    data = json.loads(out.read_text())
    assert [link["name"] for link in data["links"]] == ["crank", "parts-1", "parts-2"]
    assert [sorted(p) for p in data["problems"]] == [["at", "entities", "fix", "kind", "layer", "problem"]] * 3
    assert {p["kind"] for p in data["problems"]} == {"open_chain"} and "refused" not in data
    stray = next(p for p in data["problems"] if p["layer"] == "parts")
    assert stray["at"] == [100.0, 0.0] and stray["entities"][0].startswith("LINE (handle ")


def test_strict_refuses_a_dirty_sheet_listing_its_problems(tmp_path, capsys):
    path = dirty_sheet(tmp_path)
    out = tmp_path / "links.json"
    assert main(["import", str(path), "--strict", "--json", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("linkstress: error: sketch.dxf: --strict: 3 problems (3 open chains): (1) open ")
    assert err.count("\n") == 1 and err.rstrip().endswith(f"(every problem in {out})")
    # Its only output: the JSON, with the links that would import, every problem, and why it was refused.
    data = json.loads(out.read_text())
    assert len(data["problems"]) == 3 and data["refused"].startswith("sketch.dxf: --strict: 3 problems")


@pytest.mark.parametrize("flags, links, problem_layers", [
    (["--layers", "crank"], ["crank"], []),
    (["--layers", "crank, parts"], ["crank", "parts-1", "parts-2"], ["parts"]),
    (["--exclude-layers", "engraving"], ["crank", "parts-1", "parts-2"], ["parts"]),
    (["--exclude-layers", "engraving,parts"], ["crank"], []),
])
def test_layers_are_chosen_or_left_out(tmp_path, flags, links, problem_layers):
    path = dirty_sheet(tmp_path)
    out = tmp_path / "links.json"
    # Without problems, even --strict imports.
    strict = [] if problem_layers else ["--strict"]
    assert main(["import", str(path), *flags, *strict, "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert [link["name"] for link in data["links"]] == links
    assert [p["layer"] for p in data["problems"]] == problem_layers


def test_an_unknown_layer_exits_2_naming_the_layers_the_file_has(tmp_path, capsys):
    path = dirty_sheet(tmp_path)
    assert main(["import", str(path), "--exclude-layers", "engraving,text"]) == 2
    err = capsys.readouterr().err
    assert "sketch.dxf: no layer 'text' in the drawing (its layers are 'crank', 'engraving', 'parts')" in err


def test_a_sheet_where_nothing_is_clean_exits_2_with_its_problems(tmp_path, capsys):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (2, 0), (2, 1), (0, 1)], close=True)
    msp.add_lwpolyline([(1, 0.5), (3, 0.5), (3, 2), (1, 2)], close=True)
    msp.add_line((5, 0), (6, 0))
    assert main(["import", str(save(doc, tmp_path))]) == 2
    err = capsys.readouterr().err
    assert err.startswith("linkstress: error: sketch.dxf: no link imports, 2 problems (1 open chain, 1 pair of "
                          "outlines crossing or touching): (1) open curve: LINE")
    assert "(2) outlines cross or touch at (" in err and err.count("\n") == 1


@pytest.mark.parametrize("second", [
    [(2, 1), (0, 1), (0, 0), (2, 0)],  # starts at another corner
    [(2, 0), (0, 0), (0, 1), (2, 1)],  # clockwise
    [(2, 1), (0, 1), (0, 0), (2, 0), (2, 1)],  # and repeats its first vertex at the end
])
def test_an_outline_drawn_twice_as_closed_polylines_is_one_link_and_a_fix(tmp_path, second):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    first = msp.add_lwpolyline([(0, 0), (2, 0), (2, 1), (0, 1)], close=True)
    again = msp.add_lwpolyline(second, close=True)
    sketch = read_sketch(save(doc, tmp_path))
    assert len(sketch.links) == 1 and sketch.link().outline.area == pytest.approx(2.0, rel=1e-12)
    assert sketch.problems == ()
    assert (f"dropped 1 curve(s) drawn twice, e.g. LWPOLYLINE (handle {again.dxf.handle}, layer '0') repeats "
            f"LWPOLYLINE (handle {first.dxf.handle}, layer '0')") in sketch.fixes[0]


def test_a_gap_is_measured_to_another_curves_loose_end_not_its_own_other_end(tmp_path):
    # The bottom of a 100 x 50 mm rectangle: LINEs to (97, 0), then a 1 mm piece to (98, 0); the right
    # side starts at (100, 0). The loose end (98, 0) is 1 mm from its own other end, 2 mm from the gap's
    # other side.
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for a, b in [((0, 0), (97, 0)), ((97, 0), (98, 0)), ((100, 0), (100, 50)), ((100, 50), (0, 50)), ((0, 50), (0, 0))]:
        lines = msp.add_line(a, b)
        if a == (97, 0):
            short = lines.dxf.handle
        if a == (100, 0):
            right = lines.dxf.handle
    with pytest.raises(SketchError) as error:
        read_sketch(save(doc, tmp_path))
    assert (f"open outline: the end of LINE (handle {short}, layer '0') at (98, 0) mm is 2 mm from the nearest "
            f"curve end (LINE (handle {right}, layer '0') at (100, 0) mm)") in str(error.value)


def test_the_advised_tolerance_closes_the_gap(tmp_path):
    # A 100 x 50 mm rectangle whose bottom stops 0.5 mm short: size 111.8 mm, so 0.5 mm is 0.00447 of
    # it; with a quarter more, rounded up to two digits, 0.0056.
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for a, b in [((0, 0), (99.5, 0)), ((100, 0), (100, 50)), ((100, 50), (0, 50)), ((0, 50), (0, 0))]:
        msp.add_line(a, b)
    path = save(doc, tmp_path)
    with pytest.raises(SketchError, match=r"or raise the gap tolerance to --tolerance 0.0056$") as error:
        read_sketch(path)
    advised = float(re.search(r"--tolerance ([\d.e-]+)$", str(error.value))[1])
    assert read_sketch(path, tolerance=advised).link().largest_gap_m == pytest.approx(0.5e-3, rel=1e-9)


def test_two_outlines_sharing_a_cut_are_told_so(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20)], close=True)
    msp.add_lwpolyline([(40, 5), (70, 5), (70, 15), (40, 15)], close=True)
    msp.add_lwpolyline([(0, 40), (20, 40), (20, 60), (0, 60)], close=True)
    sketch = read_sketch(save(doc, tmp_path))
    assert len(sketch.links) == 1 and sketch.links[0].outline.bounds == pytest.approx((0, 0.04, 0.02, 0.06))
    (problem,) = sketch.problems
    assert re.fullmatch(
        r"the outlines of LWPOLYLINE \(handle \w+, layer '0'\) and LWPOLYLINE \(handle \w+, layer '0'\) share the "
        r"cut from \(40, (5|15)\) mm to \(40, (15|5)\) mm; draw them apart, or on separate layers", problem.text)


def test_a_link_whose_hole_is_left_out_is_left_out_too(tmp_path):
    # The plate's hole is drawn as a bow tie (it crosses itself): the plate must not import as if solid.
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20)], close=True, dxfattribs={"layer": "plate"})
    msp.add_lwpolyline([(10, 5), (20, 15), (20, 5), (10, 15)], close=True, dxfattribs={"layer": "plate"})
    msp.add_lwpolyline([(0, 40), (20, 40), (20, 60), (0, 60)], close=True, dxfattribs={"layer": "bar"})
    sketch = read_sketch(save(doc, tmp_path))
    assert [link.name for link in sketch.links] == ["bar"]
    crosses, left_out = sketch.problems
    assert "crosses itself at (15, 10) mm" in crosses.problem
    assert "is left out: its hole through LWPOLYLINE" in left_out.problem and left_out.layer == "plate"


def test_the_holes_of_an_open_outline_do_not_import_as_discs(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    shell = msp.add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20), (0, 1)])  # 1 mm short of closing
    hole = msp.add_circle((10, 10), 3)
    msp.add_lwpolyline([(0, 40), (20, 40), (20, 60), (0, 60)], close=True)
    sketch = read_sketch(save(doc, tmp_path))
    assert len(sketch.links) == 1 and sketch.links[0].outline.area == pytest.approx(400e-6, rel=1e-9)
    open_shell, swallowed = sketch.problems
    handle = shell.dxf.handle
    assert open_shell.problem.startswith(f"open curve: LWPOLYLINE (handle {handle}, layer '0') from (0, 0) mm")
    assert swallowed.problem.startswith(
        f"1 closed curve(s) inside the open chain through LWPOLYLINE (handle {shell.dxf.handle}, layer '0') are "
        f"left out with it, e.g. the one through CIRCLE (handle {hole.dxf.handle}, layer '0')"
    )


def scene_on(tmp_path, layer: str):
    dirty_sheet(tmp_path)
    text = BASE.replace(
        '[links.crank]\njoints = [[0.0, 0.0], [0.02, 0.0]]',
        f'[links.crank]\nsketch = "sketch.dxf"\nlayer = "{layer}"',
    )
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(text))
    return path


def test_a_scene_link_on_a_layer_with_a_problem_exits_2_with_that_problem(tmp_path, capsys):
    assert main(["analyze", str(scene_on(tmp_path, "parts"))]) == 2
    err = capsys.readouterr().err
    assert err.startswith(
        "linkstress: error: scene.toml: links.crank.sketch: sketch.dxf: layer 'parts': open curve: LINE"
    )
    assert err.count("\n") == 1


def test_a_scene_link_on_a_clean_layer_of_a_dirty_sheet_runs(tmp_path, capsys):
    assert main(["analyze", str(scene_on(tmp_path, "crank"))]) == 0


def test_an_outline_drawn_as_a_polyline_and_again_as_lines_is_one_link_and_a_fix(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (2, 0), (2, 1), (0, 1)], close=True)
    for a, b in [((2, 1), (0, 1)), ((0, 1), (0, 0)), ((0, 0), (2, 0)), ((2, 0), (2, 1))]:
        msp.add_line(a, b)
    sketch = read_sketch(save(doc, tmp_path))
    assert len(sketch.links) == 1 and sketch.link().outline.area == pytest.approx(2.0, rel=1e-12)
    assert sketch.problems == ()
    assert re.fullmatch(r"dropped 1 outline\(s\) drawn twice, e.g. the one through LINE \(handle \w+, layer '0'\) "
                        r"repeats the one through LWPOLYLINE \(handle \w+, layer '0'\) at \(0, 0\) m", sketch.fixes[0])


def test_a_stray_line_through_a_part_leaves_the_part_in(tmp_path):
    # A construction line across the plate, on its layer: it encloses nothing, so the plate and its
    # hole import; the line is the one problem.
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20)], close=True)
    msp.add_circle((20, 10), 3)
    msp.add_line((-10, 10), (50, 10))
    sketch = read_sketch(save(doc, tmp_path))
    assert len(sketch.links) == 1 and len(sketch.link("sketch-1").outline.interiors) == 1
    (problem,) = sketch.problems
    assert problem.problem.startswith("open curve: LINE")


def test_a_point_off_its_hole_centre_leaves_out_only_its_link(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for layer, y in (("good", 0), ("bad", 40)):
        msp.add_lwpolyline([(0, y), (40, y), (40, y + 20), (0, y + 20)], close=True, dxfattribs={"layer": layer})
        msp.add_circle((10, y + 10), 3, dxfattribs={"layer": layer})
    msp.add_point((11, 50), dxfattribs={"layer": "bad"})  # 1 mm off the centre (10, 50)
    sketch = read_sketch(save(doc, tmp_path))
    assert [link.name for link in sketch.links] == ["good"]
    (problem,) = sketch.problems
    assert problem.layer == "bad" and problem.at == (11.0, 50.0)
    assert "lies in a hole of link 'bad' but not at its centre (10, 50) mm" in problem.problem


def test_a_junction_of_three_curve_ends_leaves_out_only_its_outline(tmp_path):
    # Two squares sharing an edge, drawn as LINEs on layer "pair": three ends meet at (1, 0) and at
    # (1, 1). The plate on layer "plate" imports.
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    for a, b in [((0, 0), (1, 0)), ((1, 0), (2, 0)), ((2, 0), (2, 1)), ((2, 1), (1, 1)), ((1, 1), (0, 1)),
                 ((0, 1), (0, 0)), ((1, 0), (1, 1))]:
        msp.add_line(a, b, dxfattribs={"layer": "pair"})
    msp.add_lwpolyline([(0, 3), (2, 3), (2, 4), (0, 4)], close=True, dxfattribs={"layer": "plate"})
    sketch = read_sketch(save(doc, tmp_path))
    assert [link.name for link in sketch.links] == ["plate"]
    # Three chains meet at each junction: the left square's, the right square's and the middle LINE;
    # every one of the seven LINEs is named by the problem of a junction it reaches.
    assert {p.layer for p in sketch.problems} == {"pair"}
    assert len({name for p in sketch.problems for name in p.entities}) == 7
    for junction in sketch.problems:
        assert re.match(r"3 curve ends meet at \(1, (0|1)\) m \(LINE", junction.problem)
        assert junction.fix.startswith("a closed outline passes each corner once")
