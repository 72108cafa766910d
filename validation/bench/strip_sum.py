"""The seed program's (KSAM) strip-sum mass properties, kept as the baseline that benchmarks beat.

A faithful port of ``Link.centroid`` from the KSAM thesis (annex 12.3): midpoint strips of width dx
between the bounding functions U(x) and L(x) for area and centroid, and a dx-by-dx grid walked in
Python loops for the polar moment. Holes are invisible to it (U and L only). Deliberately not
vectorised: its cost is what is being measured.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class StripSumProperties:
    """Area [m^2], centroid [m], polar moment of area about the centroid [m^4], per unit thickness."""

    area: float
    centroid: tuple[float, float]
    polar: float


def strip_sum_properties(
    upper: Callable[[float], float],
    lower: Callable[[float], float],
    start: float,
    end: float,
    dx: float,
) -> StripSumProperties:
    """Area properties of the region between ``lower`` and ``upper`` on [start, end] by KSAM's strip sums."""
    area = 0.0
    x_moment = 0.0
    y_moment = 0.0
    position = start + dx / 2
    while position < end:
        high, low = upper(position), lower(position)
        strip = dx * (high - low)
        area += strip
        x_moment += position * strip
        y_moment += ((high - low) / 2 + low) * strip
        position += dx
    xo, yo = x_moment / area, y_moment / area
    polar = 0.0
    darea = dx * dx
    position = start + dx / 2
    while position < end:
        high, low = upper(position), lower(position)
        along = (position - xo) * (position - xo)
        height = low + dx / 2
        while height < high:
            polar += darea * (along + (height - yo) * (height - yo))
            height += dx
        position += dx
    return StripSumProperties(area, (xo, yo), polar)
