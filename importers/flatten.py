"""Flattening exact curves into polylines: circular and elliptic arcs, bulges, splines.

Arcs (and bulges, circles, ellipses) are flattened from their exact geometry, never through
``ezdxf.path``'s cubic Beziers. The step is chosen as for a circle of the arc's (major) radius r:
n equal steps of dt with r (1 - cos(dt / 2)) <= s, the chord (sagitta) tolerance, so every chord of
an inscribed polygon would lie within s of the curve (``linkstress.geometry.curves``' rule). An inscribed
polygon loses the area (2/3) s per unit length of curve, a relative error about (4/3) s / r;
instead the vertices are placed *area-preserving* (the midpoint rule of quadrature):

- open arc: both ends exact, n interior vertices at t0 + (k - 1/2) dt, k = 1..n, on the radius
  q r, with q solving (n - 1) sin(dt) q^2 + 2 sin(dt / 2) q = n dt, so that the fan from the centre
  has exactly the sector's area, r^2 n dt / 2;
- closed circle or ellipse: n vertices at t0 + k dt on the radius r sqrt(dt / sin dt), the regular
  polygon with the circle's area.

Area is then exact to rounding, and the first and second moments differ from the exact sector's by
O(dt^3) instead of O(dt^2): with s = 1e-4 r (223 vertices per turn) a half-disc bounded by one arc
has its centroid and polar moment within 5e-7 relative, where an inscribed polygon would be off by
1.3e-4 in area. Every vertex and chord still lies within (2/3) s of the curve. An ellipse is the
affine image of its major circle (scaling the minor direction by b/a <= 1), so the same rule with
r = a keeps it within s and preserves its area too.

Splines are evaluated from the B-spline itself (weights included) with scipy, vectorised: each knot
span takes equal parameter steps, as many as bring the chords' sagittas within the relative tolerance
x the spline's own size (the diagonal of its control points' box), capped like arcs; the interior
vertices then move off the curve by 2/3 of their chords' sagittas so that the polygon keeps the
curve's area as arcs do (a parabolic segment holds 2/3 of chord x sagitta). A tolerance of 1e-7 of the
drawing's size instead, flattened by ezdxf in Python, made a sheet of 1,176 small splines take 148 s
and 545 MB, only to be refused at ``MAX_SPLINE_VERTICES``.

Each piece also says what it is as far as circles go (:mod:`.circles`): straight, an arc or a
circle, an ellipse with equal axes, a closed spline on a circle, or another curve.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from linkstress.geometry.curves import MIN_SEGMENTS_PER_TURN
from linkstress.errors import SketchError
from linkstress.importers import circles
from linkstress.importers.library_notes import one_line
from linkstress.importers.primitives import CurveSet, Origin, Polyline, bulge_arcs, describe

if TYPE_CHECKING:
    from scipy.interpolate import BSpline

RELATIVE_SAGITTA = 1e-4
"""Default chord tolerance of an arc, as a fraction of its own (major) radius: 223 vertices per turn."""

DRAWING_SAGITTA = 1e-5
"""Cap on any arc's chord tolerance, as a fraction of the drawing's size (bounding-box diagonal):
it only binds for arcs flatter than a tenth of the drawing, which would otherwise stray from the curve."""

MAX_VERTICES = 5_000_000
"""The most vertices a sketch may flatten to (80 MB of coordinates, seconds to chain): the count is
estimated from the chord tolerance and the arcs before any is made, and a setting asking for more is refused."""

MAX_SPLINE_VERTICES = 200_000
"""The most vertices all splines together may flatten to (a circle-like spline needs about 140 at the
default tolerance; the 1,170 splines of ``validation.bench.sketch_import``'s sheet about 47,000)."""


@dataclass(frozen=True)
class Pieces:
    """Flattened curves, one piece per curve, in :meth:`CurveSet.curve_origins` order (drawing units).

    Piece k's vertices are ``xy[start[k]:start[k + 1]]``; a closed piece does not repeat its first
    vertex. ``circle[k]`` is (cx, cy, r) when the piece is a circle or an arc of one (an ellipse with
    equal axes, a closed spline on a circle), else NaN; ``shape[k]`` is one of :mod:`.circles`'
    piece shapes (``STRAIGHT``, ``ARC``, ``CIRCLE``, ``ELLIPSE``, ``SPLINE``, ``CURVE``).
    """

    xy: NDArray[np.float64]
    start: NDArray[np.intp]
    closed: NDArray[np.bool_]
    circle: NDArray[np.float64]
    shape: NDArray[np.object_]

    def __len__(self) -> int:
        return len(self.closed)

    def vertices(self, k: int) -> NDArray[np.float64]:
        return self.xy[self.start[k]:self.start[k + 1]]


@dataclass(frozen=True)
class Tolerance:
    """Chord tolerances: ``relative`` x each arc's radius (x each spline's size), at most ``cap`` [drawing units]."""

    relative: float
    cap: float

    @classmethod
    def for_size(cls, size: float, relative: float | None = None) -> "Tolerance":
        rel = RELATIVE_SAGITTA if relative is None else relative
        if not (math.isfinite(rel) and 0 < rel < 0.5):
            raise SketchError(f"the chord tolerance (--sagitta) must be a fraction of the radius in (0, 0.5), got {rel!r}")
        return cls(rel, DRAWING_SAGITTA * size)


def flatten(curves: CurveSet, tolerance: Tolerance) -> Pieces:
    """Every curve of ``curves`` as a polyline piece within ``tolerance`` (drawing units).

    The vertex count is checked against ``MAX_VERTICES`` before any vertex is made."""
    conic_rows = np.concatenate(curves.conics) if curves.conics else np.empty((0, 9))
    conic_steps = segment_counts(np.maximum(np.hypot(*conic_rows[:, 2:4].T), np.hypot(*conic_rows[:, 4:6].T)),
                                 conic_rows[:, 7], tolerance)
    segments = _Segments.of(curves.polylines)
    bulge_steps = segment_counts(segments.radius, segments.sweep, tolerance)
    line_ends = 2 * sum(len(chunk) for chunk in curves.lines)
    straight = line_ends + 2 * len(conic_rows) + len(segments.p0) + len(curves.polylines)
    _check_budget(int(conic_steps.sum()) + int(bulge_steps.sum()), len(conic_rows) + len(bulge_steps), straight,
                  tolerance)
    blocks = [_lines(curves), _conics(conic_rows, conic_steps), _polylines(curves.polylines, segments, bulge_steps),
              _splines(curves, tolerance)]
    xy = np.concatenate([b[0] for b in blocks])
    counts = np.concatenate([b[1] for b in blocks])
    if not np.isfinite(xy).all():
        raise SketchError("coordinates too large to compute with (they overflow double precision)")
    return Pieces(
        xy,
        np.concatenate([[0], np.cumsum(counts)]).astype(np.intp),
        np.concatenate([b[2] for b in blocks]).astype(bool),
        np.concatenate([b[3] for b in blocks]).reshape(-1, 3),
        np.concatenate([b[4] for b in blocks]).astype(object),
    )


def _check_budget(arc_vertices: int, arcs: int, straight: int, tolerance: Tolerance) -> None:
    """Refuse a flattening of more than ``MAX_VERTICES``: ``arc_vertices`` on ``arcs`` arcs at the
    chord tolerance asked for, ``straight`` vertices of lines and polyline corners whatever it is."""
    total = arc_vertices + straight
    if total <= MAX_VERTICES:
        return
    if straight >= MAX_VERTICES:
        raise SketchError(
            f"the drawing has {straight:,} line ends and polyline vertices, more than the {MAX_VERTICES:,} "
            "linkstress flattens; split it into one sketch per link"
        )
    # The steps of an arc go as 1 / sqrt(sagitta): the tolerance that fits in the budget.
    needed = tolerance.relative * (arc_vertices / (MAX_VERTICES - straight)) ** 2
    raise SketchError(
        f"the chord tolerance --sagitta {tolerance.relative:g} asks for about {total:,} vertices "
        f"({arc_vertices:,} on {arcs:,} arc(s)), more than the limit of {MAX_VERTICES:,}; use --sagitta "
        f"{_round_up(needed):g} or more (the default is {RELATIVE_SAGITTA:g})"
    )


def _round_up(value: float) -> float:
    """``value`` rounded up to one significant digit."""
    scale = 10.0 ** math.floor(math.log10(value))
    return math.ceil(value / scale) * scale


Block = tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.bool_], NDArray[np.float64], NDArray[np.object_]]
"""Vertices, vertex count per piece, closed, circle and shape per piece (:class:`Pieces`' columns)."""


def _empty_block() -> Block:
    return np.empty((0, 2)), np.empty(0, np.intp), np.empty(0, bool), np.empty((0, 3)), np.empty(0, object)


def _lines(curves: CurveSet) -> Block:
    if not curves.lines:
        return _empty_block()
    ends = np.concatenate(curves.lines)
    n = len(ends)
    straight = np.full(n, circles.STRAIGHT, dtype=object)
    return ends.reshape(-1, 2), np.full(n, 2, np.intp), np.zeros(n, bool), np.full((n, 3), np.nan), straight


# -- conic arcs ------------------------------------------------------------------------------


def segment_counts(radius: NDArray[np.float64], sweep: NDArray[np.float64], tolerance: Tolerance) -> NDArray[np.intp]:
    """Steps n per arc of ``radius`` and ``sweep`` [rad]: r (1 - cos(dt/2)) <= min(relative r, cap)."""
    sagitta = np.minimum(tolerance.relative * radius, tolerance.cap)
    ratio = np.clip(sagitta / radius, 1e-15, 1.0)
    max_step = 2.0 * np.arccos(1.0 - ratio)
    turns = np.abs(sweep) / (2 * math.pi)
    n = np.maximum(np.ceil(np.abs(sweep) / max_step), np.ceil(MIN_SEGMENTS_PER_TURN * turns))
    return np.maximum(n, 1).astype(np.intp)


def interior_vertices(
    centre: NDArray[np.float64], major: NDArray[np.float64], minor: NDArray[np.float64],
    start: NDArray[np.float64], sweep: NDArray[np.float64], n: NDArray[np.intp],
) -> NDArray[np.float64]:
    """The n_i area-preserving interior vertices of each open arc i, arcs one after another.

    Vertex k of arc i (k = 1..n_i) is at t = start + (k - 1/2) dt on the scaled conic
    centre + q (cos t major + sin t minor), with dt = sweep / n and q from the module's equation.
    """
    dt = sweep / n
    a = np.abs(dt)
    qa, qb, qc = (n - 1) * np.sin(a), 2 * np.sin(a / 2), n * a
    q = 2 * qc / (qb + np.sqrt(qb * qb + 4 * qa * qc))  # the positive root, stable for qa -> 0
    arc = np.repeat(np.arange(len(n)), n)
    k = np.arange(len(arc)) - np.repeat(np.cumsum(n) - n, n) + 0.5
    t = start[arc] + k * dt[arc]
    return _on_conic(centre[arc], major[arc], minor[arc], t, q[arc])


def closed_vertices(
    centre: NDArray[np.float64], major: NDArray[np.float64], minor: NDArray[np.float64],
    start: NDArray[np.float64], sweep: NDArray[np.float64], n: NDArray[np.intp],
) -> NDArray[np.float64]:
    """The n_i vertices of each closed conic: the inflated regular polygon with the curve's area."""
    dt = sweep / n
    q = np.sqrt(np.abs(dt) / np.sin(np.abs(dt)))
    curve = np.repeat(np.arange(len(n)), n)
    k = np.arange(len(curve)) - np.repeat(np.cumsum(n) - n, n)
    t = start[curve] + k * dt[curve]
    return _on_conic(centre[curve], major[curve], minor[curve], t, q[curve])


def conic_point(centre, major, minor, t) -> NDArray[np.float64]:
    """Exact points centre + cos t major + sin t minor (rows)."""
    return _on_conic(centre, major, minor, t, 1.0)


def _on_conic(centre, major, minor, t, scale) -> NDArray[np.float64]:
    c, s = np.cos(t), np.sin(t)
    scale = np.asarray(scale, float).reshape(-1, 1) if np.ndim(scale) else scale
    return centre + scale * (c[:, None] * major + s[:, None] * minor)


def _circle_metadata(centre, major, minor, closed) -> tuple[NDArray[np.float64], NDArray[np.object_]]:
    """Circles (cx, cy, r) and shapes of conics: a circle when its axes are perpendicular and of equal
    length to rounding (1e-12), an ellipse with equal axes when within ``circles.EQUAL_AXES``."""
    a, b = np.hypot(*major.T), np.hypot(*minor.T)
    skew = np.abs(np.einsum("ij,ij->i", major, minor)) / (a * b)
    unequal = np.maximum(np.abs(a - b) / np.maximum(a, b), skew)
    exact, equal = unequal <= 1e-12, unequal <= circles.EQUAL_AXES
    full = np.where(exact, circles.CIRCLE, circles.ELLIPSE)
    shape = np.where(~equal, circles.CURVE, np.where(closed, full, circles.ARC))
    return np.where(equal[:, None], np.column_stack([centre, (a + b) / 2]), np.nan), shape.astype(object)


def _conics(rows: NDArray[np.float64], n: NDArray[np.intp]) -> Block:
    """Conic rows of :class:`CurveSet` flattened in ``n`` steps each (their step follows the larger
    semi-axis: a damaged file may have a "minor" axis longer than the major)."""
    if not len(rows):
        return _empty_block()
    centre, major, minor = rows[:, 0:2], rows[:, 2:4], rows[:, 4:6]
    start, sweep, closed = rows[:, 6], rows[:, 7], rows[:, 8] > 0
    counts = np.where(closed, n, n + 2)
    out = np.empty((int(counts.sum()), 2))
    first = np.cumsum(counts) - counts
    op = ~closed
    if op.any():
        # Open arcs: exact start, interior vertices, exact end.
        m = n[op]
        out[first[op]] = conic_point(centre[op], major[op], minor[op], start[op])
        out[first[op] + m + 1] = conic_point(centre[op], major[op], minor[op], start[op] + sweep[op])
        slots = np.repeat(first[op] + 1, m) + (np.arange(m.sum()) - np.repeat(np.cumsum(m) - m, m))
        out[slots] = interior_vertices(centre[op], major[op], minor[op], start[op], sweep[op], m)
    if closed.any():
        m = n[closed]
        slots = np.repeat(first[closed], m) + (np.arange(m.sum()) - np.repeat(np.cumsum(m) - m, m))
        out[slots] = closed_vertices(centre[closed], major[closed], minor[closed], start[closed], sweep[closed], m)
    return out, counts, closed, *_circle_metadata(centre, major, minor, closed)


# -- polylines with bulges ---------------------------------------------------------------------


@dataclass(frozen=True)
class _Segments:
    """The segments of polylines, concatenated: from ``p0`` to ``p1`` with ``bulge``; ``per_polyline``
    segments each; the arcs (``centre``, ``radius``, ``start``, ``sweep``) of the ``curved`` ones."""

    p0: NDArray[np.float64]
    p1: NDArray[np.float64]
    per_polyline: NDArray[np.intp]
    curved: NDArray[np.bool_]
    centre: NDArray[np.float64]
    radius: NDArray[np.float64]
    start: NDArray[np.float64]
    sweep: NDArray[np.float64]

    @classmethod
    def of(cls, polys: list[Polyline]) -> "_Segments":
        if not polys:
            empty = np.empty(0)
            return cls(np.empty((0, 2)), np.empty((0, 2)), np.empty(0, np.intp), np.empty(0, bool),
                       np.empty((0, 2)), empty, empty, empty)
        p0_list, p1_list, b_list = [], [], []
        for p in polys:
            v, b = p.vertices, p.bulges
            nxt = np.roll(v, -1, axis=0) if p.closed else v[1:]
            p0_list.append(v if p.closed else v[:-1])
            p1_list.append(nxt)
            b_list.append(b if p.closed else b[:-1])
        p0, p1, bulge = np.concatenate(p0_list), np.concatenate(p1_list), np.concatenate(b_list)
        # A bulge on a zero-length segment draws nothing.
        curved = (bulge != 0) & np.any(p0 != p1, axis=1)
        centre, radius, start, sweep = bulge_arcs(p0[curved], p1[curved], bulge[curved])
        return cls(p0, p1, np.array([len(x) for x in p1_list], np.intp), curved, centre, radius, start, sweep)


def _polylines(polys: list[Polyline], segments: _Segments, steps: NDArray[np.intp]) -> Block:
    """Polylines whose curved segments take ``steps`` steps each."""
    if not polys:
        return _empty_block()
    p0, curved, seg_counts = segments.p0, segments.curved, segments.per_polyline
    closed = np.array([p.closed for p in polys])
    n = np.zeros(len(p0), np.intp)
    n[curved] = steps
    interior = np.empty((0, 2))
    if curved.any():
        radius = segments.radius
        zeros = np.zeros_like(radius)
        interior = interior_vertices(segments.centre, np.column_stack([radius, zeros]),
                                     np.column_stack([zeros, radius]), segments.start, segments.sweep, steps)
    # Each segment contributes its start vertex and its interior vertices; an open polyline adds its end.
    per_segment = 1 + n
    poly_of_segment = np.repeat(np.arange(len(polys)), seg_counts)
    counts = np.bincount(poly_of_segment, weights=per_segment, minlength=len(polys)).astype(np.intp) + ~closed
    out = np.empty((int(counts.sum()), 2))
    poly_first = np.cumsum(counts) - counts
    seg_offset_in_poly = np.cumsum(per_segment) - per_segment
    seg_offset_in_poly -= np.repeat(seg_offset_in_poly[np.cumsum(seg_counts) - seg_counts], seg_counts)
    seg_first = poly_first[poly_of_segment] + seg_offset_in_poly
    out[seg_first] = p0
    if len(interior):
        m = n[curved]
        slots = np.repeat(seg_first[curved] + 1, m) + (np.arange(m.sum()) - np.repeat(np.cumsum(m) - m, m))
        out[slots] = interior
    last_vertex = np.array([p.vertices[-1] for p in polys])
    out[(poly_first + counts - 1)[~closed]] = last_vertex[~closed]
    circle = np.array([_polyline_circle(p) for p in polys]).reshape(-1, 3)
    straight = np.array([not p.bulges.any() and p.circle is None for p in polys])
    shape = np.where(straight, circles.STRAIGHT, np.where(np.isnan(circle[:, 2]), circles.CURVE, circles.CIRCLE))
    return out, counts, closed, circle, shape.astype(object)


def _polyline_circle(p: Polyline) -> tuple[float, float, float]:
    """(cx, cy, r) of a polyline known to be a circle, or closed and made only of arcs of one circle."""
    if p.circle is not None:
        return p.circle
    if not p.closed or len(p.vertices) < 2 or not np.all(p.bulges != 0):
        return (np.nan, np.nan, np.nan)
    centre, radius, _, _ = bulge_arcs(p.vertices, np.roll(p.vertices, -1, axis=0), p.bulges)
    r = radius.mean()
    if np.ptp(radius) <= 1e-9 * r and np.ptp(centre, axis=0).max() <= 1e-9 * r:
        return (float(centre[:, 0].mean()), float(centre[:, 1].mean()), float(r))
    return (np.nan, np.nan, np.nan)


# -- splines -----------------------------------------------------------------------------------


def _splines(curves: CurveSet, tolerance: Tolerance) -> Block:
    """Splines flattened within ``tolerance.relative`` x their own size (capped at ``tolerance.cap``);
    a closed one whose points lie on a circle (:func:`circles.on_circle`) carries it."""
    if not curves.splines:
        return _empty_block()
    parts, found = [], []
    left = MAX_SPLINE_VERTICES
    for spline, origin in zip(curves.splines, curves.origins["splines"]):
        xy, sagitta = _spline_vertices(spline, spline_chord(spline, tolerance), left, origin)
        left -= len(xy)
        found.append(_spline_circle(xy))
        parts.append(keep_area(xy, sagitta))
    counts = np.array([len(p) for p in parts], np.intp)
    circle = np.array([(np.nan,) * 3 if c is None else c for c in found], float).reshape(-1, 3)
    shape = np.array([circles.CURVE if c is None else circles.SPLINE for c in found], dtype=object)
    return np.concatenate(parts), counts, np.zeros(len(parts), bool), circle, shape


def spline_chord(spline, tolerance: Tolerance) -> float:
    """The chord tolerance of ``spline`` [drawing units]: ``tolerance.relative`` x the diagonal of its
    control points' box (the curve lies in their convex hull), at most ``tolerance.cap``."""
    xy = np.array([(p[0], p[1]) for p in spline.control_points], float).reshape(-1, 2)
    size = float(np.hypot(*np.ptp(xy, axis=0)))
    return min(tolerance.relative * size, tolerance.cap) if size > 0 else tolerance.cap


def _spline_circle(xy: NDArray[np.float64]) -> tuple[float, float, float] | None:
    """The circle of a flattened spline whose ends meet and whose points go once around a circle."""
    if len(xy) < 4:
        return None
    ring = xy[:-1]
    circle = circles.on_circle(ring)
    if circle is None or np.hypot(*(xy[-1] - xy[0])) > circles.CIRCLE_FIT * circle[2]:
        return None
    return circle


def spline_curve(spline) -> tuple[BSpline, float, float]:
    """``spline`` (ezdxf's ``BSpline``) as scipy's B-spline of homogeneous points (w x, w y, w),
    weights included, and its parameter range (the knots at degree and at the control point count)."""
    knots = np.asarray(spline.knots(), float)
    xy = np.array([(p[0], p[1]) for p in spline.control_points], float).reshape(-1, 2)
    w = np.asarray(spline.weights(), float) if spline.is_rational else np.ones(len(xy))
    degree = spline.degree
    from scipy.interpolate import BSpline  # scipy.interpolate: tens of ms to import, for SPLINEs alone

    return BSpline(knots, np.column_stack([xy * w[:, None], w]), degree), float(knots[degree]), float(knots[len(xy)])


_PROBE = 8
"""Parameter steps per knot span at which the chords' sagittas are probed."""


def _spline_vertices(spline, distance: float, limit: int,
                     origin: Origin) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Points on ``spline`` whose chords lie within ``distance`` [drawing units] of it, and the chords'
    sagittas; refused beyond ``limit`` points.

    Each knot span takes n equal parameter steps: the chords' sagittas (midpoint distances) at
    ``_PROBE`` steps, shrinking as 1 / n^2, give the n that brings the largest within ``distance``."""
    try:
        curve, lo, hi = spline_curve(spline)
    except ValueError as error:  # scipy refuses knots that decrease or do not fit the control points
        raise SketchError(
            f"{describe(origin)} cannot be evaluated ({one_line(error)}); redraw it or convert it to a polyline") from None
    breaks = np.unique(np.asarray(spline.knots(), float).clip(lo, hi))
    if len(breaks) < 2:
        return _evaluate(curve, np.array([lo])), np.empty(0)
    if len(breaks) > limit:
        raise _too_many(origin, distance)
    sagitta, _ = _sagittas(curve, _parameters(breaks, np.full(len(breaks) - 1, _PROBE)))
    if not np.isfinite(sagitta).all():
        raise SketchError(
            f"{describe(origin)} cannot be evaluated (a weight of zero?); redraw it or convert it to a polyline")
    largest = np.abs(sagitta).reshape(-1, _PROBE).max(axis=1)
    steps = np.maximum(np.ceil(_PROBE * np.sqrt(largest / distance)), 1)
    if steps.sum() + 1 > limit:
        raise _too_many(origin, distance)
    sagitta, xy = _sagittas(curve, _parameters(breaks, steps.astype(np.intp)))
    return xy, sagitta


def _too_many(origin: Origin, distance: float) -> SketchError:
    return SketchError(
        f"the splines up to {describe(origin)} need more than the {MAX_SPLINE_VERTICES:,} vertices all "
        f"splines may take (chord tolerance {distance:.3g} drawing units); simplify them in CAD or convert "
        "them to polylines"
    )


def _evaluate(curve: BSpline, t: NDArray[np.float64]) -> NDArray[np.float64]:
    h = curve(t)
    return h[:, :2] / h[:, 2:3]


def _parameters(breaks: NDArray[np.float64], steps: NDArray[np.intp]) -> NDArray[np.float64]:
    """Parameters splitting span i (``breaks[i]`` to ``breaks[i + 1]``) into ``steps[i]`` equal steps."""
    width = np.diff(breaks)
    span = np.repeat(np.arange(len(width)), steps)
    k = np.arange(len(span)) - np.repeat(np.cumsum(steps) - steps, steps)
    return np.append(breaks[span] + width[span] * k / steps[span], breaks[-1])


def _sagittas(curve: BSpline, t: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """For the chords between the curve's points at ``t``: their signed sagittas (the curve's point
    at the middle parameter from the chord's midpoint, along its left normal); and the points."""
    xy = _evaluate(curve, t)
    middle = _evaluate(curve, (t[:-1] + t[1:]) / 2)
    _, normal = _chords(xy)
    return np.einsum("ij,ij->i", middle - (xy[1:] + xy[:-1]) / 2, normal), xy


def _chords(xy: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lengths and unit left normals of the chords between consecutive points (zero for a zero chord)."""
    chord = np.diff(xy, axis=0)
    length = np.hypot(*chord.T)
    return length, np.column_stack([-chord[:, 1], chord[:, 0]]) / np.where(length > 0, length, 1.0)[:, None]


def keep_area(xy: NDArray[np.float64], sagitta: NDArray[np.float64]) -> NDArray[np.float64]:
    """Points ``xy`` on a curve, whose chords have signed ``sagitta`` (one fewer), moved so that the
    polygon keeps the curve's area, as arcs do: a parabolic segment holds 2/3 of chord x sagitta, so
    interior vertex k moves along its two chords' mean normal by 2/3 of their sagittas' mean, weighted
    by length (a closed curve's first and last point, one vertex, alike; open ends stay on the curve).
    Every vertex stays within 2/3 of the largest sagitta of the curve."""
    length, normal = _chords(xy)
    closed = len(xy) > 3 and np.array_equal(xy[0], xy[-1])
    before = np.arange(-1, len(length) - 1) if closed else np.arange(len(length) - 1)
    after = before + 1
    mean = normal[before] + normal[after]
    size = np.hypot(*mean.T)
    weight = length[before] + length[after]
    weighted = length[before] * sagitta[before] + length[after] * sagitta[after]
    shift = (2 / 3) * weighted / np.where(weight > 0, weight, 1.0)
    move = np.where(size[:, None] > 0, mean / np.where(size > 0, size, 1.0)[:, None], 0.0) * shift[:, None]
    out = xy.copy()
    if closed:
        out[:-1] += move
        out[-1] = out[0]
    else:
        out[1:-1] += move
    return out
