"""Kt x nominal estimates at pin holes: the table, its extension, and its use on a link."""

from __future__ import annotations

import numpy as np
import pytest

from linkstress.builders import straight_bar
from linkstress.dynamics.pin_holes import BEARING_FACTOR, KT_TABLE, pin_hole_estimates, pin_hole_kt
from linkstress.loads import LinkLoadCase, PointForce
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.validation.pin_hole_kt import lug_kt


def test_kt_is_the_table_at_its_points_decreasing_and_none_beyond_it():
    for ratio, kt in KT_TABLE:
        assert pin_hole_kt(ratio) == pytest.approx(kt, rel=1e-12)
    values = [pin_hole_kt(r) for r in np.linspace(0.01, 0.7, 50)]
    assert all(a > b for a, b in zip(values, values[1:]))
    assert pin_hole_kt(0.75) is None and pin_hole_kt(0.0) is None


def test_small_holes_follow_the_bearing_asymptote():
    # Kt = 1.5 (H - d) / d: the peak is about 1.5 x the bearing stress P / (d t) for small holes.
    assert BEARING_FACTOR == pytest.approx(1.5, abs=0.01)
    assert pin_hole_kt(0.02) == pytest.approx(BEARING_FACTOR * 0.98 / 0.02, rel=1e-12)
    assert pin_hole_kt(0.3) == pytest.approx(BEARING_FACTOR * 0.7 / 0.3, rel=0.05)


def test_the_table_is_what_the_lug_fea_gives():
    kt, change = lug_kt(0.3)
    assert change < 0.01
    assert kt == pytest.approx(dict(KT_TABLE)[0.3], rel=0.01)


def test_estimates_on_a_link_use_its_depth_hole_and_pin_force():
    # 0.1 m deep, 10 mm thick bar with 30 mm holes pulled by 1 kN along its axis at both pins:
    # nominal = 1000 / ((0.1 - 0.03) 0.01) = 1.4286 MPa, Kt(0.3) = 3.347.
    bar = straight_bar(0.5, 0.1, 0.1, 0.01, STRUCTURAL_STEEL, hole_diameter=0.03)
    loads = LinkLoadCase((0, 1), np.array([[[-1000.0, 0.0], [1000.0, 0.0]]]), np.zeros((1, 2)), np.zeros(1),
                         np.zeros(1), np.zeros((1, 2)), np.zeros((1, 2)))
    first, second = pin_hole_estimates(bar, loads)
    assert first.joint == 0 and second.joint == 1
    assert first.diameter == pytest.approx(0.03, rel=1e-4) and first.depth == pytest.approx(0.1, rel=1e-12)
    assert first.nominal[0] == pytest.approx(1000 / (0.07 * 0.01), rel=1e-3)
    assert first.estimate[0] == pytest.approx(3.347 * first.nominal[0], rel=1e-3)
    assert "estimate" in first.source


def test_a_force_given_in_a_joints_hole_is_borne_by_that_pin_in_the_estimate():
    # The same bar, its pin at joint 1 loaded by [[loads.forces]] 1 kN at the hole (off its centre by
    # 5 mm) instead of a pin force: the estimate at joint 1 is the same 1.4286 MPa net-section stress.
    bar = straight_bar(0.5, 0.1, 0.1, 0.01, STRUCTURAL_STEEL, hole_diameter=0.03)
    loads = LinkLoadCase((0, 1), np.array([[[-1000.0, 0.0], [0.0, 0.0]]]), np.zeros((1, 2)), np.zeros(1),
                         np.zeros(1), np.zeros((1, 2)), np.zeros((1, 2)),
                         (PointForce(np.array([0.505, 0.0]), np.array([[1000.0, 0.0]])),))
    first, second = pin_hole_estimates(bar, loads)
    assert second.nominal[0] == pytest.approx(1000 / (0.07 * 0.01), rel=1e-3)
    assert first.nominal[0] == pytest.approx(second.nominal[0], rel=1e-12)
