"""Invariants of link profiles over random outlines (hypothesis).

Random star-shaped outlines (sorted angles, random radii) are simple polygons; some get a hole.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import Polygon

from linkstress.geometry.bounds import bounding_functions
from linkstress.geometry.mass_properties import area_properties
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.sections import section_table


@st.composite
def outlines(draw):
    n = draw(st.integers(3, 40))
    gaps = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    angles = 2 * math.pi * np.cumsum(gaps) / gaps.sum()
    radii = np.array(draw(st.lists(st.floats(0.3, 1.0), min_size=n, max_size=n)))
    scale = draw(st.floats(1e-3, 1e3))
    shell = scale * np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
    holes = []
    if draw(st.booleans()):
        r = 0.1 * scale
        phi = np.linspace(0, 2 * math.pi, 24, endpoint=False)
        holes.append(np.column_stack([r * np.cos(phi), r * np.sin(phi)])[::-1])
    assume(Polygon(shell).is_valid)  # a gap of more than 180 degrees between angles can fold the ring
    polygon = Polygon(shell, holes)
    return polygon if polygon.is_valid else Polygon(shell)


placements = st.tuples(st.floats(-180, 180), st.floats(-1e3, 1e3), st.floats(-1e3, 1e3))


@settings(max_examples=150, deadline=None)
@given(outlines(), placements)
def test_area_and_polar_moment_do_not_change_under_rotation_and_translation(polygon, placement):
    angle, dx, dy = placement
    moved = affinity.translate(affinity.rotate(polygon, angle, origin=(0, 0)), dx, dy)
    before, after = area_properties(polygon), area_properties(moved)
    size = math.sqrt(before.area)
    reach = size + math.hypot(dx, dy)  # rounding grows with the distance moved
    assert math.isclose(after.area, before.area, rel_tol=1e-9 * (reach / size) ** 2)
    assert math.isclose(after.polar, before.polar, rel_tol=1e-9 * (reach / size) ** 4)


@settings(max_examples=150, deadline=None)
@given(outlines(), st.floats(1e-3, 1.0))
def test_section_area_integrated_over_x_equals_the_area(polygon, thickness):
    # The cut length is linear between vertex abscissae, so the midpoint rule over those pieces is exact.
    breaks = np.unique(np.concatenate([np.asarray(r.coords)[:, 0] for r in [polygon.exterior, *polygon.interiors]]))
    mids = (breaks[:-1] + breaks[1:]) / 2
    table = section_table(polygon, mids, thickness)
    integral = (table.area * np.diff(breaks)).sum()
    assert math.isclose(integral, thickness * polygon.area, rel_tol=1e-9)


@settings(max_examples=150, deadline=None)
@given(outlines(), st.lists(st.floats(0, 1), min_size=1, max_size=50))
def test_upper_bound_is_never_below_lower_bound_and_brackets_every_chord(polygon, fractions):
    f = bounding_functions(polygon)
    lo, hi = f.breaks[0], f.breaks[-1]
    x = lo + (hi - lo) * np.asarray(fractions)
    upper, lower = f(np.concatenate([x, f.breaks]))
    assert (upper >= lower).all()
    table = section_table(polygon, x, 1.0)
    assert (table.top <= upper[: len(x)] + 1e-12 * (hi - lo)).all()
    assert (table.bottom >= lower[: len(x)] - 1e-12 * (hi - lo)).all()


def test_hole_centroids_and_areas_match_shapely_for_far_off_holes():
    # A plate 1000 m from the origin with a round and a square hole, drawn in either orientation.
    shell = [(1000, 1000), (1000.4, 1000), (1000.4, 1000.1), (1000, 1000.1)]
    round_hole = [(1000.1 + 0.02 * math.cos(t), 1000.05 + 0.02 * math.sin(t)) for t in np.linspace(0, 2 * math.pi, 90, endpoint=False)]
    square = [(1000.3, 1000.03), (1000.3, 1000.07), (1000.34, 1000.07), (1000.34, 1000.03)]
    outline = Polygon(shell, [round_hole, square])
    link = LinkProfile(outline, [[1000.1, 1000.05], [1000.2, 1000.05]], 0.01)
    centres, areas = link.holes
    for k, ring in enumerate(outline.interiors):
        hole = Polygon(ring)
        np.testing.assert_allclose(centres[k], hole.centroid.coords[0], rtol=0, atol=1e-12)
        assert areas[k] == pytest.approx(hole.area, rel=1e-9)
