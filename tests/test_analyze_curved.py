"""analyze on curved links, and where each figure of its stress and safety tables comes from.

A curved link's straight-beam values fall 10-18 % short of the FEA (validate on the banana coupler
and the curved rod): analyze flags the link, warns, and gives no safety factor from those values.
Every figure of a sweep's tables names the input angle it was taken at and its point (ground frame).
"""

from __future__ import annotations

import json
import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from linkstress.cli import main

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
NOTE = "not given: curved link (straight-beam value), see validate"


def banana_scene(tmp_path: Path, material: str = "yield_strength = 250e6\n") -> Path:
    """The shipped banana-coupler four-bar (12 positions, 0 to 330 deg) in ``tmp_path``, its steel
    given ``material`` lines."""
    case = CASES / "banana_coupler"
    shutil.copy(case / "banana_coupler.dxf", tmp_path)
    text = (case / "scene.toml").read_text().replace("poisson_ratio = 0.3\n", "poisson_ratio = 0.3\n" + material)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def analyze(scene: Path, tmp_path: Path, capsys, *options: str) -> tuple[list[dict], str]:
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene), "--json", str(out), *options]) == 0
    return json.loads(out.read_text(), parse_constant=pytest.fail)["positions"], capsys.readouterr().out


def test_json_flags_the_banana_coupler_curved_and_its_straight_links_not(tmp_path, capsys):
    positions, _ = analyze(banana_scene(tmp_path, ""), tmp_path, capsys)
    for position in positions:
        links = position["links"]
        assert "curved" not in links["ground"]  # no section stresses, no flag
        assert {name: links[name]["curved"] for name in ("crank", "coupler", "output")} == {
            "crank": False, "coupler": True, "output": False,
        }


def test_the_seed_links_are_not_curved(tmp_path, capsys):
    positions, text = analyze(CASES / "seed_ansys_fourbar" / "scene.toml", tmp_path, capsys)
    links = positions[0]["links"]
    assert [links[name]["curved"] for name in ("crank", "coupler", "output")] == [False, False, False]
    assert "is curved" not in text


def test_a_curved_links_safety_factor_is_null_with_its_note_and_the_reports_say_so(tmp_path, capsys):
    html_out = tmp_path / "report.html"
    positions, text = analyze(banana_scene(tmp_path), tmp_path, capsys, "--html", str(html_out))
    for position in positions:
        coupler, crank = position["links"]["coupler"], position["links"]["crank"]
        assert coupler["yield_safety_factor"] is None
        assert coupler["yield_safety_factor_note"] == NOTE
        # the pin-hole estimate is the lug's own value at the hole, not a section across the curve
        # (only where some hole's geometry is inside the Kt tables: elsewhere no estimate, no factor)
        inside = [hole["estimate_pa"] for hole in coupler["pin_holes"] if hole["estimate_pa"] is not None]
        factor = coupler.get("pin_hole_yield_safety_factor_estimate")
        if inside:
            assert factor == pytest.approx(250e6 / max(inside), rel=1e-15)
        else:
            assert factor is None
        assert crank["yield_safety_factor"] == pytest.approx(250e6 / crank["max_von_mises_pa"], rel=1e-15)
        assert "yield_safety_factor_note" not in crank
    row = next(line for line in text.splitlines() if line.strip().startswith("coupler "))
    assert NOTE in row
    assert f"coupler: yield safety factor {NOTE}" in text
    warning = next(line for line in text.splitlines() if line.startswith("warning: link coupler is curved"))
    # the wander is 0.46 section depths (tests/test_curvature.py measures the same criterion)
    assert "0.46 section depths" in warning
    assert "about 10-20 %" in warning and "linkstress validate scene.toml" in warning
    page = html_out.read_text()
    assert NOTE in page and "warning: link coupler is curved" in page


def test_without_a_yield_strength_the_warning_still_names_the_curved_link(tmp_path, capsys):
    positions, text = analyze(banana_scene(tmp_path, ""), tmp_path, capsys)
    assert "yield_safety_factor" not in positions[0]["links"]["coupler"]
    warning = next(line for line in text.splitlines() if line.startswith("warning: link coupler is curved"))
    assert "safety factor" not in warning


def named(text: str, link: str, what: str) -> re.Match:
    """The line under the stress table that names ``what`` of ``link``."""
    pattern = rf"^  {link}: {re.escape(what)} (\S+)(?: Pa)? at input (\S+) deg, (?:the pin hole at joint (\d+), centre )?at \((\S+), (\S+)\) m, ground frame$"
    found = re.search(pattern, text, re.MULTILINE)
    assert found, f"no line for {link}'s {what}"
    return found


def seed_sweep(tmp_path: Path) -> Path:
    """The seed ANSYS four-bar with a 250 MPa yield strength over four inputs, turning backwards."""
    case = CASES / "seed_ansys_fourbar"
    shutil.copy(case / "ansys_four_bars.dxf", tmp_path)
    text = (case / "scene.toml").read_text().replace("poisson_ratio = 0.3\n", "poisson_ratio = 0.3\nyield_strength = 250e6\n")
    start = text.index("[motion]")
    end = text.index("\n\n", start)
    text = text[:start] + "[motion]\ninput_angle_deg = [30.0, 60.0, 90.0, 120.0]\ninput_speed_rad_s = -1.0\n" + text[end:]
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def check_named_angles(positions: list[dict], text: str, names: tuple[str, ...]) -> None:
    """Each figure's line names the input angle (and pin hole) where the JSON has its extreme."""
    angles = np.array([p["input_angle_deg"] for p in positions])
    for name in names:
        links = [p["links"][name] for p in positions]
        k = int(np.argmax([link["max_von_mises_pa"] for link in links]))
        peak = named(text, name, "max von Mises")
        assert float(peak[2]) == angles[k]
        assert (float(peak[4]), float(peak[5])) == tuple(float(f"{v:.4g}") for v in links[k]["max_at_m"])
        if "max_von_mises_away_from_holes_pa" in links[0]:
            a = int(np.argmax([link["max_von_mises_away_from_holes_pa"] for link in links]))
            assert float(named(text, name, "max von Mises away from holes")[2]) == angles[a]
        else:
            assert f"{name}: max von Mises away from holes" not in text
        # an estimate outside the Kt tables (null) is no figure
        estimates = np.array([[-1.0 if h["estimate_pa"] is None else h["estimate_pa"] for h in link["pin_holes"]]
                              for link in links])
        if (estimates < 0).all():
            assert f"{name}: pin hole estimate" not in text
        else:
            e = int(np.argmax(estimates.max(axis=1)))
            joint = links[e]["pin_holes"][int(np.argmax(estimates[e]))]["joint"]
            for what in ("pin hole estimate", "yield safety factor at pin holes (estimate)"):
                line = named(text, name, what)
                assert (float(line[2]), int(line[3])) == (angles[e], joint)
        if not links[0]["curved"]:
            assert float(named(text, name, "yield safety factor")[2]) == angles[k]


def test_each_figure_of_the_banana_sweep_names_the_input_angle_and_point_it_comes_from(tmp_path, capsys):
    positions, text = analyze(banana_scene(tmp_path), tmp_path, capsys)
    check_named_angles(positions, text, ("crank", "coupler", "output"))
    # The output's maxima come from different inputs: the largest section value at 330 deg (within a
    # depth of its pin O4), the largest away from holes at 300 deg.
    assert float(named(text, "output", "max von Mises")[2]) == 330.0
    assert float(named(text, "output", "max von Mises away from holes")[2]) == 300.0


def test_each_figure_of_a_seed_sweep_names_its_input_angle_and_pin_hole(tmp_path, capsys):
    positions, text = analyze(seed_sweep(tmp_path), tmp_path, capsys)
    check_named_angles(positions, text, ("crank", "coupler", "output"))
    # The seed output's largest pin-hole estimate is at B (joint 1), not at its first hole O4.
    assert int(named(text, "output", "pin hole estimate")[3]) == 1


def test_the_away_from_holes_point_is_that_stations_fibre_in_the_ground_frame(tmp_path, capsys):
    # The output turns about O4 = (0.2, 0) (the scene's ground), so its member frame's origin is known.
    positions, text = analyze(banana_scene(tmp_path), tmp_path, capsys, "--stations")
    line = named(text, "output", "max von Mises away from holes")
    k = [p["input_angle_deg"] for p in positions].index(float(line[2]))
    link = positions[k]["links"]["output"]
    stations = link["stations"]
    away = np.flatnonzero(~np.array(stations["near_hole"]))
    s = away[np.argmax(np.array(stations["von_mises_pa"])[away])]
    assert stations["von_mises_pa"][s] == link["max_von_mises_away_from_holes_pa"]
    x, y = stations["x_m"][s], stations["fibre_y_m"][s]
    c, t = math.cos(math.radians(link["angle_deg"])), math.sin(math.radians(link["angle_deg"]))
    expected = (0.2 + c * x - t * y, t * x + c * y)
    assert (float(line[4]), float(line[5])) == tuple(float(f"{v:.4g}") for v in expected)


def test_the_html_tables_name_each_figures_input_angle(tmp_path, capsys):
    html_out = tmp_path / "report.html"
    _, text = analyze(banana_scene(tmp_path), tmp_path, capsys, "--html", str(html_out))
    page = html_out.read_text()
    # the same lines as the text report's, one list item each
    for line in re.findall(r"^  ((?:crank|coupler|output): .+)$", text, re.MULTILINE):
        assert f"<li>{line}</li>" in page
    assert "<th class=\"text\">at input [deg]</th>" in page
    assert "<th class=\"text\">at the pin hole of joint</th>" in page
