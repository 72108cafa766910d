"""Holes drawn on layers of their own (``--hole-layers``, a scene link's ``hole_layers``), drawing units.

Some drawings keep a part's holes and slots on a layer apart from its outline ("HOLES", "DRILL").
Read as any other layer, each such outline would be a solid link of its own lying on a part that
imports solid. Named as hole layers, their closed outlines become holes of the links they lie in,
exactly like holes drawn on the link's own layer: a round one is a pin hole (its centre a joint
when the link has no POINTs), and a POINT in it must sit at its centre.

Each outline of a hole layer must lie in the material of the links it touches: wholly inside a link
and clear of its edge and its other holes, it is a hole of that link (of each link it so lies in:
links drawn assembled overlap at their pins); inside a hole the link already has, it adds nothing
(drawn twice, or a mark); crossing or touching a link's edge or one of its holes it is a problem
that leaves that link out (it would import with a bite that is not in the part, or solid where the
part is cut); lying in no link it is a problem of its own. What a hole layer leaves out as a problem
(an open slot, two crossing holes) leaves out the links it lies in: they would import solid there.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import replace

import numpy as np
import shapely
from shapely.geometry import Polygon

from linkstress.importers.chaining import Report
from linkstress.importers.contours import Outline
from linkstress.importers.problems import HOLE_CROSSING_EDGE, HOLE_IN_NO_LINK, WITH_ANOTHER, SketchProblem


def take_holes(outlines: list[Outline], hole_layers: Collection[str], report: Report, fixes: list[str],
               found: list[SketchProblem]) -> tuple[list[Outline], list[SketchProblem]]:
    """``outlines`` less those on ``hole_layers``, which become holes of the others they lie in; the
    problems of hole outlines that cross a link's edge or a hole (that link left out) or lie in no link,
    and of links that a problem already ``found`` on a hole layer lies in (left out)."""
    on_hole_layer = [outline.layer in hole_layers for outline in outlines]
    links = [outline for outline, hole in zip(outlines, on_hole_layer) if not hole]
    holes = _holes([outline for outline, hole in zip(outlines, on_hole_layer) if hole], report, fixes)
    added, spoilt, problems = _attach(links, holes, report, fixes)
    shells = np.array([Polygon(link.shell.xy) for link in links], dtype=object)
    for problem in found:
        if problem.layer in hole_layers and len(shells):
            for k in np.flatnonzero(shapely.covers(shells, shapely.Point(problem.at))).tolist():
                if k not in spoilt:
                    spoilt.add(k)
                    problems.append(_spoilt(problem, links[k], report))
    kept = []
    for k, link in enumerate(links):
        if k in spoilt:
            continue
        if k in added:
            holes_of = sorted([*link.holes, *added[k]], key=lambda loop: tuple(loop.polygon.bounds[:2]))
            link = replace(link, holes=tuple(holes_of))
        kept.append(link)
    return kept, problems


def _holes(outlines: list[Outline], report: Report, fixes: list[str]) -> list[Outline]:
    """The hole layers' outlines less those inside another (an island in a hole, a mark), as a fix."""
    if not outlines:
        return []
    regions = np.array([Polygon(outline.shell.xy) for outline in outlines], dtype=object)
    island_at, around = shapely.STRtree(regions).query(regions, predicate="within")
    islands = np.zeros(len(outlines), bool)
    islands[island_at[island_at != around]] = True
    inner = [loop for outline in outlines for loop in outline.holes]
    if islands.any() or inner:
        first = outlines[int(np.argmax(islands))].shell if islands.any() else inner[0]
        fixes.append(f"{int(islands.sum()) + len(inner)} outline(s) of the hole layers lie inside another hole's "
                     f"outline, e.g. the one through {report.curve(first.pieces[0])}: not holes, skipped")
    return [outline for outline, island in zip(outlines, islands) if not island]


def _attach(links: list[Outline], holes: list[Outline], report: Report,
            fixes: list[str]) -> tuple[dict[int, list], set[int], list[SketchProblem]]:
    """Which ``holes`` each link (by index) gets, which links a hole crosses, and the problems."""
    added: dict[int, list] = {}
    spoilt: set[int] = set()
    problems: list[SketchProblem] = []
    if not holes:
        return added, spoilt, problems
    material = [link.polygon for link in links]
    regions = np.array([Polygon(hole.shell.xy) for hole in holes], dtype=object)
    touched_at, link_at = shapely.STRtree([Polygon(link.shell.xy) for link in links]).query(
        regions, predicate="intersects") if links else (np.zeros(0, int), np.zeros(0, int))
    inside_holes = 0
    for h, hole in enumerate(holes):
        mine = link_at[touched_at == h]
        if not len(mine):
            problems.append(_in_no_link(hole, report))
        for k in mine.tolist():
            if shapely.contains_properly(material[k], regions[h]):
                added.setdefault(k, []).append(hole.shell)
            elif any(Polygon(ring).covers(regions[h]) for ring in material[k].interiors):
                inside_holes += 1
            elif k not in spoilt:
                spoilt.add(k)
                problems.append(_crossing(hole, links[k], report))
    if inside_holes:
        fixes.append(f"{inside_holes} outline(s) of the hole layers lie in holes their links already have (drawn "
                     "twice, or marks): they add nothing")
    return added, spoilt, problems


def _in_no_link(hole: Outline, report: Report) -> SketchProblem:
    first = report.curve(hole.shell.pieces[0])
    return SketchProblem(
        hole.layer, (float(hole.shell.xy[0, 0]), float(hole.shell.xy[0, 1])), report.unit,
        tuple(report.curve(k) for k in hole.shell.pieces),
        f"the outline through {first} on hole layer {hole.layer!r} lies in no link",
        "a hole layer holds only holes of the links drawn on other layers: move it into its link, or draw it on "
        "another layer if it is a part",
        HOLE_IN_NO_LINK,
    )


def _spoilt(problem: SketchProblem, link: Outline, report: Report) -> SketchProblem:
    return SketchProblem(
        link.layer, problem.at, report.unit, tuple(report.curve(k) for k in link.shell.pieces),
        f"the link through {report.curve(link.shell.pieces[0])} is left out: its hole layer {problem.layer!r} has a "
        f"problem inside it at {report.at(problem.at)} ({problem.problem})",
        "fix that problem: without the holes it leaves out the link would import solid there",
        WITH_ANOTHER,
    )


def _crossing(hole: Outline, link: Outline, report: Report) -> SketchProblem:
    first, edge = report.curve(hole.shell.pieces[0]), report.curve(link.shell.pieces[0])
    meet = shapely.intersection(shapely.boundary(Polygon(hole.shell.xy)), shapely.boundary(link.polygon))
    where = meet.representative_point() if not meet.is_empty else shapely.Point(hole.shell.xy[0])
    return SketchProblem(
        link.layer, (float(where.x), float(where.y)), report.unit,
        tuple(report.curve(k) for k in (*hole.shell.pieces, *link.shell.pieces)),
        f"the outline through {first} on hole layer {hole.layer!r} crosses or touches the edge or a hole of the "
        f"link through {edge} at {report.at((where.x, where.y))}: that link is left out",
        "a hole lies wholly in its link's material, clear of its edge and its other holes: redraw the hole, or "
        "leave its layer out of --hole-layers if it is no hole of this link",
        HOLE_CROSSING_EDGE,
    )
