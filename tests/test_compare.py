"""The beam-against-FEA error measures shared by validate and bench."""

from __future__ import annotations

import numpy as np
import pytest

from shapely.geometry import Point, Polygon

from linkstress.geometry.builders import straight_bar
from linkstress.geometry.profile import LinkProfile
from linkstress.validation.compare import relative, resultant_error
from linkstress.validation.stations import choose_stations, comparison_stations


def stack(n, v, m):
    return np.array([[n], [v], [m]], dtype=float)  # (3, P = 1, S = len)


def test_force_differences_are_relative_to_the_largest_section_force():
    reference = stack([1000.0, 800.0], [200.0, 200.0], [50.0, 40.0])
    values = stack([1010.0, 800.0], [200.0, 195.0], [50.0, 40.0])
    assert resultant_error(values, reference, depth=0.1)[0] == pytest.approx(0.01)


def test_a_tiny_moment_is_judged_against_what_the_forces_do_over_the_depth():
    # Near a change point: M = 0.02 N m beside N = 8,100 N in a 0.05 m deep link. A 0.5 N m moment
    # difference is 0.5 / (8100 x 0.05 / 6) = 0.74 %, not 2,500 % of the tiny moment.
    reference = stack([8100.0], [10.0], [0.02])
    values = stack([8100.0], [10.0], [0.52])
    assert resultant_error(values, reference, depth=0.05)[0] == pytest.approx(0.5 / 67.5)


def test_relative_is_zero_where_nothing_is_loaded():
    np.testing.assert_array_equal(relative(np.array([1.0, 2.0]), np.array([0.0, 4.0])), [0.0, 0.5])


def test_a_link_long_for_its_holes_keeps_its_stations_five_radii_clear():
    # 1 m between 20 mm holes: cell centres from 0.1 m on (5 radii = 50 mm), no note.
    chosen = choose_stations(straight_bar(1.0, 0.1, 0.05, 0.01, hole_diameter=0.02), (0, 1))
    assert chosen.note == ""
    assert chosen.x.min() > 0.05 and chosen.x.max() < 0.95 and 0.5 in chosen.x
    np.testing.assert_array_equal(comparison_stations(straight_bar(1.0, 0.1, 0.05, 0.01, hole_diameter=0.02), (0, 1)), chosen.x)


def test_a_60_mm_crank_with_13_mm_holes_is_compared_at_its_midpoint_and_says_so():
    # Every station between the pins is at most 30 mm = 4.6 radii from one of them. (With 12 mm
    # holes the midpoint is 5 radii from both: kept or not by the outline's flattening of the hole.)
    chosen = choose_stations(straight_bar(0.06, 0.04, 0.02, 0.005, hole_diameter=0.013), (0, 1))
    np.testing.assert_allclose(chosen.x, [0.03])
    assert "short for its holes" in chosen.note and "s = 0.03 m" in chosen.note and "4.62 radii" in chosen.note


def test_a_link_whose_big_hole_spans_the_midpoint_has_no_station_and_the_note_says_why():
    # Joints 20 mm apart: a 30 mm hole at the first spans x = -15..15 mm, past the midpoint at 10 mm:
    # the midpoint cut passes 10 mm = 0.67 radii from that hole's centre, through it.
    shell = Polygon([(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)])
    holes = [Point(0.0, 0.0).buffer(0.015, 64).exterior.coords, Point(0.02, 0.0).buffer(0.002, 64).exterior.coords]
    link = LinkProfile(Polygon(shell.exterior.coords, holes), np.array([[0.0, 0.0], [0.02, 0.0]]), 0.005, None, "lug")
    chosen = choose_stations(link, (0, 1))
    assert chosen.skipped and chosen.x.shape == (0,)
    assert chosen.note.startswith("link 'lug', member [0, 1]: not compared with the FEA: its midpoint cut at s = 0.01 m")
    assert "passes through a hole (0.67 hole radii from its centre)" in chosen.note
