"""Exact area, centroid and polar moment of regions made of rectangles, discs, ellipses and sectors.

The importer tests compare imported links against these closed forms. Each part is a signed region
(holes negative); the composite follows the parallel-axis theorem: J_C = sum(J_i + A_i |c_i - C|^2).
Formulas: rectangle A = w h, J = w h (w^2 + h^2) / 12; ellipse A = pi a b, J = pi a b (a^2 + b^2) / 4;
circular sector of angle t: A = r^2 t / 2, centroid 4 r sin(t / 2) / (3 t) from the centre along the
bisector, J about the centre r^4 t / 4 (e.g. Gere & Goodno, Mechanics of Materials, appendix E).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from shapely.geometry import Polygon

from linkstress.geometry.mass_properties import area_properties


@dataclass(frozen=True)
class Part:
    """A signed region: area [L^2] (negative for a hole), centroid, polar moment about the centroid."""

    area: float
    centroid: tuple[float, float]
    polar: float

    def hole(self) -> "Part":
        return Part(-self.area, self.centroid, -self.polar)


def rectangle(x0: float, y0: float, x1: float, y1: float) -> Part:
    w, h = x1 - x0, y1 - y0
    return Part(w * h, ((x0 + x1) / 2, (y0 + y1) / 2), w * h * (w * w + h * h) / 12)


def ellipse(cx: float, cy: float, a: float, b: float) -> Part:
    return Part(math.pi * a * b, (cx, cy), math.pi * a * b * (a * a + b * b) / 4)


def disc(cx: float, cy: float, r: float) -> Part:
    return ellipse(cx, cy, r, r)


def sector(cx: float, cy: float, r: float, start: float, sweep: float) -> Part:
    """The circular sector from angle ``start`` through ``sweep`` [rad] (counter-clockwise)."""
    area = r * r * sweep / 2
    d = 4 * r * math.sin(sweep / 2) / (3 * sweep)
    mid = start + sweep / 2
    about_centre = r ** 4 * sweep / 4
    return Part(area, (cx + d * math.cos(mid), cy + d * math.sin(mid)), about_centre - area * d * d)


def half_ellipse_right(cx: float, cy: float, p: float, q: float) -> Part:
    """The half of the ellipse with semi-axes p (along x) and q (along y) where x > cx:
    A = pi p q / 2, centroid 4 p / (3 pi) right of the centre, J about the centre pi p q (p^2 + q^2) / 8."""
    area = math.pi * p * q / 2
    d = 4 * p / (3 * math.pi)
    return Part(area, (cx + d, cy), math.pi * p * q * (p * p + q * q) / 8 - area * d * d)


def regular_polygon(cx: float, cy: float, r: float, n: int) -> Part:
    """Regular n-gon of circumradius r: A = (n / 2) r^2 sin(2 pi / n), J = A r^2 (2 + cos(2 pi / n)) / 6."""
    area = n * r * r * math.sin(2 * math.pi / n) / 2
    return Part(area, (cx, cy), area * r * r * (2 + math.cos(2 * math.pi / n)) / 6)


def combine(*parts: Part) -> Part:
    area = sum(p.area for p in parts)
    cx = sum(p.area * p.centroid[0] for p in parts) / area
    cy = sum(p.area * p.centroid[1] for p in parts) / area
    polar = sum(p.polar + p.area * ((p.centroid[0] - cx) ** 2 + (p.centroid[1] - cy) ** 2) for p in parts)
    return Part(area, (cx, cy), polar)


def scaled(part: Part, factor: float) -> Part:
    """The same region in other units: lengths x factor."""
    return Part(part.area * factor ** 2, (part.centroid[0] * factor, part.centroid[1] * factor),
                part.polar * factor ** 4)


def stadium_plate() -> Part:
    """The plate most importer tests draw [mm]: a 100 x 50 rectangle with semicircular ends of radius
    25, less a circle r 5 at (0, 25), an ellipse 15 x 8 at (50, 25), a circle r 5 at (100, 25) and a
    circle r 4 at (75, 25)."""
    return combine(
        rectangle(0, 0, 100, 50), sector(100, 25, 25, -math.pi / 2, math.pi), sector(0, 25, 25, math.pi / 2, math.pi),
        disc(0, 25, 5).hole(), ellipse(50, 25, 15, 8).hole(), disc(100, 25, 5).hole(), disc(75, 25, 4).hole(),
    )


def assert_matches(polygon: Polygon, exact: Part, rel: float, size: float) -> None:
    """Area and polar moment within ``rel``, centroid within ``rel`` x ``size`` (it may be near 0)."""
    got = area_properties(polygon)
    assert abs(got.area - exact.area) <= rel * abs(exact.area), (got.area, exact.area)
    assert np.hypot(*np.subtract(got.centroid, exact.centroid)) <= rel * size, (got.centroid, exact.centroid)
    assert abs(got.polar - exact.polar) <= rel * abs(exact.polar), (got.polar, exact.polar)


def _circle_points(cx, cy, r, n=200_000, start=0.0, sweep=2 * math.pi):
    t = start + sweep * np.arange(n + 1) / n
    return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])


def test_sector_formulas_match_a_finely_divided_polygon():
    # A quarter-disc of radius 2 centred at (1, 1), from 30 degrees: a 200,000-gon is within 1e-10.
    arc = _circle_points(1, 1, 2, start=math.pi / 6, sweep=math.pi / 2)
    fine = area_properties(Polygon(np.vstack([[1, 1], arc])))
    exact = sector(1, 1, 2, math.pi / 6, math.pi / 2)
    assert abs(fine.area - exact.area) < 1e-9 * exact.area
    assert np.allclose(fine.centroid, exact.centroid, rtol=0, atol=1e-9)
    assert abs(fine.polar - exact.polar) < 1e-9 * exact.polar


def test_combine_of_a_plate_with_a_hole_matches_shapely():
    # 4 x 2 rectangle less a disc r 0.5 at (1, 1), by the parallel-axis theorem and by a fine polygon.
    hole = _circle_points(1, 1, 0.5)[:-1][::-1]
    fine = area_properties(Polygon([(0, 0), (4, 0), (4, 2), (0, 2)], [hole]))
    exact = combine(rectangle(0, 0, 4, 2), disc(1, 1, 0.5).hole())
    assert abs(fine.area - exact.area) < 1e-9 * exact.area
    assert np.allclose(fine.centroid, exact.centroid, rtol=0, atol=1e-9)
    assert abs(fine.polar - exact.polar) < 1e-9 * exact.polar


def test_half_ellipse_and_regular_polygon_formulas_match_shapely():
    t = np.linspace(-math.pi / 2, math.pi / 2, 400_001)
    half = area_properties(Polygon(np.column_stack([3 + 0.5 * np.cos(t), 1 + 2 * np.sin(t)])))
    exact = half_ellipse_right(3, 1, 0.5, 2)
    assert abs(half.area - exact.area) < 1e-9 * exact.area
    assert np.allclose(half.centroid, exact.centroid, rtol=0, atol=1e-9)
    assert abs(half.polar - exact.polar) < 1e-9 * exact.polar
    phi = 2 * math.pi * np.arange(6) / 6
    hexagon = area_properties(Polygon(np.column_stack([1 + 2 * np.cos(phi), -1 + 2 * np.sin(phi)])))
    exact = regular_polygon(1, -1, 2, 6)
    assert abs(hexagon.area - exact.area) < 1e-12 * exact.area
    assert abs(hexagon.polar - exact.polar) < 1e-12 * exact.polar
