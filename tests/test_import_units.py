"""Drawing units: the typographic units of vector and board editors (pt, px, pica), the astronomical
symbols refused as slips (pc is a parsec, not a pica), and the copy of ezdxf's $INSUNITS table."""

from __future__ import annotations

import math

import ezdxf
import ezdxf.units
import pytest

from linkstress.cli import main
from linkstress.errors import SketchError
from linkstress.importers import read_sketch
from linkstress.importers.units import INSUNITS, unit_named
from test_import_dxf import save


def test_the_insunits_table_is_ezdxfs():
    for code, (symbol, name, factor) in INSUNITS.items():
        assert ezdxf.units.METER_FACTOR[code] == factor
        assert ezdxf.units.decode(code) == symbol and ezdxf.units.unit_name(code) == name


@pytest.mark.parametrize("names, inch_fraction", [
    (("pt", "points", "point", "PT"), 1 / 72),  # PostScript point: Inkscape's and PDF's unit
    (("px", "pixels", "pixel"), 1 / 96),  # CSS pixel: Inkscape's user unit since 0.92
    (("pica", "picas"), 1 / 6),  # 12 points
])
def test_typographic_units_are_their_fraction_of_an_inch(names, inch_fraction):
    """An inch is 0.0254 m exactly (1959 international yard and pound agreement)."""
    for name in names:
        unit = unit_named(name, "units")
        assert 1 / unit.per_metre == pytest.approx(0.0254 * inch_fraction, rel=1e-15)
        assert unit.code is None  # DXF has no $INSUNITS code for them


@pytest.mark.parametrize("unit, metres_per_unit", [("pt", 0.0254 / 72), ("px", 0.0254 / 96), ("pica", 0.0254 / 6)])
def test_a_unitless_drawing_reads_in_pt_and_px(tmp_path, unit, metres_per_unit):
    # A 720 x 72 unit plate: 10 x 1 inches in points, 7.5 x 0.75 in pixels.
    doc = ezdxf.new("R2013", units=0)
    doc.modelspace().add_lwpolyline([(0, 0), (720, 0), (720, 72), (0, 72)], close=True)
    sketch = read_sketch(save(doc, tmp_path), units=unit)
    assert sketch.units == unit
    assert sketch.link().outline.area == pytest.approx(720 * 72 * metres_per_unit**2, rel=1e-12)


def test_import_units_pt_overrides_a_header_and_says_so(tmp_path, capsys):
    doc = ezdxf.new("R2013", units=4)
    doc.modelspace().add_lwpolyline([(0, 0), (720, 0), (720, 72), (0, 72)], close=True)
    assert main(["import", str(save(doc, tmp_path)), "--units", "pt"]) == 0
    out = capsys.readouterr().out
    assert "units pt (--units pt, overriding the file's $INSUNITS millimeters)" in out


@pytest.mark.parametrize("typed, meaning, metres", [
    ("pc", "a parsec", "3.1e+16"), ("PC", "a parsec", "3.1e+16"), ("ly", "a light year", "9.5e+15"),
    ("au", "an astronomical unit", "1.5e+11"), ("gm", "a gigametre", "1e+09"),
])
def test_an_astronomical_symbol_is_refused_asking_for_it_spelt_out(tmp_path, capsys, typed, meaning, metres):
    doc = ezdxf.new("R2013", units=0)
    doc.modelspace().add_lwpolyline([(0, 0), (10, 0), (10, 1), (0, 1)], close=True)
    assert main(["import", str(save(doc, tmp_path)), "--units", typed]) == 2
    err = capsys.readouterr().err
    assert f"units: {typed!r} is {meaning} ({metres} m)" in err and "must say so in full" in err
    assert ("for picas give --units pica" in err) == (typed.lower() == "pc")
    assert err.count("\n") == 1


def test_spelt_out_a_parsec_is_taken_as_meant_and_the_drawing_then_refused_for_its_reach(tmp_path):
    doc = ezdxf.new("R2013", units=0)
    doc.modelspace().add_lwpolyline([(0, 0), (10, 0), (10, 1), (0, 1)], close=True)
    with pytest.raises(SketchError, match=r"reaches 3\.09e\+17 m from the origin"):
        read_sketch(save(doc, tmp_path), units="parsecs")


def test_an_unknown_unit_lists_pt_and_px_but_not_the_refused_symbols():
    with pytest.raises(SketchError) as error:
        unit_named("furlong", "units")
    known = str(error.value).split("use one of ")[1].split(", ")
    assert {"mm", "in", "pt", "px", "pica"} <= set(known)
    assert not {"pc", "ly", "au", "gm"} & set(known)


SCENE = """
units = "{units}"

[materials.steel]
density = 7850.0

[links.plate]
sketch = "plate.dxf"
thickness = 0.01
material = "steel"

[links.ground]
joints = [[0.0, 0.0], [1.0, 0.0]]

[links.coupler]
joints = [[0.0, 0.0], [1.0, 0.0]]

[links.output]
joints = [[0.0, 0.0], [1.0, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "plate"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = 60.0
"""


@pytest.mark.parametrize("units, metres_per_unit", [("px", 0.0254 / 96), ("pt", 0.0254 / 72)])
def test_a_scenes_units_read_a_unitless_sketch_in_px_and_pt(tmp_path, units, metres_per_unit):
    from linkstress.scene.reader import load_scene

    doc = ezdxf.new("R2013", units=0)
    msp = doc.modelspace()
    msp.add_lwpolyline([(-20, -10), (120, -10), (120, 10), (-20, 10)], close=True)
    for x in (0.0, 100.0):
        msp.add_circle((x, 0.0), 4.0)
    save(doc, tmp_path, "plate.dxf")
    (tmp_path / "scene.toml").write_text(SCENE.format(units=units))
    plate = load_scene(tmp_path / "scene.toml").links["plate"].profile
    assert plate.area == pytest.approx((140 * 20 - 2 * math.pi * 16) * metres_per_unit**2, rel=1e-6)


def test_a_scenes_units_pc_is_refused_by_its_key(tmp_path, capsys):
    doc = ezdxf.new("R2013", units=0)
    doc.modelspace().add_lwpolyline([(0, 0), (10, 0), (10, 1), (0, 1)], close=True)
    save(doc, tmp_path, "plate.dxf")
    (tmp_path / "scene.toml").write_text(SCENE.format(units="pc"))
    assert main(["analyze", str(tmp_path / "scene.toml")]) == 2
    err = capsys.readouterr().err
    assert "links.plate.sketch:" in err and "'pc' is a parsec (3.1e+16 m); for picas give --units pica" in err
