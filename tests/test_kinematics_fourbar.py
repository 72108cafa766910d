"""Four-bar kinematics: Norton's textbook values, his equations, finite differences, hard cases."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from linkstress.kinematics.fourbar import (
    CHANGE_POINT,
    FEASIBLE,
    TOGGLE,
    TOO_CLOSE,
    TOO_FAR,
    FourBar,
    solve_fourbar,
)
from linkstress.kinematics.linkage_class import classify, feasible_input_ranges, output_limits, toggle_angles

pytestmark = pytest.mark.filterwarnings("error")  # no overflow or invalid value, even in filler

# Norton, Design of Machinery, problems 4-1/6-1/7-1 row g (docs/reference/textbook-fourbar.md):
# ground 6, crank 8, coupler 8, output 9 cm; theta2 = 25 deg, omega2 = 100 rad/s, alpha2 = 18 rad/s^2.
TEXTBOOK = {
    "open": (343.68511, 7.23605, 76.357225, 146.870417, -23510.09997, -19783.12970),
    "crossed": (155.72049, 132.16954, 239.119341, 168.606150, -43709.33015, -47436.30042),
}


def textbook(branch: str) -> FourBar:
    return FourBar((0.0, 0.0), (0.06, 0.0), 0.08, 0.08, 0.09, branch)


def deg(angle) -> float:
    return float(np.rad2deg(angle)) % 360.0


def norton(a, b, c, d, theta2, omega2, alpha2, branch):
    """Norton's own equations with the ground on +x: 4.10 (theta4), 4.13 (theta3), 6.18, 7.12."""
    k1, k2, k3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    k4, k5 = d / b, (c * c - d * d - a * a - b * b) / (2 * a * b)
    big_a = math.cos(theta2) - k1 - k2 * math.cos(theta2) + k3
    big_b = -2 * math.sin(theta2)
    big_c = k1 - (k2 + 1) * math.cos(theta2) + k3
    big_d = math.cos(theta2) - k1 + k4 * math.cos(theta2) + k5
    big_e = -2 * math.sin(theta2)
    big_f = k1 + (k4 - 1) * math.cos(theta2) + k5
    sign = -1 if branch == "open" else 1
    theta4 = 2 * math.atan((-big_b + sign * math.sqrt(big_b**2 - 4 * big_a * big_c)) / (2 * big_a))
    theta3 = 2 * math.atan((-big_e + sign * math.sqrt(big_e**2 - 4 * big_d * big_f)) / (2 * big_d))
    omega3 = a * omega2 / b * math.sin(theta4 - theta2) / math.sin(theta3 - theta4)
    omega4 = a * omega2 / c * math.sin(theta2 - theta3) / math.sin(theta4 - theta3)
    aa = c * math.sin(theta4)
    bb = b * math.sin(theta3)
    cc = (a * alpha2 * math.sin(theta2) + a * omega2**2 * math.cos(theta2)
          + b * omega3**2 * math.cos(theta3) - c * omega4**2 * math.cos(theta4))
    dd = c * math.cos(theta4)
    ee = b * math.cos(theta3)
    ff = (a * alpha2 * math.cos(theta2) - a * omega2**2 * math.sin(theta2)
          - b * omega3**2 * math.sin(theta3) + c * omega4**2 * math.sin(theta4))
    alpha3 = (cc * dd - aa * ff) / (aa * ee - bb * dd)
    alpha4 = (cc * ee - bb * ff) / (aa * ee - bb * dd)
    return theta3, theta4, omega3, omega4, alpha3, alpha4


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_textbook_fourbar_matches_every_printed_digit(branch):
    m = solve_fourbar(textbook(branch), [math.radians(25.0)], 100.0, 18.0)
    got = (deg(m.theta3[0]), deg(m.theta4[0]), m.omega3[0], m.omega4[0], m.alpha3[0], m.alpha4[0])
    # Each printed value is rounded: agree within half a unit of its last printed digit.
    printed_ulp = (1e-5, 1e-5, 1e-6, 1e-6, 1e-5, 1e-5)
    for value, expected, ulp in zip(got, TEXTBOOK[branch], printed_ulp):
        assert abs(value - expected) <= ulp / 2, (value, expected)
    assert m.feasible[0]


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_textbook_fourbar_matches_nortons_equations_to_1e_9(branch):
    m = solve_fourbar(textbook(branch), [math.radians(25.0)], 100.0, 18.0)
    t3, t4, w3, w4, a3, a4 = norton(0.08, 0.08, 0.09, 0.06, math.radians(25.0), 100.0, 18.0, branch)
    assert abs(math.remainder(m.theta3[0] - t3, 2 * math.pi)) <= 1e-9 * abs(t3)
    assert abs(math.remainder(m.theta4[0] - t4, 2 * math.pi)) <= 1e-9 * abs(t4)
    for value, expected in ((m.omega3[0], w3), (m.omega4[0], w4), (m.alpha3[0], a3), (m.alpha4[0], a4)):
        assert abs(value - expected) <= 1e-9 * abs(expected)


lengths = st.floats(0.2, 5.0)


@settings(max_examples=300, deadline=None)
@given(lengths, lengths, lengths, lengths, st.floats(-math.pi, math.pi), st.sampled_from(["open", "crossed"]))
def test_open_is_nortons_minus_root_everywhere(a, b, c, d, theta2, branch):
    """Norton eq. 4.10's minus root is B left of A -> O4, for every linkage and crank angle."""
    m = solve_fourbar(FourBar((0, 0), (d, 0), a, b, c, branch), [theta2], 1.0, 0.0)
    assume(m.feasible[0])
    # Eq. 4.10 divides by 2A and 4.13 by 2D: stay where Norton's formula is defined.
    big_a = math.cos(theta2) * (1 - d / c) - d / a + (a * a - b * b + c * c + d * d) / (2 * a * c)
    big_d = math.cos(theta2) * (1 + d / b) - d / a + (c * c - d * d - a * a - b * b) / (2 * a * b)
    assume(abs(big_a) > 1e-3 and abs(big_d) > 1e-3)
    t3, t4, w3, w4, *_ = norton(a, b, c, d, theta2, 1.0, 0.0, branch)
    assume(abs(math.sin(t4 - t3)) > 1e-3)
    assert abs(math.remainder(m.theta4[0] - t4, 2 * math.pi)) < 1e-9
    assert abs(math.remainder(m.theta3[0] - t3, 2 * math.pi)) < 1e-9


@st.composite
def grashof_cranks(draw):
    """(a, b, c, d) of a Grashof four-bar whose crank turns fully: the crank or the ground is
    shortest S, and S + L < P + Q."""
    others = [draw(st.floats(1.0, 5.0)) for _ in range(3)]
    room = min(min(others), sum(others) - 2 * max(others))
    assume(room > 0.05)
    shortest = draw(st.floats(0.05, 0.95)) * room
    p, q, r = draw(st.permutations(others))
    if draw(st.booleans()):
        return shortest, p, q, r  # crank shortest: crank-rocker
    return p, q, r, shortest  # ground shortest: double crank


@settings(max_examples=200, deadline=None)
@given(grashof_cranks(), st.floats(-math.pi, math.pi), st.floats(-1.0, 1.0),
       st.floats(-3.0, 3.0), st.sampled_from(["open", "crossed"]), st.floats(-math.pi, math.pi))
def test_rates_equal_finite_differences_of_positions(lengths4, theta0, alpha2, x0, branch, tilt):
    """Central differences in time of theta2(t) = theta0 + t + alpha2 t^2 / 2 (omega2 = 1 rad/s)."""
    a, b, c, d = lengths4
    assert classify(FourBar((0, 0), (d, 0), a, b, c)).grashof == "grashof"
    o2 = np.array([x0, -x0 / 2])
    o4 = o2 + d * np.array([math.cos(tilt), math.sin(tilt)])
    linkage = FourBar(tuple(o2), tuple(o4), a, b, c, branch)
    h = 1e-4
    t = np.array([-h, 0.0, h])
    m = solve_fourbar(linkage, theta0 + t + alpha2 * t * t / 2, 1.0 + alpha2 * t, alpha2)
    assume(m.feasible.all() and np.min(m.transmission_angle) > 0.05)
    for theta, omega, alpha in ((m.theta3, m.omega3, m.alpha3), (m.theta4, m.omega4, m.alpha4)):
        d_minus = math.remainder(theta[1] - theta[0], 2 * math.pi)
        d_plus = math.remainder(theta[2] - theta[1], 2 * math.pi)
        scale = 1.0 + abs(omega[1]) + abs(alpha[1])
        assert abs((d_plus + d_minus) / (2 * h) - omega[1]) <= 1e-5 * scale
        assert abs((d_plus - d_minus) / h**2 - alpha[1]) <= 1e-4 * scale
    for joint in ("A", "B"):
        p, v, acc = (getattr(m.joints[joint], k) for k in ("position", "velocity", "acceleration"))
        size = a + b + c + d
        assert np.abs((p[2] - p[0]) / (2 * h) - v[1]).max() <= 1e-5 * size * (1 + abs(m.omega4[1]))
        assert np.abs((p[2] - 2 * p[1] + p[0]) / h**2 - acc[1]).max() <= 1e-4 * size * (1 + abs(m.alpha4[1]))


@settings(max_examples=200, deadline=None)
@given(lengths, lengths, lengths, lengths, st.sampled_from(["open", "crossed"]), st.floats(-math.pi, math.pi))
def test_loop_closes_within_1e_12_of_its_size_at_every_feasible_position(a, b, c, d, branch, tilt):
    o4 = (d * math.cos(tilt) + 10.0, d * math.sin(tilt) - 5.0)
    linkage = FourBar((10.0, -5.0), o4, a, b, c, branch)
    toggles = np.array(toggle_angles(linkage))
    # A dense sweep plus angles 1e-9 rad on either side of each toggle.
    theta2 = np.concatenate([np.linspace(-math.pi, math.pi, 721), toggles - 1e-9, toggles + 1e-9])
    m = solve_fourbar(linkage, theta2, 1.0, 0.5)
    for array in (m.theta3, m.theta4, m.omega3, m.omega4, m.alpha3, m.alpha4):
        assert np.isfinite(array).all()
    ok = m.feasible
    closure = (
        np.asarray(linkage.o2) + a * np.column_stack([np.cos(theta2), np.sin(theta2)])
        + b * np.column_stack([np.cos(m.theta3), np.sin(m.theta3)])
        - c * np.column_stack([np.cos(m.theta4), np.sin(m.theta4)]) - np.asarray(o4)
    )
    assert np.abs(closure[ok]).max(initial=0.0) <= 1e-12 * max(a, b, c, d, 10.0)


def test_feasible_side_of_a_toggle_1e_9_rad_away_is_finite_on_branch_and_the_other_side_unreachable():
    # Non-Grashof (RRR1): a = 2, b = 3, c = 2.5, d = 6; the crank rocks between two toggles.
    linkage = FourBar((0.0, 0.0), (6.0, 0.0), 2.0, 3.0, 2.5, "open")
    (start, stop), = feasible_input_ranges(linkage)
    assert toggle_angles(linkage) == pytest.approx((start, stop), abs=1e-15)
    theta2 = np.array([start - 1e-9, start, start + 1e-9, stop - 1e-9, stop, stop + 1e-9])
    m = solve_fourbar(linkage, theta2, 10.0, 1.0)
    assert m.status.tolist() == [TOO_FAR, TOGGLE, FEASIBLE, FEASIBLE, TOGGLE, TOO_FAR]
    inside = m.feasible
    assert np.isfinite(m.alpha4).all() and np.isfinite(m.omega3).all()
    assert np.all(np.abs(m.omega4[inside]) > 1e3)  # rates grow like 1/sqrt(distance to the toggle)
    # On the open branch B stays left of A -> O4 right up to the toggle.
    a_pt, b_pt = m.joints["A"].position[inside], m.joints["B"].position[inside]
    to_o4, to_b = np.array([6.0, 0.0]) - a_pt, b_pt - a_pt
    assert np.all(to_o4[:, 0] * to_b[:, 1] - to_o4[:, 1] * to_b[:, 0] > 0)
    assert m.reasons[1] == "toggle: coupler and output aligned"
    assert m.reasons[0].startswith("unreachable:")


def test_rates_near_a_toggle_agree_with_finite_differences_at_1e_9_rad():
    linkage = FourBar((0.0, 0.0), (6.0, 0.0), 2.0, 3.0, 2.5, "crossed")
    (start, _), = feasible_input_ranges(linkage)
    theta = start + 1e-9 + np.array([0.0, 1e-13, 2e-13])
    m = solve_fourbar(linkage, theta, 1.0, 0.0)
    assert m.feasible.all()
    fd = (m.theta4[2] - m.theta4[0]) / 2e-13
    assert fd == pytest.approx(m.omega4[1], rel=1e-2)


def test_crank_exactly_at_dead_centre_stops_the_output_and_stays_feasible():
    # Grashof crank-rocker (GCRR): crank 1, coupler 3, output 2.5, ground 3.
    linkage = FourBar((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 2.5, "open")
    assert classify(linkage).code == "GCRR"
    limits = output_limits(linkage)
    assert {lim.kind for lim in limits} == {"extended", "folded"}
    m = solve_fourbar(linkage, [lim.input_angle for lim in limits], 50.0, 0.0)
    assert m.feasible.all()
    assert np.abs(m.omega4).max() <= 1e-12 * 50.0
    assert np.allclose(m.theta4, [lim.output for lim in limits], atol=1e-12)
    # Crank and coupler are in line there (extended: same direction, folded: opposite).
    for lim, t2, t3 in zip(limits, m.theta2, m.theta3):
        expected = 0.0 if lim.kind == "extended" else math.pi
        assert abs(math.remainder(t3 - t2 - expected, 2 * math.pi)) < 1e-12


def test_change_point_linkage_is_flagged_where_branches_meet_and_keeps_its_branch_elsewhere():
    # a + d = b + c: crank 1, coupler 3, output 2, ground 4 (Barker III-2, SCRR); change point at 180 deg.
    linkage = FourBar((0.0, 0.0), (4.0, 0.0), 1.0, 3.0, 2.0, "open")
    assert classify(linkage).code == "SCRR"
    theta2 = np.concatenate([np.radians(np.arange(0.0, 360.0, 0.5)), [math.pi - 1e-9, math.pi + 1e-9]])
    m = solve_fourbar(linkage, theta2, 1.0, 0.0)
    at_change = np.isclose(theta2, math.pi, atol=1e-8)
    assert np.all(m.status[at_change] == CHANGE_POINT)
    assert m.feasible[~at_change].all()
    assert m.reasons[int(np.argmax(at_change))].startswith("change point")
    a_pt, b_pt = m.joints["A"].position, m.joints["B"].position
    to_o4, to_b = np.array([4.0, 0.0]) - a_pt, b_pt - a_pt
    side = to_o4[:, 0] * to_b[:, 1] - to_o4[:, 1] * to_b[:, 0]
    assert np.all(side[~at_change] > 0)
    assert np.isfinite(m.alpha4).all() and np.isfinite(m.omega4).all()


def test_lengths_that_cannot_reach_report_which_way_they_fail():
    # crank 1, coupler 1, output 1, ground 2.5: A is at most 3.5, at least 1.5 from O4; b + c = 2.
    linkage = FourBar((0.0, 0.0), (2.5, 0.0), 1.0, 1.0, 1.0)
    m = solve_fourbar(linkage, [0.0, math.pi], 1.0, 1.0)
    assert m.status.tolist() == [FEASIBLE, TOO_FAR]
    # crank 3, coupler 5, output 1, ground 3: at theta2 = 0 A sits on O4, closer than b - c = 4.
    m = solve_fourbar(FourBar((0.0, 0.0), (3.0, 0.0), 3.0, 5.0, 1.0), [0.0], 1.0, 1.0)
    assert m.status.tolist() == [TOO_CLOSE]
    for array in (m.theta3, m.omega3, m.alpha4, m.joints["B"].position):
        assert np.isfinite(array).all()
    assert m.omega3[0] == 0.0 and m.alpha4[0] == 0.0


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_results_are_scale_free_from_1e_3_to_1e3_m(scale, branch):
    base = solve_fourbar(textbook(branch), np.radians(np.arange(0, 360, 5.0)), 100.0, 18.0)
    linkage = FourBar((3 * scale, -scale), (3 * scale + 0.06 / 0.08 * scale, -scale), scale, scale,
                      0.09 / 0.08 * scale, branch)
    m = solve_fourbar(linkage, np.radians(np.arange(0, 360, 5.0)), 100.0, 18.0)
    assert np.array_equal(m.feasible, base.feasible)
    assert np.allclose(m.theta3, base.theta3, rtol=0, atol=1e-12)
    assert np.allclose(m.omega4, base.omega4, rtol=1e-12)
    assert np.allclose(m.alpha3, base.alpha3, rtol=1e-11)
    size = scale * np.array([1.0, 1.0])
    shifted = (m.joints["B"].position - [3 * scale, -scale]) / size
    assert np.allclose(shifted, base.joints["B"].position / 0.08, atol=1e-12)


def test_link_points_move_rigidly_with_their_link():
    m = solve_fourbar(textbook("open"), np.radians([25.0, 100.0]), 100.0, 18.0)
    coupler = m.links["coupler"]
    # Joint B is at (b, 0) in the coupler's frame A -> B.
    p, v, a = coupler.point([0.08, 0.0])
    assert np.allclose(p, m.joints["B"].position, atol=1e-15)
    assert np.allclose(v, m.joints["B"].velocity, rtol=1e-12)
    assert np.allclose(a, m.joints["B"].acceleration, rtol=1e-10)
    many = coupler.point([[0.0, 0.0], [0.08, 0.0], [0.04, 0.01]])
    assert many[0].shape == (2, 3, 2)
    assert np.allclose(many[2][:, 1], a)
    # The output's frame origin O4 does not move.
    assert np.allclose(m.links["output"].point([0.0, 0.0])[1], 0.0)
