"""Reading DXF sketches: model-space LINE, ARC, CIRCLE, ELLIPSE, LWPOLYLINE, POLYLINE, SPLINE, POINT
and INSERT (block references, nested, with their transforms), in the units of ``$INSUNITS``.

Simple entities come through the fast tag table (:mod:`.dxf_tags`); ezdxf reads the rest of the
file and expands block references (``Insert.virtual_entities``: a non-uniformly scaled circle becomes
an ellipse). Entities on layers that are off or frozen, on ``Defpoints``, or marked invisible are
left out, like annotation (TEXT, DIMENSION, HATCH, ...), and counted in ``ignored``. Layer names
are shown and matched decoded: DXF R12 writes a non-ASCII character as ``\\U+XXXX``. A file whose
structure is broken is read with ezdxf's recover mode, and what it repaired is reported.
"""

from __future__ import annotations

import io
import re
from collections import Counter
from pathlib import Path

import ezdxf
import numpy as np
from ezdxf import decode_dxf_unicode, recover
from ezdxf.lldxf.const import DXFError

from linkstress.errors import SketchError
from linkstress.importers import dxf_geometry as geo
from linkstress.importers.dxf_tags import DamagedDXF, SimpleEntities, split_entities
from linkstress.importers.primitives import CurveSet, Origin, RawSketch, describe, no_curves, with_damage
from linkstress.importers.units import choose_unit, insunits_label, unit_from_insunits

GAP_TOLERANCE = 1e-4
"""Default endpoint gap tolerance of DXF sketches, a fraction of the drawing size."""

MAX_BLOCK_DEPTH = 64
"""Block references nest at most this deep (CAD libraries nest a few levels; a block that contains
itself is caught by name before this)."""
MAX_BLOCK_ENTITIES = 20_000
"""The most entities one block reference may expand to, counted before expanding it: ezdxf makes
each a transformed Python object (about 0.25 ms), and nested references multiply (two per level,
20 deep, are a million)."""
_BINARY = b"AutoCAD Binary DXF"
_VERTEX_SPLINE_FRAME = 16
_SUPPORTED = {"LINE", "POINT", "CIRCLE", "ARC", "ELLIPSE", "LWPOLYLINE", "POLYLINE", "SPLINE", "INSERT"}


def read_dxf(path: Path, data: bytes, units: str | None, override_units: bool = True) -> RawSketch:
    """The curves and points of the DXF file ``path`` (its bytes ``data``) in ``units`` if given, else
    in $INSUNITS; ``override_units`` False refuses ``units`` that disagree with $INSUNITS instead."""
    fixes: list[str] = []
    if data.startswith(_BINARY):
        doc, simple = _ezdxf_only(path, fixes, lambda: ezdxf.readfile(path))
    elif not ezdxf.is_dxf_file(str(path)):
        raise SketchError(
            "not a DXF file (no DXF SECTION at its start); export the sketch from CAD as DXF, or give "
            "a .csv sketch"
        )
    else:
        doc, simple = _read_text(path, data, fixes)
    has_header = _has_header(data)
    try:
        curves = CurveSet()
        ignored: Counter = Counter()
        hidden = _hidden_layers(doc)
        not_flat = _add_simple(curves, simple, hidden, ignored)
        msp = list(doc.modelspace())
        collector = _Collector(curves, hidden, ignored, _BlockSizes(doc))
        collector.entities(msp, None, (), _places(msp, simple))
        not_flat += collector.not_flat
        try:
            unit, source = _unit(doc, has_header, units, override_units)
        except SketchError:
            if not curves.curve_count():  # then the units do not matter: say what the file lacks first
                raise SketchError(no_curves(ignored)) from None
            raise
    except SketchError as error:
        raise SketchError(with_damage(str(error), fixes)) from None
    if not_flat:
        fixes.append(_flattened(not_flat, unit.name))
    return RawSketch(curves, unit, source, _format(doc, has_header, data), dict(ignored), tuple(fixes),
                     GAP_TOLERANCE)


def _flattened(not_flat: list[tuple[Origin, float, float]], unit: str) -> str:
    """The note for curves whose z varies (``not_flat``: origin, lowest and highest z), which are read
    projected onto the XY plane: a 3D polyline or a sloping line is likely not meant as a sketch."""
    origin, low, high = not_flat[0]
    note = f"{describe(origin)} is 3D: z from {low:.6g} to {high:.6g} {unit}; read in the XY plane"
    if len(not_flat) > 1:
        z = np.array([(a, b) for _, a, b in not_flat])
        note += (f" (as are {len(not_flat) - 1} more curve(s) whose z varies, z from {z.min():.6g} to "
                 f"{z.max():.6g} {unit} in all)")
    return note


def _format(doc, has_header: bool, data: bytes) -> str:
    """``DXF AC1015``: the version the file says ($ACADVER), not the one ezdxf assumes (AC1009) when
    it says none."""
    if not has_header:
        return "DXF without HEADER section (version unknown)"
    if b"$ACADVER" not in data:
        return "DXF without $ACADVER (version unknown)"
    return f"DXF {doc.loaded_dxfversion or doc.dxfversion}"


def _places(entities: list, simple: SimpleEntities) -> list[tuple[str | None, str | None]]:
    """(handle, place) of each model-space entity: the file's handle, else its position ``#37``, from
    the tag table, which lists them in ezdxf's order; ezdxf invents handles for entities that have
    none, so without the table (a binary or recovered file) its handles are all there is."""
    rest = simple.rest
    if len(rest) == len(entities) and all(h is None or h == e.dxf.get("handle") for (_, h), e in zip(rest, entities)):
        return [(h, None if h else f"#{p}") for p, h in rest]
    return [(e.dxf.get("handle"), None) for e in entities]


def _has_header(data: bytes) -> bool:
    """Whether the file has a HEADER section: without one ezdxf fills in its defaults ($INSUNITS 6,
    metres), which the file never said."""
    if data.startswith(_BINARY):
        return re.search(rb"\x02\x00?HEADER\x00", data) is not None  # group code 2 in one or two bytes
    return re.search(rb"(?:^|\n)[ \t]*2[ \t]*\r?\n[ \t]*HEADER[ \t]*\r?\n", data) is not None


def _unit(doc, has_header: bool, units: str | None, override: bool):
    """The drawing's unit and where it came from: ``units`` if given, else $INSUNITS of ``doc``'s
    header. A file without a HEADER section (OpenSCAD's exports) is unitless: ezdxf would fill in
    its default, metres, which the file never said."""
    code = _insunits(doc) if has_header else 0
    declared = unit_from_insunits(code)
    if code and declared is None and units is None:
        raise SketchError(
            f"$INSUNITS = {code} ({insunits_label(code)}) has no conversion to metres; "
            "save the drawing in mm, cm, m, in or ft, or pass its unit, e.g. --units mm"
        )
    if not has_header:
        unsaid = "it has no HEADER section, so no $INSUNITS"
    elif "$INSUNITS" not in doc.header:
        # $INSUNITS came with DXF R2000 (AC1015); R12 and older files cannot carry it.
        older = (doc.loaded_dxfversion or doc.dxfversion) < "AC1015"
        unsaid = "the file has no $INSUNITS" + (", which DXF R12 and older lack" if older else "")
    else:
        unsaid = f"$INSUNITS is {code} (unitless)"
    return choose_unit(declared, "$INSUNITS", units, default=None, unsaid=unsaid, override=override)


def _recover(path: Path, fixes: list[str]):
    """Read ``path`` in ezdxf's recover mode; list what the auditor fixed in ``fixes``."""
    try:
        doc, auditor = recover.readfile(path)
    except Exception as error:  # noqa: BLE001 - ezdxf raises many types on damaged input; all mean the same
        raise SketchError(
            f"a damaged DXF file that ezdxf cannot recover ({error}); export the sketch from CAD again"
        ) from None
    fixes.extend(f"ezdxf recover: {entry.message}" for entry in [*auditor.fixes, *auditor.errors])
    return doc


def _read_text(path: Path, data: bytes, fixes: list[str]):
    """An ASCII DXF: the fast path's simple entities and ezdxf's document of the rest, or, if the file
    is damaged, all of it from ezdxf's recover mode."""
    try:
        info = ezdxf.filemanagement.dxf_file_info(str(path))
    except Exception as damage:  # noqa: BLE001 - on damaged input ezdxf raises many types, all meaning the same
        return _damaged(path, fixes, _reason(damage))
    try:
        simple, rest = split_entities(data.decode(info.encoding, errors="surrogateescape"))
    except (DamagedDXF, LookupError) as damage:
        return _damaged(path, fixes, str(damage))
    return _ezdxf_only(path, fixes, lambda: ezdxf.read(io.StringIO(rest)), simple)


def _ezdxf_only(path: Path, fixes: list[str], read, simple: SimpleEntities | None = None):
    """``read()``'s document with the fast path's entities, or the recovered file if ezdxf fails."""
    try:
        return read(), simple or SimpleEntities()
    except Exception as damage:  # noqa: BLE001 - on damaged input ezdxf raises many types, all meaning the same
        return _damaged(path, fixes, _reason(damage))


def _reason(damage: Exception) -> str:
    """What ezdxf's exception says; a StopIteration (it ran out of tags) says nothing."""
    if isinstance(damage, StopIteration):
        return "the file ends before its structure does (truncated?)"
    return f"{type(damage).__name__}: {damage}"


def _damaged(path: Path, fixes: list[str], reason: str):
    fixes.append(f"the file is damaged ({reason}); read in ezdxf's recover mode")
    return _recover(path, fixes), SimpleEntities()


def _insunits(doc) -> int:
    try:
        return int(doc.header.get("$INSUNITS", 0))
    except (TypeError, ValueError):
        return 0


def _hidden_layers(doc) -> set[str]:
    """Names (lower case) of layers that are off or frozen, and Defpoints (never plotted)."""
    hidden = {"defpoints"}
    for layer in doc.layers:
        if layer.is_off() or layer.is_frozen():
            hidden.add(decode_dxf_unicode(layer.dxf.name).lower())
    return hidden


def _add_simple(curves: CurveSet, found: SimpleEntities, hidden: set[str],
                ignored: Counter) -> list[tuple[Origin, float, float]]:
    """The fast path's columns, through the same geometry functions as ezdxf's entities; returns
    (origin, lowest z, highest z) of the LINEs whose ends differ in z."""
    not_flat = []
    for kind in ("LINE", "ARC", "CIRCLE", "POINT", "LWPOLYLINE"):
        if not found.count(kind):
            continue
        col = found.columns[kind]
        names = {layer: decode_dxf_unicode(layer) for layer in set(found.layers[kind])}
        layers = [names[layer] for layer in found.layers[kind]]
        shown = {layer: layer.lower() not in hidden for layer in set(layers)}
        visible = np.array([shown[layer] for layer in layers])
        if not visible.all():
            ignored[f"{kind} (hidden layer)"] += int((~visible).sum())
        origins = [(kind, h, layer, None, None if h else f"#{p}")
                   for h, p, layer, v in zip(found.handles[kind], found.positions[kind], layers, visible) if v]
        extrusion = np.column_stack([col[210], col[220], col[230]])
        if kind == "LINE":
            curves.add_lines(np.column_stack([col[10], col[20], col[11], col[21]])[visible], origins)
            z = np.column_stack([col[30], col[31]])[visible]
            sloping = np.flatnonzero(z[:, 0] != z[:, 1])
            not_flat += [(origins[k], float(z[k].min()), float(z[k].max())) for k in sloping.tolist()]
        elif kind == "POINT":
            curves.add_points(np.column_stack([col[10], col[20]])[visible], origins)
        elif kind == "CIRCLE":
            rows = np.column_stack([col[10], col[20], col[40]])[visible]
            geo.add_circles(curves, np.hstack([rows, extrusion[visible]]), origins, ignored)
        elif kind == "ARC":
            rows = np.column_stack([col[10], col[20], col[40], col[50], col[51]])[visible]
            geo.add_arcs(curves, np.hstack([rows, extrusion[visible]]), origins, ignored)
        else:
            closed = (col[70].astype(np.int64) & 1).astype(bool)
            geo.add_ocs_polylines(curves, found.vertices, found.bulges, found.vertex_start, closed, extrusion,
                                  visible, origins, ignored)
    return not_flat


class _Collector:
    """Walks ezdxf entities (model space, block contents) into a CurveSet."""

    def __init__(self, curves: CurveSet, hidden: set[str], ignored: Counter, sizes: "_BlockSizes") -> None:
        self.curves, self.hidden, self.ignored, self.sizes = curves, hidden, ignored, sizes
        self.lines: list[tuple] = []
        self.line_origins: list[Origin] = []
        self.not_flat: list[tuple[Origin, float, float]] = []  # curves whose z varies: lowest, highest z

    def z_range(self, z, origin: Origin) -> None:
        """Note ``origin`` in ``not_flat`` if its points' heights ``z`` differ."""
        low, high = float(np.min(z)), float(np.max(z))
        if high > low:
            self.not_flat.append((origin, low, high))

    def entities(self, entities, insert: tuple[str, str] | None, blocks: tuple[str, ...],
                 places: list[tuple[str | None, str | None]]) -> None:
        """Add ``entities`` with their (handle, place) ``places``; inside a block reference ``insert`` =
        (the model-space INSERT as named in messages, its layer) and ``blocks`` the names of the blocks
        it is in, outermost first."""
        for entity, (handle, place) in zip(entities, places):
            self.entity(entity, insert, blocks, handle, place)
        if not blocks and self.lines:
            self.curves.add_lines(np.array(self.lines, float), self.line_origins)
            self.lines, self.line_origins = [], []

    def entity(self, e, insert: tuple[str, str] | None, blocks: tuple[str, ...], handle: str | None,
               place: str | None) -> None:
        kind = e.dxftype()
        handler = getattr(self, f"_{kind.lower()}", None) if kind in _SUPPORTED else None
        if handler is None:
            self.ignored[kind] += 1
            return
        origin: Origin = (kind, handle, None, None, place)
        try:
            layer = decode_dxf_unicode(e.dxf.get("layer", "0"))
            if insert is not None and layer == "0":
                layer = insert[1]  # block contents on layer 0 take the layer of the reference
            origin = (kind, handle, layer, None, place)
            if layer.lower() in self.hidden or e.dxf.get("invisible", 0):
                self.ignored[f"{kind} (hidden layer)"] += 1
                return
            handler(e, origin, insert or (_insert_name(handle, place), layer), blocks)
        except SketchError:
            raise
        except (DXFError, ValueError, ZeroDivisionError, TypeError, AttributeError, IndexError) as error:
            raise SketchError(f"{describe(origin)} cannot be read ({error}); redraw or explode it") from None

    def _line(self, e, origin, _insert, _blocks) -> None:
        s, t = e.dxf.start, e.dxf.end
        self.lines.append((s.x, s.y, t.x, t.y))
        self.line_origins.append(origin)
        self.z_range((s.z, t.z), origin)

    def _point(self, e, origin, _insert, _blocks) -> None:
        p = e.dxf.location
        self.curves.add_points([[p.x, p.y]], [origin])

    def _circle(self, e, origin, _insert, _blocks) -> None:
        c, ex = e.dxf.center, e.dxf.extrusion
        geo.add_circles(self.curves, np.array([[c.x, c.y, e.dxf.radius, ex.x, ex.y, ex.z]]), [origin], self.ignored)

    def _arc(self, e, origin, _insert, _blocks) -> None:
        c, ex = e.dxf.center, e.dxf.extrusion
        row = [c.x, c.y, e.dxf.radius, e.dxf.start_angle, e.dxf.end_angle, ex.x, ex.y, ex.z]
        geo.add_arcs(self.curves, np.array([row]), [origin], self.ignored)

    def _ellipse(self, e, origin, _insert, _blocks) -> None:
        tool = e.construction_tool()
        geo.add_ellipse(self.curves, np.array(tool.center), np.array(tool.major_axis), np.array(tool.minor_axis),
                        tool.start_param, tool.end_param, np.array(e.dxf.extrusion), origin, self.ignored)

    def _lwpolyline(self, e, origin, _insert, _blocks) -> None:
        pts = np.array(e.get_points("xyb"), float).reshape(-1, 3)
        geo.add_ocs_polyline(self.curves, pts[:, :2], pts[:, 2], e.closed, np.array(e.dxf.extrusion), origin,
                             self.ignored)

    def _polyline(self, e, origin, _insert, _blocks) -> None:
        if not (e.is_2d_polyline or e.is_3d_polyline):
            self.ignored["POLYLINE (mesh)"] += 1
            return
        vertices = [v for v in e.vertices if not v.dxf.get("flags", 0) & _VERTEX_SPLINE_FRAME]
        xyz = np.array([v.dxf.location for v in vertices], float).reshape(-1, 3)
        xy = xyz[:, :2]
        if e.is_3d_polyline:  # WCS vertices: z may vary (a 2D polyline's z is its plane's elevation)
            bulges, extrusion = np.zeros(len(xy)), np.array([0.0, 0.0, 1.0])
            if len(xyz):
                self.z_range(xyz[:, 2], origin)
        else:
            bulges = np.array([v.dxf.get("bulge", 0.0) for v in vertices], float)
            extrusion = np.array(e.dxf.get("extrusion", (0.0, 0.0, 1.0)), float)
        geo.add_ocs_polyline(self.curves, xy, bulges, e.is_closed, extrusion, origin, self.ignored)

    def _spline(self, e, origin, _insert, _blocks) -> None:
        if not (e.control_point_count() or e.fit_point_count()):
            self.ignored["SPLINE (no points)"] += 1
            return
        spline = e.construction_tool()
        self.curves.add_spline(spline, origin)
        self.z_range([p[2] for p in spline.control_points], origin)

    def _insert(self, e, origin, insert, blocks) -> None:
        name = e.dxf.get("name", "?")
        if not blocks:
            size = e.mcount * self.sizes.of(name, (), origin)
            if size > MAX_BLOCK_ENTITIES:
                raise SketchError(
                    f"{describe(origin)} of block {name!r} expands to {size:,} entities, more than the "
                    f"{MAX_BLOCK_ENTITIES:,} linkstress expands; explode its nested blocks in CAD or draw "
                    "one sketch per link"
                )
        skipped = Counter()
        inner = (*blocks, name)
        within = " in ".join(f"block {b!r}" for b in reversed(inner))
        index = self.sizes.index(name)
        for reference in e.multi_insert() if e.mcount > 1 else [e]:
            virtual = list(reference.virtual_entities(
                skipped_entity_callback=lambda entity, reason: skipped.update([entity.dxftype()])))
            places = [(None, f"#{index.get(id(v.source_of_copy), '?')} of {within} inserted by {insert[0]}")
                      for v in virtual]
            self.entities(virtual, insert, inner, places)
        for kind, n in skipped.items():
            self.ignored[f"{kind} in block reference (cannot be transformed)"] += n


def _insert_name(handle: str | None, place: str | None) -> str:
    """A model-space INSERT as the entities of its block name it: ``INSERT with handle 2F``, ``INSERT #12``."""
    if handle:
        return f"INSERT with handle {handle}"
    return f"INSERT {place}" if place else "an INSERT"


class _BlockSizes:
    """How many entities each block expands to, nested references included, from the block
    definitions alone (nothing is expanded); a block that contains itself is an error naming it."""

    def __init__(self, doc) -> None:
        self.doc = doc
        self.known: dict[str, int] = {}
        self.positions: dict[str, dict[int, int]] = {}

    def of(self, name: str, within: tuple[str, ...], origin: Origin) -> int:
        """Entities of block ``name``, referenced inside blocks ``within`` (outermost first) by ``origin``."""
        if name in within:
            through = within[within.index(name) + 1:]
            via = f" through block {', '.join(repr(b) for b in through)}" if through else ""
            raise SketchError(
                f"block {name!r} inserts itself{via} ({describe(origin)}); a block cannot contain "
                f"itself: delete the reference to {name!r} from its definition in CAD"
            )
        if len(within) >= MAX_BLOCK_DEPTH:
            raise SketchError(
                f"{describe(origin)}: block references nested more than {MAX_BLOCK_DEPTH} deep; explode "
                "the outer blocks in CAD"
            )
        if name not in self.known:
            block = self.doc.blocks.get(name)
            inner = (*within, name)
            self.known[name] = 0 if block is None else sum(
                e.mcount * self.of(e.dxf.get("name", "?"), inner, origin) if e.dxftype() == "INSERT" else 1
                for e in block
            )
        return self.known[name]

    def index(self, name: str) -> dict[int, int]:
        """Position (1-based) of each entity of block ``name`` in its definition, by the entity's id."""
        if name not in self.positions:
            block = self.doc.blocks.get(name)
            self.positions[name] = {} if block is None else {id(e): k + 1 for k, e in enumerate(block)}
        return self.positions[name]
