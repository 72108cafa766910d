"""The numpy neighbour search that small sketches use answers exactly as SciPy's k-d tree and sparse
graph components do on the same points: the same pairs, counts, distances, neighbours and component
numbers, also for points at the tolerance to the last bit and for ties of equal distance."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from linkstress.importers.neighbours import (
    BRUTE_FORCE_POINTS,
    components,
    count_pairs_within,
    nearest,
    pairs_within,
    within_of,
)


def tree_pairs(points, tolerance):
    pairs = cKDTree(points).query_pairs(tolerance, output_type="ndarray").reshape(-1, 2)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def boundary_points(tolerance: float) -> np.ndarray:
    """Pairs of points at the tolerance and a hair (2^-30 of it) either side, along each axis and
    diagonally (a 3-4-5 triangle), from integer origins: each pair's difference is exact."""
    rng = np.random.default_rng(7)
    points = []
    for _ in range(20):
        origin = rng.integers(-8, 8, 2).astype(float)
        for step in (np.array([tolerance, 0.0]), np.array([0.0, tolerance]), np.array([0.6, 0.8]) * tolerance):
            for scale in (1 - 2.0 ** -30, 1.0, 1 + 2.0 ** -30):
                points += [origin, origin + step * scale]
    return np.array(points)


def clouds():
    rng = np.random.default_rng(3)
    yield "random", rng.uniform(0, 10, (400, 2)), 0.3
    yield "clusters", np.repeat(rng.uniform(0, 10, (50, 2)), 4, axis=0) + rng.normal(0, 0.05, (200, 2)), 0.1
    yield "grid of ties", np.stack(np.meshgrid(np.arange(12.0), np.arange(12.0)), -1).reshape(-1, 2), 1.0
    yield "repeats", np.repeat(rng.uniform(0, 1, (30, 2)), 3, axis=0), 1e-9
    yield "at the tolerance", boundary_points(0.1), 0.1
    yield "at a tolerance of 0.5", boundary_points(0.5), 0.5
    columns = np.hstack([rng.uniform(0, 1, (300, 4)), np.repeat(rng.uniform(0, 1, (100, 2)), 3, axis=0)])
    yield "six columns", columns, 0.2


@pytest.mark.parametrize("name, points, tolerance", list(clouds()), ids=[c[0] for c in clouds()])
def test_pairs_and_their_count_are_the_k_d_trees(name, points, tolerance):
    expected = tree_pairs(points, tolerance)
    tree = cKDTree(points)
    assert np.array_equal(pairs_within(points, tolerance), expected)
    assert count_pairs_within(points, tolerance) == (tree.count_neighbors(tree, tolerance) - len(points)) // 2
    assert len(expected) > 0


def test_points_at_the_tolerance_pair_and_a_hair_beyond_do_not():
    points = boundary_points(0.5)  # 0.5 and its square are exact in binary: the boundary is sharp
    pairs = {tuple(p) for p in pairs_within(points, 0.5).tolist()}
    paired = [(k, k + 1) in pairs for k in range(0, len(points), 2)]
    # Per origin, along x then y: a hair short, at, a hair beyond the tolerance.
    along_axes = [paired[9 * k + j] for k in range(20) for j in range(6)]
    assert along_axes == [True, True, False] * 40


@pytest.mark.parametrize("name, points, tolerance", list(clouds())[:5], ids=[c[0] for c in clouds()][:5])
def test_nearest_points_are_the_k_d_trees_to_the_bit(name, points, tolerance):
    dist, near = cKDTree(points, balanced_tree=False, compact_nodes=False).query(points, k=3)
    mine_dist, mine_near = nearest(points, 3)
    assert np.array_equal(mine_dist, dist)
    # Equal distances may come in either order from the tree: the neighbours agree as sets per
    # distance, and exactly where the distances differ.
    assert np.array_equal(np.sort(mine_near, axis=1)[dist[:, 1] != dist[:, 2]],
                          np.sort(near, axis=1)[dist[:, 1] != dist[:, 2]])
    distinct = (np.diff(dist, axis=1) > 0).all(axis=1)
    assert np.array_equal(mine_near[distinct], near[distinct])


def test_the_points_within_reach_of_a_centre_are_the_trees_ball():
    points = boundary_points(0.5)
    tree = cKDTree(points)
    near_of = within_of(points, 0.5)
    for centre in points[::7]:
        assert near_of(centre) == sorted(tree.query_ball_point(centre, 0.5))


def test_components_are_numbered_as_scipy_numbers_them():
    rng = np.random.default_rng(11)
    for n, m in ((1, 0), (10, 0), (50, 30), (300, 250), (300, 600)):
        pairs = rng.integers(0, n, (m, 2))
        graph = coo_matrix((np.ones(m), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        count, label = connected_components(graph, directed=False)
        mine_count, mine_label = components(n, pairs)
        assert mine_count == count and np.array_equal(mine_label, label)


def test_a_long_chain_is_one_component():
    n = 2000
    order = np.random.default_rng(5).permutation(n)
    count, label = components(n, np.column_stack([order[:-1], order[1:]]))
    assert count == 1 and not label.any()


def test_past_the_brute_force_size_the_k_d_tree_answers_with_sorted_pairs():
    points = np.random.default_rng(9).uniform(0, 40, (BRUTE_FORCE_POINTS + 1, 2))
    pairs = pairs_within(points, 0.5)
    assert np.array_equal(pairs, tree_pairs(points, 0.5)) and len(pairs) > 100
    squared = ((points[:, None, :] - points[None, :, :]) ** 2).sum(axis=2)
    assert count_pairs_within(points, 0.5) == len(pairs) == int(np.triu(squared <= 0.25, 1).sum())
    assert np.array_equal(nearest(points, 2)[0][:, 1], np.sqrt(np.sort(squared, axis=1)[:, 1]))
