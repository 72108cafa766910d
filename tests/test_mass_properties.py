"""Exact area and mass properties of polygons (Green's theorem) against closed-form values.

Polygons are exact to 1e-12 relative; round shapes are exact for their flattened polygon and within
the flattening tolerance of the true curve (area deficit below perimeter x sagitta).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import Polygon

from linkstress.geometry.builders import stadium
from linkstress.geometry.curves import circle_points
from linkstress.geometry.mass_properties import area_properties
from linkstress.materials import Material
from linkstress.geometry.profile import LinkProfile

from conftest import rel_err


def rect(x0, y0, w, h):
    return [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]


def composite(parts):
    """Area, centroid and centroidal polar moment of signed rectangles (x0, y0, w, h, sign)."""
    areas = np.array([s * w * h for _, _, w, h, s in parts])
    cx = np.array([x0 + w / 2 for x0, _, w, _, _ in parts])
    cy = np.array([y0 + h / 2 for _, y0, _, h, _ in parts])
    own = np.array([s * w * h * (w * w + h * h) / 12 for _, _, w, h, s in parts])
    area = areas.sum()
    gx, gy = (areas * cx).sum() / area, (areas * cy).sum() / area
    polar = (own + areas * ((cx - gx) ** 2 + (cy - gy) ** 2)).sum()
    return area, (gx, gy), polar


def assert_properties(polygon, area, centroid, polar, rel):
    props = area_properties(polygon)
    size = math.sqrt(area)
    assert rel_err(props.area, area) <= rel
    assert abs(props.centroid[0] - centroid[0]) <= rel * size
    assert abs(props.centroid[1] - centroid[1]) <= rel * size
    assert rel_err(props.polar, polar) <= rel


def test_rectangle_with_two_rectangular_holes_is_exact():
    # 3 x 1 plate at (2, 5) with holes 0.4 x 0.2 at (2.3, 5.4) and 0.5 x 0.3 at (4.1, 5.2).
    parts = [(2, 5, 3, 1, 1), (2.3, 5.4, 0.4, 0.2, -1), (4.1, 5.2, 0.5, 0.3, -1)]
    polygon = Polygon(rect(2, 5, 3, 1), [rect(2.3, 5.4, 0.4, 0.2), rect(4.1, 5.2, 0.5, 0.3)])
    assert_properties(polygon, *composite(parts), rel=1e-12)


def test_triangle_is_exact():
    # Base b on the x axis, apex at (c, h): A = b h / 2, G = ((b + c) / 3, h / 3),
    # I_xx = b h^3 / 36, I_yy = b h (b^2 - b c + c^2) / 36 (about the centroid).
    b, c, h = 0.7, 0.2, 0.45
    polygon = Polygon([(0, 0), (b, 0), (c, h)])
    polar = b * h**3 / 36 + b * h * (b * b - b * c + c * c) / 36
    assert_properties(polygon, b * h / 2, ((b + c) / 3, h / 3), polar, rel=1e-12)
    props = area_properties(polygon)
    assert rel_err(props.i_xx, b * h**3 / 36) <= 1e-12


def test_l_shape_is_exact():
    # An L made of a 0.1 x 0.6 upright and a 0.5 x 0.1 foot, far from the origin.
    polygon = Polygon([(100, 200), (100.5, 200), (100.5, 200.1), (100.1, 200.1), (100.1, 200.6), (100, 200.6)])
    parts = [(100, 200, 0.5, 0.1, 1), (100, 200.1, 0.1, 0.5, 1)]
    assert_properties(polygon, *composite(parts), rel=1e-11)


def test_product_of_inertia_of_an_l_shape():
    # Composite: I_xy = sum A_i (x_i - gx)(y_i - gy) for rectangles (own I_xy = 0).
    polygon = Polygon([(0, 0), (0.5, 0), (0.5, 0.1), (0.1, 0.1), (0.1, 0.6), (0, 0.6)])
    a = np.array([0.05, 0.05])
    cx, cy = np.array([0.25, 0.05]), np.array([0.05, 0.35])
    gx, gy = (a * cx).sum() / a.sum(), (a * cy).sum() / a.sum()
    expected = (a * (cx - gx) * (cy - gy)).sum()
    assert rel_err(area_properties(polygon).i_xy, expected) <= 1e-12


def test_disc_with_offset_hole_is_exact_for_its_polygon_and_within_flattening_tolerance():
    big_r, small_r, d, sagitta = 0.05, 0.01, 0.02, 1e-6
    outer = circle_points((0, 0), big_r, sagitta)
    inner = circle_points((d, 0), small_r, sagitta)
    polygon = Polygon(outer, [inner[::-1]])
    # Regular n-gon inscribed in radius r: A = n r^2 sin(2 pi / n) / 2, J = A r^2 (2 + cos(2 pi / n)) / 6.
    def ngon(r, n):
        a = n * r * r * math.sin(2 * math.pi / n) / 2
        return a, a * r * r * (2 + math.cos(2 * math.pi / n)) / 6

    a_out, j_out = ngon(big_r, len(outer))
    a_in, j_in = ngon(small_r, len(inner))
    area = a_out - a_in
    gx = -a_in * d / area
    polar = j_out - (j_in + a_in * d * d) - area * gx * gx
    assert_properties(polygon, area, (gx, 0.0), polar, rel=1e-12)

    exact_area = math.pi * (big_r**2 - small_r**2)
    exact_gx = -math.pi * small_r**2 * d / exact_area
    exact_polar = math.pi * big_r**4 / 2 - (math.pi * small_r**4 / 2 + math.pi * small_r**2 * d * d) - exact_area * exact_gx**2
    flattening = 2 * math.pi * (big_r + small_r) * sagitta / exact_area
    assert 0 < flattening < 1e-3
    assert_properties(polygon, exact_area, (exact_gx, 0.0), exact_polar, rel=4 * flattening)


def test_stadium_within_flattening_tolerance():
    s, r, sagitta = 0.3, 0.04, 1e-7
    link = stadium(s, 2 * r, thickness=0.01, sagitta=sagitta)
    area = 2 * r * s + math.pi * r * r
    i_xx = s * (2 * r) ** 3 / 12 + math.pi * r**4 / 4
    # Each half-disc about the stadium's centre line x = s / 2:
    # int (u + s/2)^2 dA = pi r^4 / 8 + s (2 r^3 / 3) + (s^2 / 4)(pi r^2 / 2).
    i_yy = 2 * r * s**3 / 12 + 2 * (math.pi * r**4 / 8 + 2 * s * r**3 / 3 + math.pi * r * r * s * s / 8)
    flattening = (2 * s + 2 * math.pi * r) * sagitta / area
    assert_properties(link.outline, area, (s / 2, 0.0), i_xx + i_yy, rel=4 * flattening)


def test_mass_and_mass_moment_of_inertia_of_a_plate():
    # Uniform rectangular plate a x b x t: m = rho a b t, I_G = m (a^2 + b^2) / 12.
    a, b, t, rho = 1.2, 0.5, 0.1, 7850.0
    link = LinkProfile(Polygon(rect(-0.1, -0.25, a, b)), np.array([[0, 0], [1, 0]]), t, Material("steel", rho))
    m = rho * a * b * t
    assert rel_err(link.mass, m) <= 1e-12
    assert m == pytest.approx(471.0, rel=1e-12)  # the seed's crank mass (seed-ansys-fourbar.md)
    assert rel_err(link.mass_moment_of_inertia, m * (a * a + b * b) / 12) <= 1e-12
    np.testing.assert_allclose(link.center_of_mass, [0.5, 0.0], atol=1e-15)
