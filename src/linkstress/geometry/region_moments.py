"""Area moments of the part of a link to the left of each station, exactly.

The free body of a beam section needs the d'Alembert load on everything left of the cut, which is
linear in the region's area moments: A, S_x = int x dA, S_y = int y dA and J_O = int (x^2 + y^2) dA
(member frame, about the frame origin). By Green's theorem each is a line integral of f dx round
the region's boundary,

    A = -oint y dx,  S_x = -oint x y dx,  S_y = -oint y^2 / 2 dx,  J_O = -oint (x^2 y + y^3 / 3) dx,

and the cut itself is vertical (dx = 0), so it adds nothing: the region left of x takes every
boundary edge that ends left of x whole, and of each edge the cut crosses the part left of x. On a
straight edge every integrand is a cubic in the edge parameter, so Simpson's rule is exact.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Polygon

from linkstress.geometry.boundary import Boundary, boundary_of, segment_moments
from linkstress.geometry.sections import Crossings, edge_crossings, within_extent


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


def region_moments(
    outline: Polygon | Boundary, stations: ArrayLike, crossings: Crossings | None = None
) -> RegionMoments:
    """Moments of the part of ``outline`` (member frame, m; or its Boundary) left of each of
    ``stations`` [m]. ``crossings``: the edges' crossings with the sorted stations by
    ``edge_crossings`` (right-hand limit), if already made (the stations then are those of a section
    table, checked against the extent already)."""
    x = np.asarray(stations, float).ravel()
    edges = boundary_of(outline)
    if crossings is None:
        x = within_extent(x, edges.x_min, edges.x_max, "station")
    order = np.argsort(x, kind="stable")
    starts, ends = edges.starts, edges.ends
    whole = edges.moments
    # Edges wholly left of a station (right end at or before it), by their right ends.
    right = np.maximum(starts[:, 0], ends[:, 0])
    by_right = np.argsort(right)
    cumulative = np.zeros((4, len(right) + 1))
    np.cumsum(whole[:, by_right], axis=1, out=cumulative[:, 1:])
    left_of = cumulative[:, np.searchsorted(right[by_right], x, side="right")]
    # Edges the cut crosses (left end <= x < right end): the part from the crossing to the left end.
    cut = edge_crossings(starts, ends, x[order], sort=False) if crossings is None else crossings
    e = cut.edge
    point = np.column_stack([x[order][cut.station], cut.y])
    rightward = starts[e, 0] < ends[e, 0]
    part = segment_moments(
        np.where(rightward[:, None], starts[e], point), np.where(rightward[:, None], point, ends[e])
    )
    np.add.at(left_of, (slice(None), order[cut.station]), part)
    area, first_x, first_y, polar = left_of
    return RegionMoments(x, area, first_x, first_y, polar, tuple(float(v) for v in whole.sum(axis=1)))
