"""The verdict comes first: what governs each link, where, how safe and how far to trust it, with the
same figures in the text and the JSON; never below a stress the run computed without saying why; a
factor over part of the sweep, or leaving pin holes uncovered, says so beside the number. The scene's
warnings follow it in every report. The text is short by default, its numbers without round-off noise."""

from __future__ import annotations

import json
import re
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from linkstress.analysis import plan_for, run_analysis
from linkstress.cli import main
from linkstress.report.cells import column_cells, mpa, significant, without_noise
from linkstress.report.verdict import ESTIMATE, analysis_verdict
from linkstress.scene import load_scene

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
SEED = CASES / "seed_ansys_fourbar" / "scene.toml"
WARNINGS = ("thickness = 6 m: did you mean 6 mm = 0.006?", "links.crank: a second warning")


def verdict_rows(text: str) -> dict[str, list[str]]:
    """The verdict table of a report's text: per link, its cells."""
    lines = text.split("verdict: the stress that governs", 1)[1].split("\n\n", 1)[0].splitlines()
    rows = (line for line in lines[3:] if ": not analysed: " not in line)
    return {cells[0]: cells for cells in (re.split(r"\s{2,}", line.strip()) for line in rows) if not cells[0].startswith("next:")}


def assert_verdict_is_the_jsons(text: str, verdict: dict) -> None:
    """Every figure of the text's verdict is the JSON's, rounded as the text rounds it."""
    rows = verdict_rows(text)
    assert list(rows) == [row["link"] for row in verdict["rows"]]
    for row in verdict["rows"]:
        cells = rows[row["link"]]
        assert cells[1] == row["governing"]
        assert cells[2] == mpa(row["stress_pa"]) and float(cells[2]) == pytest.approx(row["stress_pa"] / 1e6, rel=5e-3)
        assert cells[3] == row["where"]
        assert float(cells[4]) == pytest.approx(row["input_angle_deg"], abs=5e-6 * abs(row["input_angle_deg"]) + 1e-9)
        for cell, key in ((cells[5], "yield_safety_factor"), (cells[6], "fatigue_safety_factor")):
            number = "-" if row[key] is None else significant(row[key])
            note = row[f"{key}_note"]
            assert cell == (f"{number} ({note})" if note else number)
        assert cells[7] == f"{row['trust']}: {row['trust_reason']}" if row["trust_reason"] else row["trust"]
    if verdict["next_step"]:
        assert f"next: {verdict['next_step']}" in text


def seed_copy(tmp_path: Path, material: str = "", motion: str = "") -> Path:
    """The seed ANSYS case in ``tmp_path``, ``material`` lines added to its steel, its [motion] replaced by ``motion``."""
    shutil.copy(SEED.parent / "ansys_four_bars.dxf", tmp_path)
    text = SEED.read_text().replace("poisson_ratio = 0.3\n", "poisson_ratio = 0.3\n" + material)
    if motion:
        start = text.index("[motion]")
        text = text[:start] + "[motion]\n" + motion + text[text.index("\n\n", start):]
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def test_the_seed_validate_prints_its_verdict_first_with_the_jsons_figures(tmp_path, capsys):
    out = tmp_path / "v.json"
    assert main(["validate", str(SEED), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    data = json.loads(out.read_text())
    assert text.splitlines()[0].startswith("verdict: the stress that governs each link")
    assert len(text.split("\n\n", 1)[0].splitlines()) <= 25
    assert_verdict_is_the_jsons(text, data["verdict"])
    crank = next(row for row in data["verdict"]["rows"] if row["link"] == "crank")
    # the crank's FEA peak at its driven pin, 11.2 MPa (validate's finest of three meshes), governs
    assert (crank["governing"], crank["where"], crank["trust"]) == ("FEA peak", "pin hole O2 (crank-ground)", "FEA")
    assert crank["stress_pa"] == data["links"]["crank"]["fea_max_von_mises_pa"]
    assert mpa(crank["stress_pa"]) == "11.2"
    # the FEA peak over the beam's maximum is the stress raiser the beam does not model, not its error
    assert data["links"]["crank"]["fea_peak_over_beam_max"] == pytest.approx(
        1 / (1 - data["links"]["crank"]["peak_error_pct"] / 100), rel=1e-9)
    assert "peak error" not in text
    assert re.search(r"(?m)^crank .* 103 x +pin hole O2 \(crank-ground\)", text)
    assert data["warnings"] == []


def test_a_converged_peak_below_a_computed_estimate_says_why_the_estimate_does_not_govern(tmp_path, capsys):
    # The seed coupler's pin A: Kt x nominal 0.696 MPa, the converged FEA 0.671 MPa (the Kt tables
    # are a few % conservative). The verdict shows the FEA's, and names the higher estimate.
    out = tmp_path / "v.json"
    assert main(["validate", str(SEED), "--json", str(out)]) == 0
    capsys.readouterr()
    data = json.loads(out.read_text())
    for row in data["verdict"]["rows"]:
        estimate = data["links"][row["link"]]["pin_estimate_max_pa"] or 0.0
        beam = data["links"][row["link"]]["beam_max_von_mises_pa"]
        if max(estimate, beam) > row["stress_pa"]:
            assert "is higher" in row["trust_reason"], row
    coupler = next(row for row in data["verdict"]["rows"] if row["link"] == "coupler")
    assert coupler["trust_reason"].endswith(
        "the pin-hole estimate 0.696 MPa at pin hole A (crank-coupler) is higher: an estimate, the FEA governs")


@pytest.mark.parametrize("case", ["seed_ansys_fourbar", "banana_coupler", "bell_crank", "six_bar", "slider_crank_curved_rod"])
def test_without_fea_the_larger_of_the_beam_and_every_estimate_governs(case):
    scene = load_scene(CASES / case / "scene.toml")
    result = run_analysis(scene, plan_for(scene))
    ok = result.feasible
    verdict = analysis_verdict(result)
    assert [row.link for row in verdict.rows] == list(result.stresses)
    for row in verdict.rows:
        stress = result.stresses[row.link]
        computed = [float(stress.max_von_mises[ok].max())]
        computed += [h.largest(ok) for h in stress.pin_holes if h.largest(ok) is not None]
        assert row.stress.value == max(computed)
        assert row.model in ("beam", "beam+Kt")
        uncovered = [h for h in stress.pin_holes if ((h.nominal > 0) & h.outside)[ok].any()]
        assert len(row.uncovered) == len(uncovered)
        if uncovered:
            # its model is "fea-peaks", which this run (the beam alone) did not compute: analyze does
            assert result.models[row.link].model == "fea-peaks" and "needs the FEA peaks" in row.reason
            assert row.link in verdict.next_step and f"linkstress analyze {scene.path}" in verdict.next_step
            assert row.trust == ("Kt estimate" if row.stress.governing == ESTIMATE else "beam only")


def test_a_factor_from_an_estimate_at_some_positions_says_at_how_many(tmp_path):
    # The six-bar's coupler: its largest stress is Kt x nominal at pin A, where the Kt tables cover
    # the geometry the pin force sees at only some of the 36 positions.
    scene = load_scene(CASES / "six_bar" / "scene.toml")
    steel = replace(scene.materials["steel"], yield_strength=250e6)
    links = {name: replace(link, material=steel) if link.material is not None else link for name, link in scene.links.items()}
    scene = replace(scene, links=links, materials={"steel": steel})
    result = run_analysis(scene, plan_for(scene))
    row = next(r for r in analysis_verdict(result).rows if r.link == "coupler")
    assert row.stress.governing == ESTIMATE and row.trust == "Kt estimate"
    hole = next(h for h in result.stresses["coupler"].pin_holes if row.stress.where.startswith(f"pin hole {'A' if h.joint == 0 else 'B'}"))
    loaded = result.feasible & (hole.nominal > 0)
    inside = int((loaded & ~hole.outside).sum())
    assert 0 < inside < int(loaded.sum()) == 36
    assert row.yield_factor.value == pytest.approx(250e6 / row.stress.value, rel=1e-15)
    assert row.yield_factor.note.startswith(f"at {inside} of 36 positions")
    assert row.yield_factor.text().startswith(f"{significant(row.yield_factor.value)} (at {inside} of 36 positions")


def test_with_peaks_the_converged_fea_governs_with_its_fatigue_factor(tmp_path, capsys):
    sweep = "input_angle_deg = {start = 0.0, stop = 300.0, num = 6}\ninput_speed_rad_s = -1.0\n"
    scene = seed_copy(tmp_path, "yield_strength = 250e6\nendurance_limit = 200e6\nultimate_strength = 400e6\n", sweep)
    out = tmp_path / "a.json"
    assert main(["analyze", str(scene), "--peaks", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    data = json.loads(out.read_text())
    assert_verdict_is_the_jsons(text, data["verdict"])
    for row in data["verdict"]["rows"]:
        summary = data["links"][row["link"]]
        assert (row["governing"], row["model"], row["trust"]) == ("FEA peak", "fea-peaks", "FEA")
        assert row["stress_pa"] == summary["peak_max_von_mises_pa"]
        assert row["yield_safety_factor"] == summary["peak_yield_safety_factor"]
        assert row["fatigue_safety_factor"] == summary["fatigue_safety_factor"]
        # five of the six positions are feasible (the change point at 180 deg is not): the whole sweep's
        assert row["yield_safety_factor_note"] is None
        assert row["fatigue_safety_factor_note"].startswith("Goodman")


def verdict_and_warnings_in(text: str) -> tuple[int, int]:
    """The line numbers of the verdict's heading and of the first warning."""
    lines = text.splitlines()
    heading = next(k for k, line in enumerate(lines) if line.startswith("verdict:"))
    warning = next(k for k, line in enumerate(lines) if line == f"warning: {WARNINGS[0]}")
    return heading, warning


@pytest.mark.parametrize("command", ["analyze", "validate"])
def test_the_scenes_warnings_follow_the_verdict_in_text_html_and_json(command, tmp_path, capsys, monkeypatch):
    module = __import__(f"linkstress.commands.{command}", fromlist=["load_scene"])
    monkeypatch.setattr(module, "load_scene", lambda path: replace(load_scene(path), warnings=WARNINGS))
    out, page = tmp_path / "out.json", tmp_path / "out.html"
    extra = ["--mesh-levels", "1"] if command == "validate" else []
    assert main([command, str(SEED), "--json", str(out), "--html", str(page), *extra]) == 0
    text = capsys.readouterr().out
    heading, warning = verdict_and_warnings_in(text)
    lines = text.splitlines()
    table_end = lines.index("", heading)
    if lines[table_end + 1].startswith("models:"):  # each link's model and why: the verdict's last part
        table_end = lines.index("", table_end + 1)
    assert warning == table_end + 1  # right after the verdict, its next step and the models
    assert f"warning: {WARNINGS[1]}" == text.splitlines()[warning + 1]
    assert json.loads(out.read_text())["warnings"] == list(WARNINGS)
    html = page.read_text()
    verdict_at, warning_at = html.index("<h2>Verdict</h2>"), html.index(WARNINGS[0])
    assert verdict_at < warning_at < html.index("<h2>Mechanism, position by position</h2>")


def test_the_short_text_holds_the_verdict_summary_and_maxima_and_details_the_rest(tmp_path, capsys):
    sweep = "input_angle_deg = {start = 0.0, stop = 350.0, num = 36}\ninput_speed_rad_s = -1.0\n"
    scene = seed_copy(tmp_path, "yield_strength = 250e6\n", sweep)
    assert main(["analyze", str(scene)]) == 0
    short = capsys.readouterr().out
    assert main(["analyze", str(scene), "--details"]) == 0
    details = capsys.readouterr().out
    assert "add --details" in short and "add --details" not in details
    for table in ("\nmotion\n", "joint forces (Fij", "section stresses (beam theory"):
        assert table not in short and table in details
    assert "link maxima over the sweep" in short and "driving torque T12" in short
    assert len(short.splitlines()) < 60 < len(details.splitlines())
    # joint forces named by the links they act between (Fij: of link i on link j)
    assert re.search(r"(?m)^\s+\S+\s+main\s+F32\s+coupler on crank at A\s", details)
    for text in (short, details):
        assert not re.search(r"\de-(1\d|[2-9]\d)\b", text), "round-off noise printed"
        assert not re.search(r"\w\.py\b", text), "a message points to a source file"
        assert text.count("Kt: the stress concentration factor") == 1


def test_validate_details_say_kt_in_words_once_and_cite_no_source_file(capsys):
    assert main(["validate", str(SEED), "--mesh-levels", "1", "--details"]) == 0
    text = capsys.readouterr().out
    assert text.count("Kt: the stress concentration factor") == 1
    assert not re.search(r"\w\.py\b", text)
    assert re.search(r"crank: FEA peak / beam maximum = \d+ x, at pin hole O2 \(crank-ground\) - the stress raiser the beam "
                     r"does not model; see the verdict", text)


@pytest.mark.parametrize("value, digits, expected", [
    (0.11888, 3, "0.119"), (11186500.0, 3, "1.12e+07"), (1234.5, 3, "1230"), (9.996, 3, "10.0"), (40.02, 3, "40.0"),
    (-0.000123456, 3, "-0.000123"), (2.5e-7, 3, "2.50e-07"), (0.0, 3, "0"), (60.0, 6, "60.0000"),
])
def test_figures_are_written_to_their_significant_digits(value, digits, expected):
    assert significant(value, digits) == expected


def test_round_off_is_written_zero_against_its_columns_scale():
    rows = [(60.0, -1.27577e-14, 100.0), (90.0, 3.5, 1.38778e-17)]
    assert column_cells(rows, (6, 6, 6)) == [["60", "0", "100"], ["90", "3.5", "0"]]
    # a column whose values are all small keeps them: noise is relative to the column's own scale
    assert column_cells([(2e-14,), (1e-14,)], (3,)) == [["2e-14"], ["1e-14"]]
    np.testing.assert_array_equal(without_noise(np.array([1.0, 1e-10, -1e-9])), [1.0, 0.0, 0.0])


def test_a_link_the_run_does_not_stress_is_named_under_the_verdict_with_why_in_text_html_and_json(tmp_path, capsys):
    """The shaper's collar and ram are one-joint blocks: no member to section, so no row; each is
    named as not analysed, never left out in silence. Its slotted lever, which the collar slides
    along, has its row (tests/test_sliding_contact.py). The rows stay the JSON's."""
    case = CASES / "whitworth_shaper"
    out, page = tmp_path / "shaper.json", tmp_path / "shaper.html"
    assert main(["analyze", str(case / "scene.toml"), "--beam-only", "--json", str(out), "--html", str(page)]) == 0
    text = capsys.readouterr().out
    verdict = json.loads(out.read_text())["verdict"]
    assert [row["link"] for row in verdict["rows"]] == ["crank", "lever", "rod"]
    assert [entry["link"] for entry in verdict["not_analysed"]] == ["collar", "ram"]
    assert "a slider, with one joint, has no member" in verdict["not_analysed"][0]["reason"]
    assert_verdict_is_the_jsons(text, verdict)
    table = text.split("verdict: the stress that governs", 1)[1].split("\n\n", 1)[0]
    html = page.read_text()
    for entry in verdict["not_analysed"]:
        assert f"{entry['link']}: not analysed: {entry['reason']}" in table
        assert f"{entry['link']}: not analysed:" in html


def test_every_stressed_link_leaves_the_not_analysed_list_empty():
    """The seed's three moving links are all stressed: nothing is listed as not analysed."""
    result = run_analysis(load_scene(SEED), replace(plan_for(load_scene(SEED)), beam_only=True))
    assert analysis_verdict(result).record()["not_analysed"] == []


def test_a_drawn_link_without_a_material_is_not_analysed_and_says_so(tmp_path):
    """The seed's coupler with its mass given by hand but no material: no section stresses, and the
    verdict names it with the reason."""
    scene_path = seed_copy(tmp_path)
    text = scene_path.read_text()
    start = text.index("[links.coupler]")
    end = text.index("\n[", start + 1)
    block = "\n".join(line for line in text[start:end].splitlines() if not line.startswith("material"))
    scene_path.write_text(text[:start] + block + "\nmass = 1.0\ninertia = 0.01\ncenter_of_mass = [0.1, 0.0]\n" + text[end:])
    scene = load_scene(scene_path)
    verdict = analysis_verdict(run_analysis(scene, replace(plan_for(scene), beam_only=True)))
    assert ("coupler", "it has no material") in verdict.unanalysed
    assert "coupler: not analysed: it has no material" in verdict.text()
