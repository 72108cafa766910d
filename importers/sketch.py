"""A sketch file turned into links: outlines with holes and joints, in metres, sketch frame.

``read_sketch`` reads a DXF or CSV sketch, flattens its curves, chains them into outlines and
assigns joints: the POINTs inside a link's outer boundary (in material, or at the centre of a
hole); a link without POINTs takes the centres of its circular holes. Joints are sorted by x, then y.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from types import MappingProxyType

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Point, Polygon

from linkstress.errors import SketchError
from linkstress.importers.chaining import close_pairs
from linkstress.importers.contours import Outline, build_contours
from linkstress.importers.dxf import read_dxf
from linkstress.importers.flatten import Tolerance, flatten
from linkstress.importers.ilogic_csv import read_csv
from linkstress.importers.library_notes import library_notes, noted, with_notes
from linkstress.importers.primitives import Origin, RawSketch, box_of, describe, with_damage
from linkstress.materials import Material
from linkstress.profile import HOLE_CENTRE_TOLERANCE, LinkProfile

POINT_RULE = "point"
HOLE_RULE = "hole centre"

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
    duplicates dropped, damage recovered); ``gap_tolerance_m`` and ``format`` as used.
    """

    path: Path
    format: str
    units: str
    units_source: str
    links: tuple[ImportedLink, ...]
    ignored: Mapping[str, int]
    fixes: tuple[str, ...]
    gap_tolerance_m: float

    @property
    def units_assumed(self) -> bool:
        """True when the file carries no units and none were given (the old iLogic CSV's cm)."""
        return self.units_source.startswith("assumed")

    def link(self, name_or_layer: str | None = None) -> ImportedLink:
        """The link named ``name_or_layer`` (or the only one on that layer); None: the only link."""
        names = ", ".join(repr(link.name) for link in self.links)
        if name_or_layer is None:
            if len(self.links) == 1:
                return self.links[0]
            raise SketchError(f"{self.path.name} holds {len(self.links)} links ({names}): say which one")
        for link in self.links:
            if link.name == name_or_layer:
                return link
        on_layer = [link for link in self.links if link.layer == name_or_layer]
        if len(on_layer) == 1:
            return on_layer[0]
        if on_layer:
            raise SketchError(
                f"{self.path.name}: layer {name_or_layer!r} holds {len(on_layer)} links "
                f"({', '.join(repr(k.name) for k in on_layer)}): name one of them"
            )
        raise SketchError(f"{self.path.name} has no link or layer {name_or_layer!r}; its links are {names}")


def read_sketch(path: str | Path, units: str | None = None, tolerance: float | None = None,
                sagitta: float | None = None, override_units: bool = True) -> Sketch:
    """Read the DXF or CSV sketch at ``path`` (by its suffix .dxf or .csv, else by its content).

    ``units``: the unit of a file that does not say (DXF ``$INSUNITS`` 0 or no HEADER, CSV without
    header units), overriding one that does (``--units``) unless ``override_units`` is False (a
    scene's ``units``: then a disagreement is refused);
    ``tolerance``: the endpoint gap tolerance as a fraction of the drawing's size (default 1e-4 for
    DXF and v1 CSV, 1e-2 for the old iLogic CSV); ``sagitta``: the chord tolerance of arcs as a
    fraction of each arc's radius (default 1e-4). Raises SketchError naming the file.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as error:
        raise SketchError(
            f"cannot read the sketch {str(path)!r}: {error.strerror or error}; give the path of a readable "
            ".dxf or .csv file"
        ) from None
    raw = None
    notes: list[str] = []
    try:
        with library_notes(notes):
            read = read_dxf if _is_dxf(path, data) else read_csv
            raw = read(path, data, units, override_units)
            sketch = _build(path, raw, tolerance, sagitta)
    except SketchError as error:
        message = str(error) if raw is None else with_damage(str(error), raw.fixes)
        raise SketchError(f"{path.name}: {message}{noted(notes)}") from None
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


def _build(path: Path, raw: RawSketch, tolerance: float | None, sagitta: float | None) -> Sketch:
    boxes, origins = raw.curves.extents()
    bounds = box_of(boxes[:raw.curves.curve_count()])
    if bounds is None:
        raise SketchError(f"no outline: the drawing has no curves{_ignored_note(raw.ignored)}")
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
    contours = build_contours(pieces, raw.curves.curve_origins(), gap * size, size, unit)
    ignored = Counter(raw.ignored)
    fixes = list(raw.fixes) + list(contours.fixes)
    links = _links(path, raw, contours.outlines, gap * size, ignored, fixes)
    for link, outline in zip(links, contours.outlines):
        loops = [outline.shell, *outline.holes]
        count = sum(loop.gaps for loop in loops)
        if count:
            g, at = outline.largest_gap
            fixes.append(
                f"link {link.name!r}: closed {count} gap(s), the largest {g:.3g} {unit} at ({at[0]:.6g}, {at[1]:.6g}) {unit}"
            )
    return Sketch(path, raw.format, unit, raw.units_source, tuple(links), MappingProxyType(dict(ignored)),
                  tuple(fixes), gap * size / raw.unit.per_metre)


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


def _ignored_note(ignored: Mapping[str, int]) -> str:
    if not ignored:
        return ""
    listed = ", ".join(f"{n} {kind}" for kind, n in sorted(ignored.items()))
    return f" it reads (only {listed} were found, which are not outline geometry)"


def _links(path: Path, raw: RawSketch, outlines: tuple[Outline, ...], tolerance: float, ignored: Counter,
           fixes: list[str]) -> list[ImportedLink]:
    """Links in metres from the outlines (drawing units), with their joints.

    The contours are simple, disjoint and nested, and each POINT is checked to lie in material or
    at a hole's centre, so every link makes a valid LinkProfile.
    """
    names, layers = _names(path, outlines, raw.curves.curve_origins())
    points = raw.curves.point_array()
    point_origins = raw.curves.origins["points"]
    owner = _owners([o.shell.polygon for o in outlines], points)
    if (owner < 0).any():
        ignored["POINT (outside every outline)"] += int((owner < 0).sum())
    per_metre = raw.unit.per_metre
    links = []
    for k, outline in enumerate(outlines):
        mine = np.flatnonzero(owner == k)
        mine = mine[_unique(points[mine], tolerance, [point_origins[i] for i in mine], names[k], fixes)]
        polygon = outline.polygon
        _check_joints(polygon, points[mine], [point_origins[i] for i in mine], names[k], raw.unit.name)
        if len(mine):
            joints, rule = points[mine], POINT_RULE
        else:
            joints = np.array([h.circle[:2] for h in outline.holes if h.circle is not None]).reshape(-1, 2)
            rule = HOLE_RULE
        joints_m = joints / per_metre
        joints_m = joints_m[np.lexsort((joints_m[:, 1], joints_m[:, 0]))]
        joints_m.setflags(write=False)
        links.append(ImportedLink(
            names[k], layers[k], shapely.transform(polygon, lambda xy: xy / per_metre), joints_m,
            (rule,) * len(joints_m),
            tuple(2 * h.circle[2] / per_metre if h.circle is not None else None for h in outline.holes),
            outline.largest_gap[0] / per_metre, tuple(h.circle_rule for h in outline.holes),
        ))
    return links


def _names(path: Path, outlines, origins) -> tuple[list[str], list[str | None]]:
    """A link is named by its shell's layer when all its curves share one (other than "0"), else
    ``<file stem>-<n>``; links sharing a layer are numbered ``<layer>-<n>``."""
    layers: list[str | None] = []
    for outline in outlines:
        found = {origins[k][2] for k in outline.shell.pieces}
        layer = found.pop() if len(found) == 1 else None
        layers.append(layer if layer not in (None, "0") else None)
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


def _owners(shells: list[Polygon], points: NDArray[np.float64]) -> NDArray[np.intp]:
    """For each point, the innermost shell that covers it, or -1."""
    owner = np.full(len(points), -1)
    if not len(points):
        return owner
    covers = shapely.covers(np.array(shells, dtype=object)[:, None], shapely.points(points)[None, :])
    areas = np.array([s.area for s in shells])
    for j in range(len(points)):
        candidates = np.flatnonzero(covers[:, j])
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


def _check_joints(polygon: Polygon, points: NDArray[np.float64], origins, name: str, unit: str) -> None:
    """A POINT in a hole must be at its centre (LinkProfile's rule); the message names the POINT."""
    if not len(points):
        return
    in_hole = ~shapely.covers(polygon, shapely.points(points))
    for p, origin in zip(points[in_hole], [o for o, h in zip(origins, in_hole) if h]):
        point = Point(p)
        hole = next(Polygon(ring) for ring in polygon.interiors if Polygon(ring).contains(point))
        c = hole.centroid
        radius = math.sqrt(hole.area / math.pi)
        if point.distance(c) > HOLE_CENTRE_TOLERANCE * radius:
            cx, cy = (v if abs(v) > 1e-12 * radius else 0.0 for v in (c.x, c.y))
            raise SketchError(
                f"{describe(origin)} at ({p[0]:.6g}, {p[1]:.6g}) {unit} lies in a hole of link {name!r} "
                f"but not at its centre ({cx:.6g}, {cy:.6g}) {unit}; a joint in a hole is the pin's "
                "centre: move the POINT there or delete it"
            )
