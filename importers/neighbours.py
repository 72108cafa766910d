"""Near neighbours among a sketch's points: pairs within a distance, nearest others, graph components.

A sketch of a few links has tens to hundreds of curve ends, and for so few a full distance matrix
in numpy answers at once, where importing SciPy's k-d tree and sparse graphs alone takes about
0.25 s of a command's start. Past ``BRUTE_FORCE_POINTS`` points the matrix (n^2 distances) would
cost more than the tree, and SciPy answers. Both give the same answers: a pair is within
``tolerance`` when its squared distance dx^2 + dy^2 is at most ``tolerance^2`` (the k-d tree's own
test), distances are sqrt(dx^2 + dy^2) evaluated in the same order, equal distances rank by index,
and pairs are listed sorted, i before j.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

BRUTE_FORCE_POINTS = 1500
"""Up to this many points the distance matrix (18 MB of float64 at 1500) is cheaper than the tree."""


def _squared(points: NDArray[np.float64], others: NDArray[np.float64]) -> NDArray[np.float64]:
    """Squared distances (n, m), summed over coordinates in order as the k-d tree sums them."""
    total = np.zeros((len(points), len(others)))
    for d in range(points.shape[1]):  # a loop over the 2 to 6 coordinates, not over points
        diff = points[:, d, None] - others[None, :, d]
        total += diff * diff
    return total


def pairs_within(points: NDArray[np.float64], tolerance: float) -> NDArray[np.intp]:
    """(M, 2) index pairs i < j of ``points`` (N, D) at most ``tolerance`` apart, sorted by i, then j."""
    points = np.asarray(points, float)
    if len(points) > BRUTE_FORCE_POINTS:
        from scipy.spatial import cKDTree  # a large drawing: the tree beats the matrix

        pairs = cKDTree(points).query_pairs(tolerance, output_type="ndarray").reshape(-1, 2)
        return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))].astype(np.intp)
    i, j = np.nonzero(np.triu(_squared(points, points) <= tolerance * tolerance, 1))
    return np.column_stack([i, j]).astype(np.intp)


def count_pairs_within(points: NDArray[np.float64], tolerance: float) -> int:
    """How many pairs i < j of ``points`` are at most ``tolerance`` apart, without listing them."""
    points = np.asarray(points, float)
    if len(points) > BRUTE_FORCE_POINTS:
        from scipy.spatial import cKDTree

        tree = cKDTree(points)
        return (int(tree.count_neighbors(tree, tolerance)) - len(points)) // 2
    near = _squared(points, points) <= tolerance * tolerance
    return (int(near.sum()) - int(np.trace(near))) // 2


def nearest(points: NDArray[np.float64], k: int) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """For each point, its ``k`` nearest points (itself among them, as the k-d tree's ``query``
    gives them): distances (n, k) ascending and their indices, equal distances by index."""
    points = np.asarray(points, float)
    n = len(points)
    if n > BRUTE_FORCE_POINTS:
        from scipy.spatial import cKDTree

        dist, near = cKDTree(points, balanced_tree=False, compact_nodes=False).query(points, k=k)
        return dist.reshape(n, k), near.reshape(n, k).astype(np.intp)
    squared = _squared(points, points)
    rows = np.arange(n)
    near = np.empty((n, k), np.intp)
    for column in range(k):  # k (at most 3) passes of argmin, which takes the lowest index of equals
        near[:, column] = np.argmin(squared, axis=1)
        squared[rows, near[:, column]] = np.inf
    return np.sqrt(_squared_to(points, near)), near


def _squared_to(points: NDArray[np.float64], near: NDArray[np.intp]) -> NDArray[np.float64]:
    """Squared distances (n, k) from each point to its points ``near``, summed as ``_squared`` sums."""
    total = np.zeros(near.shape)
    for d in range(points.shape[1]):
        diff = points[:, d, None] - points[near, d]
        total += diff * diff
    return total


def within_of(points: NDArray[np.float64], tolerance: float) -> Callable[[NDArray[np.float64]], list[int]]:
    """A function of a centre giving the indices of ``points`` at most ``tolerance`` from it, ascending."""
    points = np.asarray(points, float)
    if len(points) > BRUTE_FORCE_POINTS:
        from scipy.spatial import cKDTree

        tree = cKDTree(points)
        return lambda centre: sorted(tree.query_ball_point(centre, tolerance))
    return lambda centre: np.flatnonzero(
        _squared(np.asarray(centre, float).reshape(1, -1), points)[0] <= tolerance * tolerance).tolist()


def components(count: int, pairs: NDArray[np.intp]) -> tuple[int, NDArray[np.intp]]:
    """Connected components of the graph of ``count`` nodes and edges ``pairs`` (M, 2): how many,
    and each node's component, numbered in the order of each component's lowest node (as SciPy's
    ``connected_components`` numbers them)."""
    pairs = np.asarray(pairs, np.intp).reshape(-1, 2)
    i, j = pairs[:, 0], pairs[:, 1]
    root = np.arange(count)
    while True:
        # Hook each edge's larger root under its smaller one, then point every node at its root.
        # Roots only ever fall to a node of their own component, so at the fixed point (every edge
        # within one tree) each component's root is its lowest node; rounds grow as log(count).
        low = np.minimum(root[i], root[j])
        hooked = root.copy()
        np.minimum.at(hooked, root[i], low)
        np.minimum.at(hooked, root[j], low)
        while not np.array_equal(hooked[hooked], hooked):
            hooked = hooked[hooked]
        if np.array_equal(hooked, root):
            break
        root = hooked
    roots, numbered = np.unique(root, return_inverse=True)
    return len(roots), numbered.reshape(-1).astype(np.intp)
