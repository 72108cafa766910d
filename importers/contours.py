"""From flattened pieces to outlines with holes, as real sketches need.

- Curves no larger than the gap tolerance are dropped, and so are curves drawn twice (same ends
  and vertex mean within the tolerance; looked for only where ends branch, and among closed
  curves): both are reported as fixes.
- Open pieces are chained into rings (:mod:`.chaining`); consecutive vertices closer than
  ``DUPLICATE_VERTEX`` x the drawing size merge, and rings that enclose no area are dropped.
- Each layer is chained, checked and nested on its own: links drawn assembled, each on its own
  layer, overlap at their joints.
- Rings that cross themselves, or each other on one layer, are errors. The rest nest by
  containment within their layer: a ring inside an even number of rings is an outer boundary,
  inside an odd number a hole of the innermost one (so a part drawn inside a hole is a link of its
  own).

Everything here is in drawing units; messages say which.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from linkstress.errors import SketchError
from linkstress.importers.circles import with_circle
from linkstress.importers.chaining import Ends, Report, Rings, chain, close_pairs, closed_rings
from linkstress.importers.flatten import Pieces
from linkstress.importers.primitives import Origin

DUPLICATE_VERTEX = 1e-9
"""Consecutive ring vertices closer than this fraction of the drawing size are merged."""


@dataclass(frozen=True)
class Loop:
    """A closed ring: vertices ``xy`` (m, 2), first not repeated, and the same as a shapely ``polygon``.

    ``pieces``: indices of the curves it is made of; ``gap``: the largest gap closed in it and
    ``gap_at`` where (None if none); ``gaps``: how many gaps above rounding were closed;
    ``circle``: (cx, cy, r) when every piece is an arc of one circle, else None; ``circle_rule``:
    the rule that found it (:mod:`.circles`, which may also find a circle the pieces do not carry).
    """

    xy: NDArray[np.float64]
    polygon: Polygon
    pieces: tuple[int, ...]
    gap: float
    gap_at: tuple[float, float] | None
    gaps: int
    circle: tuple[float, float, float] | None
    circle_rule: str | None = None


@dataclass(frozen=True)
class Outline:
    """An outer boundary and its holes (loops, drawing units)."""

    shell: Loop
    holes: tuple[Loop, ...]

    @property
    def polygon(self) -> Polygon:
        """Shell counter-clockwise, holes clockwise."""
        return orient(Polygon(self.shell.xy, [h.xy for h in self.holes]), 1.0)

    @property
    def largest_gap(self) -> tuple[float, tuple[float, float] | None]:
        loop = max([self.shell, *self.holes], key=lambda lp: lp.gap)
        return loop.gap, loop.gap_at


@dataclass(frozen=True)
class Contours:
    outlines: tuple[Outline, ...]
    fixes: tuple[str, ...]


def build_contours(pieces: Pieces, origins: list[Origin], tolerance: float, size: float, unit: str) -> Contours:
    """Outlines with holes from ``pieces`` (one per origin), closing gaps up to ``tolerance``.

    Each layer is its own drawing: its curves chain only with each other, and its outlines must not
    cross or touch each other, while outlines on different layers may (links drawn assembled
    overlap at their joints). ``tolerance`` and ``size`` (the drawing's bounding-box diagonal) are in
    drawing units, named ``unit``.
    """
    report = Report(origins, unit, size)
    fixes: list[str] = []
    keep = ~_small(pieces, tolerance, report, fixes)
    keep &= ~_duplicates(pieces, np.flatnonzero(keep & pieces.closed), tolerance, report, fixes)
    layers = np.array([origin[2] for origin in origins], dtype=object)
    loops: list[Loop] = []
    outlines: list[Outline] = []
    for layer in dict.fromkeys(layers[keep].tolist()):
        on_layer = keep & (layers == layer)
        layer_loops = _layer_loops(pieces, on_layer, tolerance, size, report, fixes)
        _check_disjoint(layer_loops, report)
        loops += layer_loops
        outlines += _nest(layer_loops)
    if not loops:
        raise SketchError("no closed outline: the drawing has no curves that enclose an area")
    return Contours(tuple(sorted(outlines, key=lambda o: _lower_left(o.shell))), tuple(fixes))


def _layer_loops(pieces: Pieces, keep: NDArray[np.bool_], tolerance: float, size: float, report: Report,
                 fixes: list[str]) -> list[Loop]:
    """The simple closed loops of the pieces ``keep`` (one layer's), curves drawn twice dropped."""
    ends = Ends.of(pieces, np.flatnonzero(keep & ~pieces.closed))
    branched = ends.branched(tolerance)
    if branched.any():
        suspects = np.unique(ends.idx[np.flatnonzero(branched) // 2])
        twice = _duplicates(pieces, suspects, tolerance, report, fixes)
        if twice.any():
            keep = keep & ~twice
            ends = Ends.of(pieces, np.flatnonzero(keep & ~pieces.closed))
    rounding = DUPLICATE_VERTEX * size
    rings = Rings.concatenate(
        closed_rings(pieces, np.flatnonzero(keep & pieces.closed), tolerance),
        chain(pieces, ends, tolerance, rounding, report),
    )
    loops = [with_circle(loop, pieces) for loop in _loops(rings, rounding, report, fixes)] if len(rings) else []
    _check_simple(loops, report)
    return loops


# -- clean-up -----------------------------------------------------------------------------------


def _piece_boxes(pieces: Pieces) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    starts = pieces.start[:-1]
    return np.minimum.reduceat(pieces.xy, starts), np.maximum.reduceat(pieces.xy, starts)


def _small(pieces: Pieces, tolerance: float, report: Report, fixes: list[str]) -> NDArray[np.bool_]:
    """Pieces whose bounding box is no larger than ``tolerance``."""
    if len(pieces) == 0:
        return np.zeros(0, bool)
    lo, hi = _piece_boxes(pieces)
    small = np.hypot(*(hi - lo).T) <= tolerance
    if small.any():
        k = int(np.argmax(small))
        fixes.append(
            f"dropped {int(small.sum())} curve(s) no larger than the gap tolerance "
            f"{report.length(tolerance)}, e.g. {report.curve(k)} at {report.at(lo[k])}"
        )
    return small


def _duplicates(pieces: Pieces, idx: NDArray[np.intp], tolerance: float, report: Report,
                fixes: list[str]) -> NDArray[np.bool_]:
    """Among pieces ``idx``, those repeating an earlier one: same ends (either way round) and vertex
    mean, or for closed pieces the same bounding box and vertex mean, within ``tolerance``."""
    twice = np.zeros(len(pieces), bool)
    if len(idx) < 2:
        return twice
    counts = np.diff(pieces.start)[idx]
    take = np.repeat(pieces.start[idx], counts) + (np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts))
    xy = pieces.xy[take]
    mean = np.add.reduceat(xy, np.cumsum(counts) - counts) / counts[:, None]
    first, last = pieces.xy[pieces.start[idx]], pieces.xy[pieces.start[idx + 1] - 1]
    swap = (first[:, 0] > last[:, 0]) | ((first[:, 0] == last[:, 0]) & (first[:, 1] > last[:, 1]))
    a, b = np.where(swap[:, None], last, first), np.where(swap[:, None], first, last)
    lo, hi = np.minimum.reduceat(xy, np.cumsum(counts) - counts), np.maximum.reduceat(xy, np.cumsum(counts) - counts)
    signature = np.where(pieces.closed[idx][:, None], np.hstack([lo, hi, mean]), np.hstack([a, b, mean]))
    pairs = close_pairs(signature, tolerance, "curves")
    if not len(pairs):
        return twice
    pairs = np.sort(idx[pairs], axis=1)
    pairs = pairs[pieces.closed[pairs[:, 0]] == pieces.closed[pairs[:, 1]]]
    if not len(pairs):
        return twice
    twice[pairs[:, 1]] = True
    i, j = pairs[0]
    fixes.append(
        f"dropped {int(twice.sum())} curve(s) drawn twice, e.g. {report.curve(j)} repeats "
        f"{report.curve(i)} at {report.at(pieces.xy[pieces.start[i]])}"
    )
    return twice


def _loops(rings: Rings, eps: float, report: Report, fixes: list[str]) -> list[Loop]:
    """Loops of ``rings``, merging consecutive vertices closer than ``eps``, dropping flat rings."""
    counts = np.diff(rings.start)
    ring = np.repeat(np.arange(len(rings)), counts)
    before = np.arange(len(rings.xy)) - 1
    before[rings.start[:-1]] = rings.start[1:] - 1  # the first vertex follows the ring's last
    keep = np.hypot(*(rings.xy - rings.xy[before]).T) > eps
    xy, ring = rings.xy[keep], ring[keep]
    counts = np.bincount(ring, minlength=len(rings))
    start = np.concatenate([[0], np.cumsum(counts)]).astype(np.intp)
    after = np.arange(len(xy)) + 1
    after[start[1:][counts > 0] - 1] = start[:-1][counts > 0]
    cross = xy[:, 0] * xy[after, 1] - xy[after, 0] * xy[:, 1]
    area = np.abs(np.bincount(ring, weights=cross, minlength=len(rings))) / 2
    solid = (counts >= 3) & (area > eps * report.size)
    # A ring whose signed area vanishes may still enclose some (a figure eight): ask its hull.
    for r in np.flatnonzero(~solid & (counts >= 3)).tolist():
        hull = shapely.multipoints(xy[start[r]:start[r + 1]]).convex_hull
        solid[r] = hull.area > eps * report.size
    if not solid.all():
        k = int(np.argmin(solid))
        fixes.append(
            f"dropped {int((~solid).sum())} closed curve(s) enclosing no area, e.g. the one through "
            f"{report.curve(rings.pieces[k][0])}"
        )
    chosen = np.flatnonzero(solid)
    on_chosen = solid[ring]
    polygons = shapely.polygons(shapely.linearrings(xy[on_chosen], indices=np.searchsorted(chosen, ring[on_chosen])))
    return [
        Loop(xy[start[r]:start[r + 1]], polygon, rings.pieces[r], float(rings.gap[r]),
             None if np.isnan(rings.gap_at[r, 0]) else (float(rings.gap_at[r, 0]), float(rings.gap_at[r, 1])),
             int(rings.gaps[r]), rings.circle[r])
        for r, polygon in zip(chosen.tolist(), polygons)
    ]


# -- checks and nesting -------------------------------------------------------------------------

_WHERE = re.compile(r"\[\s*([-+\d.eE]+)\s+([-+\d.eE]+)\s*\]")


def _check_simple(loops: list[Loop], report: Report) -> None:
    valid = shapely.is_valid([loop.polygon for loop in loops])
    if valid.all():
        return
    k = int(np.argmin(valid))
    reason = shapely.is_valid_reason(loops[k].polygon)
    found = _WHERE.search(reason)
    where = f" at {report.at((float(found[1]), float(found[2])))}" if found else ""
    raise SketchError(
        f"the outline through {report.curve(loops[k].pieces[0])} crosses itself{where} "
        f"({reason.split('[')[0]}); redraw it as a simple closed curve"
    )


def _check_disjoint(loops: list[Loop], report: Report) -> None:
    rings = [loop.polygon.exterior for loop in loops]
    pairs = shapely.STRtree(rings).query(rings, predicate="intersects")
    pairs = pairs[:, pairs[0] < pairs[1]]
    if pairs.shape[1] == 0:
        return
    i, j = pairs[:, 0]
    where = rings[i].intersection(rings[j]).representative_point()
    raise SketchError(
        f"outlines cross or touch at {report.at((where.x, where.y))}: the one through "
        f"{report.curve(loops[i].pieces[0])} and the one through {report.curve(loops[j].pieces[0])}; "
        "outlines and holes must not meet"
    )


def _nest(loops: list[Loop]) -> tuple[Outline, ...]:
    """Outer boundaries (inside an even number of loops) with their holes, sorted left to right."""
    probes = shapely.points([loop.xy[0] for loop in loops])
    inside, container = shapely.STRtree([loop.polygon for loop in loops]).query(probes, predicate="within")
    depth = np.bincount(inside, minlength=len(loops))
    parent = np.full(len(loops), -1)
    for i, j in zip(inside.tolist(), container.tolist()):
        if parent[i] < 0 or depth[j] > depth[parent[i]]:
            parent[i] = j
    holes: dict[int, list[Loop]] = {}
    for i in np.flatnonzero(depth % 2 == 1).tolist():
        holes.setdefault(int(parent[i]), []).append(loops[i])
    outlines = [
        Outline(loops[i], tuple(sorted(holes.get(i, []), key=_lower_left)))
        for i in np.flatnonzero(depth % 2 == 0).tolist()
    ]
    return tuple(sorted(outlines, key=lambda o: _lower_left(o.shell)))


def _lower_left(loop: Loop) -> tuple[float, float]:
    minx, miny, _, _ = loop.polygon.bounds
    return minx, miny
