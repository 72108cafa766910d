"""Messages a user of a real DXF can act on: entities without handles named by their position,
units that say what the file lacks, decoded layer names, curves whose z varies, and drawings that hold
only a HATCH.

Every drawing is generated here: DXF text written as R12 exporters write it (no handles), or ezdxf.
"""

from __future__ import annotations

import ezdxf
import pytest

from linkstress.errors import SketchError
from linkstress.importers import read_sketch
from linkstress.importers.problems import SketchProblem


def line(x0, y0, x1, y1, layer="0", extra="") -> str:
    """A LINE record without a handle; ``extra``: more tags (z, app data)."""
    return f"0\nLINE\n8\n{layer}\n10\n{x0}\n20\n{y0}\n11\n{x1}\n21\n{y1}\n{extra}"


def polyline(points, layer="0", flags=0) -> str:
    """A POLYLINE with its VERTEX and SEQEND records, no handles; ``points`` (x, y[, z])."""
    vertex_flags = 32 if flags & 8 else 0  # 32: a 3D polyline's vertex
    vertices = "".join(
        f"0\nVERTEX\n8\n{layer}\n10\n{p[0]}\n20\n{p[1]}\n30\n{p[2] if len(p) > 2 else 0}\n70\n{vertex_flags}\n"
        for p in points)
    return f"0\nPOLYLINE\n8\n{layer}\n66\n1\n70\n{flags}\n{vertices}0\nSEQEND\n8\n{layer}\n"


def r12(path, entities: str, header: str = "9\n$ACADVER\n1\nAC1009\n", blocks: str = "", tables: str = "") -> None:
    """An R12 file as old exporters write it: no handles, no $INSUNITS."""
    head = f"0\nSECTION\n2\nHEADER\n{header}0\nENDSEC\n" if header is not None else ""
    head += f"0\nSECTION\n2\nTABLES\n{tables}0\nENDSEC\n" if tables else ""
    block_section = f"0\nSECTION\n2\nBLOCKS\n{blocks}0\nENDSEC\n" if blocks else ""
    path.write_text(f"{head}{block_section}0\nSECTION\n2\nENTITIES\n{entities}0\nENDSEC\n0\nEOF\n")


TEXT = "0\nTEXT\n8\n0\n10\n0\n20\n0\n40\n1\n1\nnote\n"


# -- entities without handles ---------------------------------------------------------------------


@pytest.mark.parametrize("app_data", ["", "102\n{MYAPP\n1\nx\n102\n}\n"], ids=["fast path", "ezdxf"])
def test_entities_without_handles_are_named_by_their_position_in_the_entities_section(tmp_path, app_data):
    # #1 a TEXT, #2 a POLYLINE (its 3 VERTEX and SEQEND records are not counted), #3 and #4 LINEs; the
    # last LINE stops 0.5 mm short of (0, 0). With app data it is read by ezdxf, else by the fast path.
    entities = (TEXT + polyline([(0, 0), (10, 0), (10, 10)], "plate") + line(10, 10, 0, 10, "plate")
                + line(0, 10, 0, 0.5, "plate", app_data))
    r12(tmp_path / "old.dxf", entities)
    with pytest.raises(SketchError) as error:
        read_sketch(tmp_path / "old.dxf", units="mm")
    message = str(error.value)
    assert "LINE #4 (layer 'plate') at (0, 0.5) mm" in message
    assert "(POLYLINE #2 (layer 'plate') at (0, 0) mm)" in message
    assert "handle" not in message  # ezdxf invents handles for the POLYLINE; none is in the file


def test_a_curve_in_a_block_is_named_by_its_place_in_the_block_and_its_insert(tmp_path):
    # Block 'TAB' holds a CIRCLE (#1) and a LINE (#2) that closes nothing; INSERT #2 puts it beside a
    # closed square (#1), the clean link.
    blocks = ("0\nBLOCK\n8\n0\n2\nTAB\n70\n0\n10\n0\n20\n0\n0\nCIRCLE\n8\n0\n10\n0\n20\n0\n40\n1\n"
              + line(3, 0, 8, 0) + "0\nENDBLK\n8\n0\n")
    entities = (polyline([(-20, -5), (-10, -5), (-10, 5), (-20, 5)], "plate", flags=1)
                + "0\nINSERT\n8\ntabs\n2\nTAB\n10\n0\n20\n0\n")
    r12(tmp_path / "block.dxf", entities, blocks=blocks)
    sketch = read_sketch(tmp_path / "block.dxf", units="mm")
    assert [link.layer for link in sketch.links] == ["plate", "tabs"]  # the circle is a disc of its own
    (problem,) = sketch.problems
    assert problem.entities == ("LINE #2 of block 'TAB' inserted by INSERT #2 (layer 'tabs')",)


def test_a_problem_names_each_entity_once_in_order():
    problem = SketchProblem(None, (0.0, 0.0), "mm", ("ARC #9", "LINE #1", "LINE #1", "ARC #9", "LINE #2"),
                            "p", "f")
    assert problem.entities == ("ARC #9", "LINE #1", "LINE #2")
    assert problem.json()["entities"] == ["ARC #9", "LINE #1", "LINE #2"]


def test_handles_are_kept_when_the_file_has_them(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    stray = doc.modelspace().add_line((0, 0), (5, 0))
    doc.modelspace().add_lwpolyline([(10, 0), (20, 0), (20, 10)], close=True)
    doc.saveas(tmp_path / "new.dxf")
    (problem,) = read_sketch(tmp_path / "new.dxf").problems
    assert problem.entities == (f"LINE (handle {stray.dxf.handle}, layer '0')",)


# -- units and version ----------------------------------------------------------------------------

SQUARE = line(0, 0, 10, 0) + line(10, 0, 10, 10) + line(10, 10, 0, 10) + line(0, 10, 0, 0)


@pytest.mark.parametrize("header, why", [
    (None, "it has no HEADER section, so no $INSUNITS"),
    ("9\n$ACADVER\n1\nAC1009\n", "the file has no $INSUNITS, which DXF R12 and older lack"),
    ("9\n$ACADVER\n1\nAC1015\n", "the file has no $INSUNITS"),
    ("9\n$ACADVER\n1\nAC1015\n9\n$INSUNITS\n70\n0\n", "$INSUNITS is 0 (unitless)"),
], ids=["no HEADER", "R12", "R2000 without $INSUNITS", "$INSUNITS 0"])
def test_the_units_message_says_what_the_file_lacks(tmp_path, header, why):
    r12(tmp_path / "square.dxf", SQUARE, header=header)
    with pytest.raises(SketchError) as error:
        read_sketch(tmp_path / "square.dxf")
    assert str(error.value).startswith(f"square.dxf: the file does not say its units ({why}): pass --units with")


@pytest.mark.parametrize("header, version", [
    (None, "DXF without HEADER section (version unknown)"),
    ("9\n$INSUNITS\n70\n4\n", "DXF without $ACADVER (version unknown)"),
    ("9\n$ACADVER\n1\nAC1006\n", "DXF AC1006"),
], ids=["no HEADER", "no $ACADVER", "AC1006"])
def test_the_format_is_the_version_the_file_says_not_ezdxfs_default(tmp_path, header, version):
    r12(tmp_path / "square.dxf", SQUARE, header=header)
    assert read_sketch(tmp_path / "square.dxf", units="mm").format == version


def test_a_drawing_without_curves_says_so_before_asking_for_units(tmp_path):
    r12(tmp_path / "empty.dxf", TEXT, header=None)
    with pytest.raises(SketchError, match=r"^empty.dxf: no outline: the drawing has no curves it reads \(only 1 TEXT "
                                          r"was found, which is not outline geometry\)$"):
        read_sketch(tmp_path / "empty.dxf")


def test_a_hatch_only_drawing_says_how_to_get_its_boundary_as_curves(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    doc.modelspace().add_hatch().paths.add_polyline_path([(0, 0), (10, 0), (10, 10)], is_closed=True)
    doc.saveas(tmp_path / "fill.dxf")
    with pytest.raises(SketchError) as error:
        read_sketch(tmp_path / "fill.dxf")
    assert str(error.value) == (
        "fill.dxf: no outline: the drawing has no curves it reads (only 1 HATCH was found, which is not "
        "outline geometry); a HATCH is a fill, not an outline: draw its boundary as curves, or regenerate the "
        "hatch's boundary in CAD (AutoCAD: HATCHGENERATEBOUNDARY) and export again")


# -- layer names ------------------------------------------------------------------------------------

LAMBDA = "\\U+039B\\U+0391"  # what R12 writes for the layer name "ΛΑ"


def test_layer_names_written_as_unicode_escapes_are_decoded_and_matched(tmp_path):
    edges = ((20, 0, 30, 0), (30, 0, 30, 10), (30, 10, 20, 10), (20, 10, 20, 0))
    squares = polyline([(0, 0), (10, 0), (10, 10), (0, 10)], LAMBDA, flags=1) + "".join(line(*e, "B") for e in edges)
    r12(tmp_path / "greek.dxf", squares)
    sketch = read_sketch(tmp_path / "greek.dxf", units="mm")
    assert sorted(link.layer for link in sketch.links) == ["B", "ΛΑ"]
    assert sketch.link("ΛΑ").name == "ΛΑ" and sketch.link(LAMBDA).name == "ΛΑ"
    for chosen in ("ΛΑ", LAMBDA):
        only = read_sketch(tmp_path / "greek.dxf", units="mm", layers=[chosen])
        others = read_sketch(tmp_path / "greek.dxf", units="mm", exclude_layers=[chosen])
        assert [link.layer for link in only.links] == ["ΛΑ"] and [link.layer for link in others.links] == ["B"]


def test_a_layer_turned_off_is_left_out_whether_its_name_is_escaped_or_not(tmp_path):
    # The LAYER table turns "ΛΑ" off (a negative colour); the LINEs on it (fast path) are read with
    # their names decoded, so the table's name must be decoded too to leave them out.
    off = f"0\nTABLE\n2\nLAYER\n70\n1\n0\nLAYER\n2\n{LAMBDA}\n70\n0\n62\n-7\n6\nCONTINUOUS\n0\nENDTAB\n"
    edges = ((20, 0, 30, 0), (30, 0, 30, 10), (30, 10, 20, 10), (20, 10, 20, 0))
    r12(tmp_path / "off.dxf", SQUARE + "".join(line(*e, LAMBDA) for e in edges), tables=off)
    sketch = read_sketch(tmp_path / "off.dxf", units="mm")
    assert len(sketch.links) == 1 and sketch.ignored == {"LINE (hidden layer)": 4}


# -- curves out of the XY plane ---------------------------------------------------------------------


def test_a_3d_polyline_is_read_in_the_xy_plane_with_a_note_of_its_z_range(tmp_path):
    # A closed 3D POLYLINE (flag 8) rising to z = 5 at one corner: its XY projection is the 10 mm square.
    wire = polyline([(0, 0, 0), (10, 0, 0), (10, 10, 5), (0, 10, 2)], "frame", flags=9)  # 9: closed, 3D
    r12(tmp_path / "wire.dxf", TEXT + wire)
    sketch = read_sketch(tmp_path / "wire.dxf", units="mm")
    assert sketch.link().outline.area == pytest.approx(100e-6, rel=1e-12)
    assert sketch.fixes == ("POLYLINE #2 (layer 'frame') is 3D: z from 0 to 5 mm; read in the XY plane",)


def test_sloping_lines_are_counted_in_one_note(tmp_path):
    # Two of the square's LINEs rise 1 and 3 mm (fast path, group codes 30 and 31); the others are flat.
    entities = (line(0, 0, 10, 0, extra="30\n0\n31\n1\n") + line(10, 0, 10, 10, extra="30\n1\n31\n3\n")
                + line(10, 10, 0, 10) + line(0, 10, 0, 0))
    r12(tmp_path / "slope.dxf", entities)
    assert read_sketch(tmp_path / "slope.dxf", units="mm").fixes == (
        "LINE #1 (layer '0') is 3D: z from 0 to 1 mm; read in the XY plane (as are 1 more curve(s) whose z "
        "varies, z from 0 to 3 mm in all)",)


@pytest.mark.parametrize("app_data", ["", "102\n{MYAPP\n1\nx\n102\n}\n"], ids=["fast path", "ezdxf"])
def test_an_arc_in_a_tilted_plane_is_refused_naming_it_by_position(tmp_path, app_data):
    # Its extrusion (210, 220, 230) is +x: drawn in the YZ plane, so no XY projection is the arc.
    arc = f"0\nARC\n8\nside\n{app_data}10\n0\n20\n0\n40\n5\n50\n0\n51\n90\n210\n1\n220\n0\n230\n0\n"
    r12(tmp_path / "tilted.dxf", TEXT + arc)
    with pytest.raises(SketchError, match=r"ARC #2 \(layer 'side'\) is not drawn in the XY plane \(extrusion \(1, 0, 0"):
        read_sketch(tmp_path / "tilted.dxf", units="mm")
