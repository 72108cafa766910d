"""From flattened pieces to outlines with holes, as real sketches need.

- Curves no larger than the gap tolerance are dropped, and so are curves drawn twice on one layer (open ones:
  same ends and vertex mean within the tolerance, looked for only where ends branch; closed ones:
  the same region, whatever vertex they start at and whichever way round), and after chaining,
  loops of one layer enclosing the same region (an outline drawn as a polyline and again as
  LINEs): all are reported as fixes. Not across layers: links drawn assembled have the same pin
  hole on two layers.
- Open pieces are chained into rings (:mod:`.chaining`); consecutive vertices closer than
  ``DUPLICATE_VERTEX`` x the drawing size merge, and rings that enclose no area are dropped.
- Each layer is chained, checked and nested on its own: links drawn assembled, each on its own
  layer, overlap at their joints.
- All rings nest by containment within their layer: a ring inside an even number of rings is an
  outer boundary, inside an odd number a hole of the innermost one (so a part drawn inside a hole is
  a link of its own).
- A dirty sheet keeps its clean outlines. A chain that stays open or branches, a ring that crosses
  itself, and two rings of one layer that cross, touch or share a cut are problems
  (:class:`SketchProblem`): those curves or rings are left out, and so is an outline whose hole is
  left out (it must not import without it), with a problem saying so.

Everything here is in drawing units; messages say which.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from linkstress.errors import SketchError
from linkstress.importers.circles import with_circle
from linkstress.importers.chaining import Ends, Report, Rings, chain, close_pairs, closed_rings
from linkstress.importers.flatten import Pieces
from linkstress.importers.neighbours import pairs_within
from linkstress.importers.primitives import Origin
from linkstress.importers.frames import LayerLoops, find_frames
from linkstress.importers.problems import (
    BRANCH, CROSSING, CUT_BY_CHAIN, OPEN_CHAIN, SELF_CROSSING, SHARED_CUT, WITH_ANOTHER, Skipped, SketchProblem,
)

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
    """An outer boundary and its holes (loops, drawing units), on ``layer`` (its shell's)."""

    shell: Loop
    holes: tuple[Loop, ...]
    layer: str | None = None

    @cached_property
    def polygon(self) -> Polygon:
        """Shell counter-clockwise, holes clockwise."""
        return orient(Polygon(self.shell.xy, [h.xy for h in self.holes]), 1.0)

    @property
    def largest_gap(self) -> tuple[float, tuple[float, float] | None]:
        loop = max([self.shell, *self.holes], key=lambda lp: lp.gap)
        return loop.gap, loop.gap_at


@dataclass(frozen=True)
class OpenChain:
    """A chain of curves left open (a problem), on ``layer``: its ``lines`` (drawing units) and the names
    of its ``curves`` (as problems name them)."""

    layer: str | None
    lines: object
    curves: frozenset[str]


@dataclass(frozen=True)
class Contours:
    """The clean outlines, the repairs made, the problems left out, the page frames skipped and the open
    chains left out (drawing units)."""

    outlines: tuple[Outline, ...]
    fixes: tuple[str, ...]
    problems: tuple[SketchProblem, ...]
    skipped: tuple[Skipped, ...] = ()
    chains: tuple[OpenChain, ...] = ()


def build_contours(pieces: Pieces, origins: list[Origin], tolerance: float, size: float, unit: str,
                   use: NDArray[np.bool_] | None = None, points: NDArray[np.float64] | None = None,
                   point_layers: list[str | None] = (), hole_layers: tuple[str, ...] = ()) -> Contours:
    """Outlines with holes from ``pieces`` (one per origin; only those ``use`` marks, default all),
    closing gaps up to ``tolerance``.

    Each layer is its own drawing: its curves chain only with each other, and its outlines must not
    cross or touch each other, while outlines on different layers may (links drawn assembled
    overlap at their joints). A page frame around the sheet (:mod:`.frames`; ``points``, the POINTs
    read, and their ``point_layers`` tell a frame from a part; loops on ``hole_layers`` are no parts) is
    skipped with its marks before
    outlines nest. What cannot make a clean outline is left out as a problem; raises SketchError
    only when nothing encloses an area and there is no problem to tell why. ``tolerance`` and
    ``size`` (the drawing's bounding-box diagonal) are in drawing units, named ``unit``.
    """
    report = Report(origins, unit, size)
    fixes: list[str] = []
    keep = np.ones(len(pieces), bool) if use is None else use.copy()
    keep &= ~_small(pieces, keep, tolerance, report, fixes)
    layers = np.array([origin[2] for origin in origins], dtype=object)
    read: list[LayerLoops] = []
    found: list[list[SketchProblem]] = []
    for layer in dict.fromkeys(layers[keep].tolist()):
        problems: list[SketchProblem] = []
        on_layer = keep & (layers == layer)
        # Only within a layer: links drawn assembled have the same pin hole on two layers.
        on_layer &= ~_duplicates(pieces, np.flatnonzero(on_layer & pieces.closed), tolerance, report, fixes)
        loops, bad, left_out = _layer_loops(pieces, on_layer, tolerance, size, report, layer, fixes, problems)
        bad |= _self_crossing(loops, report, layer, problems)
        read.append(LayerLoops(layer, loops, bad, left_out))
        found.append(problems)
    points = np.zeros((0, 2)) if points is None else points
    frames = find_frames(read, pieces, points, list(point_layers), tolerance, report, hole_layers)
    framing = {report.curve(k) for k in frames.curves}
    outlines: list[Outline] = []
    problems = []
    chains: list[OpenChain] = []
    for k, layer_loops in enumerate(read):
        kept = ~frames.loops[k]
        loops = [loop for loop, keep_it in zip(layer_loops.loops, kept) if keep_it]
        left_out = [chain for chain, mark in zip(layer_loops.chains, frames.chains[k]) if not mark]
        mine = [p for p in found[k] if not (p.kind in (OPEN_CHAIN, BRANCH) and set(p.entities) <= framing)]
        bad = layer_loops.bad[kept] | _within_open(loops, pieces, left_out, report, layer_loops.layer, mine)
        bad |= _crossing(loops, tolerance, report, layer_loops.layer, mine)
        nested = _nest(loops, bad, report, layer_loops.layer, mine)
        outlines += [replace(outline, layer=layer_loops.layer)
                     for outline in _not_cut(nested, pieces, left_out, tolerance, report, layer_loops.layer, mine)]
        problems += mine
        chains += [OpenChain(layer_loops.layer,
                             shapely.multilinestrings([shapely.linestrings(pieces.vertices(int(p))) for p in chain]),
                             frozenset(report.curve(int(p)) for p in chain)) for chain in left_out]
    if not outlines and not problems and not frames.skipped:
        raise SketchError("no closed outline: the drawing has no curves that enclose an area")
    return Contours(tuple(sorted(outlines, key=lambda o: _lower_left(o.shell))), tuple(fixes), tuple(problems),
                    frames.skipped, tuple(chains))


def _layer_loops(pieces: Pieces, keep: NDArray[np.bool_], tolerance: float, size: float, report: Report,
                 layer: str | None, fixes: list[str], problems: list[SketchProblem],
                 ) -> tuple[list[Loop], NDArray[np.bool_], list[NDArray[np.intp]]]:
    """The closed loops of the pieces ``keep`` (one layer's), curves drawn twice dropped, open or
    branched chains left out as problems; no loop found bad yet; and the pieces of every chain left
    out.

    Curves that dangle (a tick mark or leader ending on an outline's corner, a stray line) are taken
    off first, so that the outline they touch still closes; they are listed like any open chain."""
    ends = Ends.of(pieces, np.flatnonzero(keep & ~pieces.closed))
    branched = ends.branched(tolerance)
    if branched.any():
        suspects = np.unique(ends.idx[np.flatnonzero(branched) // 2])
        twice = _duplicates(pieces, suspects, tolerance, report, fixes)
        if twice.any():
            keep = keep & ~twice
            ends = Ends.of(pieces, np.flatnonzero(keep & ~pieces.closed))
    rounding = DUPLICATE_VERTEX * size
    core, dangling = dangling_pieces(ends, tolerance)
    chained, open_problems, left_out = chain(pieces, Ends.of(pieces, core), tolerance, rounding, report, layer)
    if len(dangling):
        _, dangling_problems, dangling_out = chain(pieces, Ends.of(pieces, dangling), tolerance, rounding, report, layer)
        open_problems, left_out = open_problems + dangling_problems, left_out + dangling_out
    problems += open_problems
    rings = Rings.concatenate(closed_rings(pieces, np.flatnonzero(keep & pieces.closed), tolerance), chained)
    loops = [with_circle(loop, pieces) for loop in _loops(rings, rounding, report, fixes)] if len(rings) else []
    loops = _drop_repeated_loops(loops, tolerance, report, fixes)
    return loops, np.zeros(len(loops), bool), left_out


def dangling_pieces(ends: Ends, tolerance: float) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """The open pieces of ``ends`` split into those that can close into rings and those that dangle:
    a piece with an end no other end is within ``tolerance`` of is taken off, and so on until every
    end left meets another (trees hanging off a ring come off leaf by leaf; a ring with a gap comes
    off whole, as an open chain)."""
    n = len(ends.idx)
    if n == 0:
        return ends.idx, ends.idx
    pairs = pairs_within(ends.xy, tolerance)  # a piece's own ends too: a ring of one
    neighbours = [[] for _ in range(2 * n)]
    for a, b in pairs.tolist():
        neighbours[a].append(b)
        neighbours[b].append(a)
    degree = np.array([len(x) for x in neighbours])
    alive = np.ones(n, bool)
    todo = list(np.flatnonzero(degree == 0) // 2)
    while todo:
        piece = todo.pop()
        if not alive[piece]:
            continue
        alive[piece] = False
        for end in (2 * piece, 2 * piece + 1):
            for other in neighbours[end]:
                degree[other] -= 1
                if degree[other] == 0 and alive[other // 2]:
                    todo.append(other // 2)
    return ends.idx[alive], ends.idx[~alive]


def _within_open(loops: list[Loop], pieces: Pieces, left_out: list[NDArray[np.intp]], report: Report,
                 layer: str | None, problems: list[SketchProblem]) -> NDArray[np.bool_]:
    """Loops inside the convex hull of a chain left open: they may be its holes, which without it
    would import as parts of their own (a hole as a solid disc), so they are left out with it."""
    inside = np.zeros(len(loops), bool)
    if not loops or not left_out:
        return inside
    hulls = np.array([
        shapely.convex_hull(shapely.multipoints(np.concatenate([pieces.vertices(k) for k in chain_pieces])))
        for chain_pieces in left_out
    ], dtype=object)
    # A straight stray line encloses nothing: only hulls with an area can hold holes.
    solid = np.flatnonzero(shapely.area(hulls) > 0)
    probes = shapely.points([loop.xy[0] for loop in loops])
    loop_at, hull_at = shapely.STRtree(hulls[solid]).query(probes, predicate="within")
    hull_at = solid[hull_at]
    inside[loop_at] = True
    for h in np.unique(hull_at).tolist():
        swallowed = loop_at[hull_at == h]
        first = loops[int(swallowed[0])]
        problems.append(SketchProblem(
            layer, (float(first.xy[0, 0]), float(first.xy[0, 1])), report.unit,
            tuple(report.curve(k) for i in swallowed.tolist() for k in loops[i].pieces),
            f"{len(swallowed)} closed curve(s) inside the open chain through {report.curve(int(left_out[h][0]))} "
            f"are left out with it, e.g. the one through {report.curve(first.pieces[0])}: they may be its holes",
            "close that chain (see its problem)", WITH_ANOTHER,
        ))
    return inside


def _not_cut(outlines: list[Outline], pieces: Pieces, left_out: list[NDArray[np.intp]], tolerance: float,
             report: Report, layer: str | None, problems: list[SketchProblem]) -> list[Outline]:
    """``outlines`` less those a chain left open cuts into: a chain with an end in their material,
    more than ``tolerance`` from its edges (a living hinge's slits, a slot whose outline does not
    close, engraving), or with an end on an edge from which it runs through the material (a line
    dividing a part in two). Imported without the chain, such an outline would be solid where the
    drawing cuts it. A chain that touches an outline from outside (a leader, a tick mark), lies
    along its edge, or crosses it from outside to outside (a construction line) leaves it."""
    if not outlines or not left_out:
        return outlines
    material = np.array([outline.polygon for outline in outlines], dtype=object)
    lines = [shapely.multilinestrings([shapely.linestrings(pieces.vertices(k)) for k in chain_pieces])
             for chain_pieces in left_out]
    piece = np.concatenate(left_out)
    chain_of = np.concatenate([np.full(len(c), i) for i, c in enumerate(left_out)] * 2)
    points = shapely.points(np.concatenate([pieces.xy[pieces.start[piece]], pieces.xy[pieces.start[piece + 1] - 1]]))
    end_at, outline_at = shapely.STRtree(material).query(points, predicate="dwithin", distance=tolerance)
    inside = shapely.within(points[end_at], material[outline_at])
    deep = inside & (shapely.distance(points[end_at], shapely.boundary(material[outline_at])) > tolerance)
    cut_by: dict[int, list[int]] = {}
    core: dict[int, object] = {}
    for e, o, is_deep in zip(end_at.tolist(), outline_at.tolist(), deep.tolist()):
        c = int(chain_of[e])
        if c in cut_by.get(o, ()):
            continue
        if not is_deep:
            if o not in core:
                core[o] = shapely.buffer(material[o], -tolerance)
            if shapely.length(shapely.intersection(lines[c], core[o])) <= tolerance:
                continue
        cut_by.setdefault(o, []).append(c)
    keep = np.ones(len(outlines), bool)
    for o, chains in sorted(cut_by.items()):
        keep[o] = False
        shell = outlines[o].shell
        problems.append(SketchProblem(
            layer, (float(shell.xy[0, 0]), float(shell.xy[0, 1])), report.unit,
            tuple(report.curve(int(k)) for c in chains for k in left_out[c]),
            f"the outline through {report.curve(shell.pieces[0])} is left out: {len(chains)} open chain(s) cut into "
            f"its material, e.g. the one through {report.curve(int(left_out[chains[0]][0]))}, which would import as "
            "solid what the drawing cuts",
            "draw a slit or slot as a closed outline, or move marks and engraving to a layer of their own",
            CUT_BY_CHAIN,
        ))
    return [outline for outline, k in zip(outlines, keep) if k]


# -- clean-up -----------------------------------------------------------------------------------


def _piece_boxes(pieces: Pieces) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    starts = pieces.start[:-1]
    return np.minimum.reduceat(pieces.xy, starts), np.maximum.reduceat(pieces.xy, starts)


def _small(pieces: Pieces, keep: NDArray[np.bool_], tolerance: float, report: Report,
           fixes: list[str]) -> NDArray[np.bool_]:
    """Pieces among ``keep`` whose bounding box is no larger than ``tolerance``."""
    if len(pieces) == 0:
        return np.zeros(0, bool)
    lo, hi = _piece_boxes(pieces)
    small = (np.hypot(*(hi - lo).T) <= tolerance) & keep
    if small.any():
        k = int(np.argmax(small))
        fixes.append(
            f"dropped {int(small.sum())} curve(s) no larger than the gap tolerance "
            f"{report.length(tolerance)}, e.g. {report.curve(k)} at {report.at(lo[k])}"
        )
    return small


def _duplicates(pieces: Pieces, idx: NDArray[np.intp], tolerance: float, report: Report,
                fixes: list[str]) -> NDArray[np.bool_]:
    """Among pieces ``idx``, those repeating an earlier one within ``tolerance``: open pieces with
    the same ends (either way round) and vertex mean; closed pieces enclosing the same region."""
    twice = np.zeros(len(pieces), bool)
    closed = pieces.closed[idx]
    pairs = np.concatenate([
        _same_open(pieces, idx[~closed], tolerance), _same_closed(pieces, idx[closed], tolerance),
    ])
    if not len(pairs):
        return twice
    twice[pairs[:, 1]] = True
    i, j = pairs[0]
    fixes.append(
        f"dropped {int(twice.sum())} curve(s) drawn twice, e.g. {report.curve(j)} repeats "
        f"{report.curve(i)} at {report.at(pieces.xy[pieces.start[i]])}"
    )
    return twice


def _same_open(pieces: Pieces, idx: NDArray[np.intp], tolerance: float) -> NDArray[np.intp]:
    """(M, 2) piece pairs i < j of the open pieces ``idx`` with the same ends and vertex mean."""
    if len(idx) < 2:
        return np.zeros((0, 2), np.intp)
    counts = np.diff(pieces.start)[idx]
    first_vertex = np.cumsum(counts) - counts
    take = np.repeat(pieces.start[idx], counts) + (np.arange(int(counts.sum())) - np.repeat(first_vertex, counts))
    mean = np.add.reduceat(pieces.xy[take], first_vertex) / counts[:, None]
    first, last = pieces.xy[pieces.start[idx]], pieces.xy[pieces.start[idx + 1] - 1]
    swap = (first[:, 0] > last[:, 0]) | ((first[:, 0] == last[:, 0]) & (first[:, 1] > last[:, 1]))
    a, b = np.where(swap[:, None], last, first), np.where(swap[:, None], first, last)
    pairs = close_pairs(np.hstack([a, b, mean]), tolerance, "curves")
    return np.sort(idx[pairs], axis=1).reshape(-1, 2)


def _same_closed(pieces: Pieces, idx: NDArray[np.intp], tolerance: float) -> NDArray[np.intp]:
    """(M, 2) piece pairs i < j of the closed pieces ``idx`` that enclose the same region, whatever
    vertex they start at, whichever way round, repeating the first vertex at the end or not."""
    idx = idx[np.diff(pieces.start)[idx] >= 3]
    pairs = _same_regions([Polygon(pieces.vertices(k)) for k in idx.tolist()], tolerance)
    return np.sort(idx[pairs], axis=1).reshape(-1, 2)


def _same_regions(polygons: list[Polygon], tolerance: float) -> NDArray[np.intp]:
    """(M, 2) index pairs i < j of ``polygons`` enclosing the same region: the area between them at
    most a band ``tolerance`` wide along the outline. Candidates share their bounding box within
    ``tolerance``."""
    if len(polygons) < 2:
        return np.zeros((0, 2), np.intp)
    polygons = np.array(polygons, dtype=object)
    candidates = close_pairs(shapely.bounds(polygons), tolerance, "curves")
    if not len(candidates):
        return np.zeros((0, 2), np.intp)
    used, inverse = np.unique(candidates, return_inverse=True)
    a, b = shapely.make_valid(polygons[used])[inverse.reshape(-1, 2)].T
    between = shapely.area(shapely.symmetric_difference(a, b))
    same = between <= tolerance * np.maximum(shapely.length(a), shapely.length(b))
    return np.sort(candidates[same], axis=1).reshape(-1, 2)


def _drop_repeated_loops(loops: list[Loop], tolerance: float, report: Report, fixes: list[str]) -> list[Loop]:
    """Loops of one layer enclosing the same region as an earlier one, e.g. an outline drawn as a
    closed polyline and again as LINEs: all but the first dropped, as a fix."""
    pairs = _same_regions([loop.polygon for loop in loops], tolerance)
    if not len(pairs):
        return loops
    twice = np.zeros(len(loops), bool)
    twice[pairs[:, 1]] = True
    i, j = pairs[0]
    fixes.append(
        f"dropped {int(twice.sum())} outline(s) drawn twice, e.g. the one through {report.curve(loops[j].pieces[0])} "
        f"repeats the one through {report.curve(loops[i].pieces[0])} at {report.at(loops[i].xy[0])}"
    )
    return [loop for loop, repeated in zip(loops, twice) if not repeated]


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


def _self_crossing(loops: list[Loop], report: Report, layer: str | None,
                   problems: list[SketchProblem]) -> NDArray[np.bool_]:
    """Loops that cross themselves, a problem each."""
    valid = shapely.is_valid([loop.polygon for loop in loops])
    for k in np.flatnonzero(~valid).tolist():
        reason = shapely.is_valid_reason(loops[k].polygon)
        found = _WHERE.search(reason)
        at = (float(found[1]), float(found[2])) if found else tuple(loops[k].xy[0])
        where = f" at {report.at(at)}" if found else ""
        problems.append(SketchProblem(
            layer, (float(at[0]), float(at[1])), report.unit, _curves(loops[k], report),
            f"the outline through {report.curve(loops[k].pieces[0])} crosses itself{where} ({reason.split('[')[0]})",
            "redraw it as a simple closed curve", SELF_CROSSING,
        ))
    return ~valid


def _crossing(loops: list[Loop], tolerance: float, report: Report, layer: str | None,
              problems: list[SketchProblem]) -> NDArray[np.bool_]:
    """Loops of one layer that cross, touch or share a cut with another, a problem per pair."""
    bad = np.zeros(len(loops), bool)
    if len(loops) < 2:
        return bad
    rings = [loop.polygon.exterior for loop in loops]
    pairs = shapely.STRtree(rings).query(rings, predicate="intersects")
    pairs = pairs[:, pairs[0] < pairs[1]]
    for i, j in pairs.T.tolist():
        bad[[i, j]] = True
        meet = shapely.get_parts(rings[i].intersection(rings[j]))
        cuts = [part for part in meet if part.geom_type == "LineString" and part.length > tolerance]
        first, second = report.curve(loops[i].pieces[0]), report.curve(loops[j].pieces[0])
        if cuts:
            cut = shapely.line_merge(shapely.multilinestrings(cuts))
            longest = max(shapely.get_parts(cut), key=lambda part: part.length)
            a, b = longest.coords[0], longest.coords[-1]
            at, problem = a, (
                f"the outlines of {first} and {second} share the cut from {report.at(a)} to {report.at(b)}"
            )
            fix, kind = "draw them apart, or on separate layers", SHARED_CUT
        else:
            where = meet[0].representative_point()
            at = (where.x, where.y)
            problem = (
                f"outlines cross or touch at {report.at(at)}: the one through {first} and the one through {second}"
            )
            fix, kind = "outlines and holes must not meet: draw them apart, or on separate layers", CROSSING
        problems.append(SketchProblem(
            layer, (float(at[0]), float(at[1])), report.unit, _curves(loops[i], report) + _curves(loops[j], report),
            problem, fix, kind,
        ))
    return bad


def _curves(loop: Loop, report: Report) -> tuple[str, ...]:
    return tuple(report.curve(k) for k in loop.pieces)


def _nest(loops: list[Loop], bad: NDArray[np.bool_], report: Report, layer: str | None,
          problems: list[SketchProblem]) -> list[Outline]:
    """Outer boundaries (inside an even number of loops) with their holes; one that is ``bad``, has a
    bad hole or lies inside a bad loop is left out (the bad loops still nest, so their holes stay
    holes)."""
    if not loops:
        return []
    probes = shapely.points([loop.xy[0] for loop in loops])
    regions = shapely.make_valid(np.array([loop.polygon for loop in loops], dtype=object))
    inside, container = shapely.STRtree(regions).query(probes, predicate="within")
    depth = np.bincount(inside, minlength=len(loops))
    parent = np.full(len(loops), -1)
    for i, j in zip(inside.tolist(), container.tolist()):
        if parent[i] < 0 or depth[j] > depth[parent[i]]:
            parent[i] = j
    holes: dict[int, list[int]] = {}
    for i in np.flatnonzero(depth % 2 == 1).tolist():
        holes.setdefault(int(parent[i]), []).append(i)
    # Inside a bad loop, nesting is no guide (two crossing outlines make their shared pin hole look
    # like a part drawn in a hole): what lies in one is left out with it.
    within_bad = np.zeros(len(loops), bool)
    np.logical_or.at(within_bad, inside, bad[container])
    outlines = []
    for i in np.flatnonzero((depth % 2 == 0) & ~bad & within_bad).tolist():
        container_of = container[inside == i]
        spoiler = loops[int(container_of[bad[container_of]][0])]
        problems.append(SketchProblem(
            layer, (float(loops[i].xy[0, 0]), float(loops[i].xy[0, 1])), report.unit, _curves(loops[i], report),
            f"the outline through {report.curve(loops[i].pieces[0])} is left out: it lies inside the outline through "
            f"{report.curve(spoiler.pieces[0])}, which has a problem",
            "fix that outline", WITH_ANOTHER,
        ))
    for i in np.flatnonzero((depth % 2 == 0) & ~bad & ~within_bad).tolist():
        mine = holes.get(i, [])
        spoilt = [h for h in mine if bad[h]]
        if spoilt:
            hole = loops[spoilt[0]]
            problems.append(SketchProblem(
                layer, (float(loops[i].xy[0, 0]), float(loops[i].xy[0, 1])), report.unit, _curves(loops[i], report),
                f"the outline through {report.curve(loops[i].pieces[0])} is left out: its hole through "
                f"{report.curve(hole.pieces[0])} has a problem, and the link must not import without it",
                "fix that hole", WITH_ANOTHER,
            ))
            continue
        outlines.append(Outline(loops[i], tuple(sorted((loops[h] for h in mine), key=_lower_left))))
    return outlines


def _lower_left(loop: Loop) -> tuple[float, float]:
    minx, miny, _, _ = loop.polygon.bounds
    return minx, miny
