"""DXF entity data to exact primitives: object coordinate systems, degrees and bulges.

ARC, CIRCLE, LWPOLYLINE and 2D POLYLINE are stored in their object coordinate system (OCS), which
for a planar sketch has the extrusion (0, 0, 1) or, for entities mirrored in CAD, (0, 0, -1). The
latter is the WCS seen from below: x is negated, angles become pi - angle and counter-clockwise
becomes clockwise, so a mirrored arc from a0 to a1 is the WCS arc from pi - a1 to pi - a0 and a
mirrored bulge changes sign. Entities whose plane is not parallel to XY are refused: linkstress reads
planar sketches. Both DXF readers (ezdxf objects and the fast tag table) feed these functions, so
the geometry is interpreted once.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import SketchError
from linkstress.importers.primitives import CurveSet, Origin, Polyline, describe

PLANAR = 1e-9
"""An extrusion counts as +-Z when its x and y parts are below this fraction of its length."""


def mirrored(extrusion: NDArray[np.float64], origins: list[Origin]) -> NDArray[np.bool_]:
    """True where the OCS is the mirrored XY plane (extrusion -Z); an error if not parallel to Z."""
    extrusion = np.asarray(extrusion, float).reshape(-1, 3)
    length = np.linalg.norm(extrusion, axis=1)
    tilted = ~(np.hypot(extrusion[:, 0], extrusion[:, 1]) <= PLANAR * length)
    if tilted.any():
        k = int(np.argmax(tilted))
        ex = extrusion[k]
        raise SketchError(
            f"{describe(origins[k])} is not drawn in the XY plane (extrusion ({ex[0]:.3g}, {ex[1]:.3g}, "
            f"{ex[2]:.3g})); linkstress reads planar sketches: draw the links in the XY plane"
        )
    return extrusion[:, 2] < 0


def _keep_positive(radius: NDArray[np.float64], kind: str, ignored: Counter) -> NDArray[np.bool_]:
    good = radius > 0
    if not good.all():
        ignored[f"{kind} (radius <= 0)"] += int((~good).sum())
    return good


def add_circles(curves: CurveSet, rows: NDArray[np.float64], origins: list[Origin], ignored: Counter) -> None:
    """CIRCLE rows (cx, cy, r, ex, ey, ez) in OCS."""
    rows = np.asarray(rows, float).reshape(-1, 6)
    if not len(rows):
        return
    flip = mirrored(rows[:, 3:6], origins)
    good = _keep_positive(rows[:, 2], "CIRCLE", ignored)
    centre = np.column_stack([np.where(flip, -rows[:, 0], rows[:, 0]), rows[:, 1]])[good]
    n = int(good.sum())
    curves.add_arcs(centre, rows[good, 2], np.zeros(n), np.full(n, 2 * math.pi), _pick(origins, good))


def add_arcs(curves: CurveSet, rows: NDArray[np.float64], origins: list[Origin], ignored: Counter) -> None:
    """ARC rows (cx, cy, r, start_deg, end_deg, ex, ey, ez) in OCS, counter-clockwise from start to end."""
    rows = np.asarray(rows, float).reshape(-1, 8)
    if not len(rows):
        return
    flip = mirrored(rows[:, 5:8], origins)
    a0, a1 = np.radians(rows[:, 3]), np.radians(rows[:, 4])
    sweep = np.mod(a1 - a0, 2 * math.pi)
    # Equal angles modulo 360 but different numbers (0 and 360) is a whole circle; identical ones draw nothing.
    sweep = np.where((sweep == 0) & (rows[:, 3] != rows[:, 4]), 2 * math.pi, sweep)
    good = _keep_positive(rows[:, 2], "ARC", ignored) & (sweep > 0)
    if ((sweep == 0) & (rows[:, 2] > 0)).any():
        ignored["ARC (zero sweep)"] += int(((sweep == 0) & (rows[:, 2] > 0)).sum())
    start = np.where(flip, math.pi - a1, a0)
    centre = np.column_stack([np.where(flip, -rows[:, 0], rows[:, 0]), rows[:, 1]])
    curves.add_arcs(centre[good], rows[good, 2], start[good], sweep[good], _pick(origins, good))


def add_ocs_polyline(curves: CurveSet, xy: NDArray[np.float64], bulges: NDArray[np.float64], closed: bool,
                     extrusion: NDArray[np.float64], origin: Origin, ignored: Counter) -> None:
    """An LWPOLYLINE or 2D POLYLINE: OCS vertices (m, 2) and bulges (m,)."""
    xy = np.asarray(xy, float).reshape(-1, 2)
    bulges = np.asarray(bulges, float).reshape(-1)
    if len(xy) < 2:
        ignored[f"{origin[0]} (fewer than two vertices)"] += 1
        return
    if mirrored(extrusion, [origin])[0]:
        xy = xy * [-1.0, 1.0]
        bulges = -bulges
    curves.add_polyline(Polyline(xy, bulges, bool(closed)), origin)


def add_ocs_polylines(curves: CurveSet, vertices: NDArray[np.float64], bulges: NDArray[np.float64],
                      vertex_start: NDArray[np.intp], closed: NDArray[np.bool_], extrusion: NDArray[np.float64],
                      take: NDArray[np.bool_], origins: list[Origin], ignored: Counter) -> None:
    """Many LWPOLYLINEs at once: polyline k has vertices ``vertices[vertex_start[k]:vertex_start[k + 1]]``;
    only those with ``take[k]`` are added, with ``origins`` (one per taken polyline)."""
    counts = np.diff(vertex_start)
    flip = np.zeros(len(take), bool)
    flip[take] = mirrored(extrusion[take], origins)
    sign = np.where(np.repeat(flip, counts), -1.0, 1.0)
    xy = vertices * np.column_stack([sign, np.ones_like(sign)])
    b = bulges * sign
    short = take & (counts < 2)
    if short.any():
        ignored["LWPOLYLINE (fewer than two vertices)"] += int(short.sum())
    chosen = np.flatnonzero(take)
    polylines, kept = [], []
    for k, origin in zip(chosen.tolist(), origins):
        if counts[k] >= 2:
            span = slice(vertex_start[k], vertex_start[k + 1])
            polylines.append(Polyline(xy[span], b[span], bool(closed[k])))
            kept.append(origin)
    curves.add_polylines(polylines, kept, xy, b)


def add_ellipse(curves: CurveSet, centre, major, minor, start: float, end: float, extrusion,
                origin: Origin, ignored: Counter) -> None:
    """An ELLIPSE in WCS: ``centre``, ``major`` and ``minor`` axis vectors, parameters ``start``..``end`` [rad]."""
    mirrored(extrusion, [origin])
    if not (np.linalg.norm(major[:2]) > 0 and np.linalg.norm(minor[:2]) > 0):
        ignored["ELLIPSE (zero axis)"] += 1
        return
    sweep = (end - start) % (2 * math.pi)
    if sweep == 0:
        sweep = 2 * math.pi
    curves.add_conics([centre[:2]], [major[:2]], [minor[:2]], [start], [sweep], [origin])


def _pick(origins: list[Origin], mask: NDArray[np.bool_]) -> list[Origin]:
    if mask.all():
        return origins
    return [o for o, keep in zip(origins, mask.tolist()) if keep]
