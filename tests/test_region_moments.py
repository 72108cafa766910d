"""Moments of the part of a link left of each cut: exact against clipped polygons."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from shapely import clip_by_rect
from shapely.geometry import MultiPolygon, Polygon

from linkstress.geometry.builders import stadium
from linkstress.geometry.mass_properties import area_properties
from linkstress.geometry.region_moments import region_moments


def clipped_moments(polygon: Polygon, x: float) -> np.ndarray:
    """(A, S_x, S_y, J_O) of polygon ∩ {x' <= x} from shapely's clip and Green's theorem."""
    minx, miny, maxx, maxy = polygon.bounds
    if x <= minx + 1e-9 * (maxx - minx):
        # A sliver at the leftmost vertex: moments of order width^2, and GEOS cannot clip it.
        return np.zeros(4)
    part = clip_by_rect(polygon, minx - 1, miny - 1, x, maxy + 1)
    pieces = part.geoms if isinstance(part, MultiPolygon) else [part]
    total = np.zeros(4)
    for piece in pieces:
        if piece.is_empty or piece.area == 0:
            continue
        p = area_properties(piece)
        cx, cy = p.centroid
        total += [p.area, p.area * cx, p.area * cy, p.polar + p.area * (cx * cx + cy * cy)]
    return total


@st.composite
def star_outlines(draw):
    n = draw(st.integers(3, 30))
    gaps = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    angles = 2 * math.pi * np.cumsum(gaps) / gaps.sum()
    radii = np.array(draw(st.lists(st.floats(0.3, 1.0), min_size=n, max_size=n)))
    dx, dy = draw(st.floats(-2, 2)), draw(st.floats(-2, 2))
    polygon = Polygon(np.column_stack([dx + radii * np.cos(angles), dy + radii * np.sin(angles)]))
    assume(polygon.is_valid)  # a gap of more than 180 degrees between angles can fold the ring
    return polygon


@settings(max_examples=100, deadline=None)
@given(star_outlines(), st.lists(st.floats(0, 1), min_size=1, max_size=8))
def test_left_region_moments_equal_those_of_the_clipped_polygon(polygon, fractions):
    minx, _, maxx, _ = polygon.bounds
    x = minx + (maxx - minx) * np.asarray(fractions)
    moments = region_moments(polygon, x)
    # Tolerance relative to the largest moment of the whole outline (sizes here are of order 1).
    whole = np.abs(clipped_moments(polygon, maxx + 1)).max()
    for k, xk in enumerate(moments.x):
        got = [moments.area[k], moments.first_x[k], moments.first_y[k], moments.polar[k]]
        np.testing.assert_allclose(got, clipped_moments(polygon, xk), atol=1e-10 * max(whole, 1.0))


def test_whole_region_moments_equal_the_exact_area_properties():
    link = stadium(0.3, 0.08, 0.01, hole_diameter=0.02)
    outline = link.local_outline()
    moments = region_moments(outline, [0.1])
    p = area_properties(outline)
    cx, cy = p.centroid
    np.testing.assert_allclose(
        moments.total, [p.area, p.area * cx, p.area * cy, p.polar + p.area * (cx * cx + cy * cy)],
        rtol=1e-12, atol=1e-18,
    )


def test_left_region_moments_through_pin_holes_equal_those_of_the_clipped_polygon():
    # Cuts through both pin holes and between them, and at the ends: holes run clockwise, so
    # their edges subtract exactly what the clip removes.
    link = stadium(0.3, 0.08, 0.01, hole_diameter=0.02)
    outline = link.local_outline()
    minx, _, maxx, _ = outline.bounds
    x = np.array([minx, -0.03, -0.005, 0.0, 0.007, 0.15, 0.295, 0.3, 0.31, maxx])
    moments = region_moments(outline, x)
    whole = np.abs(clipped_moments(outline, maxx + 1)).max()
    for k, xk in enumerate(x):
        got = [moments.area[k], moments.first_x[k], moments.first_y[k], moments.polar[k]]
        np.testing.assert_allclose(got, clipped_moments(outline, xk), rtol=0, atol=1e-12 * whole)
