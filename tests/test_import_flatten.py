"""Flattening arcs, bulges, ellipses and splines from their exact geometry: area-preserving vertices
within the chord tolerance, exact ends, and a vertex count set by the tolerance relative to the radius
(a spline's: to its own size)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from ezdxf.math import BSpline, global_bspline_interpolation, rational_bspline_from_arc
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

from linkstress.importers.flatten import Tolerance, flatten, segment_counts, spline_chord
from linkstress.importers.primitives import CurveSet, Polyline, bulge_arcs

ORIGIN = ("ARC", "1", "0", None)


def flat_arc(centre, radius, start, sweep, relative=1e-4, size=1e6):
    curves = CurveSet()
    curves.add_arcs([centre], [radius], [start], [sweep], [ORIGIN])
    return flatten(curves, Tolerance.for_size(size, relative)).vertices(0)


@settings(max_examples=200, deadline=None)
@given(
    radius=st.floats(1e-3, 1e3),
    start=st.floats(-10, 10),
    sweep=st.floats(1e-3, 2 * math.pi - 1e-3) | st.floats(-2 * math.pi + 1e-3, -1e-3),
    relative=st.floats(1e-6, 1e-2),
)
def test_an_arc_keeps_its_ends_its_sector_area_and_the_chord_tolerance(radius, start, sweep, relative):
    xy = flat_arc((3.0, -2.0), radius, start, sweep, relative)
    ends = np.array([[math.cos(start), math.sin(start)], [math.cos(start + sweep), math.sin(start + sweep)]])
    assert np.allclose(xy[[0, -1]], (3.0, -2.0) + radius * ends, rtol=0, atol=1e-12 * radius)
    # Every vertex, and every chord's midpoint, within s = relative x r of the circle.
    s = relative * radius
    distance = np.hypot(*(xy - (3.0, -2.0)).T)
    mids = np.hypot(*((xy[1:] + xy[:-1]) / 2 - (3.0, -2.0)).T)
    assert np.all(np.abs(distance - radius) <= s * (1 + 1e-9) + 1e-12 * radius)
    assert np.all(radius - mids <= s * (1 + 1e-9) + 1e-12 * radius)
    # The fan from the centre has the sector's area r^2 |sweep| / 2.
    fan = Polygon(np.vstack([[(3.0, -2.0)], xy])).area
    assert fan == pytest.approx(radius ** 2 * abs(sweep) / 2, rel=1e-9)


def test_the_default_tolerance_gives_223_vertices_per_turn():
    # s = 1e-4 r: 2 acos(1 - 1e-4) = 0.028285 rad per step, so ceil(2 pi / 0.028285) = 223.
    assert segment_counts(np.array([0.01, 1.0, 100.0]), np.full(3, 2 * math.pi), Tolerance(1e-4, 1.0)).tolist() == [223, 223, 223]
    # A drawing-size cap binds for flat arcs: s = min(1e-4 x 100, 1e-3) = 1e-3 -> 703 per turn.
    assert segment_counts(np.array([100.0]), np.array([2 * math.pi]), Tolerance(1e-4, 1e-3)).tolist() == [703]


def test_a_circle_is_an_inflated_regular_polygon_with_its_area_and_centroid():
    curves = CurveSet()
    curves.add_arcs([(1.0, 2.0)], [0.5], [0.0], [2 * math.pi], [ORIGIN])
    pieces = flatten(curves, Tolerance.for_size(1e6))
    ring = Polygon(pieces.vertices(0))
    assert pieces.closed.tolist() == [True] and len(pieces.vertices(0)) == 223
    assert ring.area == pytest.approx(math.pi * 0.25, rel=1e-14)
    assert np.allclose(ring.centroid.coords[0], (1.0, 2.0), rtol=0, atol=1e-15)
    assert pieces.circle[0].tolist() == [1.0, 2.0, 0.5]


@pytest.mark.parametrize("p0, p1, bulge, centre, radius, start, sweep", [
    ((0, 0), (2, 0), 1.0, (1, 0), 1.0, math.pi, math.pi),  # half circle below the chord (counter-clockwise)
    ((0, 0), (2, 0), -1.0, (1, 0), 1.0, math.pi, -math.pi),  # the same, above (clockwise)
    ((1, 0), (0, 1), math.tan(math.pi / 8), (0, 0), 1.0, 0.0, math.pi / 2),  # a quarter circle
])
def test_bulges_give_the_arc_through_their_ends(p0, p1, bulge, centre, radius, start, sweep):
    c, r, a, t = bulge_arcs(np.array([p0], float), np.array([p1], float), np.array([bulge]))
    assert np.allclose(c[0], centre, atol=1e-15) and r[0] == pytest.approx(radius, rel=1e-15)
    assert a[0] == pytest.approx(start, abs=1e-15) and t[0] == pytest.approx(sweep, rel=1e-15)


def test_a_bulged_polyline_keeps_its_vertices_and_gets_arc_vertices_between():
    curves = CurveSet()
    curves.add_polyline(Polyline(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0]]), np.array([1.0, 0.0, 0.0]), False),
                        ("LWPOLYLINE", "1", "0", None))
    xy = flatten(curves, Tolerance.for_size(10.0)).vertices(0)
    assert xy[0].tolist() == [0.0, 0.0] and xy[-2].tolist() == [2.0, 0.0] and xy[-1].tolist() == [2.0, 1.0]
    assert len(xy) == 2 + 112 + 1  # a half turn at 223 per turn: ceil(pi / 0.028285) = 112 interior vertices
    assert np.all(xy[1:-2, 1] < 0)  # the arc bulges to the right of the direction of travel


@pytest.mark.parametrize("start, sweep", [(0.0, 2 * math.pi), (0.3, 1.7), (2.0, -2.5)])
def test_an_ellipse_keeps_its_exact_parametric_sector_area(start, sweep):
    # Sector of the ellipse c + cos t M + sin t m between parameters: |M x m| |sweep| / 2.
    major, minor = np.array([3.0, 4.0]), np.array([-1.6, 1.2])  # a = 5, b = 2, perpendicular
    curves = CurveSet()
    curves.add_conics([(0.0, 0.0)], [major], [minor], [start], [sweep], [("ELLIPSE", "1", "0", None)])
    pieces = flatten(curves, Tolerance.for_size(1e6))
    xy = pieces.vertices(0)
    fan = Polygon(xy if pieces.closed[0] else np.vstack([[(0.0, 0.0)], xy])).area
    assert fan == pytest.approx(10.0 * abs(sweep) / 2, rel=1e-12)
    assert np.isnan(pieces.circle[0]).all()


SPLINES = {
    "rational circle r = 4": lambda: rational_bspline_from_arc(center=(1, 2), radius=4, start_angle=0, end_angle=360),
    "cubic through 30 points of 3 sin x": lambda: global_bspline_interpolation(
        [(x, 3 * math.sin(x)) for x in np.linspace(0, 4 * math.pi, 30)], degree=3),
    "cubic zigzag": lambda: BSpline([(0, 0), (1, 5), (2, -5), (3, 5), (4, -5), (5, 0)], order=4),
}


@pytest.mark.parametrize("name", list(SPLINES))
def test_a_spline_takes_a_few_hundred_vertices_within_its_chord_tolerance_of_the_exact_curve(name):
    spline = SPLINES[name]()
    curves = CurveSet()
    curves.add_spline(spline, ("SPLINE", "1", "0", None))
    # A drawing 1e6 across: the cap (1e-5 of it) leaves the tolerance 1e-4 x the spline's own size.
    tolerance = Tolerance.for_size(1e6)
    xy = flatten(curves, tolerance).vertices(0)
    chord = spline_chord(spline, tolerance)
    corners = np.array([(p[0], p[1]) for p in spline.control_points])
    assert chord == pytest.approx(1e-4 * math.hypot(*np.ptp(corners, axis=0)), rel=1e-12)
    assert len(xy) <= 300
    # ezdxf's evaluation of the spline at 20,001 parameters is the exact curve: each of its points lies
    # within the tolerance of the polyline, and each vertex within it of the curve (to the 20,001
    # points' own chords, below 1e-7 of the tolerance here).
    exact = np.array([(p.x, p.y) for p in spline.points(np.linspace(0, spline.max_t, 20_001))])
    assert shapely.distance(shapely.LineString(xy), shapely.points(exact)).max() <= chord
    assert shapely.distance(shapely.LineString(exact), shapely.points(xy)).max() <= chord
    # An open spline's ends are its own; a closed one's first and last vertex stay one point.
    if np.array_equal(exact[0], exact[-1]):
        assert np.array_equal(xy[0], xy[-1])
    else:
        assert np.abs(xy[[0, -1]] - exact[[0, -1]]).max() <= 1e-9 * chord


def test_the_benchmarks_spline_sheet_reads_each_part_keeping_the_splines_area(tmp_path):
    import ezdxf

    from linkstress.importers import HOLE_RULE, read_sketch
    from linkstress.validation.bench.sketch_import import spline_sheet

    assert spline_sheet(tmp_path / "sheet.dxf", parts=4) == 52
    sketch = read_sketch(tmp_path / "sheet.dxf")
    assert [link.name for link in sketch.links] == ["part0", "part1", "part2", "part3"]
    msp = ezdxf.readfile(tmp_path / "sheet.dxf").modelspace()
    for k, link in enumerate(sketch.links):
        # The part's exact outline: its 13 splines evaluated by ezdxf at 20,000 steps each (their chords
        # lose about 1e-9 of the area), less the 20 mm hole.
        tools = [e.construction_tool() for e in msp.query(f'SPLINE[layer=="part{k}"]')]
        exact = np.concatenate([[(p.x, p.y) for p in t.points(np.linspace(0, t.max_t, 20_001))][:-1] for t in tools])
        area = Polygon(exact).area - math.pi * 100
        assert link.outline.area == pytest.approx(area * 1e-6, rel=1e-6)
        assert link.joint_rules == (HOLE_RULE,)
        assert np.abs(link.joints - [[0.150 * k, 0.0]]).max() <= 1e-12
        assert len(link.outline.exterior.coords) <= 13 * 300
