"""Bounding functions U(x), L(x): highest and lowest material point at each abscissa."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import LineString, Polygon

from linkstress.geometry.bounds import bounding_functions
from linkstress.geometry.builders import stadium, straight_bar


def test_bar_bounds_are_its_top_and_bottom_over_the_full_extent():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, hole_diameter=0.02)
    f = bar.bounds()
    x = np.array([-0.1, 0.0, 0.37, 1.0, 1.1])
    upper, lower = f(x)
    np.testing.assert_allclose(upper, 0.25, rtol=1e-12)
    np.testing.assert_allclose(lower, -0.25, rtol=1e-12)
    px, pu, pl = f.polyline()
    assert px[0] == pytest.approx(-0.1) and px[-1] == pytest.approx(1.1)


def test_stadium_bounds_follow_the_round_ends_exactly_at_vertices():
    link = stadium(0.3, 0.08, 0.01, sagitta=1e-5)
    f = link.bounds()
    ring = np.asarray(link.outline.exterior.coords)[:-1]
    upper, lower = f(ring[:, 0])
    on_top = ring[:, 1] >= 0
    np.testing.assert_array_equal(upper[on_top & (ring[:, 1] > 1e-12)], ring[on_top & (ring[:, 1] > 1e-12), 1])
    np.testing.assert_array_equal(lower[ring[:, 1] < -1e-12], ring[ring[:, 1] < -1e-12, 1])


def test_bounds_jump_at_a_vertical_step_and_take_the_closure_on_the_step():
    outline = Polygon([(0, 0), (2, 0), (2, 0.1), (1, 0.1), (1, 0.2), (0, 0.2)])
    f = bounding_functions(outline)
    upper, lower = f([0.5, 1.0, 1.5])
    np.testing.assert_array_equal(upper, [0.2, 0.2, 0.1])
    np.testing.assert_array_equal(lower, [0.0, 0.0, 0.0])
    x, u, l = f.polyline()
    np.testing.assert_array_equal(x, [0, 1, 1, 2])
    np.testing.assert_array_equal(u, [0.2, 0.2, 0.1, 0.1])


def test_bounds_of_a_concave_link_match_vertical_cuts():
    # A C-shape: U and L are the outer extremes, not the chords around the gap.
    outline = Polygon([(0, 0), (1, 0), (1, 0.2), (0.2, 0.3), (1, 0.4), (1, 0.6), (0, 0.6)])
    f = bounding_functions(outline)
    for x in np.linspace(0, 1, 23):
        cut = LineString([(x, -1), (x, 2)]).intersection(outline)
        u, l = f([x])
        assert u[0] == pytest.approx(cut.bounds[3], abs=1e-12)
        assert l[0] == pytest.approx(cut.bounds[1], abs=1e-12)
