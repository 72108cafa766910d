"""A fast path for the bulk of a DXF file: simple model-space entities read as a numpy tag table.

ezdxf builds a Python object per entity and a typed tag per value, about 0.1 ms per entity: a
50,000-entity drawing takes seconds before any geometry is seen. A DXF file is a flat sequence of
(group code, value) line pairs, so the ENTITIES section's LINE, ARC, CIRCLE, POINT and LWPOLYLINE
records can be decoded column-wise with numpy instead. Everything else in the file (header, tables,
blocks, every other entity, and any simple entity this reader is not sure about: paper space, app
data groups, repeated codes) is handed back as DXF text for ezdxf to read as usual, so both readers
see each entity exactly once. A file whose structure this reader doubts raises :class:`DamagedDXF`,
and the caller reads it with ezdxf's recover mode instead.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from linkstress.importers.library_notes import one_line

SIMPLE = ("LINE", "ARC", "CIRCLE", "POINT", "LWPOLYLINE")

# Group codes each simple entity must carry exactly once, and those it may carry at most once.
_REQUIRED = {
    "LINE": (10, 20, 11, 21),
    "ARC": (10, 20, 40, 50, 51),
    "CIRCLE": (10, 20, 40),
    "POINT": (10, 20),
    "LWPOLYLINE": (),
}
_OPTIONAL = (5, 8, 210, 220, 230, 67, 60, 70, 30, 31)
# DXF group codes run from -5 to 1071; anything far outside is not a code (and must not overflow int64).
_CODE_RANGE = (-9999, 9999)
# Codes that make an entity not simple: app data and embedded objects (arbitrary codes inside).
_FOREIGN = (101, 102)


_DXF_UNICODE = re.compile(r"(\\U\+[A-Fa-f0-9]{4})")


def decode_dxf_unicode(text: str) -> str:
    """``text`` with each ``\\U+XXXX`` (how DXF R12 writes a character beyond ASCII) decoded, exactly
    as ezdxf's ``decode_dxf_unicode`` does (a piece that starts ``\\U+`` is taken as hex, even a short one);
    a piece that is not hex at all (``\\U+zzzz``) stays as written."""
    return "".join(_decoded(part) for part in _DXF_UNICODE.split(text))


def _decoded(part: str) -> str:
    if not part.startswith("\\U+"):
        return part
    try:
        return chr(int(part[3:], 16))
    except ValueError:
        return part


class DamagedDXF(Exception):
    """The file's tag structure is broken: read it with ezdxf's recover mode."""


@dataclass
class SimpleEntities:
    """Raw columns of the simple entities, one dict per type: code -> values in entity order.

    ``layers``, ``handles`` and ``positions`` (1-based in the ENTITIES section, counting every entity
    but the VERTEX, SEQEND and ATTRIB records that belong to one) per type; LWPOLYLINE also has
    ``vertices`` (V, 2), ``bulges`` (V,) and ``vertex_start`` (n + 1,) offsets. ``rest`` holds
    (position, handle or None) of each model-space entity left to ezdxf, in file order.
    """

    columns: dict[str, dict[int, NDArray[np.float64]]] = field(default_factory=dict)
    layers: dict[str, list[str]] = field(default_factory=dict)
    handles: dict[str, list[str | None]] = field(default_factory=dict)
    positions: dict[str, list[int]] = field(default_factory=dict)
    rest: list[tuple[int, str | None]] = field(default_factory=list)
    vertices: NDArray[np.float64] = field(default_factory=lambda: np.empty((0, 2)))
    bulges: NDArray[np.float64] = field(default_factory=lambda: np.empty(0))
    vertex_start: NDArray[np.intp] = field(default_factory=lambda: np.zeros(1, np.intp))

    def count(self, kind: str) -> int:
        return len(self.layers.get(kind, []))


def split_entities(text: str) -> tuple[SimpleEntities, str]:
    """The simple model-space entities of a DXF ``text``, and the DXF text of everything else."""
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    if len(lines) % 2:
        raise DamagedDXF("the file ends in the middle of a group code/value pair (truncated?)")
    try:
        codes = np.fromiter(map(int, lines[0::2]), np.int64, len(lines) // 2)
    except (ValueError, OverflowError):
        bad = _first_not_int(lines[0::2])
        raise DamagedDXF(f"line {2 * bad + 1}: {lines[2 * bad]!r} is not a group code") from None
    values = lines[1::2]
    if not len(codes) or codes[-1] != 0 or values[-1].strip() != "EOF":
        raise DamagedDXF("the file does not end with the EOF marker (truncated?)")
    zero = np.flatnonzero(codes == 0)
    names = [values[i].strip() for i in zero]
    section = _entities_section(codes, values, zero, names)
    if section is None:
        return SimpleEntities(), "\n".join(lines)
    first, last = section  # indices into ``zero``: the entities are zero[first:last]
    starts = zero[first:last]
    ends = zero[first + 1:last + 1]
    kinds = np.array(names[first:last], dtype=object)
    simple = _simple_entities(codes, values, starts, ends, kinds)
    found, taken = _decode(codes, values, starts, ends, kinds, simple)
    _places(found, codes, values, starts, ends, kinds, taken)
    # The rest of the file: the runs of tags between the entities taken, as text lines.
    keep = np.ones(len(codes) + 1, bool)
    keep[np.repeat(starts[taken], (ends - starts)[taken]) + _ranks(ends[taken] - starts[taken])] = False
    keep[-1] = False
    edges = np.flatnonzero(np.diff(np.concatenate([[False], keep])))
    rest = "\n".join(itertools.chain.from_iterable(lines[2 * a:2 * b] for a, b in zip(edges[0::2], edges[1::2])))
    return found, rest


def _places(found: SimpleEntities, codes, values, starts, ends, kinds, taken) -> None:
    """Each entity's position in the section, for the simple ones taken and the model-space rest:
    a user finds an entity without a handle by it."""
    n = len(starts)
    if not n:
        return
    position = np.cumsum(~np.isin(kinds, ("VERTEX", "SEQEND", "ATTRIB")))
    for kind, members in found.positions.items():
        found.positions[kind] = position[members].tolist()
    lo = int(starts[0])
    owner = np.repeat(np.arange(n), ends - starts)
    section = codes[lo:int(ends[-1])]
    paper = np.zeros(n, bool)
    tags = np.flatnonzero(section == 67)
    paper[owner[tags[np.array([values[lo + t].strip() not in ("", "0") for t in tags.tolist()], bool)]]] = True
    rest = ~taken & ~paper & ~np.isin(kinds, ("VERTEX", "SEQEND", "ATTRIB"))
    handles: list[str | None] = [None] * n
    tags = np.flatnonzero(section == 5)
    for t in tags[rest[owner[tags]]][::-1].tolist():  # backwards: an entity's first handle wins
        handles[owner[t]] = values[lo + t].strip()
    found.rest = [(int(position[k]), handles[k]) for k in np.flatnonzero(rest).tolist()]


def _first_not_int(texts: list[str]) -> int:
    for k, text in enumerate(texts):
        try:
            if not _CODE_RANGE[0] <= int(text) <= _CODE_RANGE[1]:
                return k
        except ValueError:
            return k
    raise AssertionError("every text is an integer")


def _ranks(lengths: NDArray[np.intp]) -> NDArray[np.intp]:
    """0..n-1 for each run length n, concatenated."""
    return np.arange(int(lengths.sum())) - np.repeat(np.cumsum(lengths) - lengths, lengths)


def _entities_section(codes, values, zero, names) -> tuple[int, int] | None:
    """Indices (into ``zero``) of the first entity of the ENTITIES section and of its ENDSEC."""
    for k, name in enumerate(names):
        i = zero[k]
        if name == "SECTION" and i + 1 < len(codes) and codes[i + 1] == 2 and values[i + 1].strip() == "ENTITIES":
            end = next((j for j in range(k + 1, len(names)) if names[j] in ("ENDSEC", "EOF")), None)
            if end is None or names[end] != "ENDSEC":
                raise DamagedDXF("the ENTITIES section has no ENDSEC")
            return k + 1, end
    return None


def _simple_entities(codes, values, starts, ends, kinds) -> NDArray[np.bool_]:
    """Which entities the fast path decodes: simple types in model space, visible, without foreign
    groups, with each required code once and each optional code at most once."""
    n = len(starts)
    candidate = np.isin(kinds, SIMPLE)
    if not candidate.any():
        return candidate
    lo = int(starts[0])
    owner = np.repeat(np.arange(n), ends - starts)  # entity of each tag in the section
    section = codes[lo:int(ends[-1])]
    counts: dict[int, NDArray[np.intp]] = {}

    def count(code: int) -> NDArray[np.intp]:
        if code not in counts:
            counts[code] = np.bincount(owner[section == code], minlength=n)
        return counts[code]

    for code in _FOREIGN:
        candidate &= count(code) == 0
    for code in _OPTIONAL:
        candidate &= count(code) <= 1
    for kind, required in _REQUIRED.items():
        is_kind = kinds == kind
        for code in required:
            candidate &= ~is_kind | (count(code) == 1)
    candidate &= (kinds != "LWPOLYLINE") | (count(10) == count(20))
    # Paper space (67 = 1) and invisible (60 = 1) entities are left to ezdxf.
    for code in (67, 60):
        tags = np.flatnonzero(section == code)
        flagged = np.array([values[lo + t].strip() not in ("", "0") for t in tags.tolist()], bool)
        candidate[owner[tags[flagged]]] = False
    return candidate


def _decode(codes, values, starts, ends, kinds, simple) -> tuple[SimpleEntities, NDArray[np.bool_]]:
    """Columns of the simple entities; also which entities were taken."""
    found = SimpleEntities()
    taken = np.zeros(len(starts), bool)
    n = len(starts)
    if not simple.any():
        return found, taken
    lo, hi = int(starts[0]), int(ends[-1])
    owner = np.repeat(np.arange(n), ends - starts)
    section_codes = codes[lo:hi]
    section_values = np.array(values[lo:hi], dtype=object)
    for kind in SIMPLE:
        members = np.flatnonzero(simple & (kinds == kind))
        if not len(members):
            continue
        mine = np.zeros(n, bool)
        mine[members] = True
        table = _KindTable(section_codes, section_values, owner, mine[owner], members)
        try:
            columns = {code: table.floats(code) for code in _REQUIRED[kind]}
            for code, default in ((210, 0.0), (220, 0.0), (230, 1.0), (70, 0.0), (30, 0.0), (31, 0.0)):
                columns[code] = table.floats(code, default)
            if kind == "LWPOLYLINE":
                found.vertices, found.bulges, found.vertex_start = table.vertices()
        except ValueError as error:
            raise DamagedDXF(f"a {kind} has a value that is not a number ({one_line(error)})") from None
        found.columns[kind] = columns
        found.layers[kind] = [layer if layer is not None else "0" for layer in table.texts(8)]
        found.handles[kind] = table.texts(5)
        found.positions[kind] = members
        taken[members] = True
    return found, taken


class _KindTable:
    """The tags of the entities of one type (``members``, entity indices in the section)."""

    def __init__(self, codes, values, owner, in_kind, members) -> None:
        self.codes, self.values, self.owner, self.in_kind, self.members = codes, values, owner, in_kind, members

    def tags(self, code: int) -> NDArray[np.intp]:
        return np.flatnonzero(self.in_kind & (self.codes == code))

    def floats(self, code: int, default: float | None = None) -> NDArray[np.float64]:
        """One number per entity: required (each has it once) or else ``default`` where absent."""
        tags = self.tags(code)
        numbers = self.values[tags].astype(float)
        if default is None:
            return numbers
        out = np.full(len(self.members), default)
        out[np.searchsorted(self.members, self.owner[tags])] = numbers
        return out

    def texts(self, code: int) -> list[str | None]:
        """One text per entity (None where absent)."""
        tags = self.tags(code)
        if len(tags) == len(self.members):  # each has it (at most once each, as checked)
            return [text.strip() for text in self.values[tags].tolist()]
        out: list[str | None] = [None] * len(self.members)
        for p, text in zip(np.searchsorted(self.members, self.owner[tags]).tolist(), self.values[tags].tolist()):
            out[p] = text.strip()
        return out

    def vertices(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
        """LWPOLYLINE vertices (10/20), their bulges (42, after the vertex it belongs to), offsets."""
        x_tags, y_tags, b_tags = self.tags(10), self.tags(20), self.tags(42)
        xy = np.column_stack([self.values[x_tags].astype(float), self.values[y_tags].astype(float)])
        bulges = np.zeros(len(x_tags))
        if len(b_tags):
            vertex = np.searchsorted(x_tags, b_tags, side="right") - 1
            if (vertex < 0).any() or (self.owner[x_tags[np.maximum(vertex, 0)]] != self.owner[b_tags]).any():
                raise ValueError("a bulge (42) comes before its polyline's first vertex")
            bulges[vertex] = self.values[b_tags].astype(float)
        per_entity = np.bincount(np.searchsorted(self.members, self.owner[x_tags]), minlength=len(self.members))
        return xy, bulges, np.concatenate([[0], np.cumsum(per_entity)]).astype(np.intp)
