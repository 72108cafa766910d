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
    """Angle (F,) [rad] of the member frame's +x and origin (F, 2) [m], with their derivatives
    ``angle1``, ``origin1`` (per unit input) and ``angle2``, ``origin2`` (per unit input squared)."""

    angle: FloatArray
    origin: FloatArray
    angle1: FloatArray
    origin1: FloatArray
    angle2: FloatArray
    origin2: FloatArray

    @classmethod
    def fixed(cls, angle: float, origin: FloatArray, n: int) -> Track:
        """A link that does not move, over ``n`` positions."""
        zero, zero2 = np.zeros(n), np.zeros((n, 2))
        return cls(np.full(n, float(angle)), np.broadcast_to(np.asarray(origin, float), (n, 2)).copy(),
                   zero, zero2, zero, zero2)

    @classmethod
    def empty(cls, n: int) -> Track:
        """Not yet solved: nan everywhere."""
        nan, nan2 = np.full(n, np.nan), np.full((n, 2), np.nan)
        return cls(nan.copy(), nan2.copy(), nan.copy(), nan2.copy(), nan.copy(), nan2.copy())

    def arm(self, local: FloatArray, rows=slice(None)) -> FloatArray:
        """R(angle) local: the point ``local`` (2,) [m] relative to the origin, ground axes (F, 2)."""
        c, s = np.cos(self.angle[rows]), np.sin(self.angle[rows])
        return np.column_stack([c * local[0] - s * local[1], s * local[0] + c * local[1]])

    def position(self, local: FloatArray, rows=slice(None)) -> FloatArray:
        """The material point ``local`` (2,) [m, member frame] in the ground frame (F, 2)."""
        return self.origin[rows] + self.arm(local, rows)

    def point(self, local: FloatArray, rows=slice(None)) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position, first and second derivatives (F, 2) of the material point ``local`` (2,):
        p = O + r, p' = O' + theta' k x r, p'' = O'' + theta'' k x r - theta'^2 r."""
        r = self.arm(local, rows)
        w, al = self.angle1[rows][:, None], self.angle2[rows][:, None]
        kr = np.column_stack([-r[:, 1], r[:, 0]])
        return self.origin[rows] + r, self.origin1[rows] + w * kr, self.origin2[rows] + al * kr - w * w * r

    def set_rates_about(self, rows, pivot: FloatArray, pivot1: FloatArray, pivot2: FloatArray) -> None:
        """The origin's derivatives at ``rows`` from a point ``pivot`` (F, 2) of the link with its
        derivatives, and the angle's derivatives already set: O' = p' + theta' k x (O - p)."""
        r = self.origin[rows] - pivot
        w, al = self.angle1[rows][:, None], self.angle2[rows][:, None]
        kr = np.column_stack([-r[:, 1], r[:, 0]])
        self.origin1[rows] = pivot1 + w * kr
        self.origin2[rows] = pivot2 + al * kr - w * w * r
