"""linkstress bench: speed against error of every stress method, measured in one run.

CI runs ``bench --quick`` once (the module fixture) and checks what it measured: errors under their
bounds (the superposed FEA peaks' against direct FEA too), never a time under a bound. The strip-sum
baseline and the Pareto front are checked against hand-computed values.
"""

from __future__ import annotations

import json
from pathlib import Path
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from linkstress.geometry.builders import stadium, straight_bar
from linkstress.cli import main
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.scene import load_scene
from linkstress.validation.bench.peaks import full_turn_scene
from linkstress.validation.bench.suite import SEED
from linkstress.validation.bench.speed_error import CaseStudy, MethodResult
from linkstress.validation.bench.strip_sections import piecewise_bounds, strip_sections, strip_stresses
from linkstress.validation.bench.markdown import GENERATED, bench_markdown, readme_summary
from test_report_html import embedded_images


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    code = main(["bench", "--quick", "--json", str(out / "bench.json"), "--html", str(out / "bench.html"),
                 "--markdown", str(out / "bench.md")])
    return code, json.loads((out / "bench.json").read_text()), (out / "bench.html").read_text(), (out / "bench.md").read_text()


@pytest.fixture(scope="module")
def quick(quick_run):
    """The quick run's exit code, JSON figures and HTML page."""
    return quick_run[:3]


def test_the_quick_bench_passes_every_error_check(quick):
    code, data, _ = quick
    assert code == 0 and data["failures"] == []
    assert all(check["passed"] for check in data["checks"])
    assert len(data["checks"]) >= 15


def test_on_the_seed_case_the_beam_engine_is_within_2_percent_of_converged_fea(quick):
    must = quick[1]["must_show"]
    assert must["beam_stations"] == 101
    assert must["beam_nominal_error_pct"] < 2.0
    assert must["fea_nominal_error_pct"] < 0.5  # validate's converged mesh against the Richardson reference
    # Times are reported, never bounded here: only that they were measured.
    assert must["beam_seconds"] > 0 and must["fea_study_seconds"] > must["fea_seconds"] > 0
    assert math.isclose(must["speedup"], must["fea_seconds"] / must["beam_seconds"])


def test_every_method_is_measured_with_a_time_and_an_error_on_every_case(quick):
    cases = quick[1]["cases"]
    assert list(cases) == ["seed_ansys_fourbar", "banana_coupler", "arc_coupler", "bell_crank"]
    # The quick run studies only the arc coupler's coupler and the bell crank's bell crank, without
    # P1; the strip sums section only links of one straight member, so they have nothing there.
    families = {"seed_ansys_fourbar": {"beam", "strip sums", "FEA P1", "FEA P2"},
                "banana_coupler": {"beam", "strip sums", "FEA P1", "FEA P2"},
                "arc_coupler": {"beam", "FEA P2"}, "bell_crank": {"beam", "FEA P2"}}
    for name, case in cases.items():
        assert {m["method"] for m in case["methods"]} == families[name]
        assert ("beam", "101 stations") in {(m["method"], m["setting"]) for m in case["methods"]}
        for m in case["methods"]:
            assert m["seconds"] > 0 and math.isfinite(m["nominal_error_pct"]), m
            if m["method"] != "strip sums":
                assert set(m["links"]) == set(case["links"])
                assert all(set(m["links"][n]["members"]) == set(case["members"][n]) for n in case["links"])


def test_the_curved_couplers_are_sectioned_along_their_centreline_within_3_percent(quick):
    cases = quick[1]["cases"]
    for name in ("banana_coupler", "arc_coupler"):
        assert cases[name]["curved_links"] == ["coupler"]
        beam = next(m for m in cases[name]["methods"] if m["setting"] == "101 stations")
        assert beam["links"]["coupler"]["nominal_error_pct"] < 3.0  # 18 % with straight vertical cuts
    banana = cases["banana_coupler"]
    beam = next(m for m in banana["methods"] if m["setting"] == "101 stations")
    assert beam["links"]["crank"]["nominal_error_pct"] < 2 and beam["links"]["output"]["nominal_error_pct"] < 2
    for strips in (m for m in banana["methods"] if m["method"] == "strip sums"):
        assert set(strips["links"]) == {"crank", "output"}
        assert strips["note"] == "not on coupler (curved): the strips are vertical cuts along the frame axis"


def test_both_arms_of_the_bell_crank_are_compared_each_within_2_percent(quick):
    bell = quick[1]["cases"]["bell_crank"]
    assert bell["links"] == ["bellcrank"] and bell["curved_links"] == []
    assert bell["note"] == "strip sums not on bellcrank (2 members): the strips are vertical cuts along the frame axis"
    # joints 0 = C, 1 = O4 (the pivot, at the corner), 2 = B; the frame's member O4 -> B first
    assert bell["members"] == {"bellcrank": ["[1, 2]", "[1, 0]"]}
    beam = next(m for m in bell["methods"] if m["setting"] == "101 stations")
    arms = beam["links"]["bellcrank"]["members"]
    assert set(arms) == {"[1, 2]", "[1, 0]"}
    for arm in arms.values():
        assert 0 < arm["nominal_error_pct"] < 2.0 and arm["resultant_error_pct"] < 1.0
    checks = {c["name"]: c for c in quick[1]["checks"]}
    for arm in ("[1, 2]", "[1, 0]"):
        check = checks[f"bell_crank: beam nominal error of bellcrank member {arm}"]
        assert check["passed"] and check["bound"] == 0.02
    for name in ("banana_coupler", "arc_coupler"):
        assert checks[f"{name}: beam nominal error of coupler member [0, 1]"]["bound"] == 0.03


def test_the_marked_pareto_front_is_exactly_the_undominated_methods(quick):
    for case in quick[1]["cases"].values():
        points = [(m["seconds"], m["nominal_error_pct"], m["pareto"]) for m in case["methods"]]
        for t, e, on_front in points:
            dominated = any(t2 <= t and e2 < e or t2 < t and e2 <= e for t2, e2, _ in points)
            assert on_front == (not dominated), (t, e)


def test_the_strip_sums_miss_exactly_the_area_of_the_pin_holes(quick):
    # The seed crank: 1.2 x 0.5 m with two 20 mm holes. Strips between U(x) and L(x) see the full
    # rectangle, so the area error is the holes' area over the exact area, whatever dx.
    holes = 2 * math.pi * 0.01**2
    expected = holes / (0.6 - holes)
    seed = quick[1]["cases"]["seed_ansys_fourbar"]
    for m in seed["methods"]:
        if m["method"] == "strip sums":
            assert m["mass_errors_pct"]["crank"]["area"] == pytest.approx(100 * expected, rel=1e-6)


def test_the_hard_cases_raise_their_flags_and_stay_bounded_where_they_raise_none(quick):
    stability = {case["case"]: case for case in quick[1]["stability"]}
    assert set(stability) == {"near toggle", "change point", "slender link", "stubby link", "hole close to the edge"}
    toggle = [row for row in stability["near toggle"]["rows"] if row["link"] == "coupler"]
    assert not toggle[-1]["feasible"] and toggle[-1]["reason"].startswith("unreachable")  # 0.01 deg past it
    assert all(row["feasible"] for row in toggle[:-1])
    assert toggle[-2]["transmission_angle_deg"] < 1.0  # 0.001 deg before it
    change = stability["change point"]["rows"]
    assert [row["reason"].startswith("change point") for row in change if row["link"] == "coupler"] == [False] * 4 + [True]
    assert any("no station is a section depth" in flag for flag in stability["stubby link"]["flags"])
    for case in stability.values():
        for row in case["rows"]:
            if row["trusted"]:
                assert row["nominal_error_pct"] < 5.0, (case["case"], row)
    assert max(row["nominal_error_pct"] for row in stability["slender link"]["rows"]) < 0.1


def test_the_report_has_a_log_log_figure_per_case_throughput_memory_and_versions(quick):
    _, data, page = quick
    images = embedded_images(page)
    assert len(images) == 4 and all(image[..., :3].std() > 0.05 for image in images)
    for heading in ("What must show", "Throughput", "FEA memory", "Hard cases", "Checks", "Versions"):
        assert heading in page
    stages = {(r["case"], r["stage"]) for r in data["throughput"]}
    assert ("seed_ansys_fourbar", "section stresses") in stages and ("seed_ansys_fourbar", "FEA (one link)") in stages
    memory = data["memory"][0]
    assert memory["peak_mb"] >= memory["baseline_mb"] > 0 and memory["dofs"] > 1000


def test_the_quick_bench_superposes_the_seed_links_within_1_percent_of_direct_fea(quick):
    superposition = quick[1]["superposition"]
    assert list(superposition["cases"]) == ["seed_ansys_fourbar"]  # the quick run's only case
    seed = superposition["cases"]["seed_ansys_fourbar"]
    assert seed["positions"] == 360  # a whole turn, one position per degree
    links = seed["links"]
    assert list(links) == ["crank", "coupler", "output"]
    # Each link's two loaded pins take a unit bearing force along each basis direction (every 10 deg)
    # their forces over the turn fall between, the body load 4 unit cases; the crank's driving torque
    # and the output's applied 2 N m one unit couple each. Of the 36 directions per pin the output's
    # pins sweep nearly all, the crank's and the coupler's fewer.
    assert {name: link["unit_cases"] for name, link in links.items()} == {"crank": 34, "coupler": 57, "output": 76}
    for link in links.values():
        # 180 deg is the seed's change point (all four links aligned): 359 feasible positions.
        assert link["sweep_positions"] == 359 and link["compared_positions"] == 6
        assert link["peak_error_pct"] <= 1.0 and link["field_error_pct"] <= 0.5
        assert link["superposition_ms_per_position"] > 0 and link["direct_ms_per_position"] > 0
    assert seed["peak_error_pct"] == max(link["peak_error_pct"] for link in links.values())
    checks = {c["name"]: c for c in quick[1]["checks"]}
    for name in links:
        peak = checks[f"seed_ansys_fourbar: superposed FEA peak of {name} against direct FEA"]
        field = checks[f"seed_ansys_fourbar: superposed FEA field of {name} against direct FEA (rms)"]
        assert peak["passed"] and peak["bound"] == 0.01
        assert field["passed"] and field["bound"] == 0.005


def test_the_seed_sweep_with_peaks_against_one_validate_is_a_finite_positive_ratio(quick):
    speed = quick[1]["superposition"]["speed"]
    assert speed["sweep_positions"] == 360 and speed["links"] == ["crank", "coupler", "output"] and speed["repeat"] == 1
    # Times are reported, never bounded here (shared machines are noisy): only that they were measured.
    assert speed["sweep_with_peaks_seconds"] > 0 and speed["validate_one_position_seconds"] > 0
    assert math.isfinite(speed["ratio"]) and speed["ratio"] > 0
    assert math.isclose(speed["ratio"], speed["sweep_with_peaks_seconds"] / speed["validate_one_position_seconds"])
    assert math.isfinite(speed["superposition_ms_per_link_position"]) and speed["superposition_ms_per_link_position"] > 0
    assert speed["met"] == (speed["ratio"] < 1.0 and speed["superposition_ms_per_link_position"] <= 1.0)


def test_the_report_shows_a_superposed_fea_row_per_link(quick):
    page = quick[2]
    assert "<h2>Superposed FEA peaks</h2>" in page
    for link in ("crank", "coupler", "output"):
        row = f'<tr><td class="text">superposed FEA</td><td class="text">seed_ansys_fourbar</td><td class="text">{link}</td>'
        assert page.count(row) == 1


def test_the_timed_sweep_is_the_seed_over_one_turn_without_repeating_0_deg(tmp_path):
    scene = load_scene(full_turn_scene(SEED, tmp_path, 360))
    np.testing.assert_allclose(scene.motion.angle_deg, np.arange(360.0))  # 0, 1, ... 359 deg
    assert scene.links["crank"].profile.area == load_scene(SEED).links["crank"].profile.area  # its sketch copied beside it


def test_bench_refuses_an_output_folder_that_does_not_exist_before_measuring(tmp_path, capsys):
    assert main(["bench", "--quick", "--json", str(tmp_path / "missing" / "bench.json")]) == 2
    assert "--json" in capsys.readouterr().err


def test_strip_sections_of_a_rectangle_are_the_solid_rectangle_at_each_strip_centre():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1)  # x from -0.1 to 1.1 m, 0.5 m deep, 0.1 m thick
    table = strip_sections(bar, (0, 1), 0.1)
    np.testing.assert_allclose(table.x, -0.05 + 0.1 * np.arange(12))
    np.testing.assert_allclose(table.area, 0.1 * 0.5)
    np.testing.assert_allclose(table.inertia, 0.1 * 0.5**3 / 12)
    np.testing.assert_allclose(table.y_na, 0.0, atol=1e-15)
    np.testing.assert_allclose(table.half_depth, 0.25)


def test_the_original_stress_model_translates_the_joint_forces_left_of_the_station():
    # 100 N up at joint 0 (x = 0) and 100 N down at joint 1 (x = 1 m); at x = 0.45 m only joint 0
    # is to the left: V = -100 N, M = (0 - 0.45) * 100 = -45 N m; the original takes sigma =
    # |M| c / I = 45 * 0.25 / (0.1 * 0.5^3 / 12) = 10,800 Pa and the average shear 100 / 0.05 =
    # 2,000 Pa, so von Mises sqrt(10800^2 + 3 * 2000^2).
    bar = straight_bar(1.0, 0.5, 0.1, 0.1)
    pins = np.array([[[0.0, 100.0], [0.0, -100.0]]])
    loads = LinkLoadCase((0, 1), pins, np.zeros((1, 2)), np.zeros(1), np.zeros(1), np.zeros((1, 2)), np.zeros((1, 2)))
    result = strip_stresses(bar, loads, strip_sections(bar, (0, 1), 0.1))
    k = 5
    assert result.sections.x[k] == pytest.approx(0.45)
    assert result.shear[0, k] == pytest.approx(-100.0) and result.moment[0, k] == pytest.approx(-45.0)
    assert result.von_mises[0, k] == pytest.approx(math.sqrt(10800.0**2 + 3 * 2000.0**2))


@settings(max_examples=50, deadline=None)
@given(st.floats(0.0, 1.0))
def test_the_piecewise_bounds_are_the_exact_bounding_functions(fraction):
    link = stadium(0.3, 0.05, 0.01, STRUCTURAL_STEEL, hole_diameter=0.01)
    upper, lower = piecewise_bounds(link, (0, 1))
    lo, hi = link.x_extent()
    x = lo + fraction * (hi - lo)
    exact_upper, exact_lower = link.bounds()([x])
    assert upper(x) == pytest.approx(exact_upper[0], abs=1e-12)
    assert lower(x) == pytest.approx(exact_lower[0], abs=1e-12)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.floats(1e-4, 10.0), st.floats(0.0, 100.0)), min_size=1, max_size=12))
def test_a_pareto_front_point_is_beaten_by_none_and_every_other_point_by_one_on_the_front(points):
    # Judge the front on the errors the methods carry (a percentage / 100 can round two apart
    # subnormal errors into one).
    points = [(t, e / 100) for t, e in points]
    methods = tuple(MethodResult("m", str(k), 1, t, e, None, None, {}) for k, (t, e) in enumerate(points))
    case = CaseStudy("c", "c", (), 1, methods, {}, {}, 0.0, (), ())
    front = set(case.pareto())
    for k, (t, e) in enumerate(points):
        beaten = [j for j, (t2, e2) in enumerate(points) if j != k and (t2 <= t and e2 < e or t2 < t and e2 <= e)]
        if k in front:
            assert not beaten
        else:
            assert any(j in front for j in beaten) or any(points[j] == (t, e) for j in front)


def test_the_markdown_page_is_the_rendering_of_the_json_written_by_the_same_run(quick_run):
    _, data, _, page = quick_run
    assert page == bench_markdown(data)
    assert page.startswith(GENERATED)
    seed = data["cases"]["seed_ansys_fourbar"]
    beam = next(m for m in seed["methods"] if m["setting"] == "101 stations")
    assert f"| beam | 101 stations | 303 | {1e3 * beam['seconds']:.3g} | {beam['nominal_error_pct']:.3g} |" in page
    assert ("all passed." if not data["failures"] else "FAILED") in page


def test_docs_benchmarks_is_written_by_the_bench_from_its_recorded_full_run():
    """docs/benchmarks.md is generated, never edited by hand: it is exactly the page of the JSON beside it."""
    docs = Path(__file__).resolve().parents[1] / "docs"
    data = json.loads((docs / "benchmarks.json").read_text())
    assert data["mode"] == "full"
    assert (docs / "benchmarks.md").read_text() == bench_markdown(data)


def test_the_readme_states_the_figures_of_that_same_run():
    repo = Path(__file__).resolve().parents[1]
    data = json.loads((repo / "docs" / "benchmarks.json").read_text())
    assert readme_summary(data) in (repo / "README.md").read_text()
