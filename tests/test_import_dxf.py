"""DXF sketches: every entity type and unit, shuffled and reversed curves, blocks, several links.

Each drawing is written with ezdxf and its links compared with closed-form area, centroid and polar
moment (tests/test_import_exact.py) to 1e-6 relative, joints to 1e-9 m.
"""

from __future__ import annotations

import math
import random

import ezdxf
import numpy as np
import pytest
from ezdxf.math import rational_bspline_from_arc

from linkstress.errors import SketchError
from linkstress.importers import HOLE_RULE, POINT_RULE, read_sketch
from test_import_exact import (
    assert_matches, combine, disc, ellipse, half_ellipse_right, rectangle, scaled, sector, stadium_plate,
)

REL = 1e-6


def plate_entities(rng: random.Random | None = None, jitter: float = 0.0) -> list[tuple]:
    """The stadium plate of ``stadium_plate()`` [drawing units] as entity recipes, every curve type:
    LINE, mirrored ARC (extrusion -Z), LWPOLYLINE with and without bulges, CIRCLE, ELLIPSE, a closed
    bulge circle, an exact rational SPLINE circle and two POINTs. With ``rng`` the recipes are
    shuffled, half the open curves reversed and their ends moved by up to ``jitter``."""
    open_curves = [
        ("line", [(0.0, 0.0), (100.0, 0.0)]),
        ("lwpolyline", [(100.0, 50.0, 0.0), (0.0, 50.0, 0.0)]),
        ("lwpolyline", [(0.0, 50.0, 1.0), (0.0, 0.0, 0.0)]),  # bulge 1: the left half circle
    ]
    if rng is not None:
        moved = []
        for kind, pts in open_curves:
            pts = [(x + rng.uniform(-jitter, jitter), y + rng.uniform(-jitter, jitter), *rest) for x, y, *rest in pts]
            if rng.random() < 0.5:
                pts = _reversed(kind, pts)
            moved.append((kind, pts))
        open_curves = moved
    recipes = open_curves + [
        # Right half circle, drawn mirrored: WCS centre (100, 25) from -90 to 90 degrees.
        ("arc", dict(center=(-100.0, 25.0), radius=25.0, start_angle=90.0, end_angle=270.0), (0.0, 0.0, -1.0)),
        ("circle", dict(center=(0.0, 25.0), radius=5.0)),
        ("ellipse", dict(center=(50.0, 25.0), major_axis=(15.0, 0.0), ratio=8.0 / 15.0)),
        ("bulge circle", [(105.0, 25.0, 1.0), (95.0, 25.0, 1.0)]),
        ("spline circle", (75.0, 25.0), 4.0),
        ("point", (0.0, 25.0)),
        ("point", (100.0, 25.0)),
    ]
    if rng is not None:
        rng.shuffle(recipes)
    return recipes


def _reversed(kind: str, pts: list[tuple]) -> list[tuple]:
    if kind == "line":
        return pts[::-1]
    # Polyline: the bulge of segment i -> i + 1 becomes minus itself on the reversed segment.
    xy = [p[:2] for p in pts][::-1]
    bulges = [p[2] for p in pts][:-1][::-1]
    return [(*p, -b) for p, b in zip(xy, bulges + [0.0])]


def draw(layout, recipes: list[tuple], layer: str = "0", offset=(0.0, 0.0)) -> None:
    ox, oy = offset
    att = {"layer": layer}
    for recipe in recipes:
        kind = recipe[0]
        if kind == "line":
            (x0, y0), (x1, y1) = recipe[1]
            layout.add_line((x0 + ox, y0 + oy), (x1 + ox, y1 + oy), dxfattribs=att)
        elif kind in ("lwpolyline", "bulge circle"):
            pts = [(x + ox, y + oy, b) for x, y, b in recipe[1]]
            layout.add_lwpolyline(pts, format="xyb", close=kind == "bulge circle", dxfattribs=att)
        elif kind == "arc":
            spec, extrusion = dict(recipe[1]), recipe[2]
            cx, cy = spec.pop("center")
            layout.add_arc((cx - ox, cy + oy), dxfattribs={**att, "extrusion": extrusion}, **spec)
        elif kind == "circle":
            cx, cy = recipe[1]["center"]
            layout.add_circle((cx + ox, cy + oy), recipe[1]["radius"], dxfattribs=att)
        elif kind == "ellipse":
            cx, cy = recipe[1]["center"]
            layout.add_ellipse((cx + ox, cy + oy), recipe[1]["major_axis"], recipe[1]["ratio"], dxfattribs=att)
        elif kind == "spline circle":
            (cx, cy), r = recipe[1], recipe[2]
            spline = rational_bspline_from_arc((cx + ox, cy + oy), r, 0, 360)
            layout.add_rational_spline(spline.control_points, spline.weights(), spline.degree, spline.knots(),
                                       dxfattribs=att)
        elif kind == "point":
            x, y = recipe[1]
            layout.add_point((x + ox, y + oy), dxfattribs=att)


def save(doc, tmp_path, name: str = "sketch.dxf"):
    path = tmp_path / name
    doc.saveas(path)
    return path


def test_every_curve_type_gives_the_exact_plate(tmp_path):
    doc = ezdxf.new("R2013", units=4)  # mm
    draw(doc.modelspace(), plate_entities(), layer="plate")
    sketch = read_sketch(save(doc, tmp_path))
    link = sketch.link("plate")
    assert sketch.units == "mm" and sketch.units_source == "$INSUNITS"
    assert_matches(link.outline, scaled(stadium_plate(), 1e-3), REL, 0.15)
    assert np.abs(link.joints - [[0.0, 0.025], [0.1, 0.025]]).max() <= 1e-9
    assert link.joint_rules == (POINT_RULE, POINT_RULE)
    assert len(link.outline.interiors) == 4
    # The CIRCLE, the bulge circle and the rational spline circle are circles, each by its rule; the
    # ellipse (axes 15 and 8) is not.
    found = sorted((rule, d) for d, rule in zip(link.hole_diameters_m, link.hole_rules) if d is not None)
    assert [rule for rule, _ in found] == ["circle", "circle", "closed spline on a circle"]
    assert [d for _, d in found] == pytest.approx([0.01, 0.01, 0.008], rel=1e-12)
    assert link.hole_rules.count(None) == 1


@pytest.mark.parametrize("code, name, metres", [(4, "mm", 1e-3), (5, "cm", 1e-2), (6, "m", 1.0), (1, "in", 0.0254), (2, "ft", 0.3048)])
def test_insunits_convert_the_drawing_to_metres(tmp_path, code, name, metres):
    doc = ezdxf.new("R2013", units=code)
    draw(doc.modelspace(), plate_entities(), layer="plate")
    sketch = read_sketch(save(doc, tmp_path))
    assert sketch.units == name
    link = sketch.link()
    assert_matches(link.outline, scaled(stadium_plate(), metres), REL, 150 * metres)
    assert np.abs(link.joints - np.array([[0.0, 25.0], [100.0, 25.0]]) * metres).max() <= 1e-9


def test_a_unitless_drawing_needs_units(tmp_path):
    doc = ezdxf.new("R2013", units=0)
    draw(doc.modelspace(), plate_entities())
    path = save(doc, tmp_path)
    with pytest.raises(SketchError, match=r"sketch.dxf: .*unitless.*pass --units"):
        read_sketch(path)
    sketch = read_sketch(path, units="cm")
    assert sketch.units == "cm" and "given" in sketch.units_source
    assert_matches(sketch.link().outline, scaled(stadium_plate(), 1e-2), REL, 1.5)
    with pytest.raises(SketchError, match=r"unknown length unit 'furlong'; use one of .*mm"):
        read_sketch(path, units="furlong")


def test_given_units_override_the_declared_units_and_say_so(tmp_path):
    doc = ezdxf.new("R2013", units=1)  # inches
    draw(doc.modelspace(), plate_entities())
    path = save(doc, tmp_path)
    sketch = read_sketch(path, units="mm")
    assert sketch.units == "mm"
    assert sketch.units_source == "--units mm, overriding the file's $INSUNITS inches"
    assert_matches(sketch.link().outline, scaled(stadium_plate(), 1e-3), REL, 0.15)
    # Giving the unit the file declares is no override.
    assert read_sketch(path, units="in").units_source == "$INSUNITS"


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_shuffled_reversed_curves_with_tiny_gaps_chain_into_the_same_plate(tmp_path, seed):
    doc = ezdxf.new("R2013", units=4)
    draw(doc.modelspace(), plate_entities(random.Random(seed), jitter=1e-6), layer="plate")
    sketch = read_sketch(save(doc, tmp_path))
    link = sketch.link()
    # Moving a corner by 1e-6 mm changes the area by about 1e-6 x 50 mm^2 / 1e4 mm^2: far below 1e-6.
    assert_matches(link.outline, scaled(stadium_plate(), 1e-3), REL, 0.15)
    assert 0 < link.largest_gap_m <= 2 * math.sqrt(2) * 1e-9
    assert any("closed" in fix and "gap" in fix for fix in sketch.fixes)


def test_several_links_are_named_by_layer_else_by_file_stem(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    draw(msp, plate_entities(), layer="crank")
    draw(msp, plate_entities(), layer="0", offset=(0.0, 200.0))
    draw(msp, plate_entities(), layer="twin", offset=(300.0, 0.0))
    draw(msp, plate_entities(), layer="twin", offset=(300.0, 200.0))
    sketch = read_sketch(save(doc, tmp_path, "four.dxf"))
    assert [link.name for link in sketch.links] == ["crank", "four-1", "twin-1", "twin-2"]
    assert sketch.link("crank").layer == "crank" and sketch.link("four-1").layer is None
    with pytest.raises(SketchError, match=r"layer 'twin' holds 2 links \('twin-1', 'twin-2'\)"):
        sketch.link("twin")
    with pytest.raises(SketchError, match=r"holds 4 links"):
        sketch.link()
    with pytest.raises(SketchError, match=r"no link or layer 'rocker'; its links are 'crank', 'four-1'"):
        sketch.link("rocker")
    moved = sketch.link("twin-2")
    assert np.abs(moved.joints - [[0.3, 0.225], [0.4, 0.225]]).max() <= 1e-9


def test_block_references_are_expanded_with_their_transforms(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    block = doc.blocks.new("PLATE")
    draw(block, plate_entities())
    pair = doc.blocks.new("NESTED")
    pair.add_blockref("PLATE", (0, 0), dxfattribs={"rotation": 90})
    msp = doc.modelspace()
    msp.add_blockref("PLATE", (500, 0), dxfattribs={"layer": "moved"})
    msp.add_blockref("PLATE", (0, 500), dxfattribs={"layer": "doubled", "xscale": 2, "yscale": 2})
    msp.add_blockref("NESTED", (1000, 1000), dxfattribs={"layer": "nested"})
    msp.add_blockref("PLATE", (2000, 0), dxfattribs={"layer": "mirrored", "xscale": -1})
    sketch = read_sketch(save(doc, tmp_path))
    exact = scaled(stadium_plate(), 1e-3)
    for name, factor in (("moved", 1), ("doubled", 2), ("nested", 1), ("mirrored", 1)):
        link = sketch.link(name)
        assert link.outline.area == pytest.approx(exact.area * factor ** 2, rel=REL)
        polar = link.profile(1.0).polar_moment_area
        assert polar == pytest.approx(exact.polar * factor ** 4, rel=REL)
    assert np.abs(sketch.link("moved").joints - [[0.5, 0.025], [0.6, 0.025]]).max() <= 1e-9
    assert np.abs(sketch.link("doubled").joints - [[0.0, 0.55], [0.2, 0.55]]).max() <= 1e-9
    # Rotated 90 degrees about the nested insert's base point, then moved to (1000, 1000) mm.
    assert np.abs(sketch.link("nested").joints - [[0.975, 1.0], [0.975, 1.1]]).max() <= 1e-9
    assert np.abs(sketch.link("mirrored").joints - [[1.9, 0.025], [2.0, 0.025]]).max() <= 1e-9
    assert_matches(sketch.link("moved").outline, _shifted(exact, 0.5, 0.0), REL, 0.15)


def _shifted(part, dx, dy):
    return type(part)(part.area, (part.centroid[0] + dx, part.centroid[1] + dy), part.polar)


def test_a_non_uniformly_scaled_circle_becomes_an_exact_ellipse(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    block = doc.blocks.new("SQUARE")
    block.add_lwpolyline([(-1, -1), (1, -1), (1, 1), (-1, 1)], close=True)
    block.add_circle((0, 0), 0.5)
    doc.modelspace().add_blockref("SQUARE", (0, 0), dxfattribs={"xscale": 2, "layer": "stretched"})
    link = read_sketch(save(doc, tmp_path)).link()
    assert_matches(link.outline, combine(rectangle(-2, -1, 2, 1), ellipse(0, 0, 1, 0.5).hole()), REL, 4)
    assert link.hole_diameters_m == (None,) and len(link.joints) == 0


def test_polylines_2d_with_bulges_and_3d_are_read(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    # A stadium from a closed 2D POLYLINE with two bulge-1 ends, a square hole from a 3D POLYLINE.
    msp.add_polyline2d([(0, 0, 0, 0, 0), (4, 0, 0, 0, 1), (4, 2, 0, 0, 0), (0, 2, 0, 0, 1)], format="xyseb", close=True)
    msp.add_polyline3d([(1, 0.5, 0), (2, 0.5, 0), (2, 1.5, 0), (1, 1.5, 0)], close=True)
    link = read_sketch(save(doc, tmp_path)).link()
    exact = combine(rectangle(0, 0, 4, 2), sector(4, 1, 1, -math.pi / 2, math.pi), sector(0, 1, 1, math.pi / 2, math.pi),
                    rectangle(1, 0.5, 2, 1.5).hole())
    assert_matches(link.outline, exact, REL, 6)


def test_a_partial_ellipse_closes_an_outline_with_a_line(tmp_path):
    # Major axis (0, 2), ratio 0.5: minor axis Z x major x 0.5 = (-1, 0); parameters pi..2 pi run
    # from (0, -2) through (1, 0) to (0, 2), the half ellipse right of the line x = 0.
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    msp.add_ellipse((0, 0), (0, 2), 0.5, start_param=math.pi, end_param=2 * math.pi)
    msp.add_line((0, 2), (0, -2))
    assert_matches(read_sketch(save(doc, tmp_path)).link().outline, half_ellipse_right(0, 0, 1, 2), REL, 4)


def test_a_fit_point_spline_is_evaluated_from_the_spline_itself(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    fit = [(0, 0), (2, -0.5), (4, 0), (4.5, 1), (4, 2), (2, 2.5), (0, 2), (-0.5, 1), (0, 0)]
    spline = msp.add_spline(fit)
    link = read_sketch(save(doc, tmp_path)).link()
    fine = np.array([(p.x, p.y) for p in spline.construction_tool().flattening(1e-9)])
    from shapely.geometry import Polygon

    assert link.outline.area == pytest.approx(Polygon(fine).area, rel=REL)
    assert np.abs(np.array(link.outline.exterior.coords)[:, None, :] - np.array(fit)[None]).min() < 1e-9


def test_annotation_and_hidden_layers_are_ignored_and_counted(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    draw(msp, plate_entities(), layer="plate")
    msp.add_text("crank", dxfattribs={"layer": "plate"})
    msp.add_mtext("note")
    msp.add_linear_dim(base=(0, -20), p1=(0, 0), p2=(100, 0)).render()
    doc.layers.add("construction").freeze()
    msp.add_line((0, 0), (500, 500), dxfattribs={"layer": "construction"})
    msp.add_line((0, 0), (-500, 500), dxfattribs={"layer": "Defpoints"})
    doc.paperspace().add_line((0, 0), (700, 700))
    sketch = read_sketch(save(doc, tmp_path))
    assert [link.name for link in sketch.links] == ["plate"]
    assert sketch.ignored["TEXT"] == 1 and sketch.ignored["MTEXT"] == 1 and sketch.ignored["DIMENSION"] == 1
    assert sketch.ignored["LINE (hidden layer)"] == 2


def test_a_link_without_points_takes_the_centres_of_its_circular_holes(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    recipes = [r for r in plate_entities() if r[0] != "point"]
    draw(doc.modelspace(), recipes)
    link = read_sketch(save(doc, tmp_path)).link()
    # The CIRCLE at x = 0, the spline circle at x = 75 and the bulge circle at x = 100 mm.
    assert np.abs(link.joints - [[0.0, 0.025], [0.075, 0.025], [0.1, 0.025]]).max() <= 1e-9
    assert link.joint_rules == (HOLE_RULE, HOLE_RULE, HOLE_RULE)


def test_points_outside_every_outline_are_ignored_and_repeated_points_dropped(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    draw(msp, plate_entities())
    msp.add_point((500, 500))
    msp.add_point((50, 45))  # in material: a third joint
    msp.add_point((50, 45))
    sketch = read_sketch(save(doc, tmp_path))
    assert sketch.ignored["POINT (outside every outline)"] == 1
    assert np.abs(sketch.link().joints - [[0.0, 0.025], [0.05, 0.045], [0.1, 0.025]]).max() <= 1e-9
    assert any("dropped 1 POINT" in fix for fix in sketch.fixes)


def test_a_point_inside_a_hole_but_off_its_centre_is_refused(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    draw(msp, [r for r in plate_entities() if r[0] != "point"])
    msp.add_point((2, 25))
    with pytest.raises(SketchError, match=r"POINT \(handle \w+, layer '0'\) at \(2, 25\) mm lies in a hole .* not at its centre \(0, 25\) mm"):
        read_sketch(save(doc, tmp_path))


def test_a_pin_hole_in_a_long_bar_stays_a_few_hundred_vertices(tmp_path):
    # 20 mm hole in a 1.2 m bar: the default chord tolerance 1e-4 r gives 223 vertices per turn.
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    msp.add_lwpolyline([(-0.1, -0.25), (1.1, -0.25), (1.1, 0.25), (-0.1, 0.25)], close=True)
    msp.add_circle((0, 0), 0.01)
    link = read_sketch(save(doc, tmp_path)).link()
    assert len(link.outline.interiors[0].coords) - 1 == 223
    assert link.outline.area == pytest.approx(0.6 - math.pi * 1e-4, rel=1e-12)



@pytest.mark.parametrize("version, fmt", [("R12", "asc"), ("R2000", "asc"), ("R2018", "asc"), ("R2013", "bin")])
def test_dxf_versions_and_binary_dxf_read_alike(tmp_path, version, fmt):
    # A 4 x 2 stadium (closed 2D POLYLINE with bulge-1 ends), a pin hole r 0.25 with its POINT, and
    # a half-disc hole r 0.25 (ARC and LINE). R12 stores no $INSUNITS: there the units are given.
    doc = ezdxf.new(version)
    msp = doc.modelspace()
    msp.add_polyline2d([(0, 0, 0, 0, 0), (4, 0, 0, 0, 1), (4, 2, 0, 0, 0), (0, 2, 0, 0, 1)], format="xyseb", close=True)
    msp.add_circle((1, 1), 0.25)
    msp.add_point((1, 1))
    msp.add_arc((3, 1), 0.25, 0, 180)
    msp.add_line((2.75, 1), (3.25, 1))
    if version != "R12":
        doc.header["$INSUNITS"] = 6
    doc.saveas(tmp_path / "v.dxf", fmt=fmt)
    link = read_sketch(tmp_path / "v.dxf", units="m" if version == "R12" else None).link()
    exact = combine(rectangle(0, 0, 4, 2), sector(4, 1, 1, -math.pi / 2, math.pi), sector(0, 1, 1, math.pi / 2, math.pi),
                    disc(1, 1, 0.25).hole(), sector(3, 1, 0.25, 0, math.pi).hole())
    assert_matches(link.outline, exact, REL, 6)
    assert link.joints.tolist() == [[1.0, 1.0]]
