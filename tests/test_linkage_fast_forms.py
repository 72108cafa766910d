"""The forms the linkage engine takes for speed give what the plain forms give.

- The crank's cosine and sine from one tangent of the half angle (t = tan(x / 2),
  cos = (1 - t^2) / (1 + t^2), sin = 2 t / (1 + t^2), the Weierstrass substitution) are within an
  ulp or two of numpy's, near 0, pi and large angles too.
- An RRR dyad hung from a point at rest (floats, no pass over zero rates) gives what it gives from
  the same point as arrays of zero rates; and its velocity and acceleration satisfy the constraints
  differentiated (C - A).(C' - A') = 0 and (C - A).(C'' - A'') + |C' - A'|^2 = 0, likewise for B.
- A link's point made from the dyad's vector C - A and a scale (no cos and sin arrays) is the point
  made from cos and sin.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkstress.kinematics.linkage import dyads
from linkstress.kinematics.linkage.placing import cos_sin
from linkstress.kinematics.linkage.tracks import Point, Track, through

RNG = np.random.default_rng(2029)


@pytest.mark.parametrize("angles", [
    RNG.uniform(-2 * math.pi, 4 * math.pi, 100_000),
    math.pi + RNG.uniform(-1e-7, 1e-7, 10_000),
    np.arange(-40, 41) * math.pi / 2,
    RNG.uniform(-1e4, 1e4, 10_000),
])
def test_cos_and_sin_from_the_half_angle_tangent_are_numpys_within_2_ulp(angles):
    c, s = cos_sin(angles)
    assert np.abs(c - np.cos(angles)).max() <= 4.5e-16
    assert np.abs(s - np.sin(angles)).max() <= 4.5e-16


def moving(n, scale=1.0):
    return Point(*(RNG.uniform(-scale, scale, n) for _ in range(6)))


@pytest.mark.parametrize("n", [1, 5, 300])
@pytest.mark.parametrize("rest", ["A", "B"])
def test_an_rrr_dyad_hung_from_a_point_at_rest_equals_the_same_point_with_zero_rates(n, rest):
    """A at about (0, 0), B at (0.3, 0.1), r1 = 0.25, r2 = 0.2: it closes (|r1 - r2| < |B - A| < r1 + r2)."""
    free = Point(*(RNG.uniform(-0.01, 0.01, n) for _ in range(2)), *(RNG.uniform(-1, 1, n) for _ in range(4)))
    fixed = Point.at_rest(np.array([0.3, 0.1]))
    zero = np.zeros(n)
    as_arrays = Point(np.full(n, 0.3), np.full(n, 0.1), zero, zero, zero, zero)
    pairs = ((free, fixed), (free, as_arrays)) if rest == "B" else ((fixed, free), (as_arrays, free))
    (a1, b1), (a2, b2) = pairs
    r1, r2 = (0.25, 0.2) if rest == "B" else (0.2, 0.25)
    short, long = dyads.rrr(a1, b1, r1, r2, -1.0), dyads.rrr(a2, b2, r1, r2, -1.0)
    for field in ("cax", "cay", "w1", "al1", "w2", "al2", "clearance", "det"):
        assert np.allclose(getattr(short, field), getattr(long, field), rtol=1e-14, atol=1e-15), field


@pytest.mark.parametrize("n", [1, 7, 500])
def test_an_rrr_dyads_rates_satisfy_its_constraints_differentiated(n):
    a = moving(n, 0.01)
    b = Point(0.3 + RNG.uniform(-0.01, 0.01, n), 0.1 + RNG.uniform(-0.01, 0.01, n), *(RNG.uniform(-1, 1, n) for _ in range(4)))
    s = dyads.rrr(a, b, 0.25, 0.2, 1.0)
    c = s.c()
    for p in (a, b):
        rx, ry = c.x - p.x, c.y - p.y
        vx, vy = c.x1 - p.x1, c.y1 - p.y1
        assert np.abs(rx * vx + ry * vy).max() < 1e-13
        assert np.abs(rx * (c.x2 - p.x2) + ry * (c.y2 - p.y2) + vx * vx + vy * vy).max() < 1e-12
    # C' = B' + w2 k x (C - B): the second link's rate is C's relative motion about B
    assert np.abs(c.x1 - (b.x1 - s.w2 * s.cby)).max() < 1e-13 and np.abs(c.y1 - (b.y1 + s.w2 * s.cbx)).max() < 1e-13


@pytest.mark.parametrize("local", [(0.2, 0.0), (0.05, -0.07), (-0.1, 0.03)])
def test_a_links_point_from_its_dyad_vector_is_the_point_from_cos_and_sin(local):
    """A link with joints 0 at (0, 0) and 1 at (0.2, 0) in its frame, joint 0 at A, joint 1 at
    A + 0.2 (cos t, sin t): its point ``local`` from the vector C - A and the scale 1 / 0.2^2 equals
    the one from cos t and sin t."""
    n = 200
    t = RNG.uniform(-math.pi, math.pi, n)
    a = moving(n)
    w, al = RNG.uniform(-3, 3, n), RNG.uniform(-9, 9, n)
    lengthwise = through(np.zeros(2), np.array([0.2, 0.0]), a, 0.2 * np.cos(t), 0.2 * np.sin(t), w, al)
    plain = Track(t, w, al, np.zeros(2), a, (np.cos(t), np.sin(t), 1.0))
    p, q = lengthwise.point(np.array(local)), plain.point(np.array(local))
    for field in ("x", "y", "x1", "y1", "x2", "y2"):
        assert np.abs(getattr(p, field) - getattr(q, field)).max() < 1e-14, field
    assert np.abs(np.angle(np.exp(1j * (lengthwise.angle - t)))).max() < 1e-15
