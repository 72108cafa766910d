"""Everything downstream of the kinematics works on a linkage drawn assembled in a DXF: section
stresses and pin-hole estimates, the HTML report with its mechanism view, validate, FEA peaks with
fatigue, and regress on a case folder."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from ezdxf.math import Matrix44

from linkstress.analysis import run_analysis
from linkstress.kinematics.linkage.examples import circles
from linkstress.scene import load_scene

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "validation" / "cases"))
from drawing import new_drawing, save, straight_link  # noqa: E402


def six_bar_pose() -> dict[str, np.ndarray]:
    """A crank-rocker whose rocker, extended 50 mm past B, drives a second rocker through a link
    [mm]: O2 (0, 0), O4 (100, 0), O6 (230, 40); crank 40 at 30 deg, coupler 120, rocker 100, link
    180, second rocker 90 (|C - O6| stays within 136 to 243 mm: it closes over the turn)."""
    o2, o4, o6 = np.zeros(2), np.array([100.0, 0.0]), np.array([230.0, 40.0])
    a = 40.0 * np.array([math.cos(math.radians(30.0)), math.sin(math.radians(30.0))])
    b = circles(a, 120.0, o4, 100.0, lambda p, q: p if p[1] > q[1] else q)
    c = o4 + (b - o4) * 1.5
    d = circles(c, 180.0, o6, 90.0, lambda p, q: p if p[1] > q[1] else q)
    return {"O2": o2, "O4": o4, "O6": o6, "A": a, "B": b, "C": c, "D": d}


def draw(path: Path) -> dict[str, list[np.ndarray]]:
    """Each link drawn along +x from the origin, then turned and moved into place (its layer)."""
    p = six_bar_pose()
    links = {"crank": [p["O2"], p["A"]], "coupler": [p["A"], p["B"]], "rocker": [p["O4"], p["B"], p["C"]],
             "link2": [p["C"], p["D"]], "out2": [p["O6"], p["D"]]}
    doc = new_drawing(units=4)
    msp = doc.modelspace()
    for layer, joints in links.items():
        doc.layers.add(layer)
        start, end = joints[0], joints[-1]
        angle = math.atan2(*(end - start)[::-1])
        along = [(float(np.hypot(*(j - start))), 0.0) for j in joints]
        before = len(msp)
        straight_link(msp, layer, along, 16.0, 6.0)
        move = Matrix44.chain(Matrix44.z_rotate(angle), Matrix44.translate(start[0], start[1], 0.0))
        for entity in list(msp)[before:]:
            entity.transform(move)
    save(doc, path)
    return links


SCENE = """title = "Six-bar drawn assembled"
[materials.steel]
density = 7850.0
youngs_modulus = 200e9
poisson_ratio = 0.3
yield_strength = 250e6
endurance_limit = 200e6
ultimate_strength = 400e6
{links}
[links.ground]
joints = [[0.0, 0.0], [0.1, 0.0], [0.23, 0.04]]

[mechanisms.six]
type = "linkage"
ground = "ground"
input = {{link = "crank", pivot = 0, to = 1}}
pins = [["ground:0", "crank:0"], ["crank:1", "coupler:0"], ["coupler:1", "rocker:1"], ["ground:1", "rocker:0"],
        ["rocker:2", "link2:0"], ["link2:1", "out2:1"], ["ground:2", "out2:0"]]

[motion]
input_angle_deg = {{start = 0.0, stop = 330.0, num = 12}}
input_speed_rad_s = 30.0

[loads]
gravity_m_s2 = [0.0, -9.81]
[loads.couples]
out2 = 0.5
{analysis}"""


def case(folder: Path, analysis: str = "") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    links = draw(folder / "six.dxf")
    tables = "".join(f'[links.{name}]\nsketch = "six.dxf"\nlayer = "{name}"\nthickness = 0.006\nmaterial = "steel"\n'
                     for name in links)
    path = folder / "scene.toml"
    path.write_text(SCENE.format(links=tables, analysis=analysis))
    return path


def test_a_sketched_linkage_gets_section_stresses_and_pin_hole_estimates(tmp_path):
    """The sketch's joints (sorted by x, then y) are the links' joints in place; the rocker's are
    O4, B, C along x. Every moving link gets section stresses in equilibrium and a Kt estimate
    at its pin holes; the power balance holds with the profiles' mass data."""
    scene = load_scene(case(tmp_path / "six"))
    assert [g.kind for g in scene.linkage.groups] == ["crank", "RRR", "RRR"]
    result = run_analysis(scene)
    assert result.feasible.all()
    assert set(result.stresses) == {"crank", "coupler", "rocker", "link2", "out2"}
    for name, stress in result.stresses.items():
        assert np.all(stress.max_von_mises > 0) and stress.mismatch.max() < 1e-6, name
        assert stress.pin_holes, name
    from linkstress.dynamics.linkage_forces import power_balance

    power_in, power_out = power_balance(scene, result.kinematics, result.forces)
    assert np.abs(power_in - power_out).max() <= 1e-9 * np.abs(power_in).max()


def test_html_report_of_a_linkage_lists_pins_and_draws_the_view(tmp_path):
    path = case(tmp_path / "six")
    out = tmp_path / "report.html"
    done = subprocess.run([sys.executable, "-m", "linkstress", "analyze", str(path), "--html", str(out), "--details"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "mechanism six: linkage of 6 links" in done.stdout
    assert "pin coupler:1-rocker:1" in done.stdout and "coupler on rocker at coupler:1" in done.stdout
    assert "T crank [N m]" in done.stdout
    page = out.read_text()
    assert "pin rocker:2-link2:0" in page and "view-data" in page and "Gruebler" in page


@pytest.mark.slow
def test_validate_peaks_and_regress_run_on_a_linkage(tmp_path):
    """validate compares the coupler with plane-stress FEA (one mesh, two positions) and passes;
    analyze --peaks gives its FEA peak and a fatigue factor; regress stores and then reproduces
    the case."""
    path = case(tmp_path / "cases" / "six", '\n[analysis]\nvalidate = ["coupler"]\npeaks = true\n')
    out = tmp_path / "validate.json"
    done = subprocess.run([sys.executable, "-m", "linkstress", "validate", str(path), "--positions", "2",
                           "--mesh-levels", "1", "--json", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    assert json.loads(out.read_text())["links"]["coupler"]["resultant_error_pct"] < 1.0
    peaks = tmp_path / "peaks.json"
    done = subprocess.run([sys.executable, "-m", "linkstress", "analyze", str(path), "--json", str(peaks)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    table = json.loads(peaks.read_text())["links"]["coupler"]
    assert table["peak_max_von_mises_pa"] > 0 and "fatigue_safety_factor" in table
    for flags in (["--update"], []):
        done = subprocess.run([sys.executable, "-m", "linkstress", "regress", str(tmp_path / "cases"), *flags],
                              capture_output=True, text=True)
        assert done.returncode == 0, done.stdout + done.stderr
