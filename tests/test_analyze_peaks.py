"""``analyze --peaks``: the FEA peak of every stressed link at every position, the sweep's worst, the
yield and fatigue safety factors taken from it, and every refusal one message with exit 2."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
import shapely

from linkstress.analysis import plan_for, run_analysis
from linkstress.cli import main
from linkstress.fatigue import FatigueStrength, safety_factor
from linkstress.scene import load_scene

SEED = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar"
LINKS = ("crank", "coupler", "output")
FATIGUE = "yield_strength = 250e6\nendurance_limit = 200e6\nultimate_strength = 400e6\nsurface_factor = 0.8\n"


def seed_scene(folder: Path, sweep: str = "{ start = 15.0, stop = 345.0, num = 12 }", material: str = FATIGUE,
               analysis: str = "") -> Path:
    """The seed four-bar over ``sweep`` with ``material`` keys added to its steel and an optional
    [analysis] table."""
    (folder / "ansys_four_bars.dxf").write_bytes((SEED / "ansys_four_bars.dxf").read_bytes())
    text = (SEED / "scene.toml").read_text()
    text = re.sub(r"(?m)^input_angle_deg = .*$", f"input_angle_deg = {sweep}", text)
    text = text.replace("poisson_ratio = 0.3\n", "poisson_ratio = 0.3\n" + material)
    scene = folder / "scene.toml"
    scene.write_text(text + analysis)
    return scene


def analyze(scene: Path, out: Path, *options: str) -> tuple[int, dict]:
    code = main(["analyze", str(scene), "--json", str(out), *options])
    return code, json.loads(out.read_text(), parse_constant=pytest.fail) if out.exists() else {}


@pytest.fixture(scope="module")
def seed_peaks(tmp_path_factory):
    folder = tmp_path_factory.mktemp("peaks")
    code, data = analyze(seed_scene(folder), folder / "out.json", "--peaks")
    return code, data, folder


def test_every_feasible_position_gives_each_links_fea_peak_where_it_is_and_its_yield_factor(seed_peaks):
    code, data, folder = seed_peaks
    assert code == 0
    scene = load_scene(folder / "scene.toml")
    motion = run_analysis(scene, plan_for(scene)).kinematics
    for k, record in enumerate(data["positions"]):
        assert record["feasible"]
        for name in LINKS:
            link = record["links"][name]
            peak = link["peak_von_mises_pa"]
            # a pin-loaded bar: its peak is at a hole, above the beam's nominal maximum
            assert peak > link["max_von_mises_pa"] > 0
            assert link["peak_yield_safety_factor"] == pytest.approx(250e6 / peak, rel=1e-12)
            # the ground-frame point, moved back into the link's member frame, is a point of its outline
            angle, origin = motion.links[name].angle[k], motion.links[name].origin[k]
            c, s = math.cos(angle), math.sin(angle)
            x, y = np.asarray(link["peak_at_m"]) - origin
            local = shapely.Point(c * x + s * y, -s * x + c * y)
            profile = scene.links[name].profile
            assert profile.local_outline(*scene.links[name].frame_joints).distance(local) <= 1e-4


def test_the_sweeps_summary_gives_the_worst_peak_the_check_and_the_fatigue_at_the_critical_point(seed_peaks):
    _, data, folder = seed_peaks
    scene = load_scene(folder / "scene.toml")
    for name in LINKS:
        summary = data["links"][name]
        peaks = [r["links"][name]["peak_von_mises_pa"] for r in data["positions"]]
        worst = int(np.argmax(peaks))
        assert summary["peak_max_von_mises_pa"] == max(peaks)
        assert summary["peak_max_input_angle_deg"] == data["positions"][worst]["input_angle_deg"]
        assert summary["peak_max_at_m"] == data["positions"][worst]["links"][name]["peak_at_m"]
        assert summary["beam_max_von_mises_pa"] == max(r["links"][name]["max_von_mises_pa"] for r in data["positions"])
        assert summary["peak_converged"] is True and summary["peak_change_pct"] < 5 and summary["peak_previous_change_pct"] < 5
        assert summary["peak_yield_safety_factor"] == pytest.approx(250e6 / max(peaks), rel=1e-12)
        # every loaded pin: the bearing directions its forces fall between (at least one), and 4 body terms
        assert summary["peak_mesh"]["unit_load_cases"] >= 2 + 4 and summary["peak_mesh"]["direction_step_deg"] == 10
        # fatigue: Goodman at the critical point, from its own alternating and mean stress, S_e = 0.8 x 200 MPa
        strength = FatigueStrength(200e6, 400e6, 250e6, surface_factor=0.8)
        assert summary["fatigue_endurance_limit_pa"] == pytest.approx(160e6, rel=1e-15)
        assert summary["fatigue_criterion"] == "goodman"
        expected = float(safety_factor("goodman", summary["fatigue_alternating_pa"], summary["fatigue_mean_pa"], strength))
        assert summary["fatigue_safety_factor"] == pytest.approx(expected, rel=1e-12)
        assert set(summary["fatigue_safety_factors"]) == {"goodman", "gerber", "asme-elliptic"}
        # the largest peak bounds the cycle's stress at every point
        assert summary["fatigue_alternating_pa"] + abs(summary["fatigue_mean_pa"]) <= max(peaks) * (1 + 1e-9)
        # the critical point is a point of the link as drawn (its sketch's frame)
        outline = scene.links[name].profile.outline
        assert outline.distance(shapely.Point(summary["fatigue_critical_at_m"])) <= 1e-3
        assert summary["fatigue_note"] == ""  # 12 positions over a whole turn (the change point at 180 deg between two), all feasible


def test_the_text_report_has_the_peak_table_and_the_frames_of_its_points(tmp_path, capsys):
    assert main(["analyze", str(seed_scene(tmp_path, "{ start = 0.0, stop = 300.0, num = 6 }")), "--peaks", "--details"]) == 0
    out = capsys.readouterr().out
    assert "FEA peak stresses over the sweep" in out
    assert "at (x, y) [m], ground frame" in out and "critical point (x, y) [m], drawing" in out
    assert re.search(r"(?m)^\s*crank\s+[\d.e+]+\s+\d", out)
    assert "nan" not in out and "inf" not in out.replace("infeasible", "")


def test_analysis_peaks_true_in_the_scene_is_the_same_as_the_flag(tmp_path, seed_peaks):
    _, flagged, _ = seed_peaks
    scene = seed_scene(tmp_path, analysis="\n[analysis]\nstresses = true\npeaks = true\n")
    code, data = analyze(scene, tmp_path / "out.json")
    assert code == 0
    for name in LINKS:
        a, b = flagged["links"][name], data["links"][name]
        assert {k: v for k, v in a.items() if k != "peak_seconds"} == {k: v for k, v in b.items() if k != "peak_seconds"}


def test_without_fatigue_data_the_factor_is_null_and_the_note_names_the_keys(tmp_path):
    scene = seed_scene(tmp_path, "{ start = 0.0, stop = 180.0, num = 4 }", material="")
    code, data = analyze(scene, tmp_path / "out.json", "--peaks")
    crank = data["links"]["crank"]
    assert code == 0 and crank["fatigue_safety_factor"] is None
    assert crank["fatigue_note"] == "no fatigue check: materials.steel gives no endurance_limit and ultimate_strength"
    assert "peak_yield_safety_factor" not in crank  # no yield strength either
    assert "peak_yield_safety_factor" not in data["positions"][0]["links"]["crank"]


def test_a_sweep_short_of_a_whole_turn_gives_the_factor_with_a_note_of_what_it_covers(tmp_path):
    code, data = analyze(seed_scene(tmp_path, "{ start = 0.0, stop = 90.0, num = 4 }"), tmp_path / "out.json", "--peaks")
    crank = data["links"]["crank"]
    assert code == 0 and crank["fatigue_safety_factor"] > 0
    assert crank["fatigue_note"].startswith("over the swept 120 deg of input only, not a whole turn")


def test_the_asme_elliptic_criterion_needs_a_yield_strength(tmp_path):
    material = "endurance_limit = 200e6\nultimate_strength = 400e6\n"
    scene = seed_scene(tmp_path, "{ start = 0.0, stop = 180.0, num = 4 }", material,
                       '\n[analysis]\nstresses = true\npeaks = true\nfatigue_criterion = "asme-elliptic"\n')
    code, data = analyze(scene, tmp_path / "out.json")
    crank = data["links"]["crank"]
    assert code == 0 and crank["fatigue_criterion"] == "asme-elliptic" and crank["fatigue_safety_factor"] is None
    assert crank["fatigue_note"] == "no fatigue check: the asme-elliptic criterion needs materials.steel.yield_strength"


@pytest.mark.parametrize(
    ("material", "analysis", "message"),
    [
        (None, '\n[analysis]\nstresses = true\nfatigue_criterion = "soderberg"\n',
         r"scene.toml: analysis.fatigue_criterion: must be one of 'goodman', 'gerber', 'asme-elliptic', got 'soderberg'"),
        (None, "\n[analysis]\nstresses = true\npeaks = 1\n", r"scene.toml: analysis.peaks: must be true or false, got 1"),
        ("", None, r"scene.toml: materials.steel.youngs_modulus: missing; the FEA of link 'crank' needs it"),
        # 3.5 mm elements, 1.56 mm on the peak mesh: about 5.7e5 quadratic triangles on the 0.6 m^2 crank,
        # within what validate meshes, but up to 78 unit cases would hold about 6.4 GB
        (None, "\n[analysis]\nstresses = true\nmesh_size_m = 0.0035\n",
         r"scene.toml: --peaks: link 'crank' would need about [\d.]+ GB for its unit load cases .* give a coarser "
         r"\[analysis\] mesh_size_m"),
    ],
)
def test_bad_peak_input_is_one_message_and_exit_2(tmp_path, capsys, material, analysis, message):
    scene = seed_scene(tmp_path, analysis=analysis or "")
    if material is not None:
        scene.write_text(scene.read_text().replace("youngs_modulus = 200e9\n", material))
    assert main(["analyze", str(scene), "--peaks", "--json", str(tmp_path / "out.json")]) == 2
    err = capsys.readouterr().err
    assert re.search(message, err) and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out.json").exists()


def test_a_sharp_notchs_peak_that_does_not_settle_gives_no_safety_factor_yield_or_fatigue(tmp_path, capsys):
    # The notched crank of the validate story: its corner's peak went 74.9 -> 90.0 -> 85.8 MPa on
    # validate's three meshes (20 %, then 4.8 %): singular, never converged. One refinement alone
    # would pass it; the peak check looks at two.
    from test_validate_story import write_notched_crank

    scene = write_notched_crank(tmp_path)
    text = scene.read_text().replace('validate = ["crank"]', 'validate = ["crank"]\npeaks = true\nmesh_size_m = 0.004')
    scene.write_text(text.replace("yield_strength = 250000000.0\n", "yield_strength = 250e6\nendurance_limit = 200e6\nultimate_strength = 400e6\n"))
    code, data = analyze(scene, tmp_path / "out.json")
    crank = data["links"]["crank"]
    assert code == 0 and crank["peak_converged"] is False
    assert crank["peak_previous_change_pct"] > 5
    assert crank["peak_yield_safety_factor"] is None and crank["fatigue_safety_factor"] is None
    assert set(crank["fatigue_safety_factors"].values()) == {None}
    assert crank["peak_note"].startswith("the FEA peak is NOT converged")
    assert crank["fatigue_note"].startswith("withheld: the FEA peak is NOT converged")
    assert all("peak_yield_safety_factor" not in r["links"]["crank"] for r in data["positions"])
    assert "NOT converged" in capsys.readouterr().out


def test_the_links_fea_in_a_process_each_gives_the_numbers_of_one_after_another(tmp_path, monkeypatch):
    # analyze runs the links' FEA peaks in a local process per core (at most one per link); with one
    # core they run here one after another. Three processes for the three links (monkeypatched cores,
    # whatever this machine has) and one must give the same JSON but for the timings.
    from linkstress import threads

    scene = seed_scene(tmp_path, sweep="[30.0, 150.0, 270.0]")
    runs = {}
    for processes in (1, 3):
        monkeypatch.setattr(threads, "cores", lambda processes=processes: processes)
        code, runs[processes] = analyze(scene, tmp_path / f"out{processes}.json", "--peaks", "--no-cache")
        assert code == 0
    apart, together = runs[3], runs[1]
    assert apart["positions"] == together["positions"]
    assert set(apart["links"]) == set(LINKS)
    for name in LINKS:
        a, b = apart["links"][name], together["links"][name]
        assert {k: v for k, v in a.items() if k != "peak_seconds"} == {k: v for k, v in b.items() if k != "peak_seconds"}
    assert apart["verdict"] == together["verdict"]
