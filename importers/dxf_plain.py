"""The header and layer table of a plain DXF file, read without ezdxf.

Once the fast tag table (:mod:`.dxf_tags`) has taken every entity of a sketch, what is left for ezdxf
is the HEADER (for ``$ACADVER`` and ``$INSUNITS``), the layer table (which layers are off or frozen)
and sections nobody reads; importing ezdxf for that costs 0.2 s, more than the whole analysis of a
small mechanism. This module reads those few values from the remaining tags, and only from a file it
is sure ezdxf would load without a complaint: ASCII text, every tag of the type its group code
requires, sections, tables and blocks well formed, no repeated handle, layer or header variable, no
block content, and a DXF version ezdxf knows. Anything else (binary DXF, encodings, blocks and
INSERTs, unusual structure, damage) gives None, and the caller reads the file with ezdxf as always,
so both ways give the same sketch.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from itertools import chain

from linkstress.importers.dxf_tags import decode_dxf_unicode

VERSIONS = ("AC1009", "AC1012", "AC1014", "AC1015", "AC1018", "AC1021", "AC1024", "AC1027", "AC1032")
"""The DXF versions ($ACADVER) ezdxf loads as they are or upgrades without a word: R12 to R2018."""
NO_VERSION = "AC1009"
"""The version ezdxf assumes when the header does not say one (DXF R12)."""
SECTIONS = ("HEADER", "CLASSES", "TABLES", "BLOCKS", "ENTITIES", "OBJECTS")
TABLES = ("LAYER", "LTYPE", "APPID", "DIMSTYLE", "STYLE", "UCS", "VIEW", "VPORT", "BLOCK_RECORD")

# ezdxf's types of group codes (ezdxf.lldxf.types): its tag compiler refuses a file whose value does
# not parse as the type of its code; a point's x code (10, 11, ...) must be followed by its y code.
POINT_CODES = frozenset((*range(10, 19), 110, 111, 112, 210, 211, 212, 213, 1010, 1011, 1012, 1013))
INT_CODES = frozenset(chain(range(60, 80), range(90, 100), range(160, 180), range(270, 300), range(370, 390),
                            range(400, 410), range(420, 430), range(440, 460), range(1060, 1072)))
FLOAT_CODES = frozenset(chain(range(10, 60), range(110, 150), range(210, 240), range(460, 470), range(1010, 1060)))
BINARY_CODES = frozenset((*range(310, 320), 1004))
_COMMENT = 999
_XDICTIONARY = "{ACAD_XDICTIONARY"  # ezdxf resolves its handle while loading, and fails if it is missing
_LAYER_KEYS = (2, 62, 70)  # the layer's name, colour (negative: off) and flags (1: frozen)


@dataclass(frozen=True)
class DocumentFacts:
    """What a sketch needs of a DXF file beside its entities, as ezdxf would give it.

    ``version``: ``$ACADVER`` as written (``AC1009`` when the header has none); ``insunits``: the
    ``$INSUNITS`` code, None when the header has none; ``hidden_layers``: names (decoded, lower case)
    of the layers that are off or frozen, and ``defpoints``; ``has_header``: whether the file has a
    HEADER section.
    """

    version: str
    insunits: int | None
    hidden_layers: frozenset[str]
    has_header: bool


def read_plain(rest: str) -> DocumentFacts | None:
    """The header values and hidden layers of an ASCII DXF file from ``rest``, its text without the
    entities the fast path took; None unless the file is plain (see the module). The caller checks
    that the file is ASCII: then the encoding it declares cannot change a character."""
    lines = rest.split("\n")
    if len(lines) % 2:
        return None
    tags = [(int(code), value) for code, value in zip(lines[0::2], lines[1::2]) if int(code) != _COMMENT]
    if not _typed(tags):
        return None
    records = _records(tags)
    if records is None:
        return None
    sections = _sections(records)
    if sections is None or not _handles_unique(sections):
        return None
    header = _header(sections.get("HEADER"))
    hidden = _hidden_layers(sections.get("TABLES", []))
    if header is None or hidden is None or not _only(sections, "CLASSES", "CLASS") or not _blocks_empty(sections):
        return None
    if len(sections.get("ENTITIES", [None])) > 1 or not _objects_plain(sections.get("OBJECTS")):
        return None
    version = header.get("$ACADVER", (1, NO_VERSION))
    if version[0] != 1 or version[1] not in VERSIONS:
        return None
    insunits = header.get("$INSUNITS")
    if insunits is not None and (insunits[0] != 70 or not _is_int(insunits[1])):
        return None
    return DocumentFacts(version[1], None if insunits is None else int(insunits[1]), hidden, "HEADER" in sections)


Tag = tuple[int, str]
Record = list[Tag]


def _is_int(text: str) -> bool:
    try:
        int(text)
    except ValueError:
        return False
    return True


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _typed(tags: list[Tag]) -> bool:
    """Whether every value parses as its code's type and every point has its y (as ezdxf demands)."""
    for k, (code, value) in enumerate(tags):
        if code in BINARY_CODES:
            return False
        if code in POINT_CODES and (k + 1 == len(tags) or tags[k + 1][0] != code + 10):
            return False
        if code in INT_CODES and not _is_int(value):
            return False
        if code in FLOAT_CODES and not _is_float(value):
            return False
    return True


def _records(tags: list[Tag]) -> list[Record] | None:
    """The tags split at each code 0 into records, the last the single EOF; None if a record name
    carries spaces, a tag precedes the first record or another EOF comes first."""
    starts = [k for k, (code, _) in enumerate(tags) if code == 0]
    if not starts or starts[0] != 0 or any(tags[k][1] != tags[k][1].strip() for k in starts):
        return None
    records = [tags[a:b] for a, b in zip(starts, starts[1:] + [len(tags)])]
    names = [record[0][1] for record in records]
    if names.count("EOF") != 1 or names[-1] != "EOF" or len(records[-1]) != 1:
        return None
    return records[:-1]


def _sections(records: list[Record]) -> dict[str, list[Record]] | None:
    """Each section's records by name (the section's own head first); None unless the records are
    sections one after another, each named once with a name of ``SECTIONS``."""
    sections: dict[str, list[Record]] = {}
    current: list[Record] | None = None
    for record in records:
        name = record[0][1]
        if name == "SECTION":
            if current is not None or len(record) < 2 or record[1][0] != 2 or record[1][1] not in SECTIONS:
                return None
            if record[1][1] in sections or (record[1][1] != "HEADER" and len(record) != 2):
                return None
            current = sections[record[1][1]] = [record]
        elif name == "ENDSEC":
            if current is None or len(record) != 1:
                return None
            current = None
        elif current is None:
            return None
        else:
            current.append(record)
    return None if current is not None else sections


def _handles_unique(sections: dict[str, list[Record]]) -> bool:
    """No handle (code 5, or 105 of a DIMSTYLE) repeats outside the header: ezdxf warns of each."""
    handles = Counter(value.strip().upper() for name, records in sections.items() if name != "HEADER"
                      for record in records for code, value in record if code in (5, 105))
    return all(count == 1 for count in handles.values())


def _header(section: list[Record] | None) -> dict[str, Tag] | None:
    """Header variable -> its value tag (code, text; a point's x tag), the last of a name winning
    as in ezdxf; None unless every name starts with ``$`` and has exactly one value (a point's x, y
    and z count as one)."""
    if section is None:
        return {}
    tags = section[0][2:]
    header: dict[str, Tag] = {}
    k = 0
    while k < len(tags):
        code, name = tags[k]
        if code != 9 or not name.startswith("$") or k + 1 == len(tags) or tags[k + 1][0] == 9:
            return None
        value = tags[k + 1]
        k += 2
        if value[0] in POINT_CODES:
            k += 1 + (k + 1 < len(tags) and tags[k + 1][0] == value[0] + 20)
        header[name] = value
    return header


def _hidden_layers(records: list[Record]) -> frozenset[str] | None:
    """The layers that are off or frozen, from the TABLES section's records; None unless each table
    is a TABLE head naming a known table once, entries of that table's type, and ENDTAB, and each
    layer has one name, at most one colour and flags, none of them in app data or extended data."""
    hidden = {"defpoints"}
    table: str | None = None
    seen_tables: set[str] = set()
    seen_layers: set[str] = set()
    for record in records[1:]:
        kind = record[0][1]
        if _outside_groups(record) is None:
            return None
        if kind == "TABLE":
            names = [value for code, value in record if code == 2]
            if table is not None or len(names) != 1 or names[0] not in TABLES or names[0] in seen_tables:
                return None
            table = names[0]
            seen_tables.add(table)
        elif kind == "ENDTAB":
            if table is None:
                return None
            table = None
        elif kind != table:
            return None
        elif kind == "LAYER":
            layer = _layer(record)
            if layer is None or layer[0].lower() in seen_layers:
                return None
            seen_layers.add(layer[0].lower())
            if layer[1] < 0 or layer[2] & 1:
                hidden.add(decode_dxf_unicode(layer[0]).lower())
    return None if table is not None else frozenset(hidden)


def _layer(record: Record) -> tuple[str, int, int] | None:
    """A LAYER entry's name, colour (7 if absent) and flags (0 if absent), or None if in doubt."""
    plain = _outside_groups(record)
    if plain is None:
        return None
    found = {code: [value for c, value in plain if c == code] for code in _LAYER_KEYS}
    inside = sum(1 for code, _ in record if code in _LAYER_KEYS) - sum(len(v) for v in found.values())
    if inside or len(found[2]) != 1 or len(found[62]) > 1 or len(found[70]) > 1:
        return None
    colour = int(found[62][0]) if found[62] else 7
    flags = int(found[70][0]) if found[70] else 0
    return found[2][0], colour, flags


def _outside_groups(record: Record) -> Record | None:
    """A record's tags outside its app data groups (102 ``{NAME`` ... 102 ``}`` or ``NAME}``) and its
    extended data (from the first 1001 on); None if a group is not closed, nests, or follows a
    subclass marker (ezdxf reads app data only before the first), is an extension dictionary, or the
    record embeds an object (101)."""
    plain: Record = []
    group: str | None = None  # the open group's name
    subclassed = False
    for code, value in record:
        if code == 1001:
            break
        if code == 101:
            return None
        subclassed |= code == 100
        if code == 102:
            if group is None and value.startswith("{") and not subclassed and value != _XDICTIONARY:
                group = value[1:]
            elif group is not None and value in ("}", group + "}"):
                group = None
            else:
                return None
        elif group is None:
            plain.append((code, value))
    return None if group is not None else plain


def _only(sections: dict[str, list[Record]], name: str, kind: str) -> bool:
    """Whether section ``name`` (if present) holds only records of ``kind``, each well grouped."""
    return all(r[0][1] == kind and _outside_groups(r) is not None for r in sections.get(name, [None])[1:])


def _blocks_empty(sections: dict[str, list[Record]]) -> bool:
    """Whether the BLOCKS section (if present) holds only definitions without content: BLOCK, each
    named, then its ENDBLK. Block content would have to be read (model space's own block holds
    entities in some files), so any sends the file to ezdxf."""
    records = sections.get("BLOCKS", [None])[1:]
    kinds = [record[0][1] for record in records]
    if kinds[0::2] != ["BLOCK"] * len(kinds[0::2]) or kinds[1::2] != ["ENDBLK"] * len(kinds[1::2]):
        return False
    named = all(sum(code == 2 and value.strip() != "" for code, value in r) == 1 for r in records[0::2])
    return len(kinds) % 2 == 0 and named and all(_outside_groups(r) is not None for r in records)


def _objects_plain(section: list[Record] | None) -> bool:
    """Whether the OBJECTS section (if present) starts with the root DICTIONARY ezdxf requires and
    each object's app data groups are well formed."""
    if section is None:
        return True
    objects = section[1:]
    return bool(objects) and objects[0][0][1] == "DICTIONARY" and all(_outside_groups(r) is not None for r in objects)
