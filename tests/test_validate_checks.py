"""validate's check judges what it says it judges, and a comparison it cannot make stops nothing.

- The check fails (exit 1) on the support reactions, the section resultants (1 %) and the nominal
  von Mises (5 %): the nominal bound holds the worst legitimate case found, a station exactly one
  section depth from a pin hole 0.4 depths across (St-Venant's tail of the bearing pressure), and
  fails a crank whose pins' fields overlap (tests/test_validate_story.py).
- A triangular coupler plate with three pins and a lightening hole at its centroid: the midpoint
  cut of every side passes through the hole's centre (each side's perpendicular bisector passes
  through an equilateral triangle's centroid), so no member has a section to compare. The plate is
  still meshed and its FEA peak and pin holes compared, its members are listed as not compared with
  the reason, the other links are checked as ever, and ``analyze --peaks`` runs. A taller plate has
  one member (its base) through the hole and one compared.

The mechanisms are generated here: a four-bar (ground 0.3 m, crank 0.1 m, output 0.2 m, both bars 20
mm deep with 8 mm pin holes and square ends half a depth past the pins) whose coupler is the plate,
drawn with ezdxf, 5 mm steel, a 200 N load on the plate's third pin.
"""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from shapely.geometry import Polygon

from linkstress.cli import main
from linkstress.geometry.builders import straight_bar

SIDE = 0.25
"""The plate's pins A (0, 0) and B (SIDE, 0) [m]: its coupler A -> B."""
PIN = 0.008
LIGHTENING = 0.06


def plate_four_bar(folder: Path, height: float = SIDE * math.sqrt(3) / 2, validate: str = "") -> Path:
    """The four-bar whose coupler is a plate round pins A, B and C (SIDE / 2, ``height``) [m], 20 mm
    of material past the pin centres, with a LIGHTENING hole at the triangle's centroid; ``validate``
    an optional ``[analysis]`` table's body."""
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    pins = [(0.0, 0.0), (SIDE, 0.0), (SIDE / 2, height)]
    outline = Polygon(pins).buffer(0.02, 64)
    msp.add_lwpolyline(list(outline.exterior.coords)[:-1], close=True, dxfattribs={"layer": "coupler"})
    for p in pins:
        msp.add_circle(p, PIN / 2, dxfattribs={"layer": "coupler"})
        msp.add_point(p, dxfattribs={"layer": "coupler"})
    msp.add_circle((SIDE / 2, height / 3), LIGHTENING / 2, dxfattribs={"layer": "coupler"})
    for k, (name, length) in enumerate((("crank", 0.1), ("output", 0.2))):
        bar = straight_bar(length, 0.02, 0.01, 0.005, hole_diameter=PIN, name=name)
        shift = np.array([0.0, -0.1 * (k + 1)])
        msp.add_lwpolyline([tuple(p + shift) for p in np.asarray(bar.outline.exterior.coords)[:-1]], close=True,
                           dxfattribs={"layer": name})
        for joint in bar.joints + shift:
            msp.add_circle(tuple(joint), PIN / 2, dxfattribs={"layer": name})
            msp.add_point(tuple(joint), dxfattribs={"layer": name})
    doc.saveas(folder / "plate.dxf")
    links = "".join(
        f'[links.{name}]\nsketch = "plate.dxf"\nlayer = "{name}"\nthickness = 0.005\nmaterial = "steel"\n'
        for name in ("crank", "coupler", "output")
    )
    scene = folder / "scene.toml"
    scene.write_text(textwrap.dedent("""\
        [materials.steel]
        density = 7850.0
        youngs_modulus = 200e9
        poisson_ratio = 0.3
        yield_strength = 250e6
        """) + links + textwrap.dedent(f"""\
        [links.ground]
        joints = [[0.0, 0.0], [0.3, 0.0]]
        [mechanisms.main]
        type = "four-bar"
        crank = "crank"
        coupler = {{link = "coupler", joints = [0, 2]}}
        output = "output"
        ground = "ground"
        [[loads.forces]]
        link = "coupler"
        at_m = [{SIDE / 2!r}, {height!r}]
        force_n = [0.0, -200.0]
        [motion]
        input_angle_deg = {{start = 0.0, stop = 330.0, num = 12}}
        input_speed_rad_s = 20.0
        """) + (f"[analysis]\n{validate}\n" if validate else ""))
    return scene


@pytest.fixture(scope="module")
def plate(tmp_path_factory):
    """validate of the equilateral plate's four-bar at 4 positions (0, 120, 210 and 330 deg), three
    meshes each: exit code, JSON, terminal text, HTML."""
    folder = tmp_path_factory.mktemp("plate")
    scene = plate_four_bar(folder)
    out = io_run(["validate", str(scene), "--positions", "4", "--json", str(folder / "v.json"),
                  "--html", str(folder / "v.html")])
    return out[0], json.loads((folder / "v.json").read_text(), parse_constant=pytest.fail), out[1], folder


def io_run(argv: list[str]) -> tuple[int, str]:
    """``linkstress ARGV``'s exit code and what it printed."""
    import contextlib
    import io

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        code = main(argv)
    return code, buffer.getvalue()


def test_a_plate_whose_every_cut_passes_through_its_lightening_hole_is_still_meshed_and_its_peak_compared(plate):
    code, data, text, _ = plate
    coupler = data["links"]["coupler"]
    assert "error" not in coupler
    assert [m["joints"] for m in coupler["members"]] == []
    notes = coupler["not_compared"]
    assert len(notes) == 2
    for note, joints in zip(notes, ("[0, 1]", "[1, 2]")):
        assert note.startswith(f"link 'coupler', member {joints}: not compared with the FEA: its midpoint cut at s = 0.125 m")
        assert "passes through a hole (0 hole radii from its centre)" in note
    assert data["not_compared"] == notes
    assert coupler["resultant_error_pct"] is None and coupler["nominal_error_pct"] is None
    assert coupler["positions"]["resultant_error_pct"] is None
    assert coupler["convergence"]["resultants"]["status"] == "not compared"
    assert coupler["convergence"]["peak"]["status"] == "converged"
    # 200 N on a 5 mm plate: the peak is at a pin hole's rim, above the bearing stress 200 / (8 x 5 mm^2)
    assert coupler["fea_max_von_mises_pa"] > 200 / (PIN * 0.005)
    assert [h["joint"] for h in coupler["pin_holes"]] == [0, 1, 2]
    assert coupler["fea_yield_safety_factor"] is not None
    # the short text names them in the check; each link's note is in --details
    assert "not compared, so not checked: coupler member 0-1, coupler member 1-2" in text


def test_the_other_links_are_checked_and_the_check_says_what_it_did_not_compare(plate):
    code, data, text, folder = plate
    assert code == 0 and data["failures"] == []
    for name in ("crank", "output"):
        link = data["links"][name]
        assert link["not_compared"] == [] and link["resultant_error_pct"] < 1.0 and link["nominal_error_pct"] < 5.0
    check = next(line for line in text.splitlines() if line.startswith("check:"))
    assert check.startswith(
        "check: passed (FEA support reactions below 0.0001 of the load, section resultants within 1 % and nominal "
        "von Mises within 5 % of the beam's); not compared, so not checked: coupler member 0-1, coupler member 1-2"
    )
    assert "not compared, so not checked: coupler member 0-1" in (folder / "v.html").read_text()


def test_a_station_one_depth_from_a_pin_hole_four_tenths_of_a_depth_across_is_within_the_nominal_bound(plate):
    # The output: 0.2 m between 8 mm holes, 20 mm deep. Its last station, s = 0.18 m, is one depth
    # (five hole radii) from the pin at 0.2 m, where the pin's bearing pressure still disturbs the
    # section: measured 4.2 % at 330 deg (the stations 1.67 depths from a pin are within 0.3 %).
    output = plate[1]["links"]["output"]
    assert np.isclose(output["nominal_stations_m"], 0.18).any()
    assert 3.5 < output["nominal_error_pct"] < 5.0
    assert output["convergence"]["nominal"]["status"] == "converged"


def test_a_taller_plate_compares_the_member_that_misses_the_hole_and_skips_the_one_through_it(tmp_path):
    # Pins 0.35 m above the base: the tree of members is the base A-B (its perpendicular bisector
    # passes through the centroid) and A-C, whose cuts near C keep five radii from the hole.
    scene = plate_four_bar(tmp_path, height=0.35, validate='validate = ["coupler"]')
    code, _ = io_run(["validate", str(scene), "--positions", "2", "--mesh-levels", "1", "--json", str(tmp_path / "v.json")])
    coupler = json.loads((tmp_path / "v.json").read_text(), parse_constant=pytest.fail)["links"]["coupler"]
    assert code == 0
    assert [m["joints"] for m in coupler["members"]] == [[0, 1]]
    (note,) = coupler["not_compared"]
    assert note.startswith("link 'coupler', member [0, 2]: not compared with the FEA")
    assert coupler["resultant_error_pct"] < 1.0


def test_analyze_peaks_runs_on_the_plate_and_gives_its_fea_peak(plate, tmp_path):
    *_, folder = plate
    code, _ = io_run(["analyze", str(folder / "scene.toml"), "--peaks", "--json", str(tmp_path / "a.json")])
    data = json.loads((tmp_path / "a.json").read_text(), parse_constant=pytest.fail)
    assert code == 0
    coupler = data["links"]["coupler"]
    assert coupler["peak_max_von_mises_pa"] > 200 / (PIN * 0.005)
    assert coupler["peak_converged"] is True
    assert all(p["links"]["coupler"]["peak_von_mises_pa"] > 0 for p in data["positions"] if p["feasible"])
