"""The part of a DXF sketch that ezdxf reads: the document (header, tables, blocks) and the entities
the fast tag table leaves (ELLIPSE, POLYLINE, SPLINE, INSERT, anything unusual), binary files, and
damaged files in its recover mode.

Imported only when a file needs it (ezdxf takes 0.2 s to import): :mod:`.dxf_plain` reads the header
and layers of a plain file whose entities the fast path took whole.
"""

from __future__ import annotations

import io
from collections import Counter
from collections.abc import Callable
from pathlib import Path

import ezdxf
import numpy as np
from ezdxf import recover
from ezdxf.lldxf.const import DXFError

from linkstress.errors import SketchError
from linkstress.importers import dxf_geometry as geo
from linkstress.importers.dxf_tags import DamagedDXF, SimpleEntities, decode_dxf_unicode
from linkstress.importers.library_notes import one_line
from linkstress.importers.primitives import CurveSet, Origin, describe

MAX_BLOCK_DEPTH = 64
"""Block references nest at most this deep (CAD libraries nest a few levels; a block that contains
itself is caught by name before this)."""
MAX_BLOCK_ENTITIES = 20_000
"""The most entities one block reference may expand to, counted before expanding it: ezdxf makes
each a transformed Python object (about 0.25 ms), and nested references multiply (two per level,
20 deep, are a million)."""
_VERTEX_SPLINE_FRAME = 16
_SUPPORTED = {"LINE", "POINT", "CIRCLE", "ARC", "ELLIPSE", "LWPOLYLINE", "POLYLINE", "SPLINE", "INSERT"}


def is_dxf_file(path: Path) -> bool:
    """ezdxf's test of an ASCII DXF file: a SECTION before anything else."""
    return ezdxf.is_dxf_file(str(path))


def read_binary(path: Path, fixes: list[str]):
    """A binary DXF file's document (and no fast-path entities), recovered if ezdxf fails."""
    return _ezdxf_only(path, fixes, lambda: ezdxf.readfile(path))


def version(doc) -> str:
    """The version the file says ($ACADVER), else the one ezdxf assumes (AC1009)."""
    return doc.loaded_dxfversion or doc.dxfversion


def insunits(doc) -> int | None:
    """The header's ``$INSUNITS`` code (0 if not a number), None if the header has none."""
    if "$INSUNITS" not in doc.header:
        return None
    try:
        return int(doc.header.get("$INSUNITS", 0))
    except (TypeError, ValueError):
        return 0


def entities(doc, simple: SimpleEntities, curves: CurveSet, hidden: set[str],
             ignored: Counter) -> list[tuple[Origin, float, float]]:
    """Add ``doc``'s model-space entities to ``curves``; returns (origin, lowest z, highest z) of the
    curves whose z varies."""
    msp = list(doc.modelspace())
    collector = _Collector(curves, hidden, ignored, _BlockSizes(doc))
    collector.entities(msp, None, (), _places(msp, simple))
    return collector.not_flat


def _recover(path: Path, fixes: list[str]):
    """Read ``path`` in ezdxf's recover mode; list what the auditor fixed in ``fixes``."""
    try:
        doc, auditor = recover.readfile(path)
    except Exception as error:  # noqa: BLE001 - ezdxf raises many types on damaged input; all mean the same
        raise SketchError(
            f"a damaged DXF file that ezdxf cannot recover ({one_line(error)}); export the sketch from CAD again"
        ) from None
    fixes.extend(f"ezdxf recover: {entry.message}" for entry in [*auditor.fixes, *auditor.errors])
    return doc


def read_text(path: Path, data: bytes, fixes: list[str], split: Callable[[str], tuple[SimpleEntities, str]]):
    """An ASCII DXF: the fast path's simple entities (``split`` of the text) and ezdxf's document of
    the rest, or, if the file is damaged, all of it from ezdxf's recover mode."""
    try:
        info = ezdxf.filemanagement.dxf_file_info(str(path))
    except Exception as damage:  # noqa: BLE001 - on damaged input ezdxf raises many types, all meaning the same
        return _damaged(path, fixes, _reason(damage))
    try:
        simple, rest = split(data.decode(info.encoding, errors="surrogateescape"))
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
    return f"{type(damage).__name__}: {one_line(damage)}"


def _damaged(path: Path, fixes: list[str], reason: str):
    fixes.append(f"the file is damaged ({reason}); read in ezdxf's recover mode")
    return _recover(path, fixes), SimpleEntities()


def hidden_layers(doc) -> set[str]:
    """Names (lower case) of layers that are off or frozen, and Defpoints (never plotted)."""
    hidden = {"defpoints"}
    for layer in doc.layers:
        if layer.is_off() or layer.is_frozen():
            hidden.add(decode_dxf_unicode(layer.dxf.name).lower())
    return hidden


def _places(entities: list, simple: SimpleEntities) -> list[tuple[str | None, str | None]]:
    """(handle, place) of each model-space entity: the file's handle, else its position ``#37``, from
    the tag table, which lists them in ezdxf's order; ezdxf invents handles for entities that have
    none, so without the table (a binary or recovered file) its handles are all there is."""
    rest = simple.rest
    if len(rest) == len(entities) and all(h is None or h == e.dxf.get("handle") for (_, h), e in zip(rest, entities)):
        return [(h, None if h else f"#{p}") for p, h in rest]
    return [(e.dxf.get("handle"), None) for e in entities]


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
            raise SketchError(f"{describe(origin)} cannot be read ({one_line(error)}); redraw or explode it") from None

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
