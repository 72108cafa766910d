"""Chaining as an invariant: any simple outline cut into pieces, shuffled, some reversed and with
ends moved by less than the tolerance, chains back into the same outline."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

from linkstress.importers.contours import build_contours
from linkstress.importers.flatten import Tolerance, flatten
from linkstress.importers.primitives import CurveSet, Polyline


@settings(max_examples=60, deadline=None)
@given(
    radii=st.lists(st.floats(0.5, 2.0), min_size=5, max_size=40),
    cuts=st.integers(1, 12),
    seed=st.integers(0, 2**32 - 1),
    jitter=st.floats(0.0, 1e-5),
)
def test_a_cut_shuffled_outline_chains_back_into_itself(radii, cuts, seed, jitter):
    rng = np.random.default_rng(seed)
    # A star-shaped ring (simple: one radius per angle), in a drawing of size about 4 + 2 x 3 = 10.
    phi = 2 * math.pi * np.arange(len(radii)) / len(radii)
    ring = np.column_stack([3 + np.array(radii) * np.cos(phi), -1 + np.array(radii) * np.sin(phi)])
    # Cut at some vertices: rotate the ring to start at the first cut, then split at the others.
    at = np.sort(rng.choice(len(ring), size=min(cuts, len(ring)), replace=False))
    closed = np.roll(ring, -at[0], axis=0)
    closed = np.vstack([closed, closed[:1]])
    bounds = np.append(at - at[0], len(ring))
    pieces = [closed[a:b + 1] for a, b in zip(bounds[:-1], bounds[1:])]
    curves = CurveSet()
    for k in rng.permutation(len(pieces)):
        xy = pieces[k] + rng.uniform(-jitter, jitter, pieces[k].shape)
        xy = xy[::-1] if rng.random() < 0.5 else xy
        curves.add_polyline(Polyline(xy, np.zeros(len(xy)), False), ("LWPOLYLINE", str(k), "0", None))
    bounds = curves.bounds()
    size = math.hypot(bounds[2] - bounds[0], bounds[3] - bounds[1])
    contours = build_contours(flatten(curves, Tolerance.for_size(size)), curves.curve_origins(), 1e-4 * size, size, "m")
    (outline,) = contours.outlines
    exact = Polygon(ring)
    # Moving each vertex by at most jitter x sqrt(2) changes the area by at most perimeter x that.
    assert abs(outline.polygon.area - exact.area) <= exact.length * 2 * jitter + 1e-12
    assert outline.largest_gap[0] <= 2 * math.sqrt(2) * jitter + 1e-15
