"""Grashof class, Barker type, toggles, limit positions and feasible input ranges of four-bars."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from linkstress.kinematics.fourbar import TOGGLE_TOLERANCE, FourBar, factor_reaches, solve_fourbar
from linkstress.kinematics.linkage_class import classify, feasible_input_ranges, output_limits, toggle_angles

pytestmark = pytest.mark.filterwarnings("error")


def fourbar(a, b, c, d, branch="open", tilt=0.0):
    return FourBar((0.0, 0.0), (d * math.cos(tilt), d * math.sin(tilt)), a, b, c, branch)


# (crank a, coupler b, output c, ground d) -> Barker type (Norton, Design of Machinery, table 2-4)
BARKER_EXAMPLES = [
    ((8, 8, 9, 6), 1, "GCCC", "grashof"),  # the textbook four-bar: ground shortest
    ((2, 7, 6, 8), 2, "GCRR", "grashof"),
    ((7, 2, 6, 8), 3, "GRCR", "grashof"),
    ((7, 6, 2, 8), 4, "GRRC", "grashof"),
    ((2, 3, 2.5, 6), 5, "RRR1", "non-grashof"),
    ((6, 3, 2.5, 2), 6, "RRR2", "non-grashof"),
    ((3, 6, 2.5, 2), 7, "RRR3", "non-grashof"),
    ((3, 2.5, 6, 2), 8, "RRR4", "non-grashof"),
    ((4, 2, 3, 1), 9, "SCCC", "change-point"),
    ((1, 3, 2, 4), 10, "SCRR", "change-point"),
    ((4, 1, 3, 2), 11, "SRCR", "change-point"),
    ((4, 3, 1, 2), 12, "SRRC", "change-point"),
    ((1, 3, 1, 3), 13, "S2X", "change-point"),  # parallelogram
    ((1, 1, 3, 3), 13, "S2X", "change-point"),  # kite
    ((2, 2, 2, 2), 14, "S3X", "change-point"),
]


@pytest.mark.parametrize("lengths, barker, code, grashof", BARKER_EXAMPLES)
def test_barker_type_follows_nortons_table(lengths, barker, code, grashof):
    kind = classify(fourbar(*lengths))
    assert (kind.barker_type, kind.code, kind.grashof) == (barker, code, grashof)


def test_grashof_crank_turns_fully_and_has_no_toggles():
    linkage = fourbar(2, 7, 6, 8)
    assert toggle_angles(linkage) == ()
    (lo, hi), = feasible_input_ranges(linkage)
    assert hi - lo == pytest.approx(2 * math.pi)


def test_grashof_double_rocker_with_the_coupler_shortest_rocks_in_two_mirror_ranges():
    linkage = fourbar(5, 1, 6, 5)  # s = coupler: GRCR, the crank can't pass the ground line
    assert classify(linkage).code == "GRCR"
    ranges = feasible_input_ranges(linkage)
    assert len(ranges) == 2
    (lo1, hi1), (lo2, hi2) = ranges
    assert lo1 == pytest.approx(-hi2) and hi1 == pytest.approx(-lo2)
    assert sorted(toggle_angles(linkage)) == pytest.approx(sorted([lo1, hi1, lo2, hi2]))


def test_lengths_that_cannot_assemble_have_no_feasible_range():
    assert feasible_input_ranges(fourbar(1, 1, 1, 4)) == ()  # ground longer than the other three
    assert feasible_input_ranges(fourbar(1, 6, 1, 1)) == ()  # coupler longer than the other three


def inside(theta, ranges):
    # A full turn holds every angle (theta - lo) % 2 pi can round up to 2 pi itself for a tiny negative theta.
    return any(hi - lo >= 2 * math.pi or (theta - lo) % (2 * math.pi) < hi - lo for lo, hi in ranges)


@settings(max_examples=300, deadline=None)
@given(st.floats(0.2, 5), st.floats(0.2, 5), st.floats(0.2, 5), st.floats(0.2, 5),
       st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi))
@example(1.0, 1.0, 1.0, 1.0, 0.0, 1e-5)
def test_feasible_ranges_agree_with_the_solver_at_any_angle(a, b, c, d, theta, tilt):
    linkage = fourbar(a, b, c, d, tilt=tilt)
    ranges = feasible_input_ranges(linkage)
    m = solve_fourbar(linkage, [theta])
    s = math.hypot(d * math.cos(tilt) - a * math.cos(theta), d * math.sin(tilt) - a * math.sin(theta))
    # Away from the toggles by the solver's own measure, 1 -/+ cos(mu) against its reach (a
    # parallelogram 6e-8 rad from its change point is 4e-9 from |b - c| in s but only 2e-15 from a
    # toggle in cos(mu); a factor that touches zero at a change point reaches 1e-7, so the square
    # four-bar with its ground tilted 1e-5 rad, at 1 - cos(mu) = 5e-11 at theta = 0, is its change point).
    cos_mu = (b * b + c * c - s * s) / (2 * b * c)
    minus, plus = factor_reaches(linkage)
    assume(abs(cos_mu) > 1 + 10 * TOGGLE_TOLERANCE or (1 - cos_mu > 10 * minus and 1 + cos_mu > 10 * plus))
    assert inside(theta, ranges) == bool(m.feasible[0])


@settings(max_examples=100, deadline=None)
@given(st.floats(0.2, 5), st.floats(0.2, 5), st.floats(0.2, 5), st.floats(0.2, 5), st.floats(-3, 3))
def test_the_solver_flags_every_toggle_angle(a, b, c, d, tilt):
    linkage = fourbar(a, b, c, d, tilt=tilt)
    toggles = toggle_angles(linkage)
    assume(toggles and classify(linkage).grashof != "change-point")
    m = solve_fourbar(linkage, toggles, 1.0, 0.0)
    assert not m.feasible.any()
    assert all(r.startswith("toggle") or r.startswith("change point") for r in m.reasons)


@settings(max_examples=100, deadline=None)
@given(st.floats(0.2, 5), st.floats(0.2, 5), st.floats(0.2, 5), st.floats(0.2, 5),
       st.sampled_from(["open", "crossed"]), st.floats(-3, 3))
def test_output_limits_lie_on_the_branch_and_stop_the_output(a, b, c, d, branch, tilt):
    linkage = fourbar(a, b, c, d, branch, tilt)
    limits = output_limits(linkage)
    assume(limits)
    m = solve_fourbar(linkage, [lim.input_angle for lim in limits], 1.0, 0.0)
    assume(np.all(m.transmission_angle > 1e-3) and m.feasible.all())
    assert np.allclose(np.remainder(m.theta4 - [lim.output for lim in limits] + 1, 2 * math.pi), 1, atol=1e-9)
    assert np.abs(m.omega4).max() < 1e-9 * max(a, b, c, d) / min(a, b, c, d) / np.min(m.transmission_angle)


def test_transmission_angle_is_nortons_acute_angle_between_coupler_and_output():
    m = solve_fourbar(fourbar(0.08, 0.08, 0.09, 0.06), [math.radians(25.0)])
    # theta3 = 343.68511 deg, theta4 = 7.23605 deg: |theta3 - theta4| = 336.44906 -> 23.55094 deg.
    assert math.degrees(m.transmission_angle[0]) == pytest.approx(23.55094, abs=1e-5)
