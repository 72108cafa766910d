"""Section tables: chords, area, neutral axis, second moment, extreme fibres and Q(y)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Polygon

from linkstress.geometry.builders import straight_bar
from linkstress.errors import GeometryError
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.sections import cut_extent, section_table


def rect(x0, y0, w, h):
    return [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]


def test_rectangle_has_i_equal_t_h_cubed_over_12_at_every_station_ends_included():
    t, h = 0.1, 0.5
    outline = Polygon(rect(-0.1, -0.2, 1.2, h))
    x = np.linspace(-0.1, 1.1, 25)
    table = section_table(outline, x, t)
    np.testing.assert_allclose(table.second_moment, t * h**3 / 12, rtol=1e-12)
    np.testing.assert_allclose(table.area, t * h, rtol=1e-12)
    np.testing.assert_allclose(table.neutral_axis, 0.05, rtol=1e-12)
    np.testing.assert_allclose(table.c_top, h / 2, rtol=1e-12)
    np.testing.assert_allclose(table.c_bottom, h / 2, rtol=1e-12)
    assert (table.n_chords == 1).all()


def test_rectangle_first_moment_is_t_over_2_times_c_squared_minus_y_squared():
    # Q(y) = t (h^2/4 - y^2) / 2 about the mid-height; Jourawski then gives tau_max = 1.5 V / A.
    t, h = 0.02, 0.3
    table = section_table(Polygon(rect(0, -h / 2, 1, h)), [0.2, 0.7], t)
    y = np.array([[-0.15, -0.1, 0.0, 0.05, 0.15]] * 2)
    expected = t * (h * h / 4 - y * y) / 2
    np.testing.assert_allclose(table.first_moment(y), expected, rtol=1e-12, atol=1e-18)
    v = 1000.0
    tau_max = v * table.first_moment(table.neutral_axis) / (table.second_moment * t)
    np.testing.assert_allclose(tau_max, 1.5 * v / (t * h), rtol=1e-12)


def test_section_through_a_pin_hole_loses_exactly_the_holes_chord():
    t, h, d = 0.1, 0.5, 0.02
    bar = straight_bar(1.0, h, 0.1, t, hole_diameter=d)
    x = np.array([-0.004, 0.0, 0.0031, 0.997, 1.0, 1.009])
    table = bar.sections(x)
    hole_rings = [Polygon(r) for r in bar.outline.interiors]
    for i, xi in enumerate(x):
        line = LineString([(xi, -1), (xi, 1)])
        chord = sum(line.intersection(hole).length for hole in hole_rings)
        assert chord > 0
        assert table.depth[i] == pytest.approx(h - chord, rel=1e-12)
        assert table.n_chords[i] == 2
        # and the flattened hole's chord is the circle's within the flattening tolerance
        offset = xi - round(xi)
        assert chord == pytest.approx(2 * math.sqrt((d / 2) ** 2 - offset**2), abs=1e-5)
    half = table.upper[1, 0]
    np.testing.assert_allclose(table.chords(1), [[-0.25, half], [-half, 0.25]], rtol=1e-12)


def test_offset_hole_moves_the_neutral_axis_and_reduces_i_by_parallel_axes():
    # Cut through a 0.1-high slot centred at y = 0.1 in a 0.5-high bar: chords [-0.25, 0.05], [0.15, 0.25].
    t = 0.1
    outline = Polygon(rect(0, -0.25, 1, 0.5), [rect(0.4, 0.05, 0.2, 0.1)])
    table = section_table(outline, [0.5], t)
    h = np.array([0.3, 0.1])
    c = np.array([-0.1, 0.2])
    yna = (h * c).sum() / h.sum()
    i = (t * h**3 / 12 + t * h * (c - yna) ** 2).sum()
    assert table.neutral_axis[0] == pytest.approx(yna, rel=1e-12)
    assert table.second_moment[0] == pytest.approx(i, rel=1e-12)
    assert table.c_top[0] == pytest.approx(0.25 - yna, rel=1e-12)
    assert table.c_bottom[0] == pytest.approx(yna + 0.25, rel=1e-12)
    # Q above a fibre inside the upper chord counts only that chord; at the bottom it is zero.
    q = table.first_moment(np.array([[0.2, -0.25, 0.25]]))
    assert q[0, 0] == pytest.approx(t * 0.05 * (0.225 - yna), rel=1e-12)
    assert q[0, 1] == pytest.approx(0.0, abs=1e-18)
    assert q[0, 2] == 0.0


def test_stations_in_any_order_give_the_same_rows_as_sorted():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, hole_diameter=0.02)
    x = np.array([0.9, -0.1, 1.0, 0.0, 0.5, 1.1, 0.003])
    shuffled = bar.sections(x)
    ordered = bar.sections(np.sort(x))
    back = np.argsort(np.argsort(x))
    np.testing.assert_array_equal(shuffled.area, ordered.area[back])
    np.testing.assert_array_equal(shuffled.second_moment, ordered.second_moment[back])


def test_station_at_a_vertical_step_takes_the_section_to_its_right_except_at_the_right_end():
    # Stepped bar: 0.2 high on [0, 1), 0.1 high on [1, 2].
    outline = Polygon([(0, 0), (2, 0), (2, 0.1), (1, 0.1), (1, 0.2), (0, 0.2)])
    table = section_table(outline, [0.0, 1.0, 2.0], 1.0)
    np.testing.assert_allclose(table.depth, [0.2, 0.1, 0.1], rtol=1e-12)


def test_member_frame_sections_of_a_rotated_link_match_the_unrotated_ones():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, hole_diameter=0.02)
    angle = 0.7
    c, s = math.cos(angle), math.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    moved = Polygon(
        np.asarray(bar.outline.exterior.coords) @ rot.T + [3, -2],
        [np.asarray(r.coords) @ rot.T + [3, -2] for r in bar.outline.interiors],
    )
    turned = LinkProfile(moved, bar.joints @ rot.T + [3, -2], bar.thickness)
    x = np.linspace(-0.1, 1.1, 41)
    np.testing.assert_allclose(turned.sections(x).second_moment, bar.sections(x).second_moment, rtol=1e-9)
    np.testing.assert_allclose(turned.sections(x).area, bar.sections(x).area, rtol=1e-9)


def test_stations_outside_the_link_are_refused_with_the_extent():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1)
    with pytest.raises(GeometryError, match=r"station x = 1.2 m is outside the link's extent \[-0.1, 1.1\]"):
        bar.sections([0.5, 1.2])
    with pytest.raises(GeometryError, match="outside"):
        bar.sections([float("nan")])


def test_cut_extent_is_the_section_tables_top_and_bottom_through_holes_and_rounded_ends():
    bar = LinkProfile(
        Polygon(
            [(-0.03 + 0.03 * math.cos(t), 0.03 * math.sin(t)) for t in np.linspace(math.pi / 2, 3 * math.pi / 2, 40)]
            + [(0.5, -0.03), (0.5, 0.03)],
            [[(0.01 * math.cos(t), 0.01 * math.sin(t)) for t in np.linspace(0, 2 * math.pi, 64, endpoint=False)]],
        ),
        [[0.0, 0.0], [0.5, 0.0]],
        0.01,
    )
    x = np.array([0.2, -0.05, 0.0, 0.005, -0.0299, 0.3])  # unsorted, through the hole and the round end
    bottom, top = cut_extent(bar.boundary(), x)
    table = bar.sections(x)
    np.testing.assert_array_equal(bottom, table.bottom)
    np.testing.assert_array_equal(top, table.top)
    assert top[0] == pytest.approx(0.03) and bottom[0] == pytest.approx(-0.03)
