"""Sketches as other programs write them: OpenSCAD's unitless LINE-only exports whose circles are
regular polygons, near-circular ellipses, closed splines, and sheets whose flat arcs of a large circle
must not inflate the drawing's size (which scales the gap tolerance).

Every drawing is generated here (DXF text or ezdxf) and its numbers come from its construction.
"""

from __future__ import annotations

import math
import textwrap

import ezdxf
import numpy as np
import pytest
from ezdxf.math import rational_bspline_from_arc

from linkstress.errors import SceneError, SketchError
from linkstress.importers import HOLE_RULE, read_sketch
from linkstress.importers.circles import CIRCLE_FIT, circle_of, regular_polygon
from linkstress.importers.summary import sketch_json, sketch_text
from linkstress.scene import load_scene
from test_scene_errors import BASE, write_crank_sketch


def polygon(cx: float, cy: float, r: float, n: int, turn: float = 0.0) -> list[tuple[float, float]]:
    """The n corners of a regular polygon on the circle (cx, cy, r), counter-clockwise."""
    return [(cx + r * math.cos(turn + 2 * math.pi * k / n), cy + r * math.sin(turn + 2 * math.pi * k / n))
            for k in range(n)]


def line_records(corners: list[tuple[float, float]]) -> str:
    """A closed loop of corners as DXF LINE records, each vertex written to six decimals as OpenSCAD does."""
    ends = zip(corners, corners[1:] + corners[:1])
    return "".join(f"0\nLINE\n8\n0\n10\n{a:.6f}\n20\n{b:.6f}\n11\n{c:.6f}\n21\n{d:.6f}\n" for (a, b), (c, d) in ends)


HEADERS = {
    "no HEADER section": "",
    "HEADER without $INSUNITS": "0\nSECTION\n2\nHEADER\n9\n$ACADVER\n1\nAC1006\n0\nENDSEC\n",
}


def openscad_dxf(path, loops: list[list[tuple[float, float]]], header: str = "") -> None:
    """An OpenSCAD-style export: LINE entities only, no units."""
    body = "".join(line_records(loop) for loop in loops)
    path.write_text(f"{header}0\nSECTION\n2\nENTITIES\n{body}0\nENDSEC\n0\nEOF\n")


def bracket() -> list[list[tuple[float, float]]]:
    """A 135 x 40 mm bracket with two 10 mm pin holes drawn as 24-gons at (20, 20) and (115, 20) mm."""
    return [[(0.0, 0.0), (135.0, 0.0), (135.0, 40.0), (0.0, 40.0)], polygon(20, 20, 5, 24), polygon(115, 20, 5, 24)]


# -- units ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("header", list(HEADERS.values()), ids=list(HEADERS))
def test_an_openscad_export_without_units_is_refused_naming_the_file_and_the_flag(tmp_path, header):
    openscad_dxf(tmp_path / "bracket.dxf", bracket(), header)
    with pytest.raises(SketchError) as error:
        read_sketch(tmp_path / "bracket.dxf")
    message = str(error.value)
    assert message.startswith("bracket.dxf: the file does not say its units") and "--units mm" in message


def test_with_units_mm_the_openscad_bracket_is_135_mm_wide_with_24_gon_pin_holes_as_joints(tmp_path):
    openscad_dxf(tmp_path / "bracket.dxf", bracket())
    sketch = read_sketch(tmp_path / "bracket.dxf", units="mm")
    link = sketch.link()
    assert sketch.units == "mm" and "given" in sketch.units_source
    assert link.outline.bounds == pytest.approx((0.0, 0.0, 0.135, 0.040), abs=1e-12)
    # The corners lie on r = 5 mm to the six decimals written: the centres and diameters to 1e-9 m.
    assert link.hole_rules == ("regular 24-gon", "regular 24-gon")
    assert link.hole_diameters_m == pytest.approx((0.010, 0.010), abs=1e-9)
    assert link.joint_rules == (HOLE_RULE, HOLE_RULE)
    assert np.abs(link.joints - [[0.020, 0.020], [0.115, 0.020]]).max() <= 1e-9
    assert "0.01 m (regular 24-gon)" in sketch_text(sketch)
    assert [h["circle_rule"] for h in sketch_json(sketch)["links"][0]["holes"]] == ["regular 24-gon"] * 2


def test_a_scene_reads_a_unitless_sketch_with_the_links_or_the_scenes_units(tmp_path):
    # The base scene's crank drawn by OpenSCAD: a 40 x 16 mm bar, 6 mm pin holes (36-gons) 20 mm apart.
    openscad_dxf(tmp_path / "crank.dxf", [[(-10.0, -8.0), (30.0, -8.0), (30.0, 8.0), (-10.0, 8.0)],
                                          polygon(0, 0, 3, 36), polygon(20, 0, 3, 36)])
    sketched = BASE.replace("[links.crank]\njoints = [[0.0, 0.0], [0.02, 0.0]]", '[links.crank]\nsketch = "crank.dxf"')
    scene_path = tmp_path / "scene.toml"
    scene_path.write_text(textwrap.dedent(sketched))
    with pytest.raises(SceneError) as error:
        load_scene(scene_path)
    assert "links.crank.sketch: crank.dxf: the file does not say its units" in str(error.value)
    assert "--units mm" in str(error.value)
    for text in (sketched.replace('sketch = "crank.dxf"', 'sketch = "crank.dxf"\nunits = "mm"'),
                 'units = "mm"\n' + sketched):
        scene_path.write_text(textwrap.dedent(text))
        crank = load_scene(scene_path).links["crank"]
        assert np.abs(crank.joints - [[0.0, 0.0], [0.02, 0.0]]).max() <= 1e-9


def test_a_scenes_units_fill_in_unitless_sketches_but_never_override_a_declared_unit(tmp_path):
    # --units overrides $INSUNITS (the report says so); a scene's units are for unitless sketches,
    # so one disagreeing with the sketch's $INSUNITS (mm) is refused, not applied.
    write_crank_sketch(tmp_path / "crank.dxf")
    text = 'units = "in"\n' + BASE.replace(
        "[links.crank]\njoints = [[0.0, 0.0], [0.02, 0.0]]", '[links.crank]\nsketch = "crank.dxf"\nlayer = "crank"')
    (tmp_path / "scene.toml").write_text(textwrap.dedent(text))
    with pytest.raises(SceneError, match=r"crank.dxf: the file declares its units as mm \(\$INSUNITS\) but units 'in'"):
        load_scene(tmp_path / "scene.toml")
    assert read_sketch(tmp_path / "crank.dxf", units="in").units_source == (
        "--units in, overriding the file's $INSUNITS millimeters")


def test_units_given_override_a_csv_headers_units_and_say_so(tmp_path):
    rows = ["# linkstress-sketch v1 units=cm"] + [f"line, {a}, {b}, {c}, {d}" for a, b, c, d in
                                                   ((0, 0, 2, 0), (2, 0, 2, 1), (2, 1, 0, 1), (0, 1, 0, 0))]
    (tmp_path / "bar.csv").write_text("\n".join(rows) + "\n")
    sketch = read_sketch(tmp_path / "bar.csv", units="mm")
    assert sketch.units_source == "--units mm, overriding the file's header's units= centimeters"
    assert sketch.link().outline.area == pytest.approx(2e-6, rel=1e-12)


# -- the regular polygon rule --------------------------------------------------------------------------


def test_a_polygon_is_a_circle_only_when_regular_with_12_or_more_corners_on_the_circle():
    assert regular_polygon(np.array(polygon(3, 4, 2, 12))) == pytest.approx((3, 4, 2), abs=1e-12)
    # Fewer than 12 corners: a hexagonal socket or an 11-gon stays a polygon.
    assert regular_polygon(np.array(polygon(3, 4, 2, 11))) is None
    # One corner moved out by 2 CIRCLE_FIT r: off the circle.
    moved = np.array(polygon(0, 0, 1, 24))
    moved[5] *= 1 + 2 * CIRCLE_FIT
    assert regular_polygon(moved) is None
    # On the circle but unevenly spread (every other step 10 % longer): not regular.
    angles = np.cumsum(np.tile([1.1, 0.9], 12)) * 2 * math.pi / 24
    assert regular_polygon(np.column_stack([np.cos(angles), np.sin(angles)])) is None
    # A loop with a curved piece is not judged by its corners.
    assert circle_of(np.array(polygon(0, 0, 1, 24)), ["straight", "curve"], None) == (None, None)


# -- ellipses and splines -----------------------------------------------------------------------------


def plate_with_hole(add_hole, tmp_path, name: str = "plate.dxf"):
    """A 100 x 60 mm plate of LINEs around a hole drawn by ``add_hole(msp)``, without POINTs."""
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    corners = [(0, 0), (100, 0), (100, 60), (0, 60)]
    for a, b in zip(corners, corners[1:] + corners[:1]):
        msp.add_line(a, b)
    add_hole(msp)
    doc.saveas(tmp_path / name)
    return read_sketch(tmp_path / name).link()


def test_an_ellipse_with_axes_equal_within_1e_7_is_a_pin_hole(tmp_path):
    link = plate_with_hole(lambda msp: msp.add_ellipse((40, 30), major_axis=(10, 0), ratio=1 - 1e-7), tmp_path)
    assert link.hole_rules == ("ellipse with equal axes",)
    # The radius is the mean of the axes, 10 (1 - 5e-8) mm.
    assert link.hole_diameters_m[0] == pytest.approx(0.020, rel=1e-7)
    assert link.joint_rules == (HOLE_RULE,) and np.abs(link.joints - [[0.040, 0.030]]).max() <= 1e-12


def test_an_ellipse_with_axis_ratio_0_9_is_no_circle(tmp_path):
    link = plate_with_hole(lambda msp: msp.add_ellipse((40, 30), major_axis=(10, 0), ratio=0.9), tmp_path)
    assert link.hole_rules == (None,) and link.hole_diameters_m == (None,)
    assert len(link.joints) == 0


def test_a_closed_spline_on_a_circle_is_a_pin_hole(tmp_path):
    def hole(msp):
        spline = rational_bspline_from_arc(center=(60, 25), radius=8, start_angle=30, end_angle=390)
        msp.add_rational_spline(spline.control_points, spline.weights(), spline.degree, spline.knots())

    link = plate_with_hole(hole, tmp_path)
    assert link.hole_rules == ("closed spline on a circle",)
    assert link.hole_diameters_m[0] == pytest.approx(0.016, rel=1e-9)
    assert np.abs(link.joints - [[0.060, 0.025]]).max() <= 1e-9
    # The spline's flattening keeps the hole's area as arcs do: 6000 - 64 pi mm^2 to 1e-6.
    assert link.outline.area == pytest.approx((6000 - 64 * math.pi) * 1e-6, rel=1e-6)


def test_a_closed_spline_off_a_circle_is_no_circle(tmp_path):
    # A closed spline through the corners of a 40 x 20 mm ellipse's 24 points.
    points = [(50 + 20 * math.cos(a), 30 + 10 * math.sin(a)) for a in np.linspace(0, 2 * math.pi, 25)]
    link = plate_with_hole(lambda msp: msp.add_spline(fit_points=points), tmp_path)
    assert link.hole_rules == (None,) and len(link.joints) == 0


# -- the drawing's size from its real extents ----------------------------------------------------------


R_LARGE = 5000.0  # mm
HALF = 170.0  # half the sheet's width [mm]


def _top_arc(msp, kind: str) -> None:
    """The top edge from (340, 200) to (0, 200) mm: an arc of radius 5 m bulging up by 2.89 mm."""
    theta = 2 * math.asin(HALF / R_LARGE)
    if kind == "ARC":
        cy = 200 - math.sqrt(R_LARGE ** 2 - HALF ** 2)
        a0 = math.degrees(math.atan2(200 - cy, HALF))
        msp.add_arc((HALF, cy), R_LARGE, a0, 180 - a0)
    else:
        msp.add_lwpolyline([(340, 200, math.tan(theta / 4)), (0, 200, 0)], format="xyb")


@pytest.mark.parametrize("kind", ["ARC", "bulge"])
def test_a_flat_arc_of_a_large_circle_counts_only_its_own_extent(tmp_path, kind):
    # A 34 cm sheet with a 0.5 mm wide, 20 mm long tab: its corners (100, 0) and (100.5, 0) are 0.5 mm
    # apart. Sized by the arc's full circle (10 m across) the gap tolerance would be 1.4 mm and the
    # four ends there would meet as a branch; sized by the sheet it is 1e-4 x 0.41 m = 0.041 mm.
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    path = [(0, 200), (0, 0), (100, 0), (100, -20), (100.5, -20), (100.5, 0), (340, 0), (340, 200)]
    for a, b in zip(path[:-1], path[1:]):
        msp.add_line(a, b)
    _top_arc(msp, kind)
    doc.saveas(tmp_path / "sheet.dxf")
    sketch = read_sketch(tmp_path / "sheet.dxf")
    sagitta = R_LARGE - math.sqrt(R_LARGE ** 2 - HALF ** 2)
    size = math.hypot(0.340, (220 + sagitta) * 1e-3)
    assert sketch.gap_tolerance_m == pytest.approx(1e-4 * size, rel=1e-12)
    theta = 2 * math.asin(HALF / R_LARGE)
    segment = R_LARGE ** 2 / 2 * (theta - math.sin(theta))
    assert sketch.link().outline.area == pytest.approx((340 * 200 + 0.5 * 20 + segment) * 1e-6, rel=1e-9)
