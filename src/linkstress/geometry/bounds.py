"""Bounding functions U(x), L(x): the highest and lowest material point of a link at abscissa x.

Between two consecutive vertex abscissae no edges meet (the outline is simple), so the top and the
bottom of the material are each one straight edge there: U and L are piecewise linear with breaks
only at vertex abscissae, where they may jump (vertical edges). Each piece is evaluated on its own
edge, so U and L are exact at every vertex.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Polygon

from linkstress.errors import GeometryError
from linkstress.geometry.boundary import Boundary, boundary_of
from linkstress.geometry.sections import edge_crossings, height_on_edge, within_extent


@dataclass(frozen=True)
class BoundingFunctions:
    """U(x) and L(x) of an outline in a member frame [m].

    ``breaks`` (n,) are the sorted vertex abscissae. Over piece k, from ``breaks[k]`` to
    ``breaks[k + 1]``, U runs linearly from ``upper_start[k]`` to ``upper_end[k]`` and L likewise.
    ``upper_at_breaks``/``lower_at_breaks`` are the extreme material points on each vertical line
    through a break (the closure: either one-sided limit or a vertex on that line).
    """

    breaks: NDArray[np.float64]
    upper_start: NDArray[np.float64]
    upper_end: NDArray[np.float64]
    lower_start: NDArray[np.float64]
    lower_end: NDArray[np.float64]
    upper_at_breaks: NDArray[np.float64]
    lower_at_breaks: NDArray[np.float64]

    def __call__(self, x: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(U(x), L(x)) [m] at abscissae ``x`` [m] inside the outline's extent."""
        x = within_extent(np.asarray(x, float), self.breaks[0], self.breaks[-1], "abscissa")
        k = np.clip(np.searchsorted(self.breaks, x, "right") - 1, 0, len(self.breaks) - 2)
        x0, x1 = self.breaks[k], self.breaks[k + 1]
        w1 = (x - x0) / (x1 - x0)
        w0 = (x1 - x) / (x1 - x0)
        upper = self.upper_start[k] * w0 + self.upper_end[k] * w1
        lower = self.lower_start[k] * w0 + self.lower_end[k] * w1
        on_break = np.isin(x, self.breaks)
        if on_break.any():
            j = np.searchsorted(self.breaks, x[on_break])
            upper[on_break] = self.upper_at_breaks[j]
            lower[on_break] = self.lower_at_breaks[j]
        return upper, lower

    def polyline(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """(x, U, L) [m] tracing both functions left to right; a jump repeats its abscissa."""
        n = len(self.breaks)
        x = np.repeat(self.breaks, 2)[1:-1]
        upper = np.column_stack([self.upper_start, self.upper_end]).ravel()
        lower = np.column_stack([self.lower_start, self.lower_end]).ravel()
        # Entry 2k - 1 ends piece k - 1 and entry 2k starts piece k at the same break: keep both
        # only where U or L jumps there.
        keep = np.ones(len(x), bool)
        ends, starts = np.arange(1, 2 * n - 3, 2), np.arange(2, 2 * n - 2, 2)
        continuous = (upper[ends] == upper[starts]) & (lower[ends] == lower[starts])
        keep[starts[continuous]] = False
        return x[keep], upper[keep], lower[keep]


def bounding_functions(outline: Polygon | Boundary) -> BoundingFunctions:
    """U(x) and L(x) of ``outline``, given in the member frame [m] (or as its Boundary)."""
    edges = boundary_of(outline)
    starts, ends = edges.starts, edges.ends
    breaks = np.unique(starts[:, 0])
    if len(breaks) < 2:
        raise GeometryError("the outline has no extent along the member axis")
    mids = (breaks[:-1] + breaks[1:]) / 2
    cut = edge_crossings(starts, ends, mids)
    first = np.searchsorted(cut.station, np.arange(len(mids)), "left")
    last = np.searchsorted(cut.station, np.arange(len(mids)), "right") - 1
    top, bottom = cut.edge[last], cut.edge[first]

    def along(edge: NDArray[np.intp], x: NDArray[np.float64]) -> NDArray[np.float64]:
        return height_on_edge(starts[edge], ends[edge], x)

    upper_start, upper_end = along(top, breaks[:-1]), along(top, breaks[1:])
    lower_start, lower_end = along(bottom, breaks[:-1]), along(bottom, breaks[1:])
    vertex_break = np.searchsorted(breaks, starts[:, 0])
    upper_at = np.full(len(breaks), -np.inf)
    lower_at = np.full(len(breaks), np.inf)
    np.maximum.at(upper_at, vertex_break, starts[:, 1])
    np.minimum.at(lower_at, vertex_break, starts[:, 1])
    upper_at[:-1] = np.maximum(upper_at[:-1], upper_start)
    upper_at[1:] = np.maximum(upper_at[1:], upper_end)
    lower_at[:-1] = np.minimum(lower_at[:-1], lower_start)
    lower_at[1:] = np.minimum(lower_at[1:], lower_end)
    return BoundingFunctions(
        breaks, upper_start, upper_end, lower_start, lower_end, upper_at, lower_at
    )
