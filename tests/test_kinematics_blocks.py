"""Sweeps solved a block at a time, on threads: the same numbers as one block; the angle helper."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkstress.kinematics import FourBar, SliderCrank, blocks, solve_fourbar, solve_slider_crank
from linkstress.kinematics.blocks import angle_of
from linkstress.kinematics import fourbar, slider_crank
from linkstress.kinematics.fourbar import CHANGE_POINT, FEASIBLE, TOGGLE, TOO_FAR

pytestmark = pytest.mark.filterwarnings("error")  # no overflow or invalid value, even in filler


def arrays(motion):
    """Every array a sweep returns, by name."""
    found = {name: getattr(motion, name) for name in (
        "theta3", "theta4", "omega3", "omega4", "alpha3", "alpha4", "status",
        "slider_position", "slider_velocity", "slider_acceleration",
    ) if getattr(motion, name) is not None}
    for joint, jm in motion.joints.items():
        found |= {f"{joint}.{k}": getattr(jm, k) for k in ("position", "velocity", "acceleration")}
    return found


def in_blocks_of(monkeypatch, size, solve):
    monkeypatch.setattr(blocks, "BLOCK", size)
    return solve()


# Non-Grashof (a = 2, b = 3, c = 2.5, d = 6): the crank rocks between two toggles and cannot reach
# the rest of the turn; a + d = b + c (1, 3, 2, 4): a change point at 180 deg, crossed by the sweep;
# a parallelogram (1, 3, 1, 3): change points at 0 and 180 deg with named assembly modes.
FOURBARS = {
    "toggles and unreachable": FourBar((1.0, 2.0), (7.0, 3.0), 2.0, 3.0, 2.5, "open"),
    "change point": FourBar((0.0, 0.0), (4.0, 0.0), 1.0, 3.0, 2.0, "crossed"),
    "parallelogram": FourBar((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, "open"),
}


@pytest.mark.parametrize("name", list(FOURBARS))
def test_four_bar_in_blocks_of_7_on_threads_equals_one_block_bit_for_bit(monkeypatch, name):
    linkage = FOURBARS[name]
    # 3,002 angles over two turns (none within 1.7e-3 rad of 0 or 180 deg, outside a change point's
    # reach, so that the sweep crosses them), then the toggle and change-point angles themselves
    points = [point.angle for point in fourbar.branch_points(linkage)]
    theta2 = np.concatenate([np.linspace(-2.0, 2.0 + 4 * math.pi, 3002), points])
    rng = np.random.default_rng(7)
    omega2, alpha2 = rng.normal(size=theta2.size), rng.normal(size=theta2.size)
    one = in_blocks_of(monkeypatch, theta2.size, lambda: solve_fourbar(linkage, theta2, omega2, alpha2))
    many = in_blocks_of(monkeypatch, 7, lambda: solve_fourbar(linkage, theta2, omega2, alpha2))
    for key, value in arrays(one).items():
        assert np.array_equal(arrays(many)[key], value), key
    assert many.crossings == one.crossings
    statuses = set(one.status.tolist())
    assert FEASIBLE in statuses and len(statuses) > 1  # the sweep meets infeasible positions
    if name == "toggles and unreachable":
        assert {TOGGLE, TOO_FAR} <= statuses
    else:
        assert CHANGE_POINT in statuses and one.crossings


def test_slider_crank_in_blocks_of_7_on_threads_equals_one_block_bit_for_bit(monkeypatch):
    # offset 1, crank 1, rod 1.5: where the crank is more than 30 deg below the slider line the
    # rod cannot reach it; the sweep ends on its two toggles
    linkage = SliderCrank((0.0, 0.0), 1.0, 1.5, 1.0, 0.0, "crossed")
    points = [point.angle for point in slider_crank.branch_points(linkage)]
    theta2 = np.concatenate([np.linspace(-7.0, 7.0, 2999), points])
    one = in_blocks_of(monkeypatch, theta2.size, lambda: solve_slider_crank(linkage, theta2, 3.0, -2.0))
    many = in_blocks_of(monkeypatch, 7, lambda: solve_slider_crank(linkage, theta2, 3.0, -2.0))
    for key, value in arrays(one).items():
        assert np.array_equal(arrays(many)[key], value), key
    assert set(one.status.tolist()) == {slider_crank.FEASIBLE, slider_crank.TOGGLE, slider_crank.TOO_FAR}


def test_angle_of_is_arctan2_within_an_ulp_of_pi_all_round_and_exact_on_the_axes():
    angles = np.linspace(-math.pi, math.pi, 100_001)
    lengths = np.geomspace(1e-9, 1e9, angles.size)
    x, y = lengths * np.cos(angles), lengths * np.sin(angles)
    got = angle_of(y, x, np.empty_like(x), np.empty_like(x))
    assert np.abs(got - np.arctan2(y, x)).max() <= math.ulp(math.pi)
    # the axes, with both signs of zero: x = 0 divides by zero, x = -0 and y = -0 pick the side
    x = np.array([1.0, 0.0, -0.0, -1.0, -1.0, 0.0, -0.0])
    y = np.array([0.0, 2.0, 2.0, 0.0, -0.0, -2.0, -2.0])
    got = angle_of(y, x, np.empty_like(x), np.empty_like(x))
    assert got.tolist() == np.arctan2(y, x).tolist() == [0.0, math.pi / 2, math.pi / 2, math.pi, -math.pi,
                                                         -math.pi / 2, -math.pi / 2]


def test_angle_of_the_zero_vector_is_nan_without_a_warning():
    zero = np.zeros(3)
    assert np.isnan(angle_of(zero, zero, np.empty(3), np.empty(3))).all()
