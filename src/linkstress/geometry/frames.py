"""Member frames: origin at a link's first joint, +x toward its second."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray


@dataclass(frozen=True)
class MemberFrame:
    """A rigid 2D frame.

    origin [m] in the sketch (or ground) frame; angle [rad] of the frame's +x axis, counter-clockwise
    from the sketch frame's +x.
    """

    origin: tuple[float, float]
    angle: float

    @classmethod
    def through(cls, first: ArrayLike, second: ArrayLike) -> "MemberFrame":
        """The frame with origin at ``first`` and +x toward ``second`` (points [m])."""
        p, q = np.asarray(first, float), np.asarray(second, float)
        d = q - p
        if not np.hypot(*d) > 0:
            raise ValueError(f"member frame needs two distinct joints, got {p.tolist()} twice")
        return cls((float(p[0]), float(p[1])), float(np.arctan2(d[1], d[0])))

    @property
    def rotation(self) -> NDArray[np.float64]:
        """2x2 matrix whose columns are the frame's unit axes in the outer frame."""
        c, s = np.cos(self.angle), np.sin(self.angle)
        return np.array([[c, -s], [s, c]])

    def to_local(self, points: ArrayLike) -> NDArray[np.float64]:
        """Points (..., 2) [m] from the outer frame into this frame."""
        return (np.asarray(points, float) - self.origin) @ self.rotation

    def to_global(self, points: ArrayLike) -> NDArray[np.float64]:
        """Points (..., 2) [m] from this frame into the outer frame."""
        return np.asarray(points, float) @ self.rotation.T + self.origin

    def vector_to_local(self, vectors: ArrayLike) -> NDArray[np.float64]:
        """Free vectors (forces, accelerations) (..., 2) into this frame's axes."""
        return np.asarray(vectors, float) @ self.rotation

    def vector_to_global(self, vectors: ArrayLike) -> NDArray[np.float64]:
        """Free vectors (..., 2) from this frame's axes into the outer frame's."""
        return np.asarray(vectors, float) @ self.rotation.T
