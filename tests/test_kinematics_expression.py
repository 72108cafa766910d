"""Input motion as a function of time: safe parsing and exact derivatives."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from linkstress.errors import InputError
from linkstress.kinematics.expression import Expression, ExpressionError
from linkstress.kinematics.motion import MotionError, angle_motion, angle_range, timed_motion

T = np.linspace(0.05, 0.95, 19)


@pytest.mark.parametrize(
    "text, value, first, second",
    [
        ("90*sin(2*pi*t)", 90 * np.sin(2 * np.pi * T), 180 * np.pi * np.cos(2 * np.pi * T),
         -360 * np.pi**2 * np.sin(2 * np.pi * T)),
        ("3*t**2 - t + 2", 3 * T**2 - T + 2, 6 * T - 1, 6 + 0 * T),
        ("exp(-t)/t", np.exp(-T) / T, -np.exp(-T) / T - np.exp(-T) / T**2,
         np.exp(-T) / T + 2 * np.exp(-T) / T**2 + 2 * np.exp(-T) / T**3),
        ("sqrt(t)*log(t)", np.sqrt(T) * np.log(T), (np.log(T) + 2) / (2 * np.sqrt(T)), -np.log(T) / (4 * T**1.5)),
        ("t**t", T**T, T**T * (np.log(T) + 1), T**T * ((np.log(T) + 1) ** 2 + 1 / T)),
        ("atan(t) + asin(t) - acos(t)", np.arctan(T) + 2 * np.arcsin(T) - np.pi / 2,
         1 / (1 + T**2) + 2 / np.sqrt(1 - T**2), -2 * T / (1 + T**2) ** 2 + 2 * T / (1 - T**2) ** 1.5),
        ("tanh(t) + cosh(t) - sinh(-t) + tan(t) + abs(t - 2) + e*cos(t)",
         np.tanh(T) + np.cosh(T) + np.sinh(T) + np.tan(T) + 2 - T + np.e * np.cos(T),
         1 - np.tanh(T) ** 2 + np.sinh(T) + np.cosh(T) + 1 / np.cos(T) ** 2 - 1 - np.e * np.sin(T),
         -2 * np.tanh(T) * (1 - np.tanh(T) ** 2) + np.cosh(T) + np.sinh(T)
         + 2 * np.tan(T) / np.cos(T) ** 2 - np.e * np.cos(T)),
    ],
)
def test_derivatives_are_exact(text, value, first, second):
    f, df, ddf = Expression(text).jet(T)
    assert np.allclose(f, value, rtol=1e-14, atol=1e-14)
    assert np.allclose(df, first, rtol=1e-13, atol=1e-13)
    assert np.allclose(ddf, second, rtol=1e-12, atol=1e-12)


@settings(max_examples=100, deadline=None)
@given(st.floats(-3, 3), st.floats(0.1, 5), st.floats(-2, 2), st.floats(0, 1))
def test_derivatives_agree_with_finite_differences(amplitude, frequency, offset, t):
    e = Expression(f"{amplitude}*sin({frequency}*t + {offset})**3 / (2 + cos(t))")
    h = 1e-4
    f, df, ddf = e.jet([t - h, t, t + h])
    assert (f[2] - f[0]) / (2 * h) == pytest.approx(df[1], abs=1e-5 * (1 + abs(df[1])) * frequency**2)
    assert (f[2] - 2 * f[1] + f[0]) / h**2 == pytest.approx(ddf[1], abs=1e-3 * (1 + abs(ddf[1])) * frequency**2)


@pytest.mark.parametrize(
    "text, culprit",
    [
        ("__import__('os').system('true')", "call \"__import__('os').system\""),
        ("t.__class__", "'t.__class__'"),
        ("open('scene.toml')", "call 'open'"),
        ("(lambda: 1)()", "call 'lambda: 1'"),
        ("[t for t in range(9)]", "'[t for t in range(9)]'"),
        ("x + 1", "'x'"),
        ("sin", "'sin'"),
        ("sin(t, t)", "call 'sin'"),
        ("t if t else 1", "'t if t else 1'"),
        ("'90'", "\"'90'\""),
        ("t == 1", "'t == 1'"),
        ("9" * 400, "too large"),
        ("-" * 200 + "t", "nests deeper than 100"),
        ("", "non-empty string"),
        ("90 *", "not a valid expression"),
    ],
)
def test_anything_outside_the_whitelist_is_refused_naming_the_piece(text, culprit):
    with pytest.raises(ExpressionError) as error:
        Expression(text, where="motion.input_angle_deg.expression")
    message = str(error.value)
    assert message.startswith("motion.input_angle_deg.expression: ")
    assert culprit in message


def test_a_value_that_is_not_finite_is_an_error_naming_the_time():
    with pytest.raises(InputError, match=r"not finite at t = 0.0; keep arguments of log"):
        Expression("log(t)", where="motion").jet([0.0, 1.0])


def test_timed_motion_converts_degrees_and_their_derivatives_to_radians():
    t = np.linspace(0.0, 1.0, 5)
    motion = timed_motion(Expression("90*sin(2*pi*t)"), t)
    assert np.allclose(motion.angle_deg, [0, 90, 0, -90, 0], atol=1e-12)
    assert np.allclose(motion.angle, np.radians(motion.angle_deg))
    assert motion.speed[0] == pytest.approx(math.radians(90 * 2 * math.pi))
    assert motion.acceleration[1] == pytest.approx(-math.radians(90 * 4 * math.pi**2))
    assert motion.time is t or np.array_equal(motion.time, t)


def test_angle_motion_takes_one_speed_or_one_per_angle():
    motion = angle_motion(angle_range(0.0, 90.0, 4), 2.0, [0.0, 1.0, 2.0, 3.0])
    assert motion.angle_deg.tolist() == [0.0, 30.0, 60.0, 90.0]
    assert motion.speed.tolist() == [2.0] * 4
    assert motion.time is None
    with pytest.raises(MotionError, match=r"motion.input_acceleration_rad_s2: give one number, or a list of 4"):
        angle_motion([0.0, 1.0, 2.0, 3.0], 1.0, [1.0, 2.0])
    with pytest.raises(MotionError, match="finite"):
        angle_motion([0.0, float("nan")])
