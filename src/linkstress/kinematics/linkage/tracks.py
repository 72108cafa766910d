"""A point's and a link's motion over a block of path positions, x and y apart, and the whole
path's store of link poses for the groups solved by Newton.

Rates are per unit of whatever drives the input: time, when the crank is seeded with the input's
speed and acceleration (q' = dq/dt, q'' = d2q/dt2), or the input itself, when seeded with 1 and 0
(q' = dq/dx, q'' = d2q/dx2, what a Newton group's continuation needs). The equations of every
group are the same either way (they are its constraints differentiated once and twice along the
path), and the chain rule links the two: qdot = q' xdot, qddot = q'' xdot^2 + q' xddot.

x and y are kept in separate contiguous arrays: a (B, 2) array's columns are strided, and every
pass over a strided column copies it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
Values = FloatArray | float
"""(B,) over a block, or a float where the quantity is the same at every position."""


@dataclass(frozen=True)
class Point:
    """A point's position (x, y) [m] and its first (x1, y1) and second (x2, y2) derivatives, ground
    frame. ``fixed``: a point of the ground (floats, zero derivatives)."""

    x: Values
    y: Values
    x1: Values
    y1: Values
    x2: Values
    y2: Values
    fixed: bool = False

    @classmethod
    def at_rest(cls, p: FloatArray) -> Point:
        return cls(float(p[0]), float(p[1]), 0.0, 0.0, 0.0, 0.0, True)


class Track:
    """A link's pose over a block: the angle [rad] of its member frame's +x, its angular rate ``w``
    and acceleration ``al``; one of its points, ``anchor``, at ``local`` (2,) [m, member frame],
    with that point's motion; and its rotation, cos = k ux and sin = k uy with ``turn`` = (ux, uy,
    k) (k a float: ux, uy are often a vector along the link, at hand, of length 1 / k).
    ``fixed``: the ground."""

    __slots__ = ("angle", "w", "al", "local", "anchor", "fixed", "turn", "_cos_sin")

    def __init__(self, angle: Values, w: Values, al: Values, local: FloatArray, anchor: Point,
                 turn: tuple[Values, Values, float], fixed: bool = False) -> None:
        self.angle, self.w, self.al, self.local, self.anchor, self.fixed = angle, w, al, local, anchor, fixed
        self.turn = turn
        self._cos_sin = None

    @classmethod
    def ground(cls, angle: float, origin: FloatArray) -> Track:
        return cls(angle, 0.0, 0.0, np.zeros(2), Point.at_rest(origin), (math.cos(angle), math.sin(angle), 1.0), True)

    @property
    def cos(self) -> Values:
        return self._rotation()[0]

    @property
    def sin(self) -> Values:
        return self._rotation()[1]

    def _rotation(self) -> tuple[Values, Values]:
        if self._cos_sin is None:
            ux, uy, k = self.turn
            self._cos_sin = (ux, uy) if k == 1.0 else (ux * k, uy * k)
        return self._cos_sin

    def point(self, local: FloatArray) -> Point:
        """The material point ``local`` (2,) [m, member frame]: p = a + r, r = R(local - anchor's),
        p' = a' + w k x r, p'' = a'' + al k x r - w^2 r (rigid-body kinematics)."""
        lx, ly = float(local[0] - self.local[0]), float(local[1] - self.local[1])
        if lx == 0.0 and ly == 0.0:
            return self.anchor
        (ux, uy, k), a = self.turn, self.anchor
        lx, ly = lx * k, ly * k
        rx, ry = (ux * lx, uy * lx) if ly == 0.0 else (ux * lx - uy * ly, uy * lx + ux * ly)
        if self.fixed:
            return Point(a.x + rx, a.y + ry, 0.0, 0.0, 0.0, 0.0, True)
        w, al = self.w, self.al
        ww = w * w
        return Point(a.x + rx, a.y + ry, a.x1 - w * ry, plus(a.y1, w * rx),
                     a.x2 - (al * ry + ww * rx), plus(a.y2, al * rx - ww * ry))


def plus(a: Values, b: Values) -> Values:
    """a + b, without a pass over the arrays where a is a float 0 (a point at rest)."""
    return b if isinstance(a, float) and a == 0.0 else a + b


def through(local_a: FloatArray, local_c: FloatArray, a: Point, cax: FloatArray, cay: FloatArray,
            w: Values, al: Values) -> Track:
    """The track of a link whose point ``local_a`` is at A and ``local_c`` at C = A + (cax, cay),
    turning at ``w``, ``al``: the rotation R taking l = local_c - local_a onto C - A is
    cos = l.(C - A) / |l|^2, sin = l x (C - A) / |l|^2 (|C - A| = |l|: the link is rigid). Where l
    runs along the frame's +x (a link's joints 0 -> 1), cos and sin are C - A over |l|, and the
    angle is C - A's own."""
    lx, ly = local_c - local_a
    scale = 1.0 / (lx * lx + ly * ly)
    p, q = lx * scale, ly * scale
    if q == 0.0 and p > 0.0:
        return Track(np.arctan2(cay, cax), w, al, local_a, a, (cax, cay, p))
    cos, sin = cax * p + cay * q, cay * p - cax * q
    return Track(np.arctan2(sin, cos), w, al, local_a, a, (cos, sin, 1.0))


class PathTracks:
    """Every link's pose over the whole path, for the groups that are solved along it by Newton:
    each moving link's angle, cos, sin, w, al (F,) and its origin's motion x, y, x1, y1, x2, y2
    (F,), rates per unit input; the ground's as constants. Every entry is written before it is read
    (a group writes all positions of its links: nan where it cannot close)."""

    FIELDS = ("angle", "cos", "sin", "w", "al", "x", "y", "x1", "y1", "x2", "y2")

    def __init__(self, moving: tuple[str, ...], ground: str, ground_angle: float, ground_origin: FloatArray,
                 n: int) -> None:
        self.arrays = {name: {f: np.empty(n) for f in self.FIELDS} for name in moving}
        self.ground, self.ground_track = ground, Track.ground(ground_angle, ground_origin)

    def window(self, name: str, rows) -> Track:
        """Link ``name``'s track at path positions ``rows`` (its anchor is its origin)."""
        if name == self.ground:
            return self.ground_track
        a = self.arrays[name]
        origin = Point(*(a[f][rows] for f in ("x", "y", "x1", "y1", "x2", "y2")))
        return Track(a["angle"][rows], a["w"][rows], a["al"][rows], np.zeros(2), origin,
                     (a["cos"][rows], a["sin"][rows], 1.0))

    def store(self, name: str, rows, track: Track, origin: Point) -> None:
        """Write link ``name``'s ``track`` with its ``origin`` at path positions ``rows``."""
        a = self.arrays[name]
        for f, value in (("angle", track.angle), ("cos", track.cos), ("sin", track.sin), ("w", track.w),
                         ("al", track.al), ("x", origin.x), ("y", origin.y), ("x1", origin.x1), ("y1", origin.y1),
                         ("x2", origin.x2), ("y2", origin.y2)):
            a[f][rows] = value

    def angle(self, name: str, rows, order: int = 0) -> FloatArray:
        """The link's angle (order 0) or its derivative (1, 2) at ``rows`` (B,)."""
        if name == self.ground:
            value = self.ground_track.angle if order == 0 else 0.0
            return np.full(_count(rows), value)
        return self.arrays[name][("angle", "w", "al")[order]][rows]

    def origin(self, name: str, rows, order: int = 0) -> FloatArray:
        """The origin's position (order 0) or its derivative (1, 2) at ``rows`` (B, 2)."""
        if name == self.ground:
            a = self.ground_track.anchor
            value = (a.x, a.y) if order == 0 else (0.0, 0.0)
            return np.tile(np.asarray(value, float), (_count(rows), 1))
        a = self.arrays[name]
        suffix = ("", "1", "2")[order]
        return np.column_stack([a["x" + suffix][rows], a["y" + suffix][rows]])


def _count(rows) -> int:
    """How many positions an index array or mask ``rows`` picks."""
    rows = np.asarray(rows)
    return int(rows.sum()) if rows.dtype == bool else rows.size
