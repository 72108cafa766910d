"""The boundary of an outline as arrays of straight edges: what every cut through a link walks.

Exterior counter-clockwise, holes clockwise, so that the material is on the left of every edge.
Moving an outline into a member frame leaves drawn vertical edges off by rounding; such edges are
snapped back to vertical (``rounding_slack``), or the section at that end would shrink to a point.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient


@dataclass(frozen=True)
class Boundary:
    """Edges from ``starts`` to ``ends`` (E, 2) [m]; each ring's edges are consecutive."""

    starts: NDArray[np.float64]
    ends: NDArray[np.float64]

    @property
    def x_min(self) -> float:
        return float(self.starts[:, 0].min())

    @property
    def x_max(self) -> float:
        return float(self.starts[:, 0].max())

    @cached_property
    def moments(self) -> NDArray[np.float64]:
        """(4, E): each edge's share of the region moments A, S_x, S_y, J_O (``segment_moments``)."""
        return segment_moments(self.starts, self.ends)

    @classmethod
    def from_rings(cls, rings: list[NDArray[np.float64]], snap_x: float = 0.0) -> "Boundary":
        """Edges of closed rings given as vertices (n, 2) without the repeated first vertex. With
        ``snap_x`` > 0 [m], edges whose ends differ in x by at most that much become exactly vertical."""
        starts = [_snap_vertical(r, snap_x) if snap_x > 0 else r for r in rings]
        ends = [np.concatenate([r[1:], r[:1]]) for r in starts]
        return cls(np.concatenate(starts), np.concatenate(ends))


def segment_moments(start: NDArray[np.float64], end: NDArray[np.float64]) -> NDArray[np.float64]:
    """(4, n): the four line integrals -int (y, x y, y^2 / 2, x^2 y + y^3 / 3) dx along straight
    segments start -> end (n, 2) [m] (the integrals of x(s), y(s) linear in s, in closed form)."""
    x0, y0 = start[:, 0], start[:, 1]
    x1, y1 = end[:, 0], end[:, 1]
    step = x0 - x1  # the minus sign of every integral
    x01 = x0 * x1
    return np.stack([
        step * (y0 + y1) / 2,
        step * (x0 * (2 * y0 + y1) + x1 * (y0 + 2 * y1)) / 6,
        step * (y0 * y0 + y0 * y1 + y1 * y1) / 6,
        step * (y0 * (3 * x0 * x0 + 2 * x01 + x1 * x1) + y1 * (x0 * x0 + 2 * x01 + 3 * x1 * x1)
                + (y0 + y1) * (y0 * y0 + y1 * y1)) / 12,
    ])


def oriented_rings(polygon: Polygon) -> list[NDArray[np.float64]]:
    """Vertices (n, 2) of the exterior (counter-clockwise) and of each hole (clockwise)."""
    polygon = orient(polygon, sign=1.0)
    return [np.asarray(r.coords, float)[:-1] for r in [polygon.exterior, *polygon.interiors]]


def rounding_slack(rings: list[NDArray[np.float64]]) -> float:
    """Differences in x [m] below this are rounding from moving an outline into a member frame."""
    xy = np.concatenate(rings)
    return 1e-12 * max(float(np.abs(xy).max()), float(np.ptp(xy[:, 0])))


def boundary_of(outline: Polygon | Boundary) -> Boundary:
    """The snapped boundary of ``outline`` (a member-frame Polygon), or ``outline`` if already one."""
    if isinstance(outline, Boundary):
        return outline
    rings = oriented_rings(outline)
    return Boundary.from_rings(rings, rounding_slack(rings))


def _snap_vertical(xy: NDArray[np.float64], tol: float) -> NDArray[np.float64]:
    """Give each run of vertices joined by near-vertical edges the x of the run's first vertex."""
    x = xy[:, 0]
    steps = np.abs(np.concatenate([x[1:], x[:1]]) - x) <= tol
    if steps.all() or not steps.any():
        return xy
    # Start the ring after a step that is not near-vertical, so no run wraps around the end.
    shift = int(np.argmin(steps)) + 1
    xy = np.concatenate([xy[shift:], xy[:shift]])
    steps = np.concatenate([steps[shift:], steps[:shift]])
    index = np.arange(len(xy))
    run_start = np.maximum.accumulate(np.where(np.concatenate([[False], steps[:-1]]), 0, index))
    snapped = xy.copy()
    snapped[:, 0] = xy[run_start, 0]
    return snapped
