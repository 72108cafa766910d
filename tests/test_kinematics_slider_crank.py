"""Slider-crank kinematics: exact formulas, finite differences, inclined lines, toggles, limits."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from linkstress.kinematics.linkage_class import (
    slider_feasible_input_ranges,
    slider_limits,
    slider_toggle_angles,
    stroke,
)
from linkstress.kinematics.slider_crank import FEASIBLE, TOGGLE, TOO_FAR, SliderCrank, solve_slider_crank

pytestmark = pytest.mark.filterwarnings("error")


def test_zero_offset_follows_the_textbook_position_velocity_and_acceleration():
    """In-line slider-crank (Norton sec. 4.7 / 6.7 with c = 0): x = a cos t + sqrt(b^2 - a^2 sin^2 t),
    and with constant omega the exact derivatives of that x."""
    a, b, w = 0.05, 0.2, 300.0
    theta = np.radians(np.arange(0.0, 360.0, 7.5))
    m = solve_slider_crank(SliderCrank((0.0, 0.0), a, b), theta, w, 0.0)
    root = np.sqrt(b * b - (a * np.sin(theta)) ** 2)
    x = a * np.cos(theta) + root
    # d/dt and d2/dt2 of x(theta(t)) with theta' = w: exact differentiation of the line above.
    dx = -a * np.sin(theta) * w - a * a * np.sin(theta) * np.cos(theta) * w / root
    ddx = (-a * np.cos(theta) * w * w
           - a * a * np.cos(2 * theta) * w * w / root
           - (a * a * np.sin(theta) * np.cos(theta)) ** 2 * w * w / root**3)
    assert m.feasible.all()
    assert np.allclose(m.slider_position, x, rtol=0, atol=1e-15)
    assert np.allclose(m.slider_velocity, dx, rtol=1e-12, atol=1e-12)
    assert np.allclose(m.slider_acceleration, ddx, rtol=1e-11, atol=1e-9)
    assert np.allclose(m.joints["B"].position[:, 1], 0.0, atol=1e-17)
    assert np.allclose(m.joints["B"].position[:, 0], x, atol=1e-15)
    # Dead centres: the slider stops at theta = 0 and 180 deg.
    assert abs(m.slider_velocity[0]) < 1e-12 and abs(m.slider_velocity[24]) < 1e-12
    assert stroke(SliderCrank((0.0, 0.0), a, b)) == pytest.approx(2 * a, rel=1e-15)


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_inclined_line_through_o2_is_the_horizontal_case_turned(branch):
    tilt = math.radians(30.0)
    theta = np.radians(np.arange(0.0, 360.0, 10.0))
    flat = solve_slider_crank(SliderCrank((0.0, 0.0), 1.0, 3.0, 0.0, 0.0, branch), theta, 2.0, 0.5)
    turned = solve_slider_crank(SliderCrank((1.0, 2.0), 1.0, 3.0, 0.0, tilt, branch), theta + tilt, 2.0, 0.5)
    assert np.allclose(turned.slider_position, flat.slider_position, atol=1e-14)
    assert np.allclose(turned.slider_acceleration, flat.slider_acceleration, atol=1e-13)
    assert np.allclose(np.remainder(turned.theta3 - flat.theta3 - tilt + 1, 2 * math.pi), 1.0, atol=1e-14)
    assert np.allclose(turned.omega3, flat.omega3, atol=1e-13)
    direction = np.array([math.cos(tilt), math.sin(tilt)])
    along = (turned.joints["B"].position - [1.0, 2.0]) @ direction
    assert np.allclose(along, turned.slider_position, atol=1e-14)
    assert np.allclose(turned.joints["B"].velocity, turned.slider_velocity[:, None] * direction, atol=1e-13)


@settings(max_examples=200, deadline=None)
@given(st.floats(0.2, 2.0), st.floats(2.5, 6.0), st.floats(-0.3, 0.3), st.floats(-math.pi, math.pi),
       st.floats(-math.pi, math.pi), st.floats(-1.0, 1.0), st.sampled_from(["open", "crossed"]))
def test_rates_equal_finite_differences_of_positions(a, b, offset_ratio, tilt, theta0, alpha2, branch):
    """The rod is longer than crank + |offset|, so the crank turns fully (a Grashof slider-crank)."""
    e = offset_ratio * (b - a)
    linkage = SliderCrank((0.3, -0.2), a, b, e, tilt, branch)
    h = 1e-4
    t = np.array([-h, 0.0, h])
    m = solve_slider_crank(linkage, theta0 + t + alpha2 * t * t / 2, 1.0 + alpha2 * t, alpha2)
    assert m.feasible.all()
    x = m.slider_position
    assert (x[2] - x[0]) / (2 * h) == pytest.approx(m.slider_velocity[1], abs=1e-6 * (a + b))
    assert (x[2] - 2 * x[1] + x[0]) / h**2 == pytest.approx(m.slider_acceleration[1], abs=1e-4 * (a + b))
    d_minus = math.remainder(m.theta3[1] - m.theta3[0], 2 * math.pi)
    d_plus = math.remainder(m.theta3[2] - m.theta3[1], 2 * math.pi)
    assert (d_plus + d_minus) / (2 * h) == pytest.approx(m.omega3[1], abs=1e-6)
    assert (d_plus - d_minus) / h**2 == pytest.approx(m.alpha3[1], abs=1e-4)
    # The loop closes: B is on the slider line, a rod's length from A.
    normal = np.array([-math.sin(tilt), math.cos(tilt)])
    b_pt, a_pt = m.joints["B"].position, m.joints["A"].position
    assert np.allclose((b_pt - [0.3, -0.2]) @ normal, e, atol=1e-12 * (a + b))
    assert np.allclose(np.hypot(*(b_pt - a_pt).T), b, rtol=1e-12)
    direction = np.array([math.cos(tilt), math.sin(tilt)])
    assert np.all(((b_pt - a_pt) @ direction) * (1 if branch == "open" else -1) > 0)


def test_offset_puts_the_slider_line_left_of_its_direction():
    m = solve_slider_crank(SliderCrank((0.0, 0.0), 1.0, 4.0, offset=0.5), [math.radians(90.0)], 1.0, 0.0)
    # A = (0, 1); B on y = 0.5, rod 4: x = sqrt(16 - 0.25).
    assert m.joints["B"].position[0] == pytest.approx([math.sqrt(15.75), 0.5], abs=1e-15)
    assert m.slider_position[0] == pytest.approx(math.sqrt(15.75), abs=1e-15)


def test_rod_shorter_than_crank_plus_offset_toggles_and_reports_the_unreachable_angles():
    # crank 2, rod 1.5, offset 0: the crank rocks where |2 sin(phi)| <= 1.5.
    linkage = SliderCrank((0.0, 0.0), 2.0, 1.5)
    toggles = slider_toggle_angles(linkage)
    assert len(toggles) == 4
    assert np.allclose(np.abs(np.sin(toggles)), 0.75, atol=1e-15)
    ranges = slider_feasible_input_ranges(linkage)
    assert len(ranges) == 2
    edges = np.array([x for r in ranges for x in r])
    m = solve_slider_crank(linkage, np.concatenate([edges, edges - 1e-9, edges + 1e-9]), 1.0, 0.0)
    assert np.all(m.status[:4] == TOGGLE)
    assert sorted(m.status[4:].tolist()) == [FEASIBLE] * 4 + [TOO_FAR] * 4
    assert m.reasons[0] == "toggle: connecting rod perpendicular to the slider line"
    for array in (m.omega3, m.alpha3, m.slider_velocity, m.slider_acceleration, m.theta3):
        assert np.isfinite(array).all()


@settings(max_examples=100, deadline=None)
@given(st.floats(0.2, 3.0), st.floats(0.2, 3.0), st.floats(-2.0, 2.0), st.floats(-math.pi, math.pi))
def test_feasible_ranges_agree_with_the_solver(a, b, e, theta):
    linkage = SliderCrank((0.0, 0.0), a, b, e, 0.3)
    ranges = slider_feasible_input_ranges(linkage)
    inside = any(math.remainder(theta - lo, 2 * math.pi) % (2 * math.pi) < hi - lo for lo, hi in ranges)
    m = solve_slider_crank(linkage, [theta])
    margin = abs(abs(e - a * math.sin(theta - 0.3)) - b) / b
    assume(margin > 1e-9)
    assert inside == bool(m.feasible[0])


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_dead_centres_stop_the_slider(branch):
    linkage = SliderCrank((0.0, 0.0), 1.0, 3.0, 0.4, 0.2, branch)
    limits = slider_limits(linkage)
    assert {lim.kind for lim in limits} == {"extended", "folded"}
    m = solve_slider_crank(linkage, [lim.input_angle for lim in limits], 10.0, 0.0)
    assert m.feasible.all()
    assert np.abs(m.slider_velocity).max() < 1e-12
    assert np.allclose(m.slider_position, [lim.output for lim in limits], atol=1e-14)
    # Offset stroke: sqrt((b + a)^2 - e^2) - sqrt((b - a)^2 - e^2) (Norton sec. 4.7)
    assert stroke(linkage) == pytest.approx(math.sqrt(16 - 0.16) - math.sqrt(4 - 0.16), rel=1e-14)


@pytest.mark.parametrize("scale", [1e-3, 1e3])
def test_results_are_scale_free(scale):
    theta = np.radians(np.arange(0.0, 360.0, 15.0))
    base = solve_slider_crank(SliderCrank((0.0, 0.0), 1.0, 3.0, 0.5, 0.1), theta, 7.0, 2.0)
    m = solve_slider_crank(SliderCrank((scale, scale), scale, 3 * scale, 0.5 * scale, 0.1), theta, 7.0, 2.0)
    assert np.allclose(m.alpha3, base.alpha3, rtol=1e-12)
    assert np.allclose(m.slider_acceleration / scale, base.slider_acceleration, rtol=1e-12)
