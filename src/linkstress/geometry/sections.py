"""Beam sections of a plate link: the material chords of vertical cuts and their properties.

A link is a plate of constant thickness t drawn in its member frame (x along the member, y across).
The cut at station x meets the material in one or more chords [a_k, b_k] (a pin hole splits it in
two). The section is those chords extruded by t, so with h_k = b_k - a_k:

    A = t sum h_k,  y_na = t sum (b_k^2 - a_k^2) / 2 / A,  I = t sum ((b_k - y_na)^3 - (a_k - y_na)^3) / 3

All stations are cut at once: each boundary edge is matched with the sorted stations it spans
(a binary search), so the cost grows with the number of crossings, not edges x stations.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Polygon

from linkstress.errors import GeometryError
from linkstress.geometry.boundary import Boundary, boundary_of


END_SLACK = 1e-9
"""Stations closer than this fraction of the link's extent beyond an end are taken at that end."""


def within_extent(x: NDArray[np.float64], lo: float, hi: float, what: str) -> NDArray[np.float64]:
    """``x`` [m] with values a rounding error (``END_SLACK``) beyond [lo, hi] moved onto the end; else an error."""
    slack = END_SLACK * (hi - lo)
    x = np.where((x < lo) & (x >= lo - slack), lo, x)
    x = np.where((x > hi) & (x <= hi + slack), hi, x)
    outside = (x < lo) | (x > hi) | ~np.isfinite(x)
    if outside.any():
        bad = float(x[outside].flat[0])
        raise GeometryError(
            f"{what} x = {bad!r} m is outside the link's extent [{lo:.6g}, {hi:.6g}] m in its member frame"
        )
    return x


@dataclass(frozen=True)
class Crossings:
    """Where boundary edges cross vertical lines: station index, edge index and height y [m]."""

    station: NDArray[np.intp]
    edge: NDArray[np.intp]
    y: NDArray[np.float64]


def edge_crossings(
    starts: NDArray[np.float64],
    ends: NDArray[np.float64],
    stations: NDArray[np.float64],
    left_limit: bool = False,
    sort: bool = True,
) -> Crossings:
    """Crossings of edges (E, 2)-(E, 2) with the vertical lines x = stations (sorted ascending).

    An edge spanning [lo, hi] in x crosses station s when lo <= s < hi (the right-hand limit of the
    cut), or lo < s <= hi with ``left_limit``; vertical edges never cross. Either rule makes every
    closed ring cross every line an even number of times. Crossings come sorted by station, then y
    unless ``sort`` is False.
    """
    x0, y0 = starts.T
    x1, y1 = ends.T
    lo, hi = np.minimum(x0, x1), np.maximum(x0, x1)
    side = "right" if left_limit else "left"
    first = np.searchsorted(stations, lo, side)
    count = np.searchsorted(stations, hi, side) - first
    count[hi == lo] = 0
    edge = np.repeat(np.arange(len(x0)), count)
    offset = np.cumsum(count) - count
    station = first[edge] + np.arange(len(edge)) - offset[edge]
    y = height_on_edge(starts[edge], ends[edge], stations[station])
    if not sort:
        return Crossings(station, edge, y)
    order = np.lexsort((y, station))
    return Crossings(station[order], edge[order], y[order])


def height_on_edge(
    start: NDArray[np.float64], end: NDArray[np.float64], x: NDArray[np.float64]
) -> NDArray[np.float64]:
    """y [m] of the straight edges start -> end (E, 2) at abscissae x (E,); the vertex's own y at its x."""
    x0, y0 = start.T
    x1, y1 = end.T
    y = (y0 * (x1 - x) + y1 * (x - x0)) / (x1 - x0)
    return np.where(x == x0, y0, np.where(x == x1, y1, y))


def cut_extent(outline: Polygon | Boundary, stations: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lowest and highest y [m] of the material on the cuts at ``stations`` [m] inside the outline's
    x extent (member frame), without the rest of a section table."""
    x = np.asarray(stations, float).ravel()
    edges = boundary_of(outline)
    x = within_extent(x, edges.x_min, edges.x_max, "station")
    order = np.argsort(x)
    cut = edge_crossings(edges.starts, edges.ends, x[order], sort=False)
    bottom = np.full(len(x), np.inf)
    top = np.full(len(x), -np.inf)
    np.minimum.at(bottom, order[cut.station], cut.y)
    np.maximum.at(top, order[cut.station], cut.y)
    if not np.isfinite(top).all():
        bad = float(x[~np.isfinite(top)][0])
        raise GeometryError(f"station x = {bad!r} m cuts no material of the link")
    return bottom, top


@dataclass(frozen=True)
class SectionTable:
    """Section properties at stations along a member, all arrays indexed by station.

    Member frame [m]: x along the member, y across it. ``lower``/``upper`` (M, K) hold the chord ends,
    padded with zero-length chords beyond ``n_chords``. ``depth`` is the summed chord length [m];
    ``area`` [m^2] and ``second_moment`` [m^4] (about the neutral axis, bending in the plane) include
    the thickness; ``top``/``bottom`` are the extreme fibres' y and ``c_top``/``c_bottom`` their
    distances from the neutral axis [m].
    """

    x: NDArray[np.float64]
    thickness: float
    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    n_chords: NDArray[np.intp]
    depth: NDArray[np.float64]
    area: NDArray[np.float64]
    neutral_axis: NDArray[np.float64]
    second_moment: NDArray[np.float64]
    top: NDArray[np.float64]
    bottom: NDArray[np.float64]
    crossings: Crossings | None = field(default=None, repr=False, compare=False)
    """The edge crossings the table was cut from (``edge_crossings`` at the sorted stations short of the
    outline's right end, right-hand limit), which ``region_moments`` can reuse: stations at the right
    end come last in that order and take every edge whole there."""

    @property
    def c_top(self) -> NDArray[np.float64]:
        return self.top - self.neutral_axis

    @property
    def c_bottom(self) -> NDArray[np.float64]:
        return self.neutral_axis - self.bottom

    @property
    def present(self) -> NDArray[np.bool_]:
        """(M, K): the real chords of ``lower``/``upper`` (the rest is padding)."""
        return np.arange(self.lower.shape[1])[None, :] < self.n_chords[:, None]

    def chords(self, i: int) -> NDArray[np.float64]:
        """The material chords (n, 2) [a, b] of station ``i``, bottom to top."""
        n = self.n_chords[i]
        return np.column_stack([self.lower[i, :n], self.upper[i, :n]])

    def first_moment(self, y: ArrayLike) -> NDArray[np.float64]:
        """Q(y) [m^3]: first moment about the neutral axis of the section area above the fibre y.

        ``y`` [m, member frame] has shape (M,) (one fibre per station) or (M, F) (F fibres per station).
        Jourawski's shear stress at that fibre is V Q / (I t).
        """
        y = np.asarray(y, float)
        fibres = y if y.ndim == 2 else y[:, None]
        yna = self.neutral_axis[:, None, None]
        a = np.maximum(self.lower[:, None, :], fibres[:, :, None]) - yna
        b = np.maximum(self.upper[:, None, :], fibres[:, :, None]) - yna
        q = self.thickness * ((b * b - a * a) / 2).sum(axis=2)
        return q if y.ndim == 2 else q[:, 0]


def section_table(outline: Polygon | Boundary, stations: ArrayLike, thickness: float) -> SectionTable:
    """Sections of ``outline`` (member frame, m; or its Boundary) at ``stations`` [m] for a plate
    ``thickness`` [m].

    A station on a vertical boundary takes the section just to its right, except at the outline's
    right end, which takes the section just to its left. Stations outside the outline's x extent
    (by more than ``END_SLACK`` of it) are an error.
    """
    x = np.asarray(stations, float).ravel()
    edges = boundary_of(outline)
    starts, ends = edges.starts, edges.ends
    minx, maxx = edges.x_min, edges.x_max
    x = within_extent(x, minx, maxx, "station")
    order = np.argsort(x, kind="stable")
    xs = x[order]
    at_end = xs == maxx
    inner = edge_crossings(starts, ends, xs[~at_end])
    station_sorted, y = inner.station, inner.y
    if at_end.any():
        right_end = edge_crossings(starts, ends, xs[at_end], left_limit=True)
        station_sorted = np.concatenate([station_sorted, right_end.station + int((~at_end).sum())])
        y = np.concatenate([y, right_end.y])
    pairs = y.reshape(-1, 2)
    pair_station = order[station_sorted[::2]]
    return _table_from_chords(x, thickness, pair_station, pairs[:, 0], pairs[:, 1], inner)


def _table_from_chords(
    x: NDArray[np.float64],
    thickness: float,
    station: NDArray[np.intp],
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    crossings: Crossings | None = None,
) -> SectionTable:
    m = len(x)
    order = np.argsort(station, kind="stable")
    station, a, b = station[order], a[order], b[order]
    n_chords = np.bincount(station, minlength=m)
    if (n_chords == 0).any():
        bad = float(x[n_chords == 0][0])
        raise GeometryError(f"station x = {bad!r} m cuts no material of the link")
    k = int(n_chords.max())
    rank = np.arange(len(station)) - (np.cumsum(n_chords) - n_chords)[station]
    lower = np.zeros((m, k))
    upper = np.zeros((m, k))
    lower[station, rank] = a
    upper[station, rank] = b
    present = np.arange(k)[None, :] < n_chords[:, None]
    top = np.where(present, upper, -np.inf).max(axis=1)
    bottom = np.where(present, lower, np.inf).min(axis=1)
    depth = (upper - lower).sum(axis=1)
    # Moments about the cut's mid-height first, so that far-off member frames keep their digits.
    mid = (top + bottom) / 2
    lo, hi = lower - mid[:, None], upper - mid[:, None]
    first = ((hi * hi - lo * lo) / 2).sum(axis=1)
    safe_depth = np.where(depth > 0, depth, 1.0)
    neutral_axis = mid + np.where(depth > 0, first / safe_depth, 0.0)
    lo, hi = lower - neutral_axis[:, None], upper - neutral_axis[:, None]
    second = thickness * ((hi**3 - lo**3) / 3).sum(axis=1)
    return SectionTable(
        x=x,
        thickness=float(thickness),
        lower=lower,
        upper=upper,
        n_chords=n_chords,
        depth=depth,
        area=thickness * depth,
        neutral_axis=neutral_axis,
        second_moment=second,
        top=top,
        bottom=bottom,
        crossings=crossings,
    )
