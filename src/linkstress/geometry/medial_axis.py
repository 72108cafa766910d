"""The path along a link's material from one joint to another: its medial axis.

The medial axis of a plate (holes filled) is the locus of the centres of the largest circles that fit
in it: along a bar of any shape it is the bar's midline, through a round boss around a pin it runs
straight to the pin's centre, and round a bend it follows the bend. It is approximated by the edges
of the Voronoi diagram of points spaced evenly along the outline that lie wholly inside the
outline (the error falls as the square of the spacing: under 0.1 % of the length with a tenth of
the bar's width); its side branches (to the corners of a square end, the outer corner of a
dog-leg) are dead ends, so the shortest path along it between two joints is the path along the
material. Everything is in the caller's frame [m].
"""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon

MERGE = 1e-9
"""Fraction of the sample spacing within which two Voronoi vertices are one node."""

JOIN_REACH = 2.0
"""Sample spacings beyond its nearest vertex of the axis within which a joint joins the axis."""


def medial_path(
    shell: Polygon, a: NDArray[np.float64], b: NDArray[np.float64], spacing: float,
) -> NDArray[np.float64] | None:
    """The shortest path (K, 2) [m] from ``a`` to ``b`` along the medial axis of ``shell`` (a polygon
    without holes), sampled every ``spacing`` [m] along its boundary; None when the axis does not
    join them. Each joint joins the axis at its vertices nearest to it (within ``JOIN_REACH`` samples
    of the nearest): a pin at the centre of a round boss or a bar's round end is where the axis
    ends."""
    # scipy's graphs only for curved members: an analysis of straight links never loads it
    from scipy.sparse import coo_array
    from scipy.sparse.csgraph import dijkstra

    ring = shell.exterior
    samples = shapely.line_interpolate_point(ring, np.arange(0.0, ring.length, spacing))
    edges = shapely.get_parts(shapely.voronoi_polygons(shapely.multipoints(samples), only_edges=True))
    shapely.prepare(shell)
    ends = shapely.get_coordinates(edges[shapely.contains_properly(shell, edges)]).reshape(-1, 2, 2)
    if not len(ends):
        return None
    node, first = _nodes(np.round(ends.reshape(-1, 2) / (MERGE * spacing)).astype(np.int64))
    points = ends.reshape(-1, 2)[first]
    count = len(points)
    rows, cols = [node[0::2]], [node[1::2]]
    weights = [np.hypot(*(ends[:, 1] - ends[:, 0]).T)]
    for k, joint in enumerate((a, b)):
        gap = np.hypot(*(points - joint).T)
        near = np.flatnonzero(gap <= float(gap.min()) + JOIN_REACH * spacing)
        rows.append(np.full(len(near), count + k))
        cols.append(near)
        weights.append(np.maximum(gap[near], MERGE * spacing))  # a zero weight would be no edge
    graph = coo_array(
        (np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))), shape=(count + 2, count + 2),
    ).tocsr()
    distance, previous = dijkstra(graph, directed=False, indices=count, return_predecessors=True)
    if not np.isfinite(distance[count + 1]):
        return None
    order = [count + 1]
    while order[-1] != count:
        order.append(int(previous[order[-1]]))
    return np.vstack([points, a, b])[order[::-1]]


def _nodes(keys: NDArray[np.int64]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """For integer points ``keys`` (K, 2): each one's node (K,), equal points one node, and each
    node's first point; as ``np.unique(keys, axis=0, return_index=True, return_inverse=True)``
    gives them, which imports numpy.ma."""
    order = np.lexsort((keys[:, 1], keys[:, 0]))
    ordered = keys[order]
    new = np.r_[True, (ordered[1:] != ordered[:-1]).any(axis=1)]
    node = np.empty(len(keys), dtype=np.intp)
    node[order] = np.cumsum(new) - 1
    return node, order[new]
