"""Flattening exact curves into polylines within a chord (sagitta) tolerance.

A chord of a circle of radius r spanning the angle dphi deviates from the arc by the sagitta
s = r (1 - cos(dphi / 2)); choosing dphi from s keeps every point of the polyline within s of the
curve, and the area between them below perimeter x s.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

MIN_SEGMENTS_PER_TURN = 16


def arc_segments(radius: float, sweep: float, sagitta: float) -> int:
    """Number of equal chords that keep an arc of ``radius`` [m] and ``sweep`` [rad] within ``sagitta`` [m]."""
    if radius <= 0 or sagitta <= 0:
        raise ValueError(f"arc needs radius > 0 and sagitta > 0, got {radius} and {sagitta}")
    ratio = min(sagitta / radius, 1.0)
    max_step = 2.0 * math.acos(1.0 - ratio)
    min_by_turn = MIN_SEGMENTS_PER_TURN * abs(sweep) / (2 * math.pi)
    return max(1, math.ceil(abs(sweep) / max_step), math.ceil(min_by_turn))


def arc_points(
    center: tuple[float, float],
    radius: float,
    start: float,
    end: float,
    sagitta: float,
) -> NDArray[np.float64]:
    """Points (n + 1, 2) [m] on the arc from angle ``start`` to ``end`` [rad] (either direction), ends included."""
    n = arc_segments(radius, end - start, sagitta)
    phi = np.linspace(start, end, n + 1)
    return np.column_stack([center[0] + radius * np.cos(phi), center[1] + radius * np.sin(phi)])


def circle_points(center: tuple[float, float], radius: float, sagitta: float) -> NDArray[np.float64]:
    """Vertices (n, 2) [m] of a closed polygon inscribed in a circle, counter-clockwise, no repeat."""
    return arc_points(center, radius, 0.0, 2 * math.pi, sagitta)[:-1]
