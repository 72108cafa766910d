"""Which outlines of a sheet are parts: what a designer would call a link, and what is a mark (drawing units).

A sheet holds more closed outlines than parts. Outlines without joints (no POINT, no round hole),
which no mechanism can use, are sorted out here; outlines with joints are always parts:

- an outline without joints and without holes lying in the material of an outline on another layer
  (a round one may carry a POINT at its centre) is a likely hole or slot drawn on its own layer: a
  problem that leaves out both, since the part would import solid where the drawing cuts it; the fix
  names ``--hole-layers`` (:mod:`.hole_layers`);
- an outline without joints inside a hole of another outline is a pin or a mark drawn in that hole:
  skipped;
- an outline without joints smaller than ``MARK_FRACTION`` of the sheet (its bounding box's diagonal
  against the drawing's) is a text glyph or a drill mark: skipped.

The open chains of a layer (problems) that cross or touch an outline of that layer skipped as a mark,
no more than ``MARK_CHAIN`` times its size (a drill mark's cross), are skipped with it.

Layers whose name says they hold annotation (``ANNOTATION_WORDS``: text, dimensions, title block,
border) are not read at all unless named in ``--layers``; the layer named ``frame`` is not among
them, being a mechanism's ground by name (:mod:`.assembly`).
"""

from __future__ import annotations

import re
from collections.abc import Collection, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from linkstress.importers.chaining import Report
from linkstress.importers.contours import OpenChain, Outline
from linkstress.importers.problems import (
    HOLE_ON_OWN_LAYER, IN_A_HOLE, SMALL_OUTLINE, Skipped, SketchProblem,
)
from linkstress.messages import capped
from linkstress.geometry.profile import HOLE_CENTRE_TOLERANCE

MARK_FRACTION = 0.02
"""An outline without joints smaller than this fraction of the sheet is a glyph or a mark: on an A4
sheet (364 mm across) a letter 2.5 mm tall is about 0.9 % of it, a 5 mm drill mark's bounding box 1.9 %."""
MARK_CHAIN = 3.0
"""An open chain crossing a mark is part of it (a cross through a drill mark's circle) up to this many
times the mark's size (bounding-box diagonals)."""
ANNOTATION_WORDS = frozenset({
    "text", "texts", "txt", "annotation", "annotations", "anno", "annot", "dimension", "dimensions", "dim",
    "dims", "title", "titleblock", "titles", "border", "borders", "label", "labels", "notes",
})
"""Words (a layer name's parts between non-letters, any case) that name a layer of annotation."""


def annotation_layers(layers: Collection[str | None], asked: Collection[str] = ()) -> list[str]:
    """The layers among ``layers`` whose name says they hold annotation (``TEXT``, ``Dimensions``,
    ``title-block``, ``AM_BORDER``), less those ``asked`` for by name."""
    found = []
    for layer in layers:
        if layer is None or layer in asked:
            continue
        words = {word.lower() for word in re.split(r"[^A-Za-z]+|(?<=[a-z])(?=[A-Z])", layer) if word}
        if words & ANNOTATION_WORDS:
            found.append(layer)
    return found


@dataclass(frozen=True)
class Sorted:
    """Which outlines are parts (``keep``), what was skipped, the problems of holes on their own layer,
    and the curves of the open chains skipped with a mark (``marked``: their problems go)."""

    keep: NDArray[np.bool_]
    skipped: tuple[Skipped, ...]
    problems: tuple[SketchProblem, ...]
    marked: frozenset[str] = frozenset()


def sort_outlines(outlines: list[Outline], joints: list[NDArray[np.float64]], size: float,
                  report: Report, chains: Sequence[OpenChain] = ()) -> Sorted:
    """Sort ``outlines`` (drawing units) whose joints, as they would import, are ``joints`` (each (n, 2),
    POINTs or round holes' centres), on a sheet ``size`` across, with the open ``chains`` that cross the
    marks (see the module)."""
    n = len(outlines)
    keep = np.ones(n, bool)
    if n == 0:
        return Sorted(keep, (), ())
    marks = _Marks(outlines, list(chains), report)
    polygons = np.array([outline.polygon for outline in outlines], dtype=object)
    layers = np.array([outline.layer for outline in outlines], dtype=object)
    jointless = np.array([len(j) == 0 for j in joints])
    candidate = np.array([not outline.holes and (len(j) == 0 or _centre_only(outline, j))
                          for outline, j in zip(outlines, joints)])
    problems: list[SketchProblem] = []
    at, container = shapely.STRtree(polygons).query(polygons[candidate], predicate="within")
    at = np.flatnonzero(candidate)[at]
    other_layer = layers[at] != layers[container]
    at, container = at[other_layer], container[other_layer]
    for c in sorted(set(container.tolist())):  # (np.unique would load numpy.ma: docs/design.md, start-up)
        inside = at[container == c]
        keep[inside] = False
        keep[c] = False
        problems.append(_hole_on_own_layer(outlines[c], [outlines[i] for i in inside.tolist()], report))
    skipped = []
    counts = shapely.get_num_interior_rings(polygons)
    if counts.sum():
        hole_owner = np.repeat(np.arange(n), counts)
        rings = shapely.get_interior_ring(polygons[hole_owner], np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts))
        at, hole = shapely.STRtree(shapely.polygons(rings)).query(polygons, predicate="within")
        in_hole = np.zeros(n, bool)
        in_hole[at[hole_owner[hole] != at]] = True
        in_hole &= keep & jointless
        if in_hole.any():
            keep &= ~in_hole
            skipped += marks.grouped(np.flatnonzero(in_hole), IN_A_HOLE,
                                     "outline(s) without joints inside a hole of another link: taken for pins or marks "
                                     "drawn in the hole and skipped")
    box = shapely.bounds(polygons)
    small = keep & jointless & (np.hypot(box[:, 2] - box[:, 0], box[:, 3] - box[:, 1]) < MARK_FRACTION * size)
    if small.any():
        keep &= ~small
        skipped += marks.grouped(np.flatnonzero(small), SMALL_OUTLINE,
                                 f"outline(s) without joints smaller than {100 * MARK_FRACTION:g} % of the sheet: taken "
                                 "for text glyphs or drill marks and skipped; a part needs its joints (POINTs or round "
                                 "pin holes)")
    return Sorted(keep, tuple(skipped), tuple(problems), frozenset(marks.marked))


def _extent(geometries) -> NDArray[np.float64]:
    """The diagonal of each geometry's bounding box."""
    box = shapely.bounds(np.asarray(geometries, dtype=object)).reshape(-1, 4)
    return np.hypot(box[:, 2] - box[:, 0], box[:, 3] - box[:, 1])


def _centre_only(outline: Outline, joints: NDArray[np.float64]) -> bool:
    """A round outline whose joints all sit at its centre: a pin hole drawn with its centre mark."""
    circle = outline.shell.circle
    return circle is not None and bool(
        (np.hypot(*(joints - np.array(circle[:2])).T) <= HOLE_CENTRE_TOLERANCE * circle[2]).all())


def _hole_on_own_layer(link: Outline, inside: list[Outline], report: Report) -> SketchProblem:
    """The problem of outlines ``inside`` the material of ``link``, on other layers."""
    layers = list(dict.fromkeys(outline.layer for outline in inside))
    names = [report.curve(outline.shell.pieces[0]) for outline in inside]
    given = ",".join(str(layer) for layer in layers)
    scene = ", ".join(f'"{layer}"' for layer in layers)
    first = inside[0].shell.xy[0]
    return SketchProblem(
        link.layer, (float(first[0]), float(first[1])), report.unit,
        tuple(report.curve(k) for outline in inside for k in outline.shell.pieces)
        + tuple(report.curve(k) for k in link.shell.pieces),
        f"{len(inside)} outline(s) on layer(s) {capped(repr(layer) for layer in layers)} lie wholly inside the "
        f"link through {report.curve(link.shell.pieces[0])}, through {capped(names)}: likely holes or slots drawn "
        "on their own layer, which would leave the link solid there; the link and they are left out",
        f"give --hole-layers {given} (a scene link: hole_layers = [{scene}]) to take them as the link's holes, "
        f"or --exclude-layers {given} if they are marks",
        HOLE_ON_OWN_LAYER,
    )


class _Marks:
    """Outlines skipped as marks, grouped per layer, with the small open ``chains`` that cross them."""

    def __init__(self, outlines: list[Outline], chains: list[OpenChain], report: Report) -> None:
        self.outlines, self.chains, self.report = outlines, chains, report
        self.marked: set[str] = set()

    def grouped(self, which: NDArray[np.intp], kind: str, note: str) -> list[Skipped]:
        """A :class:`Skipped` per layer for the outlines ``which``: how many, the first few by their curves,
        and the chains of that layer crossing them."""
        by_layer: dict[str | None, list[int]] = {}
        for k in which.tolist():
            by_layer.setdefault(self.outlines[k].layer, []).append(k)
        found = []
        for layer, ks in by_layer.items():
            outlines = [self.outlines[k] for k in ks]
            crossing = self._crossing(layer, outlines)
            curves = [self.report.curve(p) for o in outlines for loop in (o.shell, *o.holes) for p in loop.pieces]
            lines = f", with {len(crossing)} open chain(s) crossing them (a drill mark's cross)" if crossing else ""
            first = outlines[0].shell.xy[0]
            found.append(Skipped(
                kind, layer, (float(first[0]), float(first[1])), self.report.unit,
                tuple(curves) + tuple(sorted(name for chain in crossing for name in chain.curves)),
                f"{len(ks)} {note}{lines}; through "
                f"{capped(self.report.curve(o.shell.pieces[0]) for o in outlines)}",
                len(ks),
            ))
        return found

    def _crossing(self, layer: str | None, outlines: list[Outline]) -> list[OpenChain]:
        """The chains of ``layer`` not yet taken that cross or touch one of ``outlines``, at most
        ``MARK_CHAIN`` times its size."""
        mine = [chain for chain in self.chains if chain.layer == layer and not chain.curves <= self.marked]
        if not mine:
            return []
        polygons = [o.polygon for o in outlines]
        at, mark = shapely.STRtree(polygons).query([c.lines for c in mine], predicate="intersects")
        small = _extent([mine[k].lines for k in at.tolist()]) <= MARK_CHAIN * _extent([polygons[m] for m in mark.tolist()])
        crossing = [mine[k] for k in sorted(set(at[small].tolist()))]
        for chain in crossing:
            self.marked |= chain.curves
        return crossing

