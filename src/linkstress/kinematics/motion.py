"""The input motion of a machine's main crank: angles, speeds and accelerations over P positions.

Angles are given in degrees (as the user writes them) and kept alongside their radian values;
speeds [rad/s] and accelerations [rad/s^2] are counter-clockwise positive. A motion given as a
function of time ``theta(t)`` [deg] takes its speed and acceleration from the function's exact time
derivatives (``linkstress.kinematics.expression``): omega = pi/180 dtheta/dt,
alpha = pi/180 d2theta/dt2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from linkstress.errors import InputError
from linkstress.kinematics.expression import Expression

FloatArray = NDArray[np.float64]


class MotionError(InputError):
    """An input motion with non-finite or mismatched values."""


@dataclass(frozen=True)
class InputMotion:
    """The main crank's motion at P positions.

    angle_deg (P,) [deg] as given; angle (P,) [rad]; speed (P,) [rad/s]; acceleration (P,)
    [rad/s^2]; time (P,) [s] when the motion is a function of time, else None. A linkage driven by
    a slider's stroke has ``quantity`` "stroke": then ``angle_deg`` and ``angle`` both hold the
    stroke [m], ``speed`` [m/s] and ``acceleration`` [m/s^2] its rates.
    """

    angle_deg: FloatArray
    angle: FloatArray
    speed: FloatArray
    acceleration: FloatArray
    time: FloatArray | None = None
    quantity: str = "angle"

    @property
    def is_stroke(self) -> bool:
        return self.quantity == "stroke"

    @property
    def n_positions(self) -> int:
        return self.angle.shape[0]


def angle_motion(
    angles_deg: ArrayLike,
    speed: ArrayLike = 0.0,
    acceleration: ArrayLike = 0.0,
    where: str = "motion",
) -> InputMotion:
    """Crank angles [deg] with speeds [rad/s] and accelerations [rad/s^2]: scalars or one per angle."""
    angle_deg = _finite_vector(angles_deg, f"{where}.input_angle_deg")
    n = angle_deg.shape[0]
    w = _per_position(speed, n, f"{where}.input_speed_rad_s")
    al = _per_position(acceleration, n, f"{where}.input_acceleration_rad_s2")
    return InputMotion(angle_deg, np.deg2rad(angle_deg), w, al)


def stroke_motion(strokes_m: ArrayLike, speed: ArrayLike = 0.0, acceleration: ArrayLike = 0.0,
                  where: str = "motion") -> InputMotion:
    """A slider's strokes [m] with speeds [m/s] and accelerations [m/s^2]: scalars or one per stroke."""
    stroke = _finite_vector(strokes_m, f"{where}.input_stroke_m")
    n = stroke.shape[0]
    v = _per_position(speed, n, f"{where}.input_speed_m_s")
    a = _per_position(acceleration, n, f"{where}.input_acceleration_m_s2")
    return InputMotion(stroke, stroke.copy(), v, a, quantity="stroke")


def timed_stroke(stroke_m_of_t: Expression, time: ArrayLike) -> InputMotion:
    """A slider's stroke [m] as a function of time [s], its rates from exact derivatives."""
    t = _finite_vector(time, f"{stroke_m_of_t.where} time")
    value, rate, curvature = stroke_m_of_t.jet(t)
    return InputMotion(np.array(value), np.array(value), np.asarray(rate, float), np.asarray(curvature, float), t,
                       quantity="stroke")


def angle_range(start: float, stop: float, num: int) -> FloatArray:
    """``num`` evenly spaced angles from ``start`` to ``stop`` [deg], both included."""
    return np.linspace(float(start), float(stop), int(num))


def timed_motion(angle_deg_of_t: Expression, time: ArrayLike) -> InputMotion:
    """Crank angle [deg] as a function of time [s], its speed and acceleration from exact derivatives."""
    t = _finite_vector(time, f"{angle_deg_of_t.where} time")
    theta, rate, curvature = angle_deg_of_t.jet(t)
    return InputMotion(
        np.array(theta), np.deg2rad(theta), np.deg2rad(rate), np.deg2rad(curvature), t
    )


def _finite_vector(values: ArrayLike, where: str) -> FloatArray:
    array = np.atleast_1d(np.asarray(values, float))
    if array.ndim != 1 or array.size == 0:
        raise MotionError(f"{where}: give at least one value, as a number or a flat list of numbers")
    if not np.isfinite(array).all():
        raise MotionError(f"{where}: every value must be a finite number")
    return array


def _per_position(values: ArrayLike, n: int, where: str) -> FloatArray:
    array = np.asarray(values, float)
    if array.ndim == 0:
        array = np.full(n, float(array))
    if array.shape != (n,):
        raise MotionError(f"{where}: give one number, or a list of {n} numbers (one per input angle)")
    if not np.isfinite(array).all():
        raise MotionError(f"{where}: every value must be a finite number")
    return array
