"""A sketch file turned into links: outlines with holes and joints, in metres, sketch frame.

``read_sketch`` reads a DXF or CSV sketch (all its layers, or those asked for), flattens its
curves, chains them into outlines and assigns joints: the POINTs inside a link's outer boundary (in
material, or at the centre of a hole); a link without POINTs takes the centres of its circular
holes. Joints are sorted by x, then y.

A dirty sheet keeps its clean links: an open or branched chain, a crossing outline or a POINT off a
hole's centre is a :class:`SketchProblem` that leaves out only what it names (and the link of a hole
it names). Only a sheet where no link imports, or a file-level fault (unreadable, no curves, scale,
reach), raises SketchError.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Collection, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from types import MappingProxyType

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Point, Polygon

from linkstress.errors import SketchError
from linkstress.inputs import SKETCH_BYTES, read_bounded
from linkstress.messages import capped
from linkstress.importers.chaining import Report, close_pairs
from linkstress.importers.contours import OpenChain, Outline, build_contours
from linkstress.importers.dxf import read_dxf
from linkstress.importers.dxf_tags import decode_dxf_unicode
from linkstress.importers.flatten import Tolerance, flatten
from linkstress.importers.hole_layers import take_holes
from linkstress.importers.library_notes import library_notes, noted, with_notes
from linkstress.importers.parts import annotation_layers, sort_outlines
from linkstress.importers.primitives import Origin, RawSketch, box_of, describe, no_curves, with_damage
from linkstress.importers.problems import (
    ANNOTATION_LAYER, BRANCH, MAX_LISTED, OPEN_CHAIN, POINT_IN_OTHER_HOLE, POINT_OFF_CENTRE, Skipped, SketchProblem,
    listed, skipped_counted,
)
from linkstress.materials import Material
from linkstress.geometry.profile import HOLE_CENTRE_TOLERANCE, LinkProfile

POINT_RULE = "point"
HOLE_RULE = "hole centre"
ROUND_HOLE = 0.97
"""A hole whose largest inscribed circle fills less of it than this is not round (a keyway, a flat,
a slot): a POINT off its centroid is then refused as being in a hole no pin is modelled in, not as
being off its centre (a regular 12-gon, the coarsest polygon taken for a circle, fills 0.977)."""

MAX_REACH_M = 1e6
"""No curve or POINT of a sketch may reach farther than this from its origin [m]: a machine, not a map."""
MIN_SIZE_M = 1e-9
"""A drawing less than this across [m] has the wrong units: no link is a nanometre."""
MAX_OFFSET = 1e6
"""How many drawing sizes its curves may lie from the origin: at 1e6 sizes a coordinate's rounding
(1.1e-16 relative) is 1.1e-10 of the size, still ten times below the vertex merging distance
(``contours.DUPLICATE_VERTEX``, 1e-9 of the size); farther out gaps and corners blur."""
MIN_GAP_TOLERANCE = 1e-9
"""The smallest gap tolerance, as a fraction of the drawing size: vertices closer than this merge anyway."""


@dataclass(frozen=True)
class ImportedLink:
    """One link of a sketch, in metres and in the sketch frame.

    ``outline``: shapely Polygon (shell counter-clockwise, holes clockwise); ``joints`` (n, 2) sorted
    by x then y, each found by the rule in ``joint_rules`` ("point" or "hole centre");
    ``hole_diameters_m``: per hole of ``outline.interiors``, its diameter when it is a circle, else
    None, and ``hole_rules`` the rule that found it a circle (:mod:`.circles`); ``largest_gap_m``: the
    largest gap closed while chaining its curves.
    """

    name: str
    layer: str | None
    outline: Polygon
    joints: NDArray[np.float64]
    joint_rules: tuple[str, ...]
    hole_diameters_m: tuple[float | None, ...]
    largest_gap_m: float
    hole_rules: tuple[str | None, ...]

    def profile(self, thickness: float, material: Material | None = None, name: str | None = None) -> LinkProfile:
        """The link as a plate of ``thickness`` [m] of ``material``."""
        return LinkProfile(self.outline, self.joints, thickness, material, name or self.name)


@dataclass(frozen=True)
class Sketch:
    """What a sketch file holds: its links and how they were read.

    ``units``: the drawing's unit name (e.g. "mm") and ``units_source`` where it came from;
    ``ignored``: what was left out, by entity type; ``fixes``: repairs made (gaps closed,
    duplicates dropped, damage recovered); ``gap_tolerance_m`` and ``format`` as used;
    ``problems``: what was left out because no clean outline could be made of it; ``skipped``: what
    was read but is not a part (a page frame, glyphs and marks, annotation layers); ``hole_layers``:
    the layers whose outlines were taken as holes of the links they lie in.
    """

    path: Path
    format: str
    units: str
    units_source: str
    links: tuple[ImportedLink, ...]
    ignored: Mapping[str, int]
    fixes: tuple[str, ...]
    gap_tolerance_m: float
    problems: tuple[SketchProblem, ...] = ()
    skipped: tuple[Skipped, ...] = ()
    hole_layers: tuple[str, ...] = ()

    @property
    def units_assumed(self) -> bool:
        """True when the file carries no units and none were given (the old iLogic CSV's cm)."""
        return self.units_source.startswith("assumed")

    def link(self, name_or_layer: str | None = None) -> ImportedLink:
        """The link named ``name_or_layer`` (or the only one on that layer); None: the only link.

        A layer with a problem (the named link's own, or the one asked for), or a sheet with one when
        no name is given, is refused with the problems: what was left out there may be the link
        meant, or part of it.
        """
        names = capped(repr(link.name) for link in self.links)
        if name_or_layer is not None:
            name_or_layer = decode_dxf_unicode(name_or_layer)  # as the drawing's layer names are
        if name_or_layer is None:
            if len(self.links) == 1 and not self.problems:
                return self.links[0]
            if self.problems:
                raise SketchError(
                    f"{self.path.name} holds {len(self.links)} clean link(s) ({names}) and "
                    f"{listed(self.problems)}; name a clean link or layer, or fix the drawing"
                )
            raise SketchError(f"{self.path.name} holds {len(self.links)} links ({names}): say which one")
        named = [link for link in self.links if link.name == name_or_layer]
        layer = named[0].layer if named else name_or_layer
        layer_problems = [p for p in self.problems if p.layer == layer]
        if layer_problems:
            # What was left out on the link's layer may be part of it (a slot whose outline does not close).
            raise SketchError(f"{self.path.name}: layer {layer!r}: {listed(layer_problems)}")
        if named:
            return named[0]
        on_layer = [link for link in self.links if link.layer == name_or_layer]
        if len(on_layer) == 1:
            return on_layer[0]
        if on_layer:
            raise SketchError(
                f"{self.path.name}: layer {name_or_layer!r} holds {len(on_layer)} links "
                f"({capped(repr(k.name) for k in on_layer)}): name one of them"
            )
        raise SketchError(f"{self.path.name} has no link or layer {name_or_layer!r}; its links are {names}")


class SketchRefused(SketchError):
    """No link of a sketch imports: the message, and in ``sketch`` (no links) every problem and what was
    skipped, for ``import --json`` to write all of them."""

    def __init__(self, message: str, sketch: Sketch) -> None:
        super().__init__(message)
        self.sketch = sketch


def read_sketch(path: str | Path, units: str | None = None, tolerance: float | None = None,
                sagitta: float | None = None, layers: Collection[str] | None = None,
                exclude_layers: Collection[str] = (), override_units: bool = True,
                hole_layers: Collection[str] = ()) -> Sketch:
    """Read the DXF or CSV sketch at ``path`` (by its suffix .dxf or .csv, else by its content).

    ``units``: the unit of a file that does not say (DXF ``$INSUNITS`` 0 or no HEADER, CSV without
    header units), overriding one that does (``--units``) unless ``override_units`` is False (a
    scene's ``units``: then a disagreement is refused);
    ``tolerance``: the endpoint gap tolerance as a fraction of the drawing's size (default 1e-4 for
    DXF and v1 CSV, 1e-2 for the old iLogic CSV); ``sagitta``: the chord tolerance of arcs as a
    fraction of each arc's radius (default 1e-4); ``layers``: read only these layers (None: all),
    ``exclude_layers``: leave these out; the drawing's size is that of the curves read;
    ``hole_layers``: layers whose closed outlines are holes of the links they lie in
    (:mod:`.hole_layers`), read even when ``layers`` does not name them. Layers named for annotation
    (:func:`.parts.annotation_layers`) are read only when ``layers`` names them. Raises SketchError
    naming the file when the file itself is at fault, :class:`SketchRefused` when no link imports;
    problems that leave out only part of the drawing are in ``Sketch.problems``, what is not a part
    in ``Sketch.skipped``.
    """
    path = Path(path)
    try:
        data = read_bounded(path, SKETCH_BYTES, "sketch")
    except OSError as error:
        raise SketchError(
            f"cannot read the sketch {str(path)!r}: {error.strerror or error}; give the path of a readable "
            ".dxf or .csv file"
        ) from None
    raw = None
    notes: list[str] = []
    try:
        with library_notes(notes):
            if _is_dxf(path, data):
                raw = read_dxf(path, data, units, override_units)
            else:
                from linkstress.importers.ilogic_csv import read_csv  # imported for a CSV sketch only

                raw = read_csv(path, data, units, override_units)
            sketch = _build(path, raw, tolerance, sagitta, layers, exclude_layers, tuple(hole_layers))
    except SketchError as error:
        message = str(error) if raw is None else with_damage(str(error), raw.fixes)
        message = f"{path.name}: {message}{noted(notes)}"
        if isinstance(error, SketchRefused):
            raise SketchRefused(message, replace(error.sketch, fixes=with_notes(error.sketch.fixes, notes))) from None
        raise SketchError(message) from None
    return replace(sketch, fixes=with_notes(sketch.fixes, notes))


def _is_dxf(path: Path, data: bytes) -> bool:
    suffix = path.suffix.lower()
    if suffix == ".dxf":
        return True
    if suffix == ".csv":
        return False
    head = data.lstrip()[:64]
    first_two = [line.strip() for line in head.splitlines()[:2]]
    return head.startswith(b"AutoCAD Binary DXF") or first_two == [b"0", b"SECTION"] or first_two[:1] == [b"999"]


def _build(path: Path, raw: RawSketch, tolerance: float | None, sagitta: float | None,
           layers: Collection[str] | None, exclude_layers: Collection[str], hole_layers: tuple[str, ...]) -> Sketch:
    boxes, origins = raw.curves.extents()
    ignored = Counter(raw.ignored)
    hole_layers = tuple(decode_dxf_unicode(name) for name in hole_layers)
    use = _on_layers(origins, layers, exclude_layers, ignored, hole_layers)
    curves = raw.curves.curve_count()
    skipped = _annotation(origins, boxes, use, [*(layers or ()), *hole_layers], raw.unit.name)
    boxes, origins = boxes[use], [o for o, u in zip(origins, use) if u]
    bounds = box_of(boxes[:int(use[:curves].sum())])
    if bounds is None:
        if skipped:
            raise SketchError(f"no outline: every curve read is on a layer named for annotation "
                              f"({capped(repr(item.layer) for item in skipped)}); name it in --layers to read it")
        kept = " on the layers read" if layers is not None or exclude_layers else ""
        raise SketchError(no_curves(raw.ignored, kept))
    _check_reach(raw, boxes, origins)
    size = math.hypot(bounds[2] - bounds[0], bounds[3] - bounds[1])
    if not size > 0:
        raise SketchError("no outline: all curves sit at one point")
    _check_scale(raw, bounds, size)
    gap = raw.gap_tolerance if tolerance is None else tolerance
    if not (isinstance(gap, (int, float)) and math.isfinite(gap) and MIN_GAP_TOLERANCE <= gap < 0.5):
        raise SketchError(
            f"the gap tolerance (--tolerance) is a fraction of the drawing size in [{MIN_GAP_TOLERANCE:g}, 0.5), "
            f"got {gap!r}"
        )
    unit = raw.unit.name
    pieces = flatten(raw.curves, Tolerance.for_size(size, sagitta))
    use_points = use[curves:]
    points = raw.curves.point_array()[use_points]
    point_layers = [o[2] for o, u in zip(raw.curves.origins["points"], use_points) if u]
    contours = build_contours(pieces, raw.curves.curve_origins(), gap * size, size, unit, use[:curves], points,
                              point_layers, hole_layers)
    fixes = list(raw.fixes) + list(contours.fixes)
    problems = list(contours.problems)
    skipped += contours.skipped
    report = Report(raw.curves.curve_origins(), unit, size)
    outlines = list(contours.outlines)
    if hole_layers:
        outlines, hole_problems = take_holes(outlines, hole_layers, report, fixes, problems)
        problems += hole_problems
    links = _links(path, raw, outlines, use_points, gap * size, ignored, fixes, problems, skipped, report,
                   contours.chains)
    sketch = Sketch(path, raw.format, unit, raw.units_source, tuple(links), MappingProxyType(dict(ignored)),
                    tuple(fixes), gap * size / raw.unit.per_metre, tuple(problems), tuple(skipped), hole_layers)
    if not links:
        raise SketchRefused(_no_link(problems, skipped), sketch)
    return sketch


def _no_link(problems: list[SketchProblem], skipped: list[Skipped]) -> str:
    """Why no link imports: the problems, else what was skipped."""
    if problems:
        return listed(problems) if len(problems) == 1 else f"no link imports, {listed(problems)}"
    kinds: Counter = Counter()
    for item in skipped:
        kinds[item.kind] += item.count
    what = ", ".join(skipped_counted(n, kind) for kind, n in kinds.items())
    return (f"no link imports: the sheet holds no part, only {what}; a part is a closed outline with its joints "
            "(POINTs or round pin holes)")


def _annotation(origins: list[Origin], boxes: NDArray[np.float64], use: NDArray[np.bool_], asked: list[str],
                unit: str) -> list[Skipped]:
    """Leave out (in ``use``) the curves and POINTs (``origins``, their bounding ``boxes``) on layers named
    for annotation that were not ``asked`` for by name: a :class:`Skipped` per such layer, at its first
    curve's lower left corner."""
    on = np.array([origin[2] for origin in origins], dtype=object)
    skipped = []
    for layer in annotation_layers(dict.fromkeys(on[use].tolist()), asked):
        mine = use & (on == layer)
        use &= ~mine
        count, first = int(mine.sum()), int(np.argmax(mine))
        skipped.append(Skipped(
            ANNOTATION_LAYER, layer, (float(boxes[first, 0]), float(boxes[first, 1])), unit,
            tuple(describe(origins[k]) for k in np.flatnonzero(mine)[:MAX_LISTED]),
            f"layer {layer!r} is named for annotation (text, dimensions, title block, border): its {count} curve(s) "
            f"and POINT(s) were not read; name it in --layers to read it",
        ))
    return skipped


def _on_layers(origins: list[Origin], layers: Collection[str] | None, exclude: Collection[str],
               ignored: Counter, hole_layers: tuple[str, ...] = ()) -> NDArray[np.bool_]:
    """Which curves and POINTs (``origins``) lie on the layers read (``layers`` and the ``hole_layers``),
    counting the rest in ``ignored``; a layer name the drawing lacks is refused, naming the layers it has."""
    on = np.array([origin[2] for origin in origins], dtype=object)
    if layers is None and not exclude and not hole_layers:
        return np.ones(len(origins), bool)
    # The drawing's names are decoded (``\U+039B`` is a capital lambda); so are those given.
    layers = None if layers is None else [*(decode_dxf_unicode(name) for name in layers), *hole_layers]
    exclude = [decode_dxf_unicode(name) for name in exclude]
    if set(exclude) & set(hole_layers):
        both = sorted(set(exclude) & set(hole_layers))
        raise SketchError(f"layer(s) {capped(repr(n) for n in both)} given both as hole layers and in "
                          "--exclude-layers; keep one")
    present = sorted({layer for layer in on.tolist() if layer is not None})
    unknown = sorted((set(layers or ()) | set(exclude) | set(hole_layers)) - set(present))
    if unknown:
        has = f"its layers are {capped((repr(n) for n in present), 20)}" if present else "it has no layers"
        raise SketchError(
            f"no layer {', '.join(repr(n) for n in unknown[:MAX_LISTED])} in the drawing ({has}); check --layers, "
            "--exclude-layers and --hole-layers"
        )
    use = np.ones(len(origins), bool) if layers is None else np.isin(on, list(layers))
    use &= ~np.isin(on, list(exclude))
    if not use.all():
        ignored["curve or POINT (on a layer left out)"] += int((~use).sum())
    return use


def _check_reach(raw: RawSketch, boxes: NDArray[np.float64], origins: list[Origin]) -> None:
    """Refuse a curve or POINT (``boxes`` in drawing units, from ``origins``) farther than
    ``MAX_REACH_M`` from the origin, naming it."""
    with np.errstate(over="ignore"):
        reach = np.abs(boxes).max(axis=1) / raw.unit.per_metre
    if reach.max() > MAX_REACH_M:
        k = int(np.argmax(reach))
        raise SketchError(
            f"{describe(origins[k])} reaches {reach[k]:.3g} m from the origin, beyond the {MAX_REACH_M:g} m a "
            f"sketch may span; fix or delete it, or check the drawing's units ({raw.unit.name}, "
            f"{raw.units_source})"
        )


def _check_scale(raw: RawSketch, bounds: tuple[float, float, float, float], size: float) -> None:
    """Refuse a drawing too small to be a part, or so far from the origin that rounding blurs its gaps."""
    unit = raw.unit.name
    if size / raw.unit.per_metre < MIN_SIZE_M:
        raise SketchError(
            f"the drawing is {size / raw.unit.per_metre:.3g} m across, smaller than {MIN_SIZE_M:g} m; check "
            f"the drawing's units ({unit}, {raw.units_source}) or scale it to the part's size"
        )
    offset = max(abs(v) for v in bounds)
    if offset > MAX_OFFSET * size:
        raise SketchError(
            f"the drawing is {size:.3g} {unit} across but lies {offset:.3g} {unit} from the origin, more than "
            f"{MAX_OFFSET:g} times its size: double precision cannot resolve its gaps there; move the "
            "drawing near the origin"
        )


def _links(path: Path, raw: RawSketch, outlines: list[Outline], use_points: NDArray[np.bool_],
           tolerance: float, ignored: Counter, fixes: list[str], problems: list[SketchProblem],
           skipped: list[Skipped], report: Report, chains: tuple[OpenChain, ...] = ()) -> list[ImportedLink]:
    """Links in metres from the outlines that are parts (drawing units), with their joints (the POINTs
    ``use_points``).

    The contours are simple, disjoint and nested, and each POINT is checked to lie in material or
    at a hole's centre, so every link makes a valid LinkProfile; a link with a POINT in a hole off
    its centre is left out as a problem. Outlines that are no parts (:mod:`.parts`) are skipped or
    left out as problems first.
    """
    points = raw.curves.point_array()[use_points]
    point_origins = [o for o, u in zip(raw.curves.origins["points"], use_points) if u]
    point_layers = [origin[2] for origin in point_origins]
    left_out = {problem.layer for problem in problems if problem.layer is not None}
    owner = _owners([o.shell.polygon for o in outlines], points, [o.layer for o in outlines], point_layers, left_out)
    if (owner < 0).any():
        ignored["POINT (outside every outline)"] += int((owner < 0).sum())
    # The joints each outline would have, before any is judged a part: its POINTs, else its round holes' centres.
    order = np.argsort(owner, kind="stable")
    bounds = np.searchsorted(owner[order], np.arange(len(outlines) + 1))
    would_be = [points[order[bounds[k]:bounds[k + 1]]] if bounds[k + 1] > bounds[k] else _hole_centres(outline)
                for k, outline in enumerate(outlines)]
    parts = sort_outlines(outlines, would_be, report.size, report, chains)
    # The open chains skipped with a mark (a drill mark's cross) are no longer problems.
    problems[:] = [p for p in problems if not (p.kind in (OPEN_CHAIN, BRANCH) and set(p.entities) <= parts.marked)]
    problems += parts.problems
    skipped += parts.skipped
    # Among the parts: a POINT of an outline that is no part belongs to no link.
    index = np.full(len(outlines) + 1, -1)
    index[np.flatnonzero(parts.keep)] = np.arange(int(parts.keep.sum()))
    kept = [outline for outline, keep in zip(outlines, parts.keep) if keep]
    return _made(path, raw, kept, points, point_origins, index[owner], tolerance, fixes, problems)


def _hole_centres(outline: Outline) -> NDArray[np.float64]:
    return np.array([h.circle[:2] for h in outline.holes if h.circle is not None]).reshape(-1, 2)


def _made(path: Path, raw: RawSketch, outlines: list[Outline], points: NDArray[np.float64], point_origins: list[Origin],
          owner: NDArray[np.intp], tolerance: float, fixes: list[str], problems: list[SketchProblem]) -> list[ImportedLink]:
    """The links of ``outlines`` (parts), each with the POINTs it ``owner``s as its joints, else its round
    holes' centres; one with a POINT in a hole off its centre is left out as a problem."""
    curve_origins = raw.curves.curve_origins()
    names, layers = _names(path, outlines)
    per_metre = raw.unit.per_metre
    links = []
    for k, outline in enumerate(outlines):
        mine = np.flatnonzero(owner == k)
        mine = mine[_unique(points[mine], tolerance, [point_origins[i] for i in mine], names[k], fixes)]
        polygon = outline.polygon
        off_centre = _off_centre(polygon, points[mine], [point_origins[i] for i in mine], names[k],
                                 curve_origins[outline.shell.pieces[0]][2], raw.unit.name)
        if off_centre is not None:
            problems.append(off_centre)
            continue
        if len(mine):
            joints, rule = points[mine], POINT_RULE
        else:
            joints, rule = _hole_centres(outline), HOLE_RULE
        joints_m = joints / per_metre
        joints_m = joints_m[np.lexsort((joints_m[:, 1], joints_m[:, 0]))]
        joints_m.setflags(write=False)
        links.append(ImportedLink(
            names[k], layers[k], shapely.transform(polygon, lambda xy: xy / per_metre), joints_m,
            (rule,) * len(joints_m),
            tuple(2 * h.circle[2] / per_metre if h.circle is not None else None for h in outline.holes),
            outline.largest_gap[0] / per_metre, tuple(h.circle_rule for h in outline.holes),
        ))
        count = sum(loop.gaps for loop in [outline.shell, *outline.holes])
        if count:
            g, at = outline.largest_gap
            fixes.append(
                f"link {names[k]!r}: closed {count} gap(s), the largest {g:.3g} {raw.unit.name} at "
                f"({at[0]:.6g}, {at[1]:.6g}) {raw.unit.name}"
            )
    return links


def _names(path: Path, outlines: list[Outline]) -> tuple[list[str], list[str | None]]:
    """A link is named by its shell's layer when all its curves share one (other than "0"), else
    ``<file stem>-<n>``; links sharing a layer are numbered ``<layer>-<n>``."""
    layers = [outline.layer if outline.layer != "0" else None for outline in outlines]
    per_layer = Counter(layers)
    seen: Counter = Counter()
    names = []
    for layer in layers:
        seen[layer] += 1
        if layer is None:
            names.append(f"{path.stem}-{seen[layer]}")
        elif per_layer[layer] > 1:
            names.append(f"{layer}-{seen[layer]}")
        else:
            names.append(layer)
    taken: Counter = Counter(names)
    return [n if taken[n] == 1 else f"{n}#{k + 1}" for k, n in enumerate(names)], layers


def _owners(shells: list[Polygon], points: NDArray[np.float64], shell_layers: list[str | None],
            point_layers: list[str], left_out: set[str]) -> NDArray[np.intp]:
    """For each point, the innermost shell that covers it, or -1: among the shells on the point's
    own layer when one of them covers it (links drawn assembled share their pins' places), else
    among all, unless curves of the point's layer were ``left_out`` as problems: a POINT of a lever
    whose outline was left out is no joint of the frame it lies on."""
    owner = np.full(len(points), -1)
    if not len(points):
        return owner
    covers = shapely.covers(np.array(shells, dtype=object)[:, None], shapely.points(points)[None, :])
    areas = np.array([s.area for s in shells])
    layers = np.array(shell_layers, dtype=object)
    for j in range(len(points)):
        candidates = np.flatnonzero(covers[:, j])
        same = candidates[layers[candidates] == point_layers[j]]
        if len(same) or point_layers[j] in left_out:
            candidates = same
        if len(candidates):
            owner[j] = candidates[np.argmin(areas[candidates])]
    return owner


def _unique(points, tolerance, origins, name, fixes: list[str]) -> NDArray[np.bool_]:
    """Which points to keep: of points closer than ``tolerance``, the first."""
    if len(points) < 2:
        return np.ones(len(points), bool)
    # Exact repeats first (a sort), so that a pile of POINTs on one spot makes no pairs.
    _, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    keep = np.zeros(len(points), bool)
    keep[first] = True
    pairs = first[close_pairs(points[first], tolerance, "POINTs")]
    keep[np.max(pairs, axis=1)] = False
    if not keep.all():
        repeat = int(np.flatnonzero(~keep)[0])
        partner = pairs[np.max(pairs, axis=1) == repeat]
        i, j = (np.sort(partner[0]) if len(partner) else (first[inverse.ravel()[repeat]], repeat))
        fixes.append(
            f"link {name!r}: dropped {int((~keep).sum())} POINT(s) repeating another, e.g. "
            f"{describe(origins[j])} repeats {describe(origins[i])}"
        )
    return keep


def _off_centre(polygon: Polygon, points: NDArray[np.float64], origins, name: str, layer: str | None,
                unit: str) -> SketchProblem | None:
    """A POINT in a hole must be at its centre (LinkProfile's rule): the first that is not, as a
    problem naming it, else None."""
    if not len(points):
        return None
    in_hole = ~shapely.covers(polygon, shapely.points(points))
    for p, origin in zip(points[in_hole], [o for o, h in zip(origins, in_hole) if h]):
        point = Point(p)
        hole = next(Polygon(ring) for ring in polygon.interiors if Polygon(ring).contains(point))
        c = hole.centroid
        radius = math.sqrt(hole.area / math.pi)
        if point.distance(c) > HOLE_CENTRE_TOLERANCE * radius:
            inscribed = shapely.length(shapely.maximum_inscribed_circle(hole, 1e-4 * radius)) / radius
            if inscribed**2 < ROUND_HOLE:
                return SketchProblem(
                    layer, (float(p[0]), float(p[1])), unit, (describe(origin),),
                    f"{describe(origin)} at ({p[0]:.6g}, {p[1]:.6g}) {unit} lies in a hole of link {name!r} that is not "
                    f"round (its largest inscribed circle fills {100 * inscribed**2:.0f} % of it: a keyway, a flat, a slot)",
                    "linkstress puts a pin only in a round hole, at its centre: draw the bore round to analyse the link "
                    "(a keyway's or flat's own stress is then not modelled: check it apart), or delete the POINT",
                    POINT_IN_OTHER_HOLE,
                )
            cx, cy = (v if abs(v) > 1e-12 * radius else 0.0 for v in (c.x, c.y))
            return SketchProblem(
                layer, (float(p[0]), float(p[1])), unit, (describe(origin),),
                f"{describe(origin)} at ({p[0]:.6g}, {p[1]:.6g}) {unit} lies in a hole of link {name!r} "
                f"but not at its centre ({cx:.6g}, {cy:.6g}) {unit}",
                "a joint in a hole is the pin's centre: move the POINT there or delete it", POINT_OFF_CENTRE,
            )
    return None
