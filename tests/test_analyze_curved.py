"""analyze on curved links, and where each figure of its stress and safety tables comes from.

A curved link is sectioned square to its centreline, with curved-beam (Winkler-Bach) stresses where
its radius is under ten section depths: analyze flags the link, says which theory each member took,
and gives its safety factor from those values. Every figure of a sweep's tables names the input
angle it was taken at and its point (ground frame).
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
from linkstress.report.places import joint_names
from linkstress.scene import load_scene

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"


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
    """The JSON positions and the text (with --details: the stress table and its lines) of analysing ``scene``."""
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene), "--json", str(out), "--details", *options]) == 0
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


def test_a_curved_links_members_take_winkler_bach_and_give_its_safety_factor(tmp_path, capsys):
    html_out = tmp_path / "report.html"
    positions, text = analyze(banana_scene(tmp_path), tmp_path, capsys, "--html", str(html_out))
    for position in positions:
        coupler, crank = position["links"]["coupler"], position["links"]["crank"]
        (member,) = coupler["members"]
        assert member["joints"] == [0, 1] and member["beam_theory"] == "curved"
        assert member["max_von_mises_pa"] == coupler["max_von_mises_pa"] and member["max_at_m"] == coupler["max_at_m"]
        assert crank["members"][0]["beam_theory"] == "straight"
        for link in (coupler, crank):
            assert link["yield_safety_factor"] == pytest.approx(250e6 / link["max_von_mises_pa"], rel=1e-15)
            assert "yield_safety_factor_note" not in link
    note = next(line for line in text.splitlines() if line.startswith("note: link coupler, member [0, 1] is curved"))
    # the centreline bulges 40 mm from the line through the pins, the bar is 30 mm deep
    assert "strays 1.3 section depths from the line through its joints" in note and "Winkler-Bach" in note
    assert "is curved" in html_out.read_text()


def test_without_a_yield_strength_the_note_still_names_the_curved_link(tmp_path, capsys):
    positions, text = analyze(banana_scene(tmp_path, ""), tmp_path, capsys)
    assert "yield_safety_factor" not in positions[0]["links"]["coupler"]
    assert any(line.startswith("note: link coupler, member [0, 1] is curved") for line in text.splitlines())


def named(text: str, link: str, what: str) -> re.Match:
    """The line under the stress table that names ``what`` of ``link``."""
    pattern = rf"^  {link}: {re.escape(what)} (\S+)(?: MPa)? at input (\S+) deg, (?:the pin hole at (\S+), centre )?at \((\S+), (\S+)\) m, ground frame$"
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


def joint_labels(scene: Path) -> dict[str, tuple[str, ...]]:
    """Each link's joints by the names the reports give them (Norton's letters: O2, A, B, O4)."""
    return {name: tuple(j.label for j in joints) for name, joints in joint_names(load_scene(scene)).items()}


def check_named_angles(positions: list[dict], text: str, names: tuple[str, ...], labels: dict[str, tuple[str, ...]]) -> None:
    """Each figure's line names the input angle (and pin hole, by its joint's name in ``labels``)
    where the JSON has its extreme."""
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
                assert (float(line[2]), line[3]) == (angles[e], labels[name][joint])
        assert float(named(text, name, "yield safety factor")[2]) == angles[k]


def test_each_figure_of_the_banana_sweep_names_the_input_angle_and_point_it_comes_from(tmp_path, capsys):
    scene = banana_scene(tmp_path)
    positions, text = analyze(scene, tmp_path, capsys)
    check_named_angles(positions, text, ("crank", "coupler", "output"), joint_labels(scene))
    # The output's maxima come from different inputs: the largest section value at 330 deg (within a
    # depth of its pin O4), the largest away from holes at 300 deg.
    assert float(named(text, "output", "max von Mises")[2]) == 330.0
    assert float(named(text, "output", "max von Mises away from holes")[2]) == 300.0


def test_each_figure_of_a_seed_sweep_names_its_input_angle_and_pin_hole(tmp_path, capsys):
    scene = seed_sweep(tmp_path)
    positions, text = analyze(scene, tmp_path, capsys)
    check_named_angles(positions, text, ("crank", "coupler", "output"), joint_labels(scene))
    # The seed output's largest pin-hole estimate is at B (joint 1), not at its first hole O4.
    assert named(text, "output", "pin hole estimate")[3] == "B"


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
    # --beam-only: the figures' notes of the beam report alone (the FEA peaks' mesh lines have their own table)
    _, text = analyze(banana_scene(tmp_path), tmp_path, capsys, "--html", str(html_out), "--beam-only")
    page = html_out.read_text()
    # the same lines as the text report's, one list item each
    for line in re.findall(r"^  ((?:crank|coupler|output): .+)$", text, re.MULTILINE):
        assert f"<li>{line}</li>" in page
    assert "<th class=\"text\">at input [deg]</th>" in page
    assert "<th class=\"text\">at the pin hole</th>" in page
