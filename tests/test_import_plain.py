"""A plain DXF file (ASCII, entities the fast path reads, a clean header and tables) is read without
ezdxf, into exactly the sketch that ezdxf's reading gives: the same links (outlines to the bit,
areas, joints and their rules, holes), units and where they came from, format, ignored entities,
fixes and problems. Files it is not sure of go to ezdxf as before."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import ezdxf
import pytest

from linkstress.errors import SketchError
from linkstress.importers import dxf, read_sketch
from linkstress.importers.dxf_tags import SimpleEntities, decode_dxf_unicode

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
SHIPPED = sorted(CASES.glob("*/*.dxf"))


def plain_facts(path: Path):
    data = path.read_bytes()
    return dxf._read_plain(data, dxf._has_header(data))[0]


def through_ezdxf(monkeypatch, path: Path, entities_too: bool = True, **options):
    """The sketch as read with the plain reader switched off (ezdxf reads header, tables and the rest),
    checked (``entities_too``) to be the sketch read with the fast tag table off too (ezdxf reads
    every entity)."""
    with monkeypatch.context() as patch:
        patch.setattr(dxf, "_read_plain", lambda data, has_header: (None, SimpleEntities()))
        sketch = read_sketch(path, **options)
        if entities_too:
            patch.setattr(dxf, "split_entities", lambda text: (SimpleEntities(), text))
            assert_same_sketch(read_sketch(path, **options), sketch)
    return sketch


def assert_same_sketch(a, b) -> None:
    assert (a.format, a.units, a.units_source) == (b.format, b.units, b.units_source)
    assert a.gap_tolerance_m == b.gap_tolerance_m
    assert dict(a.ignored) == dict(b.ignored) and a.fixes == b.fixes and a.problems == b.problems
    assert len(a.links) == len(b.links) > 0
    for x, y in zip(a.links, b.links):
        assert (x.name, x.layer, x.joint_rules, x.hole_diameters_m, x.hole_rules, x.largest_gap_m) == (
            y.name, y.layer, y.joint_rules, y.hole_diameters_m, y.hole_rules, y.largest_gap_m)
        assert x.outline.wkb == y.outline.wkb and x.outline.area == y.outline.area
        assert x.joints.tobytes() == y.joints.tobytes()


@pytest.mark.parametrize("path", SHIPPED, ids=[p.name for p in SHIPPED])
def test_each_shipped_sketch_reads_plain_into_the_sketch_ezdxf_gives(monkeypatch, path):
    assert plain_facts(path) is not None
    assert_same_sketch(read_sketch(path), through_ezdxf(monkeypatch, path))


def slot_link(layout, layer: str, y: float, length: float) -> None:
    """A 24 mm deep link of LINEs and ARCs along y, pin holes (CIRCLEs with POINTs) at x = 0 and ``length``."""
    att = {"layer": layer}
    layout.add_line((0, y - 12), (length, y - 12), dxfattribs=att)
    layout.add_line((length, y + 12), (0, y + 12), dxfattribs=att)
    layout.add_arc((length, y), 12, -90, 90, dxfattribs=att)
    layout.add_arc((0, y), 12, 90, 270, dxfattribs=att)
    for x in (0.0, length):
        layout.add_circle((x, y), 5, dxfattribs=att)
        layout.add_point((x, y), dxfattribs=att)


def four_bar_sketch(layout, layers=("crank", "coupler"), polyline: bool = True) -> None:
    """Two links in mm: a crank (an LWPOLYLINE with bulges, or LINEs and ARCs) and a coupler of
    LINEs and ARCs, pin holes as CIRCLEs with POINTs, on ``layers``."""
    crank, coupler = layers
    if polyline:
        layout.add_lwpolyline([(0, -10, 0.0), (100, -10, 1.0), (100, 10, 0.0), (0, 10, 1.0)], format="xyb",
                              close=True, dxfattribs={"layer": crank})
        for x in (0.0, 100.0):
            layout.add_circle((x, 0), 4, dxfattribs={"layer": crank})
            layout.add_point((x, 0), dxfattribs={"layer": crank})
    else:
        slot_link(layout, crank, 0.0, 100.0)
    slot_link(layout, coupler, 60.0, 150.0)


def drawing(version: str, units: int | None = 4, hide: str | None = None):
    doc = ezdxf.new(version) if units is None else ezdxf.new(version, units=units)
    for name in ("crank", "coupler", "notes"):
        doc.layers.add(name)
    if hide == "off":
        doc.layers.get("notes").off()
    elif hide == "frozen":
        doc.layers.get("notes").freeze()
    return doc


@pytest.mark.parametrize("version", ["R2000", "R2004", "R2007", "R2010", "R2013", "R2018"])
@pytest.mark.parametrize("hide", [None, "off", "frozen"])
def test_generated_sketches_of_every_version_read_plain_as_ezdxf_reads_them(tmp_path, monkeypatch, version, hide):
    doc = drawing(version, hide=hide)
    msp = doc.modelspace()
    four_bar_sketch(msp)
    msp.add_line((-50, -50), (-40, -40), dxfattribs={"layer": "notes"})  # a stray line: a problem if shown
    msp.add_line((300, 0), (310, 0), dxfattribs={"layer": "Defpoints"})
    doc.saveas(tmp_path / "sketch.dxf")
    assert plain_facts(tmp_path / "sketch.dxf") is not None
    if hide is None:
        with pytest.raises(SketchError, match="open curve"):
            read_sketch(tmp_path / "sketch.dxf", layers=["notes"])
    sketch = read_sketch(tmp_path / "sketch.dxf")
    assert sorted(link.name for link in sketch.links) == ["coupler", "crank"]
    assert_same_sketch(sketch, through_ezdxf(monkeypatch, tmp_path / "sketch.dxf"))


@pytest.mark.parametrize("units, given, expected", [
    (4, None, ("mm", "$INSUNITS")),
    (1, None, ("in", "$INSUNITS")),
    (1, "mm", ("mm", "--units mm, overriding the file's $INSUNITS inches")),
    (0, "cm", ("cm", "given by the caller (--units or the scene's units)")),
    (9, "mm", ("mm", "given by the caller (--units or the scene's units)")),  # mils: no conversion
])
def test_units_come_from_insunits_as_through_ezdxf(tmp_path, monkeypatch, units, given, expected):
    doc = drawing("R2010", units=units)
    four_bar_sketch(doc.modelspace())
    doc.saveas(tmp_path / "units.dxf")
    assert plain_facts(tmp_path / "units.dxf").insunits == units
    sketch = read_sketch(tmp_path / "units.dxf", units=given)
    assert (sketch.units, sketch.units_source) == expected
    assert_same_sketch(sketch, through_ezdxf(monkeypatch, tmp_path / "units.dxf", units=given))


def test_a_file_without_insunits_is_refused_with_the_same_message_both_ways(tmp_path, monkeypatch):
    doc = drawing("R2010", units=None)
    four_bar_sketch(doc.modelspace())
    del doc.header["$INSUNITS"]
    doc.saveas(tmp_path / "bare.dxf")
    assert plain_facts(tmp_path / "bare.dxf").insunits is None
    with pytest.raises(SketchError) as plain:
        read_sketch(tmp_path / "bare.dxf")
    with pytest.raises(SketchError) as slow:
        through_ezdxf(monkeypatch, tmp_path / "bare.dxf")
    assert str(plain.value) == str(slow.value)
    assert "the file has no $INSUNITS" in str(plain.value)


def test_an_r12_drawing_with_escaped_layer_names_reads_plain(tmp_path, monkeypatch):
    doc = ezdxf.new("R12")
    doc.layers.add("\u039bcrank")
    doc.layers.add("coupler").off()
    msp = doc.modelspace()
    four_bar_sketch(msp, layers=("\u039bcrank", "\u039bcrank"), polyline=False)
    msp.add_line((-50, -50), (-40, -40), dxfattribs={"layer": "coupler"})
    doc.saveas(tmp_path / "r12.dxf")
    data = (tmp_path / "r12.dxf").read_bytes()
    assert data.isascii() and b"\\U+039" in data  # the capital lambda written escaped
    assert plain_facts(tmp_path / "r12.dxf").version == "AC1009"
    sketch = read_sketch(tmp_path / "r12.dxf", units="mm")
    assert sketch.links[0].layer == "\u039bcrank" and sketch.ignored == {"LINE (hidden layer)": 1}
    assert_same_sketch(sketch, through_ezdxf(monkeypatch, tmp_path / "r12.dxf", units="mm"))


def test_a_file_of_entities_alone_without_header_reads_plain(tmp_path, monkeypatch):
    doc = drawing("R2010")
    four_bar_sketch(doc.modelspace())
    doc.saveas(tmp_path / "full.dxf")
    text = (tmp_path / "full.dxf").read_text()
    start = text.index("ENTITIES") - len("  0\nSECTION\n  2\n")
    end = text.index("ENDSEC", start) + len("ENDSEC\n")
    (tmp_path / "bare.dxf").write_text(text[start:end] + "  0\nEOF\n")  # as OpenSCAD writes
    assert plain_facts(tmp_path / "bare.dxf").has_header is False
    sketch = read_sketch(tmp_path / "bare.dxf", units="mm")
    assert sketch.format == "DXF without HEADER section (version unknown)"
    # ezdxf alone reads a header-less file as R12, where an LWPOLYLINE's closing flag is lost: only
    # the fast tag table reads this crank closed, with or without the plain reader.
    assert_same_sketch(sketch, through_ezdxf(monkeypatch, tmp_path / "bare.dxf", entities_too=False, units="mm"))


def declined(tmp_path, change) -> bool:
    doc = drawing("R2013")
    four_bar_sketch(doc.modelspace())
    change(doc)
    doc.saveas(tmp_path / "other.dxf")
    return plain_facts(tmp_path / "other.dxf") is None


@pytest.mark.parametrize("what, change", [
    ("an ELLIPSE", lambda doc: doc.modelspace().add_ellipse((500, 0), (20, 0), 0.5)),
    ("a SPLINE", lambda doc: doc.modelspace().add_spline([(500, 0), (510, 5), (520, 0)])),
    ("a block reference", lambda doc: (doc.blocks.new("PIN").add_circle((0, 0), 2),
                                       doc.modelspace().add_blockref("PIN", (500, 0)))),
    ("a block definition with content", lambda doc: doc.blocks.new("PIN").add_circle((0, 0), 2)),
    ("a paper-space line", lambda doc: doc.paperspace().add_line((0, 0), (1, 1))),
    ("a non-ASCII layer name", lambda doc: doc.modelspace().add_point((1, 1), dxfattribs={"layer": "\u00e9"})),
])
def test_a_file_with_what_the_plain_reader_does_not_know_goes_to_ezdxf(tmp_path, what, change):
    assert declined(tmp_path, change)


def test_a_garbled_header_or_table_goes_to_ezdxf_and_its_recover_mode(tmp_path):
    doc = drawing("R2013")
    four_bar_sketch(doc.modelspace())
    doc.saveas(tmp_path / "good.dxf")
    text = (tmp_path / "good.dxf").read_text()
    layer_colour = text.index("\n 62\n", text.index("AcDbLayerTableRecord"))
    for name, garbled in [
        ("insunits", text.replace("$INSUNITS\n 70\n4\n", "$INSUNITS\n 70\nfour\n")),
        ("colour", text[:layer_colour] + "\n 62\n7.5x" + text[text.index("\n", layer_colour + 5):]),
        ("section", text.replace("  2\nCLASSES\n", "  2\nCLASSIC\n", 1)),
        ("two EOF", text.replace("ENDSEC\n  0\nSECTION\n  2\nOBJECTS", "ENDSEC\n  0\nEOF\n  0\nSECTION\n  2\nOBJECTS")),
    ]:
        (tmp_path / f"{name}.dxf").write_text(garbled)
        assert plain_facts(tmp_path / f"{name}.dxf") is None, name
    assert any("recover" in fix for fix in read_sketch(tmp_path / "colour.dxf").fixes)


def test_binary_dxf_goes_to_ezdxf(tmp_path):
    doc = drawing("R2013")
    four_bar_sketch(doc.modelspace())
    doc.saveas(tmp_path / "binary.dxf", fmt="bin")
    assert plain_facts(tmp_path / "binary.dxf") is None
    assert sorted(link.name for link in read_sketch(tmp_path / "binary.dxf").links) == ["coupler", "crank"]


def test_dxf_unicode_decodes_as_ezdxf_decodes():
    for text in ["plain", "\\U+039Bcrank", "a\\U+00e9b\\U+00E9", "\\U+12", "x\\U+12", "\\\\U+0041", "\\U+D800"]:
        assert decode_dxf_unicode(text) == ezdxf.decode_dxf_unicode(text)
    # not hex after the escape: ezdxf raises; ours keeps it as written, so that a layer name or a
    # --layers value like it is a name, never a traceback
    with pytest.raises(ValueError):
        ezdxf.decode_dxf_unicode("\\U+zzzz")
    assert decode_dxf_unicode("\\U+zzzz") == "\\U+zzzz"


def test_reading_the_seed_sketch_imports_neither_ezdxf_nor_scipy():
    program = (
        "import sys; from linkstress.importers import read_sketch; "
        f"read_sketch({str(CASES / 'seed_ansys_fourbar' / 'ansys_four_bars.dxf')!r}); "
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('ezdxf', 'scipy')))"
    )
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


ENTITIES = (
    "  0\nSECTION\n  2\nENTITIES\n"
    "  0\nLWPOLYLINE\n  8\ncrank\n 90\n4\n 70\n1\n 10\n0\n 20\n-10\n 10\n100\n 20\n-10\n 42\n1\n"
    " 10\n100\n 20\n10\n 10\n0\n 20\n10\n 42\n1\n"
    "  0\nCIRCLE\n  8\ncrank\n 10\n0\n 20\n0\n 40\n4\n  0\nCIRCLE\n  8\ncrank\n 10\n100\n 20\n0\n 40\n4\n"
    "  0\nLINE\n  8\nnotes\n 10\n-50\n 20\n-50\n 11\n-40\n 21\n-40\n  0\nENDSEC\n"
)
"""A crank (a closed LWPOLYLINE with bulges, two pin holes) and a stray LINE on layer notes, in mm."""


def header(version: str = "AC1015", extra: str = "") -> str:
    return f"  0\nSECTION\n  2\nHEADER\n  9\n$ACADVER\n  1\n{version}\n  9\n$INSUNITS\n 70\n4\n{extra}  0\nENDSEC\n"


def layers(notes: str = "", colour: int = 7, flags: int = 0, more: str = "") -> str:
    entry = "  0\nLAYER\n{}  2\n{}\n 70\n{}\n 62\n{}\n  6\nCONTINUOUS\n"
    return ("  0\nSECTION\n  2\nTABLES\n  0\nTABLE\n  2\nLAYER\n 70\n2\n" + entry.format("", "crank", 0, 7)
            + entry.format(notes, "notes", flags, colour) + more + "  0\nENDTAB\n  0\nENDSEC\n")


BLOCK = ("  0\nSECTION\n  2\nBLOCKS\n  0\nBLOCK\n  8\n0\n  2\n*Model_Space\n 70\n0\n 10\n0\n 20\n0\n"
         "{}  0\nENDBLK\n  8\n0\n  0\nENDSEC\n")
"""The BLOCKS section with model space's block, its content (DXF text) to be filled in."""
HAND_WRITTEN = {
    # name: (the file's text, read plain?)
    "R2000 without OBJECTS or BLOCKS": (header() + layers() + ENTITIES, True),
    "a comment first, as LibreCAD writes": ("999\ndxfrw 0.6.3\n" + header() + layers() + ENTITIES, True),
    "R12 without tables": (header("AC1009") + ENTITIES, True),
    "a layer off (negative colour)": (header() + layers(colour=-7) + ENTITIES, True),
    "a layer frozen and locked": (header() + layers(flags=5) + ENTITIES, True),
    "a point in the header": (header(extra="  9\n$EXTMIN\n 10\n0\n 20\n0\n 30\n0\n") + layers() + ENTITIES, True),
    "an empty model-space block": (header() + layers() + BLOCK.format("") + ENTITIES, True),
    "a missing reactor": (header() + layers("102\n{ACAD_REACTORS\n330\n1F\n102\n}\n", -7) + ENTITIES, True),
    "an extension dictionary": (header() + layers("102\n{ACAD_XDICTIONARY\n360\n1F\n102\n}\n", -7) + ENTITIES, False),
    "an app data group not closed": (header() + layers("102\n{ACAD_REACTORS\n330\n1F\n", -7) + ENTITIES, False),
    "two layers differing in case": (header() + layers(colour=-7, more="  0\nLAYER\n  2\nNOTES\n 70\n0\n 62\n7\n")
                                     + ENTITIES, False),
    "a handle twice": (header() + layers("  5\n10\n", more="  0\nLAYER\n  5\n10\n  2\nx\n 70\n0\n 62\n7\n")
                       + ENTITIES, False),
    "an $INSUNITS of 4.0": (header().replace(" 70\n4\n", " 70\n4.0\n") + layers() + ENTITIES, False),
    "a header point without y": (header(extra="  9\n$EXTMIN\n 10\n0\n 30\n0\n") + layers() + ENTITIES, False),
    "a model-space block with a LINE": (header() + layers() + BLOCK.format(
        "  0\nLINE\n  8\n0\n 10\n0\n 20\n0\n 11\n1\n 21\n1\n") + ENTITIES, False),
    "an unknown table": (header() + layers(more="  0\nENDTAB\n  0\nTABLE\n  2\nFOO\n") + ENTITIES, False),
    "version R10": (header("AC1006") + layers() + ENTITIES, False),
}


@pytest.mark.parametrize("name", HAND_WRITTEN)
def test_hand_written_files_read_plain_only_when_sure_and_always_as_through_ezdxf(tmp_path, monkeypatch, name):
    text, plain = HAND_WRITTEN[name]
    (tmp_path / "hand.dxf").write_text(text + "  0\nEOF\n")
    assert (plain_facts(tmp_path / "hand.dxf") is not None) == plain

    def read():
        try:
            return read_sketch(tmp_path / "hand.dxf")
        except SketchError as error:
            return str(error)

    fast = read()
    with monkeypatch.context() as patch:
        patch.setattr(dxf, "_read_plain", lambda data, has_header: (None, SimpleEntities()))
        slow = read()
    if isinstance(fast, str) or isinstance(slow, str):
        assert fast == slow
    else:
        assert_same_sketch(fast, slow)
