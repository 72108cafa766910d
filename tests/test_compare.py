"""The beam-against-FEA error measures shared by validate and bench."""

from __future__ import annotations

import numpy as np
import pytest

from linkstress.validation.compare import relative, resultant_error


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
