"""Page frames: the border a drawing sheet draws around everything, which is no part (drawing units).

A sheet exported with its frame has a closed outline around every other outline. Nested as outlines
nest, that frame would be a link whose holes are the parts (and the parts' pin holes links of their
own), and the tick marks and title-block lines that end on it would cut into its "material", leaving
it out with the parts inside it. So before outlines nest, a frame is found and skipped:

- it is the largest closed loop of the sheet (any layer), a rectangle (its area that of its smallest
  enclosing rectangle, within ``RECTANGLE``), not crossing itself, and covers every other loop;
- it is no part: it has no joints of its own: no round hole directly inside it on its layer, no
  POINT in its material (inside it and inside no other loop: on its own layer, inside no loop of
  that layer);
- it holds a part: some loop inside it, neither round (a pin hole) nor on a hole layer, holds two
  joints, POINTs or round loops (so a plate with a window is not a frame of its window, nor one whose
  holes are drawn on a layer of their own with a pin marked in one).

A double border (the trimmed sheet and the frame inside it) is two frames: each is looked for again
once the one around it is skipped. The open chains and the joint-free loops that touch a frame
(tick marks, zone dividers, a title block's lines and cells), or touch what touches it, without
entering any other outline, are its marks and are skipped with it.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import NDArray

from linkstress.importers.chaining import Report
from linkstress.importers.flatten import Pieces
from linkstress.importers.problems import PAGE_FRAME, Skipped

if TYPE_CHECKING:
    from linkstress.importers.contours import Loop

RECTANGLE = 1e-6
"""A frame's area and its smallest enclosing rectangle's agree within this fraction."""


@dataclass(frozen=True)
class LayerLoops:
    """One layer's closed loops (``bad``: a problem already leaves it out) and the pieces of each of its
    open chains left out as a problem."""

    layer: str | None
    loops: list["Loop"]
    bad: NDArray[np.bool_]
    chains: list[NDArray[np.intp]]


@dataclass(frozen=True)
class Frames:
    """What a sheet's frames take away: per layer (as given), the loops and the open chains that are
    frames or their marks, the curves of those (to drop their problems) and a :class:`Skipped` per frame."""

    loops: list[NDArray[np.bool_]]
    chains: list[NDArray[np.bool_]]
    curves: frozenset[int]
    skipped: tuple[Skipped, ...]


def find_frames(layers: list[LayerLoops], pieces: Pieces, points: NDArray[np.float64], point_layers: list,
                tolerance: float, report: Report, hole_layers: Collection[str] = ()) -> Frames:
    """The page frames of a sheet and their marks (see the module); ``points`` (n, 2) the POINTs read,
    with their layers; ``tolerance``: the gap tolerance (drawing units); ``hole_layers``: layers that hold
    holes, not parts."""
    owner = [(k, i) for k, layer in enumerate(layers) for i in range(len(layer.loops))]
    frame_loops = [np.zeros(len(layer.loops), bool) for layer in layers]
    chain_marks = [np.zeros(len(layer.chains), bool) for layer in layers]
    if len(owner) < 2:
        return Frames(frame_loops, chain_marks, frozenset(), ())
    loops = [layers[k].loops[i] for k, i in owner]
    polys = np.array([loop.polygon for loop in loops], dtype=object)
    area = shapely.area(polys)
    layer_of = np.array([layers[k].layer for k, _ in owner], dtype=object)
    bad = np.array([bool(layers[k].bad[i]) for k, i in owner])
    circle = np.array([loop.circle is not None for loop in loops])
    # What may hold a part's joints: no round loop (a pin hole), nothing on a hole layer.
    holder = ~circle & np.array([layers[k].layer not in hole_layers for k, _ in owner])
    tree = shapely.STRtree(polys)
    # Which loops each POINT and each round loop's centre lie in (the round loop in itself too).
    point_at, point_in = tree.query(shapely.points(points), predicate="within") if len(points) else (np.zeros(0, int),) * 2
    point_layer = np.array(point_layers, dtype=object)
    centres = np.flatnonzero(circle)
    centre_at, centre_in = tree.query(shapely.points([loops[c].circle[:2] for c in centres]), predicate="within") \
        if len(centres) else (np.zeros(0, int),) * 2
    centre_at = centres[centre_at]
    remaining = np.ones(len(loops), bool)
    found: list[int] = []
    while remaining.sum() >= 2:
        c = int(np.argmax(np.where(remaining, area, -np.inf)))
        others = remaining.copy()
        others[c] = False
        if bad[c] or not _rectangle(polys[c]) or not shapely.covered_by(polys[others], polys[c]).all():
            break
        if not _holds_part(others & holder, point_in, centre_at, centre_in) or _has_joints(
                c, others, layer_of, point_at, point_in, point_layer, centre_at, centre_in):
            break
        found.append(c)
        remaining[c] = False
    if not found:
        return Frames(frame_loops, chain_marks, frozenset(), ())
    for c in found:
        frame_loops[owner[c][0]][owner[c][1]] = True
    marks_of = _marks(found, layers, loops, polys, remaining, circle, point_in, centre_in, pieces, tolerance)
    curves: set[int] = set()
    skipped = []
    for c, (loop_marks, chain_list) in zip(found, marks_of):
        mark_curves = [piece for m in loop_marks for piece in loops[m].pieces]
        for k, j in chain_list:
            chain_marks[k][j] = True
            mark_curves += layers[k].chains[j].tolist()
        for m in loop_marks:
            frame_loops[owner[m][0]][owner[m][1]] = True
        curves |= set(loops[c].pieces) | set(mark_curves)
        count = len(loop_marks) + len(chain_list)
        marks = f", with the {count} mark(s) that touch it (tick marks, title block lines and cells)" if count else ""
        skipped.append(Skipped(
            PAGE_FRAME, layer_of[c], (float(loops[c].xy[0, 0]), float(loops[c].xy[0, 1])), report.unit,
            tuple(report.curve(k) for k in [*loops[c].pieces, *mark_curves]),
            f"the outline through {report.curve(loops[c].pieces[0])} holds every other outline and has no joints of its "
            f"own (no POINT in its material, no round hole): taken for the sheet's frame and skipped{marks}; if it is "
            "a part, give it its joints (POINTs or round pin holes)",
        ))
    return Frames(frame_loops, chain_marks, frozenset(curves), tuple(skipped))


def _rectangle(polygon) -> bool:
    """The polygon fills its smallest enclosing rectangle (within ``RECTANGLE`` of its area)."""
    return bool(abs(shapely.area(shapely.oriented_envelope(polygon)) - polygon.area) <= RECTANGLE * polygon.area)


def _holds_part(holders: NDArray[np.bool_], point_in, centre_at, centre_in) -> bool:
    """Some loop of ``holders`` (those inside a frame that may be parts) holds two joints: POINTs or round
    loops' centres."""
    joints = np.bincount(point_in, minlength=len(holders))
    joints += np.bincount(centre_in[centre_in != centre_at], minlength=len(holders))
    return bool((holders & (joints >= 2)).any())


def _has_joints(c: int, others, layer_of, point_at, point_in, point_layer, centre_at, centre_in) -> bool:
    """Loop ``c`` would have joints as a link: a round loop of its layer directly inside it, or a POINT
    in its material (inside ``c`` and no other loop; one of its own layer, inside no other loop of it)."""
    same = others & (layer_of == layer_of[c])
    inside = np.zeros(len(others), bool)
    inside[centre_at[centre_in == c]] = True
    held = np.zeros(len(others), bool)  # round loops inside another loop of c's layer than c and themselves
    held[centre_at[(centre_in != centre_at) & (centre_in != c) & same[centre_in]]] = True
    if (inside & same & ~held).any():
        return True
    n = len(point_layer)
    in_c, held_same, held_any = np.zeros(n, bool), np.zeros(n, bool), np.zeros(n, bool)
    in_c[point_at[point_in == c]] = True
    held_same[point_at[same[point_in]]] = True
    held_any[point_at[others[point_in]]] = True
    own_layer = point_layer == layer_of[c]
    return bool((in_c & np.where(own_layer, ~held_same, ~held_any)).any())


def _marks(found: list[int], layers: list[LayerLoops], loops: list["Loop"], polys, remaining, circle, point_in,
           centre_in, pieces: Pieces, tolerance: float) -> list[tuple[list[int], list[tuple[int, int]]]]:
    """For each frame of ``found``, the loops (indices into ``loops``) and open chains ((layer, chain))
    that touch it, or touch one of these, within ``tolerance``, entering no other loop: joint-free loops
    (not round, holding no POINT or round loop) and chains that cross into no such loop."""
    chain_ids = [(k, j) for k, layer in enumerate(layers) for j in range(len(layer.chains))]
    chain_geoms = [shapely.multilinestrings([shapely.linestrings(pieces.vertices(int(p))) for p in layers[k].chains[j]])
                   for k, j in chain_ids]
    holds = np.zeros(len(loops), bool)
    holds[point_in] = True
    holds[centre_in] = True  # a round loop holds its own centre: round loops are parts' holes, never marks
    free = remaining & ~holds & ~circle
    solid = np.flatnonzero(remaining & ~free)
    # A chain that enters a part (a leader ending on it) is no frame mark: its own problem stands.
    enters = np.zeros(len(chain_geoms), bool)
    if chain_geoms and len(solid):
        at, _ = shapely.STRtree(polys[solid]).query(np.array(chain_geoms, dtype=object), predicate="intersects")
        enters[at] = True
    free_loops = np.flatnonzero(free)
    items = [shapely.boundary(p) for p in polys[free_loops]] + chain_geoms
    eligible = np.concatenate([np.ones(len(free_loops), bool), ~enters])
    taken = np.zeros(len(items), bool)
    result = []
    tree = shapely.STRtree(np.array(items, dtype=object)) if items else None
    for c in found:
        if tree is None:
            result.append(([], []))
            continue
        frontier = [shapely.boundary(polys[c])]
        mine: list[int] = []
        while frontier:
            _, near = tree.query(np.array(frontier, dtype=object), predicate="dwithin", distance=tolerance)
            touched = np.zeros(len(items), bool)
            touched[near[eligible[near]]] = True
            new = np.flatnonzero(touched & ~taken)
            taken[new] = True
            mine += new.tolist()
            frontier = [items[n] for n in new.tolist()]
        result.append((
            [int(free_loops[n]) for n in sorted(mine) if n < len(free_loops)],
            [chain_ids[n - len(free_loops)] for n in sorted(mine) if n >= len(free_loops)],
        ))
    return result
