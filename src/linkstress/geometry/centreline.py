"""The centreline of a curved member: where a banana, an arc or a U runs between two joints.

A member is straight unless the material between its joints curves. Cuts square to the line
between the joints give a first midline, whose bow says whether it does (``centreline``); a curved
member's centreline is then traced along the material from one joint to the other (its medial axis:
``linkstress.geometry.medial_axis``, through a boss to its pin and round every bend) and its points
moved onto the midpoints of the cuts square to it. Everything is in the link's load frame.
"""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import LineString, Point, Polygon

from linkstress.geometry.medial_axis import medial_path
from linkstress.geometry.member_cuts import CutLines, Edges, cut_lines, through_axis

CURVED_WANDER = 0.1
"""A member is curved when the bow of its midline (``centreline``) is more than this many section
depths."""


REGULAR_WIDTH = 2.0
"""A first-midline cut wider than this many times the median runs along a lug or another arm."""


NOTCHED = 0.95
"""A first-midline cut narrower than this fraction of the usual width may be a notch's."""


CENTRELINE_POINTS = 41
"""Points of a curved member's centreline between its joints."""


TRACE_STEP = 0.1
"""Spacing of the traced centreline's points, and of the outline's samples its medial axis is found
from, in bar widths."""


POLISH_PASSES = 3
"""Moves of the traced centreline's points from the medial axis onto the midpoints of the cuts
through them square to the centreline (the chord between their neighbours): the medial axis is
equidistant from the edges, the centreline midway across the cuts, which differ a little where the
bar tapers. Each pass takes the tangents of the last."""

POLISH_REACH = 0.1
"""Bar widths from the medial axis beyond which a cut's midpoint is not taken: such a cut runs into a
corner's other arm or a junction, where the medial axis is the better centreline."""


def _widths(edges: Edges, path: NDArray[np.float64]) -> NDArray[np.float64]:
    """(K - 2,) [m]: the widths of the cuts square to ``path`` at its inner points."""
    chord = path[2:] - path[:-2]
    bottom, top, _ = through_axis(cut_lines(edges, path[1:-1], chord / np.hypot(*chord.T)[:, None]), len(path) - 2)
    return top - bottom


def first_midline(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distances [m] from ``a`` toward ``b`` of the centreline's points between them."""
    return float(np.hypot(*(b - a))) * np.arange(1, CENTRELINE_POINTS + 1) / (CENTRELINE_POINTS + 1)


def centreline(
    edges: Edges, a: NDArray[np.float64], b: NDArray[np.float64], square: CutLines,
) -> tuple[NDArray[np.float64], float, float]:
    """The material centreline (K, 2) [m] from joint point ``a`` to ``b``, its usual section depth [m]
    clear of the joints, and how far it strays from a straight line, in those depths.

    Cuts square to the line a-b at ``first_midline`` (``square``, v measured from that line) give a
    first midline. Its points whose cut is more than
    ``REGULAR_WIDTH`` times the usual (median) width cut along a lug or another arm and are left out;
    the rest, more than their width from each joint (a lug's rounded end says nothing of the bar's
    axis), measure its bow: the spread of a least-squares cubic through them about their
    least-squares line, or their own spread about it where larger (a kink close to a joint moves too
    few points to bend the cubic), refitted without the few points a notch moves off the first fit
    (those whose section is narrower than ``NOTCHED`` of the usual), in their median width. A member
    is curved when that bow exceeds ``CURVED_WANDER``, or when the line a-b leaves the material by
    more than half the usual width (a U, a hook: their straight cuts run along the legs, and say
    little); else it keeps the line a-b. A curved one's centreline is traced along the material
    (``_traced``)."""
    span = b - a
    length = float(np.hypot(*span))
    along = span / length
    count = CENTRELINE_POINTS
    points = a + np.outer(first_midline(a, b), along)
    bottom, top, _ = through_axis(square, count)
    width = top - bottom
    points = points + ((bottom + top) / 2)[:, None] * np.array([-along[1], along[0]])
    far = (np.hypot(*(points - a).T) > width) & (np.hypot(*(points - b).T) > width)
    usual = median(width[far]) if far.any() else median(width)
    regular = width <= REGULAR_WIDTH * usual
    clear = regular & far
    # the line a-b itself leaves the material by more than half a usual width (a U, a hook, a banana)
    astray = bool((np.maximum(np.maximum(bottom, -top), 0.0) > usual / 2).any())
    depth, wander = float(width.min()), 0.0
    if clear.sum() >= 4:
        local = (points[clear] - a) @ np.column_stack([along, [-along[1], along[0]]])
        x, y = local.T
        depth = median(width[clear])
        # the bow of a cubic through the midline; the few points a notch moves off it (more than
        # CURVED_WANDER depths; a notch narrows the section there) are left out of a second fit. A
        # kink moves them too, without narrowing the bar: those count
        fit = np.polyval(np.polyfit(x, y, 3), x)
        kept = (np.abs(y - fit) <= CURVED_WANDER * depth) | (width[clear] >= NOTCHED * depth)
        if kept.sum() >= max(4, 0.8 * len(x)):
            x, y = x[kept], y[kept]
        line = np.polyval(np.polyfit(x, y, 1), x)
        bow = np.polyval(np.polyfit(x, y, 3), x) - line
        # a kink near a joint bends too few points for the cubic: their own spread about the line
        wander = max(float(np.ptp(bow)), float(np.ptp(y - line))) / depth
    if wander <= CURVED_WANDER and not astray:
        return np.array([a, b]), depth, wander
    return _traced(edges, a, b, depth, wander)


def _traced(edges: Edges, a, b, depth: float, wander: float) -> tuple[NDArray[np.float64], float, float]:
    """A curved member's centreline from ``a`` to ``b`` (``centreline``): the path along the
    material's medial axis (``linkstress.geometry.medial_axis``), resampled every ``TRACE_STEP`` of the
    bar's width, its points clear of the joints' lugs moved onto the midpoints of the cuts square to
    it; the line a-b (with ``depth`` and ``wander``) where no path joins them."""
    shell = Polygon(edges.outline.exterior)
    # the mean width of a bar: its area over half its perimeter (a boss adds a little)
    width = 2 * shell.area / shell.length
    path = medial_path(shell, a, b, TRACE_STEP * width)
    if path is None:
        return np.array([a, b]), depth, wander
    line = LineString(path)
    path = shapely.get_coordinates(shapely.line_interpolate_point(
        line, np.linspace(0.0, line.length, max(3, int(np.ceil(line.length / (TRACE_STEP * width))) + 1)),
    ))
    widths = _widths(edges, path)
    usual = median(widths)
    along = (b - a) / np.hypot(*(b - a))
    # how far the traced centreline strays from the line a-b, in depths
    wander = float(np.abs((path - a) @ np.array([-along[1], along[0]])).max()) / usual
    # clear of each joint's lug (a boss: its radius; a bar's end: half its width), and
    # cut square across the bar, not along a lug or another arm
    lugs = [max(shell.exterior.distance(Point(p)), usual / 2) for p in (a, b)]
    clear = (np.hypot(*(path - a).T) > lugs[0]) & (np.hypot(*(path - b).T) > lugs[1])
    clear[1:-1] &= widths <= REGULAR_WIDTH * usual
    inner = np.flatnonzero(clear[1:-1]) + 1
    medial = path[inner]
    for _ in range(POLISH_PASSES):
        chord = path[inner + 1] - path[inner - 1]
        tangent = chord / np.hypot(*chord.T)[:, None]
        bottom, top, _ = through_axis(cut_lines(edges, medial, tangent), len(inner))
        middle = medial + ((bottom + top) / 2)[:, None] * np.column_stack([-tangent[:, 1], tangent[:, 0]])
        # a midpoint far off the medial axis is that of a cut into a corner or a junction, not a bar's
        near = np.hypot(*(middle - medial).T) <= POLISH_REACH * usual
        path[inner] = np.where(near[:, None], middle, medial)
    points = path[1:-1]
    width = _widths(edges, path)
    far = (np.hypot(*(points - a).T) > width) & (np.hypot(*(points - b).T) > width)
    depth = float(width[far].min()) if far.any() else depth
    return path, depth, wander


def median(values: NDArray[np.float64]) -> float:
    """The median of a non-empty 1-D array, as ``np.median`` gives it (the mean of the two middle
    values of an even count). Sorted here: ``np.median`` imports ``numpy.ma``, 10 ms of every
    ``analyze``'s start for a few widths."""
    ordered = np.sort(np.asarray(values, float))
    n = len(ordered)
    return float(0.5 * (ordered[(n - 1) // 2] + ordered[n // 2]))
