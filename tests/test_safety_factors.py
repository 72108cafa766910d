"""Safety factors against yield: the material's yield strength over the stress a link reaches."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from linkstress.cli import main
from linkstress.report.cells import significant
from linkstress.safety import finite_or_none, yield_factor

CASE = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar"


def seed_scene(tmp_path: Path, material: str = "", motion: str = "") -> Path:
    """The seed ANSYS case in ``tmp_path`` with ``material`` lines added to its steel and its
    [motion] table's lines replaced by ``motion`` when given."""
    shutil.copy(CASE / "ansys_four_bars.dxf", tmp_path)
    text = (CASE / "scene.toml").read_text()
    text = text.replace("poisson_ratio = 0.3\n", "poisson_ratio = 0.3\n" + material)
    if motion:
        start = text.index("[motion]")
        end = text.index("\n\n", start)
        text = text[:start] + "[motion]\n" + motion + text[end:]
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def analyze(scene: Path, tmp_path: Path, capsys, *options: str) -> tuple[dict, str]:
    """The JSON and the text (with --details, the stress table) of analysing ``scene``."""
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene), "--json", str(out), "--details", *options]) == 0
    return json.loads(out.read_text(), parse_constant=pytest.fail), capsys.readouterr().out


def stress_rows(text: str) -> dict[str, dict[str, str]]:
    """The detailed stress table's rows: per link, its cells by column header."""
    table = text.split("section stresses (beam theory", 1)[1].split("\nwhere each figure", 1)[0].splitlines()[1:]
    headers = re.split(r"\s{2,}", table[0].strip())
    rows = [re.split(r"\s{2,}", line.strip()) for line in table[2:]]
    return {row[0]: dict(zip(headers, row)) for row in rows}


def test_the_factor_is_the_yield_strength_over_the_stress_and_infinite_at_no_stress():
    factors = yield_factor(250e6, np.array([125e6, 1e6, 0.0]))
    assert factors.tolist() == [2.0, 250.0, np.inf]
    assert finite_or_none(factors) == [2.0, 250.0, None]


def test_each_seed_link_reports_its_yield_strength_over_its_largest_stresses(tmp_path, capsys):
    data, text = analyze(seed_scene(tmp_path, "yield_strength = 250e6\n"), tmp_path, capsys)
    links = data["positions"][0]["links"]
    for name in ("crank", "coupler", "output"):
        link = links[name]
        assert link["yield_safety_factor"] == pytest.approx(250e6 / link["max_von_mises_pa"], rel=1e-15)
        # Only estimates inside the Kt tables count; outside them the estimate is null.
        inside = [hole["estimate_pa"] for hole in link["pin_holes"] if not hole["kt_outside_table"]]
        assert [hole["estimate_pa"] is None for hole in link["pin_holes"]] == [hole["kt_outside_table"] for hole in link["pin_holes"]]
        factor = link.get("pin_hole_yield_safety_factor_estimate")
        assert factor == (pytest.approx(250e6 / max(inside), rel=1e-15) if inside else None)
    # the coupler's section peak is 20,159 Pa at 60 deg (nominal: a station within a depth of pin B,
    # by the body-load term away from holes 20,150 Pa at the next station): a factor of 12,402
    assert links["coupler"]["yield_safety_factor"] == pytest.approx(12_402, rel=1e-3)
    assert stress_rows(text)["coupler"]["yield safety factor, sections"] == "12400"
    # the verdict's factor is the governing stress's: Kt x nominal at the coupler's pin A, 0.696 MPa
    verdict = {row["link"]: row for row in data["verdict"]["rows"]}
    assert verdict["coupler"]["yield_safety_factor"] == pytest.approx(250e6 / verdict["coupler"]["stress_pa"], rel=1e-15)
    assert verdict["coupler"]["governing"] == "pin-hole estimate"


def test_without_a_yield_strength_no_factor_is_reported(tmp_path, capsys):
    data, text = analyze(seed_scene(tmp_path), tmp_path, capsys)
    assert not any("safety" in key for key in data["positions"][0]["links"]["coupler"])
    assert "yield safety factor, sections" not in text  # no factor columns in the stress table
    for row in data["verdict"]["rows"]:
        assert (row["yield_safety_factor"], row["yield_safety_factor_note"]) == (None, "no yield_strength")
        assert re.search(rf"(?m)^{row['link']} .* - \(no yield_strength\) ", text)


def test_a_link_without_stress_has_no_factor_rather_than_an_infinite_one(tmp_path, capsys):
    still = 'input_angle_deg = 60.0\ninput_speed_rad_s = 0.0\n'
    scene = seed_scene(tmp_path, "yield_strength = 250e6\n", still)
    scene.write_text(scene.read_text().replace("output = 2.0", "output = 0.0"))
    data, text = analyze(scene, tmp_path, capsys)
    coupler = data["positions"][0]["links"]["coupler"]
    assert coupler["max_von_mises_pa"] == 0.0
    assert coupler["yield_safety_factor"] is None
    assert "- (no stress)" in text


def test_validate_gives_the_factor_against_a_converged_fea_peak(tmp_path, capsys):
    # The default three-level study: every peak of the seed changes < 0.5 % over the last refinement.
    scene = seed_scene(tmp_path, "yield_strength = 250e6\n")
    out = tmp_path / "validate.json"
    assert main(["validate", str(scene), "--json", str(out), "--details"]) == 0
    text = capsys.readouterr().out
    data = json.loads(out.read_text(), parse_constant=pytest.fail)
    links = data["links"]
    verdict = {row["link"]: row for row in data["verdict"]["rows"]}
    for name, link in links.items():
        assert link["fea_yield_safety_factor"] == pytest.approx(250e6 / link["fea_max_von_mises_pa"], rel=1e-15)
        assert f"{name}: yield safety factor {link['fea_yield_safety_factor']:.3g} against the FEA peak" in text
        # the verdict takes the converged FEA peak, and its factor
        assert verdict[name]["governing"] == "FEA peak" and verdict[name]["trust"] == "FEA"
        assert verdict[name]["yield_safety_factor"] == link["fea_yield_safety_factor"]
    # the coupler's FEA peak at its pins, 6.705e5 Pa (validate's text on the seed), against 250 MPa
    assert links["coupler"]["fea_yield_safety_factor"] == pytest.approx(373, rel=0.01)


def test_validate_on_one_mesh_gives_no_factor_since_the_peaks_convergence_is_unchecked(tmp_path, capsys):
    # One mesh is the study's coarsest: a hole's peak there is typically below the converged one.
    scene = seed_scene(tmp_path, "yield_strength = 250e6\n")
    out = tmp_path / "validate.json"
    assert main(["validate", str(scene), "--mesh-levels", "1", "--json", str(out), "--details"]) == 0
    text = capsys.readouterr().out
    data = json.loads(out.read_text())
    verdict = {row["link"]: row for row in data["verdict"]["rows"]}
    for name, link in data["links"].items():
        assert link["fea_yield_safety_factor"] is None
        assert "--mesh-levels 1" in link["fea_yield_safety_factor_reason"]
        assert link["convergence"]["peak"]["status"] == "not checked"
        assert f"{name}: no yield safety factor: one mesh" in text
        # the verdict shows the (larger) unchecked FEA peak as a lower bound, with no factor
        assert verdict[name]["trust"] == "one mesh"
        assert verdict[name]["stress_pa"] >= link["fea_max_von_mises_pa"]
        if verdict[name]["governing"] == "FEA peak":
            assert verdict[name]["yield_safety_factor"] is None


def test_validate_without_a_yield_strength_gives_no_factor(tmp_path, capsys):
    out = tmp_path / "validate.json"
    assert main(["validate", str(seed_scene(tmp_path)), "--mesh-levels", "1", "--json", str(out)]) == 0
    links = json.loads(out.read_text())["links"]
    assert all(link["fea_yield_safety_factor"] is None for link in links.values())
    assert "yield safety factor" not in capsys.readouterr().out


def test_the_table_gives_each_links_lowest_factor_over_the_sweep(tmp_path, capsys):
    sweep = "input_angle_deg = [30.0, 60.0, 90.0, 120.0]\ninput_speed_rad_s = -1.0\n"
    data, text = analyze(seed_scene(tmp_path, "yield_strength = 250e6\n", sweep), tmp_path, capsys)
    peaks = [p["links"]["coupler"]["max_von_mises_pa"] for p in data["positions"]]
    lowest, highest = significant(250e6 / max(peaks)), significant(250e6 / min(peaks))
    assert lowest != highest
    assert stress_rows(text)["coupler"]["yield safety factor, sections"] == lowest


def test_a_pin_hole_no_estimate_covers_is_flagged_beside_the_factors_with_where_to_find_its_stress(tmp_path, capsys):
    # The seed crank's pivot O2 (joint 0) carries the driving torque and the output's O4 the 2 N m
    # couple: both holes are outside the Kt tables, so neither factor of those links covers them
    # when their FEA peaks do not run (--beam-only; by default those two links' model is the FEA peaks).
    data, text = analyze(seed_scene(tmp_path, "yield_strength = 250e6\n"), tmp_path, capsys, "--beam-only")
    holes = {name: [h["joint"] for h in link["pin_holes"] if h["kt_outside_table"]]
             for name, link in data["positions"][0]["links"].items() if "pin_holes" in link}
    assert holes == {"crank": [0], "coupler": [], "output": [0]}
    notes = [line for line in text.splitlines() if line.startswith("* ")]
    assert [n.split(":")[0] for n in notes] == ["* crank", "* output"]
    assert "O2 (at 1 of 1 positions)" in notes[0] and "O4 (at 1 of 1 positions)" in notes[1]
    assert all("analyze --peaks" in n for n in notes)
    # the verdict's factor names the hole it leaves uncovered beside the number, and says what to run
    verdict = {row["link"]: row for row in data["verdict"]["rows"]}
    assert verdict["crank"]["uncovered"] == ["pin hole O2 (crank-ground)"]
    assert verdict["output"]["uncovered"] == ["pin hole O4 (output-ground)"]
    assert verdict["coupler"]["uncovered"] == []
    assert verdict["crank"]["yield_safety_factor_note"] == "O2 not covered"
    assert verdict["coupler"]["yield_safety_factor_note"] is None
    assert "without --beam-only for the FEA peaks of crank, output" in data["verdict"]["next_step"]


def test_with_peaks_the_flag_points_to_the_fea_peak_table(tmp_path, capsys):
    sweep = "input_angle_deg = [30.0, 60.0]\ninput_speed_rad_s = -1.0\n"
    scene = seed_scene(tmp_path, "yield_strength = 250e6\n", sweep)
    assert main(["analyze", str(scene), "--peaks", "--details"]) == 0
    notes = [line for line in capsys.readouterr().out.splitlines() if line.startswith("* ")]
    assert notes and all("the FEA peak table below gives the stress there" in n for n in notes)


def test_the_html_safety_table_names_the_pin_holes_no_factor_covers(tmp_path):
    report = tmp_path / "report.html"
    scene = seed_scene(tmp_path, "yield_strength = 250e6\n")
    assert main(["analyze", str(scene), "--html", str(report), "--beam-only"]) == 0
    text = report.read_text()
    table = text.split("<h3>Safety factors against yield</h3>", 1)[1].split("</table>", 1)[0]
    rows = {row.split("</td>", 1)[0]: row for row in table.split('<tr><td class="text">')[1:]}
    assert "pin holes NO factor covers" in table
    assert rows["crank"].endswith('<td class="text">O2 (at 1 of 1 positions)</td></tr>')
    assert rows["output"].endswith('<td class="text">O4 (at 1 of 1 positions)</td></tr>')
    assert rows["coupler"].endswith('<td class="text">-</td></tr>')
    assert "analyze --peaks gives the FEA peak there" in text
