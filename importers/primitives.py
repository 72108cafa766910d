"""The exact curves and points of a sketch, in drawing units, as the readers find them.

Readers (DXF, CSV) add primitives here; :mod:`linkstress.importers.flatten` turns each curve into
one piece of polyline. Circles, arcs and ellipses are all *conic arcs*:
``p(t) = centre + cos(t) major + sin(t) minor`` for ``t`` from ``start`` to ``start + sweep`` [rad];
a circle has perpendicular ``major`` and ``minor`` of equal length, its radius.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from linkstress.errors import SketchError
from linkstress.importers.units import DrawingUnit

if TYPE_CHECKING:
    from ezdxf.math import BSpline  # made by ezdxf for a SPLINE entity only

Origin = tuple[str, str | None, str | None, int | None, str | None]
"""Where a curve or point came from: (kind, DXF handle, layer, CSV line number, place), ``place``
finding a DXF entity without a handle (R12, OpenSCAD and DXFWRITE write none): ``#37``, its position
in the ENTITIES section, or ``#3 of block 'PIN' inserted by INSERT #12``."""


def describe(origin: Origin) -> str:
    """``LINE (handle 2F, layer 'crank')``, ``LINE #37 (layer '0')`` or ``circle on line 12``: the
    culprit in a message."""
    kind, handle, layer, line, place = origin
    if line is not None:
        return f"{kind} on line {line}"
    details = [f"handle {handle}"] if handle else []
    if layer is not None:
        details.append(f"layer {layer!r}")
    name = f"{kind} {place}" if place else kind
    return f"{name} ({', '.join(details)})" if details else name


@dataclass(frozen=True)
class Polyline:
    """Vertices (m, 2) with a bulge per vertex (tan of a quarter of the arc's sweep to the next vertex,
    positive counter-clockwise); ``closed`` adds the segment from the last vertex back to the first.
    ``circle`` (cx, cy, r) when the polyline is known to trace a circle (e.g. a sampled CSV circle)."""

    vertices: NDArray[np.float64]
    bulges: NDArray[np.float64]
    closed: bool
    circle: tuple[float, float, float] | None = None


class CurveSet:
    """Collects exact primitives and points from one sketch file (a builder, filled once by a reader)."""

    def __init__(self) -> None:
        self.lines: list[NDArray[np.float64]] = []  # chunks (n, 4): x0, y0, x1, y1
        self.conics: list[NDArray[np.float64]] = []  # chunks (n, 9): centre, major, minor, start, sweep, closed
        self.polylines: list[Polyline] = []
        self.splines: list[BSpline] = []
        self.points: list[NDArray[np.float64]] = []  # chunks (n, 2)
        self.origins: dict[str, list[Origin]] = {k: [] for k in ("lines", "conics", "polylines", "splines", "points")}

    # -- adding primitives -----------------------------------------------------------------

    def add_lines(self, ends: ArrayLike, origins: list[Origin]) -> None:
        """Straight lines, rows (x0, y0, x1, y1)."""
        ends = _finite(ends, 4, origins)
        self.lines.append(ends)
        self.origins["lines"].extend(origins)

    def add_arcs(self, centre: ArrayLike, radius: ArrayLike, start: ArrayLike, sweep: ArrayLike,
                 origins: list[Origin]) -> None:
        """Circular arcs from angle ``start`` through signed ``sweep`` [rad]; |sweep| = 2 pi is a full circle."""
        centre = np.asarray(centre, float).reshape(-1, 2)
        r = np.asarray(radius, float).reshape(-1)
        zeros = np.zeros_like(r)
        self.add_conics(centre, np.column_stack([r, zeros]), np.column_stack([zeros, r]), start, sweep, origins)

    def add_conics(self, centre: ArrayLike, major: ArrayLike, minor: ArrayLike, start: ArrayLike,
                   sweep: ArrayLike, origins: list[Origin]) -> None:
        """Elliptic (or circular) arcs; |sweep| >= 2 pi (to rounding) makes a closed curve."""
        start = np.asarray(start, float).reshape(-1)
        sweep = np.asarray(sweep, float).reshape(-1)
        full = np.abs(sweep) >= 2 * math.pi * (1 - 1e-12)
        sweep = np.where(full, np.copysign(2 * math.pi, sweep), sweep)
        rows = np.column_stack([
            np.asarray(centre, float).reshape(-1, 2), np.asarray(major, float).reshape(-1, 2),
            np.asarray(minor, float).reshape(-1, 2), start, sweep, full,
        ])
        rows = _finite(rows, 9, origins)
        self.conics.append(rows)
        self.origins["conics"].extend(origins)

    def add_polyline(self, polyline: Polyline, origin: Origin) -> None:
        _finite(polyline.vertices, 2, [origin])
        _finite(polyline.bulges, 1, [origin])
        self.polylines.append(polyline)
        self.origins["polylines"].append(origin)

    def add_polylines(self, polylines: list[Polyline], origins: list[Origin], *arrays: NDArray[np.float64]) -> None:
        """Many polylines; ``arrays`` (their concatenated vertices and bulges) are checked at once."""
        for array in arrays:
            if not np.isfinite(array).all():
                for p, origin in zip(polylines, origins):
                    _finite(p.vertices, 2, [origin])
                    _finite(p.bulges, 1, [origin])
        self.polylines.extend(polylines)
        self.origins["polylines"].extend(origins)

    def add_spline(self, spline: BSpline, origin: Origin) -> None:
        _finite(spline.control_points, None, [origin])
        self.splines.append(spline)
        self.origins["splines"].append(origin)

    def add_points(self, xy: ArrayLike, origins: list[Origin]) -> None:
        self.points.append(_finite(xy, 2, origins))
        self.origins["points"].extend(origins)

    # -- reading back --------------------------------------------------------------------------

    def point_array(self) -> NDArray[np.float64]:
        return np.concatenate(self.points) if self.points else np.empty((0, 2))

    def curve_origins(self) -> list[Origin]:
        """Origins of every curve in the order the flattened pieces come: lines, conics, polylines, splines."""
        o = self.origins
        return o["lines"] + o["conics"] + o["polylines"] + o["splines"]

    def curve_count(self) -> int:
        return len(self.curve_origins())

    def extents(self) -> tuple[NDArray[np.float64], list[Origin]]:
        """A box (minx, miny, maxx, maxy) per curve, in :meth:`curve_origins` order, then one per point,
        with their origins. Arcs and bulges by their own extent (ends and the axis extremes they pass),
        so a flat arc of a large circle counts only as long as it is; splines by their control points
        (the curve lies in their convex hull)."""
        boxes = [np.hstack([np.minimum(c[:, 0:2], c[:, 2:4]), np.maximum(c[:, 0:2], c[:, 2:4])]) for c in self.lines]
        boxes += [arc_boxes(c[:, 0:2], c[:, 2:4], c[:, 4:6], c[:, 6], c[:, 7]) for c in self.conics]
        shapes = [np.vstack([p.vertices, _bulge_extent(p)]) if p.bulges.any() else p.vertices for p in self.polylines]
        shapes += [np.asarray([(v[0], v[1]) for v in s.control_points], float).reshape(-1, 2) for s in self.splines]
        if shapes:
            xy = np.concatenate(shapes)
            first = np.cumsum([len(x) for x in shapes]) - [len(x) for x in shapes]
            boxes.append(np.hstack([np.minimum.reduceat(xy, first), np.maximum.reduceat(xy, first)]))
        boxes += [np.hstack([p, p]) for p in self.points]
        return np.concatenate(boxes or [np.empty((0, 4))]).reshape(-1, 4), self.curve_origins() + self.origins["points"]

    def bounds(self) -> tuple[float, float, float, float] | None:
        """A box (minx, miny, maxx, maxy) holding every curve (splines conservatively); None if none."""
        return box_of(self.extents()[0][:self.curve_count()])


def box_of(boxes: NDArray[np.float64]) -> tuple[float, float, float, float] | None:
    """The box (minx, miny, maxx, maxy) holding ``boxes`` (rows of the same); None if there are none."""
    if not len(boxes):
        return None
    return float(boxes[:, 0].min()), float(boxes[:, 1].min()), float(boxes[:, 2].max()), float(boxes[:, 3].max())

def no_curves(ignored: Mapping[str, int], kept: str = "") -> str:
    """The message for a drawing without curves (``kept``: e.g. " on the layers read"), saying what it
    holds instead; a HATCH's boundary is the likely outline, so say how to get it as curves."""
    if not ignored:
        return f"no outline: the drawing has no curves{kept}"
    found = ", ".join(f"{n} {kind}" for kind, n in sorted(ignored.items()))
    one = sum(ignored.values()) == 1
    message = (f"no outline: the drawing has no curves{kept} it reads (only {found} "
               f"{'was' if one else 'were'} found, which {'is' if one else 'are'} not outline geometry)")
    if any(kind.startswith("HATCH") for kind in ignored):
        message += ("; a HATCH is a fill, not an outline: draw its boundary as curves, or regenerate the "
                    "hatch's boundary in CAD (AutoCAD: HATCHGENERATEBOUNDARY) and export again")
    return message


def with_damage(message: str, fixes: tuple[str, ...] | list[str]) -> str:
    """``message``, noting that the file was damaged (and read in recover mode) if it was."""
    damage = next((fix for fix in fixes if fix.startswith("the file is damaged")), None)
    return f"{message} (note: {damage})" if damage else message


def bulge_arcs(p0: NDArray[np.float64], p1: NDArray[np.float64], bulge: NDArray[np.float64]):
    """Centre, radius, start angle and signed sweep [rad] of the arcs from p0 to p1 with ``bulge``.

    bulge = tan(sweep / 4), positive counter-clockwise; the centre lies at distance
    (c / 4)(1 / b - b) from the chord's midpoint along its left normal (c = chord length).
    """
    u = p1 - p0
    c = np.hypot(*u.T)
    left = np.column_stack([-u[:, 1], u[:, 0]]) / c[:, None]
    centre = (p0 + p1) / 2 + left * ((c / 4) * (1 / bulge - bulge))[:, None]
    sweep = 4 * np.arctan(bulge)
    radius = c / (2 * np.abs(np.sin(sweep / 2)))
    start = np.arctan2(p0[:, 1] - centre[:, 1], p0[:, 0] - centre[:, 0])
    return centre, radius, start, sweep


def arc_boxes(centre: NDArray[np.float64], major: NDArray[np.float64], minor: NDArray[np.float64],
              start: NDArray[np.float64], sweep: NDArray[np.float64]) -> NDArray[np.float64]:
    """Boxes (minx, miny, maxx, maxy) of conic arcs centre + cos t major + sin t minor, t from
    ``start`` through signed ``sweep`` [rad]: their ends and the extremes of x and y they pass.

    x(t) is extreme where its derivative -major_x sin t + minor_x cos t vanishes, at
    t = atan2(minor_x, major_x) and that plus pi; likewise y."""
    tx, ty = np.arctan2(minor[:, 0], major[:, 0]), np.arctan2(minor[:, 1], major[:, 1])
    t = np.column_stack([tx, tx + math.pi, ty, ty + math.pi, start, start + sweep])
    ahead = np.where(sweep[:, None] >= 0, np.mod(t - start[:, None], 2 * math.pi),
                     np.mod(start[:, None] - t, 2 * math.pi))
    passed = ahead <= np.abs(sweep)[:, None]
    passed[:, 4:] = True
    xy = centre[:, None, :] + np.cos(t)[:, :, None] * major[:, None, :] + np.sin(t)[:, :, None] * minor[:, None, :]
    xy = np.where(passed[:, :, None], xy, xy[:, 4:5, :])  # an extreme not passed: the start instead
    return np.hstack([xy.min(axis=1), xy.max(axis=1)])


def _bulge_extent(p: Polyline) -> NDArray[np.float64]:
    """Corners of the boxes of the polyline's bulged segments (:func:`arc_boxes`)."""
    v = p.vertices
    nxt = np.roll(v, -1, axis=0)
    curved = (p.bulges != 0) & np.any(v != nxt, axis=1)
    if not p.closed:
        curved[-1] = False
    if not curved.any():
        return np.empty((0, 2))
    centre, radius, start, sweep = bulge_arcs(v[curved], nxt[curved], p.bulges[curved])
    zeros = np.zeros_like(radius)
    box = arc_boxes(centre, np.column_stack([radius, zeros]), np.column_stack([zeros, radius]), start, sweep)
    return np.concatenate([box[:, :2], box[:, 2:]])


def _finite(values: ArrayLike, width: int | None, origins: list[Origin]) -> NDArray[np.float64]:
    array = np.asarray(values, float)
    if width is not None:
        array = array.reshape(-1, width) if width > 1 else array.reshape(-1)
    finite = np.isfinite(array)
    if not finite.all():
        rows = ~finite.reshape(len(array), -1).all(axis=1) if array.ndim > 1 else ~finite
        k = int(np.argmax(rows)) if len(origins) > 1 else 0
        raise SketchError(f"{describe(origins[min(k, len(origins) - 1)])} has a coordinate that is not a finite number")
    return array


@dataclass(frozen=True)
class RawSketch:
    """What a reader found in a file, before flattening: curves and points in ``unit``.

    ``units_source`` says where the unit came from (the file, the caller, or an assumption);
    ``ignored`` counts what was left out, by entity type; ``fixes`` lists repairs already made;
    ``gap_tolerance`` is the reader's default endpoint tolerance, a fraction of the drawing size.
    """

    curves: CurveSet
    unit: DrawingUnit
    units_source: str
    format: str
    ignored: dict[str, int]
    fixes: tuple[str, ...]
    gap_tolerance: float

