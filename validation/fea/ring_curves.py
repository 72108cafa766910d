"""Exact curves behind a flattened ring: circles, circular arcs, smooth spline runs and lines.

The importers flatten arcs, circles and splines into many short chords (a sagitta of a micrometre
or less). Meshed chord by chord, every chord would become at least one element edge and the mesh
would be refined by the drawing, not by the stresses. So before meshing, a ring is read back into
the curves it came from:

- a ring whose vertices all lie on one circle, finely flattened, is that circle; its radius is the
  equal-area radius sqrt(A / pi), so that the meshed plate has the profile's mass;
- a run of at least ``MIN_ARC_CHORDS`` chords on one circle is a circular arc through its end
  vertices (split so that no arc sweeps more than ``MAX_ARC_SWEEP``);
- a run of at least three chords, each shorter than ``short`` and turning less than
  ``SMOOTH_TURN`` at each vertex, is an interpolating spline through its vertices;
- every other chord stays a straight line.

A whole ring is a circle when a least-squares circle through its vertices (Kasa's algebraic fit)
has them all within ``CIRCLE_TOLERANCE`` of its radius. Within a ring, the circle through three
consecutive vertices is their circumcircle; consecutive vertices belong to one circle when their
circumcircles agree within ``CIRCLE_TOLERANCE`` of the radius plus the circumcentre's rounding
error, which grows as 1 / (angle between chords)^2 for very fine flattening.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

CIRCLE_TOLERANCE = 1e-6
"""Relative agreement of circumcentres and radii for vertices on one circle."""
ROUNDING = 1e-14
"""Relative rounding error of a circumcentre computed from vertices of that relative precision."""
FINE_SAGITTA = 1e-3
"""Largest chord sagitta, relative to the radius, of a flattened (not a polygonal) circle."""
MIN_ARC_CHORDS = 4
MAX_ARC_SWEEP = 2 * math.pi / 3
SMOOTH_TURN = math.radians(15.0)


@dataclass(frozen=True)
class Circle:
    """A full circle: ``centre`` (2,) and ``radius`` [m]."""

    centre: NDArray[np.float64]
    radius: float


@dataclass(frozen=True)
class Arc:
    """A circular arc from ``start`` to ``end`` (2,) [m] about ``centre``, sweep below pi."""

    start: NDArray[np.float64]
    centre: NDArray[np.float64]
    end: NDArray[np.float64]


@dataclass(frozen=True)
class Spline:
    """An interpolating spline through ``points`` (n, 2) [m], ends included."""

    points: NDArray[np.float64]


@dataclass(frozen=True)
class Line:
    """A straight segment from ``start`` to ``end`` (2,) [m]."""

    start: NDArray[np.float64]
    end: NDArray[np.float64]


Piece = Arc | Spline | Line


def ring_curves(coords: NDArray[np.float64], short: float) -> Circle | tuple[Piece, ...]:
    """The circle, or the chain of arcs, splines and lines, that ring ``coords`` (n, 2) [m] was flattened from.

    The ring may repeat its first vertex at the end. ``short`` [m]: chords shorter than this may be
    joined into splines (pass the finest mesh size: longer chords cost no extra elements).
    Consecutive pieces share their end vertices, and the chain closes.
    """
    xy = np.asarray(coords, float)
    if len(xy) > 1 and np.array_equal(xy[0], xy[-1]):
        xy = xy[:-1]
    centre, radius, spread = _fitted_circle(xy)
    if spread <= CIRCLE_TOLERANCE * radius and _finely_flattened(xy, radius):
        area = abs(_signed_area(xy))
        return Circle(centre, math.sqrt(area / math.pi))
    centres, radii = _circumcircles(xy)
    same = _same_circle(xy, centres, radii)
    arc_id, arc_centres = _arc_edges(xy, centres, radii, same)
    breaks = _breaks(xy, arc_id, arc_centres, short)
    return tuple(_pieces(xy, breaks, arc_id, arc_centres))


def _circumcircles(xy: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Circumcentre (n, 2) and radius (n,) of each vertex with its two neighbours (inf when collinear)."""
    a, b, c = np.roll(xy, 1, axis=0), xy, np.roll(xy, -1, axis=0)
    ab, ac = b - a, c - a
    d = 2 * (ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    ab2, ac2 = (ab * ab).sum(axis=1), (ac * ac).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ux = (ac[:, 1] * ab2 - ab[:, 1] * ac2) / d
        uy = (ab[:, 0] * ac2 - ac[:, 0] * ab2) / d
    centres = a + np.column_stack([ux, uy])
    radii = np.hypot(ux, uy)
    bad = ~np.isfinite(radii) | (d == 0)
    radii[bad] = np.inf
    centres[bad] = np.nan
    return centres, radii


def _same_circle(xy, centres: NDArray[np.float64], radii: NDArray[np.float64]) -> NDArray[np.bool_]:
    """same[k]: vertices k and k + 1 have one circumcircle (within ``CIRCLE_TOLERANCE`` and rounding)."""
    chord = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
    magnitude = np.abs(xy).max()
    with np.errstate(divide="ignore", invalid="ignore"):
        turn = (chord + np.roll(chord, 1)) / (2 * radii)
        tolerance = CIRCLE_TOLERANCE * radii + ROUNDING * magnitude / (turn * turn)
        allowed = np.minimum(tolerance, np.roll(tolerance, -1))
        nxt_c, nxt_r = np.roll(centres, -1, axis=0), np.roll(radii, -1)
        gap = np.hypot(*(centres - nxt_c).T)
        return np.isfinite(radii) & np.isfinite(nxt_r) & (gap <= allowed) & (np.abs(radii - nxt_r) <= allowed)


def _fitted_circle(xy: NDArray[np.float64]) -> tuple[NDArray[np.float64], float, float]:
    """Kasa's least-squares circle through ``xy``: centre, mean radius, spread of the vertex radii."""
    mean = xy.mean(axis=0)
    d = xy - mean
    rows = np.column_stack([d, np.ones(len(d))])
    (a, b, _), *_ = np.linalg.lstsq(rows, (d * d).sum(axis=1), rcond=None)
    centre = mean + np.array([a, b]) / 2
    r = np.hypot(*(xy - centre).T)
    return centre, float(r.mean()), float(r.max() - r.min())


def _finely_flattened(xy: NDArray[np.float64], radius: float) -> bool:
    chord = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
    sagitta = radius - np.sqrt(np.maximum(radius * radius - chord * chord / 4, 0.0))
    return bool((sagitta <= FINE_SAGITTA * radius).all())


def _arc_edges(xy, centres, radii, same) -> tuple[NDArray[np.intp], list[NDArray[np.float64]]]:
    """arc_id[k] for edge k (vertex k -> k + 1): the arc it belongs to, or -1; and each arc's centre."""
    n = len(xy)
    arc_id = np.full(n, -1)
    arc_centres: list[NDArray[np.float64]] = []
    chord = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
    ends = np.flatnonzero(~same)
    # Vertices ends[i] + 1 .. ends[i + 1] share one circumcircle: their arc runs over the edges
    # ends[i] .. ends[i + 1] (from the vertex before the run to the vertex after it).
    for a, b in zip(ends, np.roll(ends, -1)):
        run = (a + 1 + np.arange((b - a) % n or n)) % n
        edges = np.concatenate([[a], run])[:n]
        r = float(np.median(radii[run]))
        fine = math.isfinite(r) and bool((chord[edges] <= 2 * r * math.sqrt(2 * FINE_SAGITTA)).all())
        if len(edges) >= MIN_ARC_CHORDS and fine and (arc_id[edges] == -1).all():
            arc_id[edges] = len(arc_centres)
            arc_centres.append(_fitted_circle(xy[np.concatenate([edges, [(edges[-1] + 1) % n]])])[0])
    return arc_id, arc_centres


def _breaks(xy, arc_id, arc_centres, short) -> NDArray[np.bool_]:
    """breaks[v]: a piece ends at vertex v (between edge v - 1 and edge v)."""
    n = len(xy)
    prev_edge = np.roll(arc_id, 1)
    free = arc_id == -1
    edge = np.roll(xy, -1, axis=0) - xy
    length = np.hypot(*edge.T)
    heading = np.arctan2(edge[:, 1], edge[:, 0])
    turn = np.abs(np.angle(np.exp(1j * (heading - np.roll(heading, 1)))))
    smooth = free & np.roll(free, 1) & (length < short) & (np.roll(length, 1) < short) & (turn < SMOOTH_TURN)
    breaks = (arc_id != prev_edge) | (free & ~smooth)
    breaks |= _short_spline_breaks(free, breaks)
    breaks |= _long_arc_breaks(xy, arc_id, arc_centres, breaks)
    if not breaks.any():
        breaks[[0, n // 2]] = True
    return breaks


def _short_spline_breaks(free, breaks) -> NDArray[np.bool_]:
    """Free runs of fewer than three edges become lines: a break at each of their vertices."""
    extra = np.zeros_like(breaks)
    if not breaks.any():
        return extra
    starts = np.flatnonzero(breaks)
    ends = np.roll(starts, -1)
    n = len(breaks)
    for s, e in zip(starts, ends):
        count = (e - s) % n or n
        if free[s] and count < 3:
            extra[(s + np.arange(count)) % n] = True
    return extra


def _long_arc_breaks(xy, arc_id, arc_centres, breaks) -> NDArray[np.bool_]:
    """Extra vertices that split arcs sweeping more than ``MAX_ARC_SWEEP`` into equal parts."""
    extra = np.zeros_like(breaks)
    n = len(xy)
    for a, centre in enumerate(arc_centres):
        edges = np.flatnonzero(arc_id == a)
        first = int(edges[breaks[edges]][0])
        count = len(edges)
        path = xy[(first + np.arange(count + 1)) % n]
        radius = np.hypot(*(path - centre).T).mean()
        sweep = (2 * np.arcsin(np.minimum(np.hypot(*np.diff(path, axis=0).T) / (2 * radius), 1.0))).sum()
        parts = math.ceil(sweep / MAX_ARC_SWEEP)
        if parts > 1:
            cuts = np.round(np.arange(1, parts) * count / parts).astype(int)
            extra[(first + cuts) % n] = True
    return extra


def _pieces(xy, breaks, arc_id, arc_centres):
    n = len(xy)
    starts = np.flatnonzero(breaks)
    for s, e in zip(starts, np.roll(starts, -1)):
        count = (e - s) % n or n
        idx = (s + np.arange(count + 1)) % n
        if arc_id[s] >= 0:
            yield Arc(xy[idx[0]], arc_centres[arc_id[s]], xy[idx[-1]])
        elif count >= 3:
            yield Spline(xy[idx])
        else:
            yield Line(xy[idx[0]], xy[idx[-1]])


def _signed_area(xy: NDArray[np.float64]) -> float:
    x, y = xy[:, 0] - xy[0, 0], xy[:, 1] - xy[0, 1]
    return 0.5 * float((x * np.roll(y, -1) - np.roll(x, -1) * y).sum())
