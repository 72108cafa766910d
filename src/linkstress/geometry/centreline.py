"""The centreline of a curved member: where a banana, an arc or a U runs between two joints.

A member is straight unless the material between its joints curves. Cuts square to the line
between the joints give a first midline, whose bow says whether it does (``centreline``); a curved
member's centreline is then traced along the material from one joint to the other (``_march``) and
its points moved onto the midpoints of the cuts square to it. Everything is in the link's load frame.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from linkstress.geometry.member_cuts import CutLines, Edges, cut_lines, through_axis

CURVED_WANDER = 0.1
"""A member is curved when the bow of its midline (``centreline``) is more than this many section
depths."""


REGULAR_WIDTH = 2.0
"""A first-midline cut wider than this many times the median runs along a lug or another arm."""


CENTRELINE_POINTS = 41
"""Points of a curved member's centreline between its joints."""


MARCH_STEP = 0.1
"""Steps of the centreline's tracing, in section depths."""


POLISH_PASSES = 20
"""Moves of the traced centreline's points onto the midpoints of the cuts square to it (the chord
between their neighbours), which straighten the kink of the tracing's first steps."""


ARRIVAL_COS = math.cos(math.radians(45.0))
"""Within half a width of its end joint, a tracing heading within 45 degrees of it has arrived (its
last steps would run through the joint's lug)."""


START_RAYS = 72
"""Directions tried for where a bar leaves its joint."""


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
    least-squares line (refitted without the few points a notch or a hole moves off the first fit),
    in their median width. A
    member is curved when that bow exceeds ``CURVED_WANDER``, or when the line a-b leaves the material by more than half the
    usual width (a U, a hook: their straight cuts run along the legs, and say little); else it keeps
    the line a-b. A curved one's centreline is traced from a along the bar (``_march``; from b if
    that does not arrive)."""
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
        # the bow of a cubic through the midline; the few points a notch or a hole moves off it (more
        # than CURVED_WANDER depths) are left out of a second fit
        fit = np.polyval(np.polyfit(x, y, 3), x)
        kept = np.abs(y - fit) <= CURVED_WANDER * depth
        if kept.sum() >= max(4, 0.8 * len(x)):
            x, y = x[kept], y[kept]
        bow = np.polyval(np.polyfit(x, y, 3), x) - np.polyval(np.polyfit(x, y, 1), x)
        wander = float(np.ptp(bow)) / depth
    if wander <= CURVED_WANDER and not astray:
        return np.array([a, b]), depth, wander
    # from either joint, toward the first midline's points clear of the joints, else along the bar
    tries = [(a, b, None), (b, a, None)]
    if clear.sum() >= 3:
        tries = [(a, b, (points[clear][0] - a, usual)), (b, a, (points[clear][-1] - b, usual)), *tries]
    for start, end, heading in tries:
        path = _march(edges, start, end, heading)
        if path is not None:
            path = path if start is a else path[::-1]
            break
    else:
        return np.array([a, b]), depth, wander
    usual = median(_widths(edges, path))
    # how far the traced centreline strays from the line a-b, in depths
    wander = float(np.abs((path - a) @ np.array([-along[1], along[0]])).max()) / usual
    # a section depth from each joint: the points there cut through a lug
    inner = np.flatnonzero((np.hypot(*(path - a).T) > usual) & (np.hypot(*(path - b).T) > usual))
    inner = inner[(inner > 0) & (inner < len(path) - 1)]
    for _ in range(POLISH_PASSES):
        chord = path[inner + 1] - path[inner - 1]
        tangent = chord / np.hypot(*chord.T)[:, None]
        bottom, top, _ = through_axis(cut_lines(edges, path[inner], tangent), len(inner))
        path[inner] += ((bottom + top) / 2)[:, None] * np.column_stack([-tangent[:, 1], tangent[:, 0]])
    points = path[1:-1]
    width = _widths(edges, path)
    far = (np.hypot(*(points - a).T) > width) & (np.hypot(*(points - b).T) > width)
    depth = float(width[far].min()) if far.any() else depth
    return np.vstack([a, points, b]), depth, wander


def _march(edges: Edges, a, b, start: tuple[NDArray[np.float64], float] | None = None) -> NDArray[np.float64] | None:
    """The centreline (K, 2) [m] from ``a`` to ``b`` traced in steps of ``MARCH_STEP`` of the bar's
    width, starting along ``start`` (a direction and the bar's width [m]; by default along the bar,
    ``_bar_start``): each step looks a step ahead along the last chord,
    moves to the midpoint of the cut square to it there, and takes the chord to that point as the
    next direction; None if it does not arrive at ``b`` (``ARRIVAL_COS``) before it has run half the
    outline's perimeter."""
    direction, width = start or _bar_start(edges, a, b)
    tangent = np.asarray(direction, float) / np.hypot(*direction)
    step = MARCH_STEP * width
    point, points = np.asarray(a, float), [np.asarray(a, float)]
    for _ in range(int(edges.perimeter / 2 / step) + 1):
        gap = b - point
        distance = np.hypot(*gap)
        # arrived: a step away, or within the lug (half a width) heading into it
        if distance <= 1.5 * step or (distance <= width / 2 and gap @ tangent >= distance * ARRIVAL_COS):
            return np.vstack([*points, b])
        ahead = point + step * tangent
        lines = cut_lines(edges, ahead[None, :], tangent[None, :])
        if not len(lines.station):
            return None  # stepped off the material
        bottom, top, _ = through_axis(lines, 1)
        middle = ahead + (bottom[0] + top[0]) / 2 * np.array([-tangent[1], tangent[0]])
        chord = middle - point
        tangent = chord / np.hypot(*chord)
        point = middle
        points.append(point)
    return None


def _bar_start(edges: Edges, a, b) -> tuple[NDArray[np.float64], float]:
    """The direction (2,) in which the bar leaves joint ``a`` toward ``b``, and its width [m] there: of
    ``START_RAYS`` rays from a, the one along which the material runs farthest, weighted by (1 + cos)
    / 2 of its angle to b (so a bar running on past a joint goes toward b); the width is that of the
    cut square to it, a third of that run along."""
    angles = 2 * np.pi * np.arange(START_RAYS) / START_RAYS
    rays = np.column_stack([np.cos(angles), np.sin(angles)])
    # a cut square to the ray's normal lies along the ray: its top is how far the material runs
    lines = cut_lines(edges, np.broadcast_to(a, rays.shape).copy(), np.column_stack([rays[:, 1], -rays[:, 0]]))
    _, run, _ = through_axis(lines, START_RAYS)
    toward = (b - a) / np.hypot(*(b - a))
    k = int(np.argmax(run * (1 + rays @ toward) / 2))
    across = a + rays[k] * run[k] / 3
    bottom, top, _ = through_axis(cut_lines(edges, across[None, :], rays[k][None, :]), 1)
    return rays[k], float(top[0] - bottom[0])


def median(values: NDArray[np.float64]) -> float:
    """The median of a non-empty 1-D array, as ``np.median`` gives it (the mean of the two middle
    values of an even count). Sorted here: ``np.median`` imports ``numpy.ma``, 10 ms of every
    ``analyze``'s start for a few widths."""
    ordered = np.sort(np.asarray(values, float))
    n = len(ordered)
    return float(0.5 * (ordered[(n - 1) // 2] + ordered[n // 2]))
