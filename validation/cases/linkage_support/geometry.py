"""Positions step by step, for the cases' independent truths: circle-circle and circle-line
intersections and rigid placement, vectorised over positions (arrays (P, 2) in metres).

The formulas are the dyad closed forms of Uicker, Pennock & Shigley, Theory of Machines and
Mechanisms, ch. 4 (and Norton, Design of Machinery, sec. 4.5): a point P at distance a from A and b
from B lies at P = A + x e + s h e_perp with d = |B - A|, x = (a^2 - b^2 + d^2) / (2 d),
h = sqrt(a^2 - x^2), e = (B - A) / d and e_perp = e turned +90 deg; on a line Q + t u at distance r
from A, t solves t^2 + 2 t u.(Q - A) + |Q - A|^2 - r^2 = 0.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


class AssemblyError(ValueError):
    """A step that cannot close: the circles (or the circle and the line) do not meet."""


def circle_circle(a: ArrayLike, ra: ArrayLike, b: ArrayLike, rb: ArrayLike, side: int) -> FloatArray:
    """The point at ``ra`` from ``a`` and ``rb`` from ``b`` (points (P, 2) or (2,), radii scalars or
    (P,)) on the ``side`` of a -> b: +1 left, -1 right."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    ra, rb = np.asarray(ra, float), np.asarray(rb, float)
    d = b - a
    length = np.hypot(d[..., 0], d[..., 1])
    x = (ra**2 - rb**2 + length**2) / (2 * length)
    h2 = ra**2 - x**2
    if np.any(h2 < 0):
        raise AssemblyError(f"two circles (radii up to {np.max(ra):g} and {np.max(rb):g} m) do not meet at "
                            f"{int(np.sum(h2 < 0))} positions")
    e = d / length[..., None]
    e_perp = np.stack([-e[..., 1], e[..., 0]], axis=-1)
    return a + x[..., None] * e + side * np.sqrt(h2)[..., None] * e_perp


def circle_line(a: ArrayLike, r: float, q: ArrayLike, u: ArrayLike, root: int) -> FloatArray:
    """The point at ``r`` from ``a`` on the line through ``q`` along the unit ``u``: ``root`` +1
    the one further along u, -1 the one behind."""
    a, q, u = (np.asarray(v, float) for v in (a, q, u))
    w = q - a
    half_b = np.sum(u * w, axis=-1)
    c = np.sum(w * w, axis=-1) - r**2
    disc = half_b**2 - c
    if np.any(disc < 0):
        raise AssemblyError(f"a circle of radius {r} misses its line at {int(np.sum(disc < 0))} positions")
    t = -half_b + root * np.sqrt(disc)
    return q + t[..., None] * u


def placed(p: ArrayLike, q: ArrayLike, along: float, across: float) -> FloatArray:
    """The point of a rigid link at ``along`` the direction p -> q from p and ``across`` to its
    left (each (P, 2) or (2,); any length units, the direction made unit here)."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    d = q - p
    e = d / np.hypot(d[..., 0], d[..., 1])[..., None]
    return p + along * e + across * np.stack([-e[..., 1], e[..., 0]], axis=-1)


def local_coordinates(p: ArrayLike, q: ArrayLike, point: ArrayLike) -> tuple[float, float]:
    """(along, across): ``point`` in the frame of p -> q (origin p), the inverse of ``placed``."""
    p, q, point = (np.asarray(v, float) for v in (p, q, point))
    e = (q - p) / np.hypot(*(q - p))
    w = point - p
    return float(w @ e), float(w @ np.array([-e[1], e[0]]))


def unit(angle: ArrayLike) -> FloatArray:
    """(cos, sin) of ``angle`` [rad], shape (..., 2)."""
    angle = np.asarray(angle, float)
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def distance(p: ArrayLike, q: ArrayLike) -> FloatArray:
    """|q - p| over the last axis."""
    d = np.asarray(q, float) - np.asarray(p, float)
    return np.hypot(d[..., 0], d[..., 1])
