"""A link's pose along the input path, with its first and second derivatives with respect to the input.

The engine solves positions and rates per unit input (x: the input angle [rad] or stroke [m]):
q, dq/dx, d2q/dx2. The time rates follow by the chain rule, qdot = q' xdot and
qddot = q'' xdot^2 + q' xddot, so that one solve serves any speed and acceleration of the input.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass
class Track:
    """Angle (F,) [rad] of the member frame's +x, its cosine and sine (F,), and origin (F, 2) [m],
    with their derivatives ``angle1``, ``origin1`` (per unit input) and ``angle2``, ``origin2`` (per
    unit input squared)."""

    angle: FloatArray
    origin: FloatArray
    angle1: FloatArray
    origin1: FloatArray
    angle2: FloatArray
    origin2: FloatArray
    cos: FloatArray
    sin: FloatArray

    @classmethod
    def fixed(cls, angle: float, origin: FloatArray, n: int) -> Track:
        """A link that does not move, over ``n`` positions (read-only views of one value each)."""
        zero, zero2 = np.broadcast_to(0.0, (n,)), np.broadcast_to(0.0, (n, 2))
        return cls(np.broadcast_to(float(angle), (n,)), np.broadcast_to(np.asarray(origin, float), (n, 2)),
                   zero, zero2, zero, zero2, np.broadcast_to(np.cos(angle), (n,)), np.broadcast_to(np.sin(angle), (n,)))

    @classmethod
    def empty(cls, n: int) -> Track:
        """Not yet solved: every entry is written before it is read (a group fills all its rows)."""
        return cls(np.empty(n), np.empty((n, 2)), np.empty(n), np.empty((n, 2)), np.empty(n), np.empty((n, 2)),
                   np.empty(n), np.empty(n))

    def set_angle(self, rows, angle: FloatArray, cos: FloatArray | None = None, sin: FloatArray | None = None) -> None:
        """The angle at ``rows``, with its cosine and sine (computed when not given)."""
        self.angle[rows] = angle
        self.cos[rows] = np.cos(angle) if cos is None else cos
        self.sin[rows] = np.sin(angle) if sin is None else sin

    def arm(self, local: FloatArray, rows=slice(None)) -> FloatArray:
        """R(angle) local: the point ``local`` (2,) [m] relative to the origin, ground axes (F, 2)."""
        c, s = self.cos[rows], self.sin[rows]
        out = np.empty((len(c), 2))
        out[:, 0] = c * local[0] - s * local[1]
        out[:, 1] = s * local[0] + c * local[1]
        return out

    def position(self, local: FloatArray, rows=slice(None)) -> FloatArray:
        """The material point ``local`` (2,) [m, member frame] in the ground frame (F, 2)."""
        return self.origin[rows] + self.arm(local, rows)

    def point(self, local: FloatArray, rows=slice(None)) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position, first and second derivatives (F, 2) of the material point ``local`` (2,):
        p = O + r, p' = O' + theta' k x r, p'' = O'' + theta'' k x r - theta'^2 r."""
        r = self.arm(local, rows)
        w, al = self.angle1[rows], self.angle2[rows]
        p, p1, p2 = self.origin[rows] + r, self.origin1[rows].copy(), self.origin2[rows].copy()
        ww = w * w
        p1[:, 0] -= w * r[:, 1]
        p1[:, 1] += w * r[:, 0]
        p2[:, 0] -= al * r[:, 1] + ww * r[:, 0]
        p2[:, 1] += al * r[:, 0] - ww * r[:, 1]
        return p, p1, p2

    def set_rates_about(self, rows, pivot: FloatArray, pivot1: FloatArray, pivot2: FloatArray) -> None:
        """The origin's derivatives at ``rows`` from a point ``pivot`` (F, 2) of the link with its
        derivatives, and the angle's derivatives already set: O' = p' + theta' k x (O - p)."""
        r = self.origin[rows] - pivot
        w, al = self.angle1[rows], self.angle2[rows]
        ww = w * w
        o1, o2 = self.origin1[rows], self.origin2[rows]
        o1[:, 0] = pivot1[:, 0] - w * r[:, 1]
        o1[:, 1] = pivot1[:, 1] + w * r[:, 0]
        o2[:, 0] = pivot2[:, 0] - al * r[:, 1] - ww * r[:, 0]
        o2[:, 1] = pivot2[:, 1] + al * r[:, 0] - ww * r[:, 1]
