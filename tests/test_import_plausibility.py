"""A drawing read in the wrong unit: links over 5 m or pin holes under 0.5 mm give one warning line (text
and JSON) naming the --units that makes them ordinary; ordinary drawings give none.

Every drawing is generated here with ezdxf. Worked numbers: an inch is 25.4 mm, so a 500-unit link
read in inches is 12.7 m and a 3.2-unit pin hole 81.28 mm; read in mm they are 500 mm and 3.2 mm.
"""

from __future__ import annotations

import json

import ezdxf
import pytest

from linkstress.cli import main
from linkstress.importers import read_sketch, unit_warnings
from test_import_dxf import save
from test_import_sheets import bar


def linkage(tmp_path, insunits: int, lengths: list[float], depth: float, hole: float):
    """Bars ``lengths`` long (centre to centre) ``depth`` deep with pin holes of ``hole``, one per layer,
    in drawing units, the header saying ``insunits``."""
    doc = ezdxf.new("R2013", units=insunits)
    for k, length in enumerate(lengths):
        bar(doc.modelspace(), 0, 3 * depth * k, length, depth=depth, hole=hole, layer=f"link{k}", points=True)
    return save(doc, tmp_path)


def test_a_strandbeest_drawn_in_mm_under_an_inch_header_warns_and_names_mm(tmp_path, capsys):
    # Outlines 480 + 20 = 500 units long: 12.7 m in inches, pins of 81.28 mm.
    path = linkage(tmp_path, 1, [480.0, 300.0, 390.0], 20.0, 3.2)
    (warning,) = unit_warnings(read_sketch(path))
    assert warning == ("links up to 12.7 m long and pin holes of 81.3 mm: the drawing looks drawn in millimeters while "
                       "its header ($INSUNITS) says inches; give --units mm (then links up to 500 mm long and pin holes "
                       "of 3.2 mm)")
    out = tmp_path / "links.json"
    assert main(["import", str(path), "--json", str(out)]) == 0
    text = capsys.readouterr().out.splitlines()
    assert text[2] == f"warning: {warning}"  # under the headline
    assert json.loads(out.read_text())["warnings"] == [warning]
    assert main(["import", str(path), "--units", "mm"]) == 0
    assert "warning" not in capsys.readouterr().out


def test_a_drawing_in_cm_under_an_mm_header_has_pin_holes_of_0_3_mm_and_names_cm(tmp_path):
    # 15 cm links with 3 mm pins read as mm: 17 mm outlines, 0.3 mm pins. cm (x10) fits, and so would
    # inches (x25.4: 7.6 mm pins, 432 mm links): the unit nearest in scale is named.
    path = linkage(tmp_path, 4, [15.0, 9.0], 2.0, 0.3)
    (warning,) = unit_warnings(read_sketch(path))
    assert warning.startswith("links up to 17 mm long and pin holes of 0.3 mm: the drawing looks drawn in centimeters "
                              "while its header ($INSUNITS) says millimeters; give --units cm (then links up to 170 mm "
                              "long and pin holes of 3 mm)")


def test_a_unit_given_on_the_command_line_is_named_as_such(tmp_path):
    path = linkage(tmp_path, 0, [480.0], 20.0, 3.2)
    (warning,) = unit_warnings(read_sketch(path, units="in"))
    assert ("the drawing looks drawn in millimeters while it is read in inches (given by the caller (--units or the "
            "scene's units)); give --units mm") in warning


def test_sizes_no_unit_makes_ordinary_warn_without_naming_one(tmp_path):
    # Pins 2e-4 of the link: whatever the unit, either the link is over 2 m or the pin under 1 mm.
    path = linkage(tmp_path, 6, [10.0], 1.0, 0.002)
    (warning,) = unit_warnings(read_sketch(path))
    assert warning.endswith("no mechanism is that size, while its header ($INSUNITS) says meters; check the drawing's units")


@pytest.mark.parametrize("insunits, lengths, depth, hole", [
    (4, [40.0, 120.0, 90.0], 16.0, 6.0),  # a small four-bar in mm
    (4, [1200.0], 200.0, 40.0),  # a 1.4 m press arm
    (1, [6.0, 10.0], 1.0, 0.25),  # a linkage in inches with 1/4 inch pins
    (6, [4.8], 0.2, 0.05),  # a 5 m boom: at the limit, not over it
    (4, [20.0], 5.0, 0.5),  # a 0.5 mm pin: at the limit, not under it
])
def test_ordinary_drawings_give_no_warning(tmp_path, capsys, insunits, lengths, depth, hole):
    path = linkage(tmp_path, insunits, lengths, depth, hole)
    assert unit_warnings(read_sketch(path)) == ()
    out = tmp_path / "links.json"
    assert main(["import", str(path), "--json", str(out)]) == 0
    assert "warning" not in capsys.readouterr().out and json.loads(out.read_text())["warnings"] == []


def test_the_links_checked_can_be_a_scenes_subset(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    bar(doc.modelspace(), 0, 0, 100, layer="crank")
    bar(doc.modelspace(), 0, 100, 6000, depth=100, hole=30, layer="beam")
    sketch = read_sketch(save(doc, tmp_path))
    assert unit_warnings(sketch, [sketch.link("crank")]) == ()
    assert len(unit_warnings(sketch, [sketch.link("beam")])) == 1


def test_a_scene_reader_words_the_fix_its_own_way(tmp_path):
    path = linkage(tmp_path, 1, [480.0], 20.0, 3.2)
    (warning,) = unit_warnings(read_sketch(path), fix='save the sketch in {unit} (its $INSUNITS)')
    assert "says inches; save the sketch in mm (its $INSUNITS) (then links up to 500 mm" in warning


def test_a_scene_taking_links_from_a_drawing_in_the_wrong_unit_warns_once_naming_the_sketch(tmp_path):
    """The scene reader asks the same question of the links it takes from each sketch, and its fix is
    the sketch's unit (a scene's units cannot override a unit its header declares)."""
    from linkstress.scene import load_scene

    path = linkage(tmp_path, 1, [480.0, 300.0], 20.0, 3.2)
    links = "".join(
        f'[links.link{k}]\nsketch = "{path.name}"\nlayer = "link{k}"\nthickness = 0.005\nmaterial = "steel"\n' for k in (0, 1)
    )
    scene = tmp_path / "scene.toml"
    scene.write_text(
        '[materials.steel]\ndensity = 7850.0\n' + links
        + '[links.ground]\njoints = [[0.0, 0.0], [1.0, 0.0]]\n'
        + '[mechanisms.main]\ntype = "slider-crank"\ncrank = "link1"\ncoupler = "link0"\nground = "ground"\n'
        + '[motion]\ninput_angle_deg = 30.0\n'
    )
    warnings = [w for w in load_scene(scene).warnings if w.startswith(path.name)]
    assert len(warnings) == 1
    assert "looks drawn in millimeters while its header ($INSUNITS) says inches; save the sketch in mm" in warnings[0]
