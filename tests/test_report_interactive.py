"""The HTML report's interactive view of the mechanism: its frame data (no browser) and, in headless
Chromium, a slider that redraws the links, their stress colours, the joints and the angle text."""

from __future__ import annotations

import json
import math
import os
import re
from pathlib import Path

import numpy as np
import pytest
from test_report_html import CHROMIUM_FLAGS, find_chromium

from linkstress.analysis import run_analysis
from linkstress.cli import main
from linkstress.report.mechanism_view import MAX_VIEW_FRAMES, view_data, view_frames, view_html
from linkstress.scene.reader import load_scene

REPO = Path(__file__).resolve().parents[1]
SEED = REPO / "validation" / "cases" / "seed_ansys_fourbar"


def seed_sweep(folder: Path, sweep: str = "{start = 0.0, stop = 350.0, num = 36}", analysis: str = "") -> Path:
    """The seed four-bar (1.0 m crank, 1.5 m coupler) swept over ``sweep``: a Grashof change-point
    linkage whose coupler lines up with the others at 180 deg, where the position is infeasible."""
    (folder / "ansys_four_bars.dxf").write_bytes((SEED / "ansys_four_bars.dxf").read_bytes())
    text = re.sub(r"(?m)^input_angle_deg = .*$", f"input_angle_deg = {sweep}", (SEED / "scene.toml").read_text())
    scene = folder / "scene.toml"
    scene.write_text(text + analysis)
    return scene


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    scene = seed_sweep(folder)
    out = folder / "seed.html"
    assert main(["analyze", str(scene), "--html", str(out)]) == 0
    return out, run_analysis(load_scene(scene))


def page_data(text: str) -> dict:
    return json.loads(re.search(r'<script type="application/json" id="view-data">(.*?)</script>', text, re.S).group(1))


def sketch_to_ground(sketch_joints, ground_joints):
    """The rigid motion that takes two sketch points onto two ground points, as a function of points (n, 2)."""
    (p0, p1), (q0, q1) = np.asarray(sketch_joints), np.asarray(ground_joints)
    turn = math.atan2(*(q1 - q0)[::-1]) - math.atan2(*(p1 - p0)[::-1])
    rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    return lambda points: q0 + (np.asarray(points) - p0) @ rotation.T


def placed(ring, pose) -> np.ndarray:
    """A ring in its member frame placed by a view pose [x, y, angle]."""
    ring = np.asarray(ring)
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.column_stack([pose[0] + c * ring[:, 0] - s * ring[:, 1], pose[1] + s * ring[:, 0] + c * ring[:, 1]])


def test_a_sweep_of_up_to_720_positions_is_shown_whole_and_a_longer_one_evenly_thinned_with_its_ends():
    assert view_frames(36).tolist() == list(range(36))
    frames = view_frames(10_000)
    assert len(frames) == MAX_VIEW_FRAMES == 720
    assert frames[0] == 0 and frames[-1] == 9999
    # 9999 / 719 = 13.9 positions apart, so every step is 13 or 14.
    assert set(np.diff(frames).tolist()) == {13, 14}


def test_the_coupler_outline_at_a_position_is_its_sketch_outline_carried_onto_the_joints_a_and_b(sweep):
    _, result = sweep
    data = view_data(result)
    k = 8  # input 80 deg
    coupler = result.scene.links["coupler"]
    joints = result.kinematics.loops["main"].joints
    # Independently of member frames: the coupler's sketch joints 0 and 1 go onto A and B.
    to_ground = sketch_to_ground(coupler.joints[:2], [joints["A"].position[k], joints["B"].position[k]])
    expected = to_ground(np.asarray(coupler.profile.outline.exterior.coords))
    drawn = placed(data["links"]["coupler"]["rings"][0], data["links"]["coupler"]["pose"][k])
    rounding = 10.0 ** -data["decimals"]
    # The view keeps a subset of the outline's vertices (those the drawing needs), each where it belongs.
    gaps = np.linalg.norm(drawn[:, None, :] - expected[None, :, :], axis=2).min(axis=1)
    assert len(drawn) >= 5 and gaps.max() < 2 * rounding
    assert np.allclose(drawn[0], expected[0], atol=2 * rounding)
    # The holes: two pin holes, each ring around its joint.
    holes = data["links"]["coupler"]["rings"][1:]
    centres = sorted(placed(h, data["links"]["coupler"]["pose"][k]).mean(axis=0).round(3).tolist() for h in holes)
    assert np.allclose(centres, sorted([joints["A"].position[k].round(3).tolist(), joints["B"].position[k].round(3).tolist()]),
                       atol=2e-3)


def test_the_frame_data_gives_each_links_stress_and_each_joint_force_and_null_where_infeasible(sweep):
    _, result = sweep
    data = view_data(result)
    bad = data["feasible"].index(False)
    assert data["input_angle_deg"][bad] == 180.0 and data["reason"][bad]
    assert data["links"]["coupler"]["pose"][bad] is None and data["joints"]["main.A"][bad] is None
    k = 8
    assert data["links"]["crank"]["von_mises_mpa"][k] == pytest.approx(
        result.stresses["crank"].max_von_mises[k] / 1e6, abs=10.0 ** -data["stress_scale"]["decimals"])
    assert data["stress_scale"]["max_mpa"] == pytest.approx(
        max(s.max_von_mises[result.feasible].max() for s in result.stresses.values()) / 1e6, rel=1e-3)
    f32 = next(f for f in data["forces"] if f["label"] == "main.F32")
    assert f32["joint"] == "main.A"
    assert f32["force_n"][k] == pytest.approx(result.forces.mechanisms["main"].forces["F32"][k].tolist(), abs=0.5)
    # The largest force of the sweep is drawn a quarter of the mechanism's size long.
    assert data["force_scale_m_per_n"] * data["largest_force_n"] == pytest.approx(0.25 * data["size_m"], rel=1e-3)


def test_without_stresses_or_forces_the_view_has_no_colours_and_no_arrows_and_says_so(tmp_path):
    scene = seed_sweep(tmp_path, analysis="\n[analysis]\nkinematics = true\n")
    result = run_analysis(load_scene(scene))
    data = view_data(result)
    assert "stress_scale" not in data and "forces" not in data
    assert all("von_mises_mpa" not in link for link in data["links"].values())
    text = view_html(result)
    assert "No section stresses were computed in this analysis: the links are not coloured." in text
    assert "No joint forces were computed in this analysis: no arrows." in text


def test_a_long_sweep_says_how_many_of_its_positions_the_view_shows_and_stays_small(tmp_path):
    scene = seed_sweep(tmp_path, sweep="{start = 0.0, stop = 359.0, num = 2000}")
    text = view_html(run_analysis(load_scene(scene)))
    assert "720 of the sweep&#x27;s 2000 positions, evenly chosen" in text
    assert len(page_data(text)["frames"]) == 720
    # About 280 bytes a position shown: the links' rings once, then poses, stresses, joints and forces.
    assert len(text) < 250_000


# --- in a real browser ---------------------------------------------------------------------------

def browser():
    """Playwright's sync API and the chromium to drive, or a skip (a failure where CI requires them)."""
    required = os.environ.get("LINKSTRESS_REQUIRE_BROWSER") == "1"
    executable = find_chromium()
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        sync_playwright = None
    missing = "chromium" if executable is None else "the playwright package" if sync_playwright is None else None
    if missing:
        if required:
            pytest.fail(f"{missing} is required here (LINKSTRESS_REQUIRE_BROWSER=1) but not installed")
        pytest.skip(f"no {missing} on this machine; .ci/run installs Debian's chromium and the test extra")
    return sync_playwright, executable


def drawn(page) -> dict:
    """What the view shows now: the coupler's path and fill, the joint A, the angle text."""
    return page.evaluate("""() => {
        const coupler = document.querySelector('path[data-link="coupler"]');
        const a = document.querySelector('circle[data-joint="main.A"]');
        return {d: coupler.getAttribute('d'), fill: coupler.getAttribute('fill'),
                vm: coupler.getAttribute('data-von-mises-mpa'), visible: coupler.getAttribute('visibility'),
                a: [Number(a.getAttribute('cx')), -Number(a.getAttribute('cy'))],
                angle: document.getElementById('view-angle').textContent};
    }""")


def stress_colour(value: float, scale: dict) -> str:
    """The view's colour of ``value`` [MPa]: linear between the scale's colour stops."""
    stops = np.array([[int(c[i:i + 2], 16) for i in (1, 3, 5)] for c in scale["colours"]], float)
    t = min(max(value / scale["max_mpa"], 0.0), 1.0) * (len(stops) - 1)
    i = min(int(t), len(stops) - 2)
    rgb = np.floor(stops[i] + (t - i) * (stops[i + 1] - stops[i]) + 0.5).astype(int)
    return f"rgb({rgb[0]}, {rgb[1]}, {rgb[2]})"


def first_point(d: str) -> np.ndarray:
    x, y = re.match(r"M(-?[\d.]+),(-?[\d.]+)", d).groups()
    return np.array([float(x), -float(y)])


def test_moving_the_slider_redraws_the_links_colours_joints_and_angle_from_the_frame_data(sweep, tmp_path):
    sync_playwright, executable = browser()
    report, result = sweep
    data = page_data(report.read_text())
    joints = result.kinematics.loops["main"].joints
    rounding = 10.0 ** -data["decimals"]
    problems = []
    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=executable, args=list(CHROMIUM_FLAGS))
        try:
            page = chromium.new_page(viewport={"width": 1100, "height": 1200})
            page.on("console", lambda m: problems.append(m.text) if m.type in ("error", "warning") else None)
            page.on("pageerror", lambda e: problems.append(str(e)))
            page.goto(report.as_uri())
            before = drawn(page)
            page.fill("#view-slider", "8")
            page.dispatch_event("#view-slider", "input")
            after = drawn(page)
            page.focus("#view-slider")
            page.keyboard.press("ArrowRight")
            keyed = drawn(page)
            bad = data["feasible"].index(False)
            page.fill("#view-slider", str(bad))
            page.dispatch_event("#view-slider", "input")
            infeasible = drawn(page)
            page.locator("#mechanism-view").screenshot(path=str(tmp_path / "view.png"))
        finally:
            chromium.close()
    assert not problems
    assert before["angle"] == "input angle 0.0 deg, position 1 of 36"
    assert after["angle"] == "input angle 80.0 deg, position 9 of 36"
    assert keyed["angle"] == "input angle 90.0 deg, position 10 of 36"
    assert after["d"] != before["d"] and after["fill"] != before["fill"] and after["a"] != before["a"]
    # What is drawn is the frame's data: the joint where the kinematics put it, the outline placed by
    # the pose, the colour of the link's von Mises on the sweep's one scale.
    for k, shown in ((0, before), (8, after)):
        assert np.allclose(shown["a"], joints["A"].position[k], atol=rounding)
        coupler = data["links"]["coupler"]
        assert np.allclose(first_point(shown["d"]), placed(coupler["rings"][0][:1], coupler["pose"][k])[0], atol=rounding)
        assert float(shown["vm"]) == coupler["von_mises_mpa"][k]
        assert shown["fill"] == stress_colour(coupler["von_mises_mpa"][k], data["stress_scale"])
    assert infeasible["angle"].startswith("input angle 180.0 deg, position 19 of 36 \u2014 infeasible: ")
    assert infeasible["visible"] == "hidden"


def test_with_peaks_each_link_is_coloured_by_its_fea_peak_at_each_position_and_the_view_says_so(tmp_path):
    # The seed's 12 positions with --peaks: every link's colour is its superposed FEA peak at that
    # position (at a pin hole, several times the beam's largest section value), the dot where it is.
    from linkstress.analysis import plan_for
    from linkstress.report.mechanism_view import BEAM, FEA_PEAK

    scene = load_scene(seed_sweep(tmp_path, "{start = 0.0, stop = 330.0, num = 12}"))
    result = run_analysis(scene, plan_for(scene).with_peaks())
    data = view_data(result)
    ok = result.feasible
    for name in ("crank", "coupler", "output"):
        link, peaks = data["links"][name], result.peaks[name]
        assert link["stress_label"] == FEA_PEAK
        shown = np.array([v if v is not None else np.nan for v in link["von_mises_mpa"]])
        # to four digits of the sweep's largest, as every value of the view
        np.testing.assert_allclose(shown[ok], peaks.peak[ok] / 1e6, rtol=0, atol=0.5 * 10.0 ** -data["stress_scale"]["decimals"])
        assert (shown[ok] > 1.5 * result.stresses[name].max_von_mises[ok] / 1e6).all()
        at = np.array([p for p in link["max_at_m"] if p is not None])
        np.testing.assert_allclose(at, result.to_ground(name, peaks.peak_at[ok], np.flatnonzero(ok)), atol=1e-4)
    assert data["stress_scale"]["label"] == FEA_PEAK
    assert data["stress_scale"]["max_mpa"] == pytest.approx(max(p.peak_max for p in result.peaks.values()) / 1e6, rel=1e-3)
    text = view_html(result)
    assert "Links filled by their FEA peak von Mises (anywhere in the link, pin holes included" in text
    beam_only = view_data(run_analysis(scene, plan_for(scene)))
    assert {link["stress_label"] for link in beam_only["links"].values() if "stress_label" in link} == {BEAM}
