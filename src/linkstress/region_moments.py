"""Area moments of the part of a link to the left of each station, exactly.

The free body of a beam section needs the d'Alembert load on everything left of the cut, which is
linear in the region's area moments: A, S_x = int x dA, S_y = int y dA and J_O = int (x^2 + y^2) dA
(member frame, about the frame origin). With chords [a_k, b_k] of the cut at abscissa xi, the
integrands over xi are

    m0 = sum (b - a),  xi m0,  m1 = sum (b^2 - a^2) / 2,  xi^2 m0 + m2,  m2 = sum (b^3 - a^3) / 3,

and a and b are linear in xi between consecutive vertex abscissae, so every integrand is a
polynomial of degree <= 3 there and Simpson's rule on each piece is exact.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Polygon

from linkstress.boundary import Boundary, boundary_of
from linkstress.sections import edge_crossings, within_extent


@dataclass(frozen=True)
class RegionMoments:
    """Moments [m^2, m^3, m^3, m^4] of the region x' <= x at each station x [m], per unit thickness.

    ``area``, ``first_x`` (int x dA), ``first_y`` (int y dA), ``polar`` (int x^2 + y^2 dA, about the
    member-frame origin). ``total`` holds the same four for the whole outline.
    """

    x: NDArray[np.float64]
    area: NDArray[np.float64]
    first_x: NDArray[np.float64]
    first_y: NDArray[np.float64]
    polar: NDArray[np.float64]
    total: tuple[float, float, float, float]


def _cut_moments(starts, ends, xs, left_limit: bool) -> NDArray[np.float64]:
    """(len(xs), 3): m0, m1, m2 of the cuts at sorted abscissae ``xs``."""
    cut = edge_crossings(starts, ends, xs, left_limit=left_limit)
    a, b = cut.y[0::2], cut.y[1::2]
    station = cut.station[0::2]
    out = np.zeros((len(xs), 3))
    np.add.at(out[:, 0], station, b - a)
    np.add.at(out[:, 1], station, (b * b - a * a) / 2)
    np.add.at(out[:, 2], station, (b**3 - a**3) / 3)
    return out


def region_moments(outline: Polygon | Boundary, stations: ArrayLike) -> RegionMoments:
    """Moments of the part of ``outline`` (member frame, m; or its Boundary) left of each of
    ``stations`` [m]."""
    x = np.asarray(stations, float).ravel()
    edges = boundary_of(outline)
    starts, ends = edges.starts, edges.ends
    lo, hi = edges.x_min, edges.x_max
    x = within_extent(x, lo, hi, "station")
    nodes = np.unique(np.concatenate([starts[:, 0], x]))
    left, right = nodes[:-1], nodes[1:]
    width = right - left
    mid = (left + right) / 2
    # Left ends and midpoints interleave in sorted order: one sweep of the edges cuts both.
    both = _cut_moments(starts, ends, np.column_stack([left, mid]).ravel(), left_limit=False)
    at_left, at_mid = both[0::2], both[1::2]
    at_right = _cut_moments(starts, ends, right, left_limit=True)

    def simpson(f_left, f_mid, f_right):
        return width * (f_left + 4 * f_mid + f_right) / 6

    pieces = np.column_stack([
        simpson(at_left[:, 0], at_mid[:, 0], at_right[:, 0]),
        simpson(left * at_left[:, 0], mid * at_mid[:, 0], right * at_right[:, 0]),
        simpson(at_left[:, 1], at_mid[:, 1], at_right[:, 1]),
        simpson(left**2 * at_left[:, 0] + at_left[:, 2], mid**2 * at_mid[:, 0] + at_mid[:, 2],
                right**2 * at_right[:, 0] + at_right[:, 2]),
    ])
    cumulative = np.vstack([np.zeros(4), np.cumsum(pieces, axis=0)])
    at_station = cumulative[np.searchsorted(nodes, x)]
    return RegionMoments(
        x=x,
        area=at_station[:, 0],
        first_x=at_station[:, 1],
        first_y=at_station[:, 2],
        polar=at_station[:, 3],
        total=tuple(float(v) for v in cumulative[-1]),
    )
