"""Rates by central finite differences of positions in the input, for the cases' independent truths.

The first and second derivatives in the input x (an angle [rad] or a stroke [m]) use the
eighth-order central stencils on x + k h, k = -4..4 (Fornberg, "Generation of finite difference
formulas on arbitrarily spaced grids", Math. Comp. 51 (1988), table 1):

    f'  = [4/5 (f1 - f-1) - 1/5 (f2 - f-2) + 4/105 (f3 - f-3) - 1/280 (f4 - f-4)] / h
    f'' = [-205/72 f0 + 8/5 (f1 + f-1) - 1/5 (f2 + f-2) + 8/315 (f3 + f-3) - 1/560 (f4 + f-4)] / h^2

Time rates follow by the chain rule: v = f' xdot, a = f'' xdot^2 + f' xddot.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

OFFSETS = np.arange(-4, 5)
"""The stencil's points x + k h, in this order along the first axis of sampled values."""
FIRST = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
SECOND = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])


def stencil(x: FloatArray, h: float) -> FloatArray:
    """The inputs (9, P) at which to sample: x + k h for k = -4..4."""
    return np.asarray(x, float)[None, :] + OFFSETS[:, None] * h


def derivatives(samples: FloatArray, h: float) -> tuple[FloatArray, FloatArray]:
    """(f', f'') in the input from ``samples`` (9, P, ...) taken on ``stencil``."""
    samples = np.asarray(samples, float)
    first = np.tensordot(FIRST, samples, axes=(0, 0)) / h
    second = np.tensordot(SECOND, samples, axes=(0, 0)) / h**2
    return first, second


def angle_derivatives(angles: FloatArray, h: float) -> tuple[FloatArray, FloatArray]:
    """(phi', phi'') of angles [rad] (9, P) sampled on ``stencil``: differences from the middle
    sample are wrapped into (-pi, pi], so that a turn through +-pi is no jump."""
    angles = np.asarray(angles, float)
    steps = np.angle(np.exp(1j * (angles - angles[4])))
    return derivatives(steps, h)


def in_time(first: FloatArray, second: FloatArray, speed: FloatArray, acceleration: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(velocity, acceleration) from the input derivatives (P, ...) and the input's speed and
    acceleration (P,): v = f' xdot, a = f'' xdot^2 + f' xddot."""
    shape = (-1,) + (1,) * (np.ndim(first) - 1)
    speed, acceleration = np.reshape(speed, shape), np.reshape(acceleration, shape)
    return first * speed, second * speed**2 + first * acceleration
