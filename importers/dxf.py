"""Reading DXF sketches: model-space LINE, ARC, CIRCLE, ELLIPSE, LWPOLYLINE, POLYLINE, SPLINE, POINT
and INSERT (block references, nested, with their transforms), in the units of ``$INSUNITS``.

Simple entities come through the fast tag table (:mod:`.dxf_tags`). When they are all the file
holds beside a header and tables in good order, :mod:`.dxf_plain` reads those too and ezdxf is
never imported; otherwise ezdxf (:mod:`.dxf_document`) reads the rest of the file and expands block
references (``Insert.virtual_entities``: a non-uniformly scaled circle becomes an ellipse).
Entities on layers that are off or frozen, on ``Defpoints``, or marked invisible are left out, like
annotation (TEXT, DIMENSION, HATCH, ...), and counted in ``ignored``. Layer names are shown and
matched decoded: DXF R12 writes a non-ASCII character as ``\\U+XXXX``. A file whose structure is
broken is read with ezdxf's recover mode, and what it repaired is reported.
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import numpy as np

from linkstress.errors import SketchError
from linkstress.importers import dxf_geometry as geo
from linkstress.importers.dxf_plain import DocumentFacts, read_plain
from linkstress.importers.dxf_tags import DamagedDXF, SimpleEntities, decode_dxf_unicode, split_entities
from linkstress.importers.primitives import CurveSet, Origin, RawSketch, describe, no_curves, with_damage
from linkstress.importers.units import choose_unit, insunits_label, unit_from_insunits

GAP_TOLERANCE = 1e-4
"""Default endpoint gap tolerance of DXF sketches, a fraction of the drawing size."""

_BINARY = b"AutoCAD Binary DXF"


def read_dxf(path: Path, data: bytes, units: str | None, override_units: bool = True) -> RawSketch:
    """The curves and points of the DXF file ``path`` (its bytes ``data``) in ``units`` if given, else
    in $INSUNITS; ``override_units`` False refuses ``units`` that disagree with $INSUNITS instead."""
    fixes: list[str] = []
    has_header = _has_header(data)
    facts, simple = _read_plain(data, has_header)
    doc = None
    if facts is None:
        from linkstress.importers import dxf_document as document  # ezdxf: 0.2 s to import

        if data.startswith(_BINARY):
            doc, simple = document.read_binary(path, fixes)
        elif not document.is_dxf_file(path):
            raise SketchError(
                "not a DXF file (no DXF SECTION at its start); export the sketch from CAD as DXF, or give "
                "a .csv sketch"
            )
        else:
            doc, simple = document.read_text(path, data, fixes, split_entities)
        facts = DocumentFacts(document.version(doc), document.insunits(doc), frozenset(document.hidden_layers(doc)),
                              has_header)
    try:
        curves = CurveSet()
        ignored: Counter = Counter()
        not_flat = _add_simple(curves, simple, facts.hidden_layers, ignored)
        if doc is not None:
            not_flat += document.entities(doc, simple, curves, set(facts.hidden_layers), ignored)
        try:
            unit, source = _unit(facts, has_header, units, override_units)
        except SketchError:
            if not curves.curve_count():  # then the units do not matter: say what the file lacks first
                raise SketchError(no_curves(ignored)) from None
            raise
    except SketchError as error:
        raise SketchError(with_damage(str(error), fixes)) from None
    if not_flat:
        fixes.append(_flattened(not_flat, unit.name))
    return RawSketch(curves, unit, source, _format(facts.version, has_header, data), dict(ignored), tuple(fixes),
                     GAP_TOLERANCE)


def _read_plain(data: bytes, has_header: bool) -> tuple[DocumentFacts | None, SimpleEntities]:
    """A plain file read whole without ezdxf (:mod:`.dxf_plain`): its header and layers, and its
    entities from the fast path; (None, nothing) for any other file."""
    if data.startswith(_BINARY) or not data.isascii():
        return None, SimpleEntities()
    try:
        simple, rest = split_entities(data.decode("ascii"))
    except DamagedDXF:
        return None, SimpleEntities()
    plain = read_plain(rest)
    if plain is None or plain.has_header != has_header:
        return None, SimpleEntities()
    return plain, simple


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


def _format(version: str, has_header: bool, data: bytes) -> str:
    """``DXF AC1015``: the version the file says ($ACADVER), not the one ezdxf assumes (AC1009) when
    it says none."""
    if not has_header:
        return "DXF without HEADER section (version unknown)"
    if b"$ACADVER" not in data:
        return "DXF without $ACADVER (version unknown)"
    return f"DXF {version}"


def _has_header(data: bytes) -> bool:
    """Whether the file has a HEADER section: without one ezdxf fills in its defaults ($INSUNITS 6,
    metres), which the file never said."""
    if data.startswith(_BINARY):
        return re.search(rb"\x02\x00?HEADER\x00", data) is not None  # group code 2 in one or two bytes
    return re.search(rb"(?:^|\n)[ \t]*2[ \t]*\r?\n[ \t]*HEADER[ \t]*\r?\n", data) is not None


def _unit(doc: DocumentFacts, has_header: bool, units: str | None, override: bool):
    """The drawing's unit and where it came from: ``units`` if given, else $INSUNITS of ``doc``'s
    header. A file without a HEADER section (OpenSCAD's exports) is unitless: ezdxf would fill in
    its default, metres, which the file never said."""
    code = (doc.insunits or 0) if has_header else 0
    declared = unit_from_insunits(code)
    if code and declared is None and units is None:
        raise SketchError(
            f"$INSUNITS = {code} ({insunits_label(code)}) has no conversion to metres; "
            "save the drawing in mm, cm, m, in or ft, or pass its unit, e.g. --units mm"
        )
    if not has_header:
        unsaid = "it has no HEADER section, so no $INSUNITS"
    elif doc.insunits is None:
        # $INSUNITS came with DXF R2000 (AC1015); R12 and older files cannot carry it.
        older = doc.version < "AC1015"
        unsaid = "the file has no $INSUNITS" + (", which DXF R12 and older lack" if older else "")
    else:
        unsaid = f"$INSUNITS is {code} (unitless)"
    return choose_unit(declared, "$INSUNITS", units, default=None, unsaid=unsaid, override=override)


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
