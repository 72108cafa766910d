"""``linkstress analyze``: the JSON contract, the table, and exit code 2 for bad scenes."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from linkstress.cli import main

REPO = Path(__file__).resolve().parents[1]

SEED = """
[links.crank]
joints = [[0.0, 0.0], [1.0, 0.0]]
mass = 471.0
inertia = 66.33
center_of_mass = [0.5, 0.0]

[links.coupler]
joints = [[0.0, 0.0], [1.5, 0.0]]
mass = 667.25
inertia = 171.6
center_of_mass = [0.75, 0.0]

[links.output]
joints = [[0.0, 0.0], [1.5, 0.0]]

[links.ground]
joints = [[0.0, 0.0], [2.0, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = [60.0, 180.0]
input_speed_rad_s = -1.0
"""


def scene_file(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(text))
    return path


def read_json(path: Path) -> dict:
    def refuse(constant):
        raise AssertionError(f"{constant} in JSON")

    return json.loads(path.read_text(), parse_constant=refuse)


def test_json_has_the_design_shape_and_the_seeds_values(tmp_path, capsys):
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene_file(tmp_path, SEED)), "--json", str(out), "--details"]) == 0
    data = read_json(out)
    first, second = data["positions"]
    assert set(first) == {"input_angle_deg", "feasible", "reason", "links", "transmission_angle_deg"}
    assert 0 < first["transmission_angle_deg"]["main"] <= 90
    assert (first["input_angle_deg"], first["feasible"], first["reason"]) == (60.0, True, "")
    assert set(first["links"]) == {"crank", "coupler", "output", "ground"}
    coupler = first["links"]["coupler"]
    assert set(coupler) == {"angle_deg", "omega_rad_s", "alpha_rad_s2", "acc_G_m_s2"}
    # The seed's published kinematics (docs/reference/seed-ansys-fourbar.md), 3 decimals.
    assert coupler["acc_G_m_s2"] == pytest.approx([-0.758, -0.605], abs=5e-4)
    assert coupler["alpha_rad_s2"] == pytest.approx(0.459, abs=5e-4)
    assert first["links"]["output"]["alpha_rad_s2"] == pytest.approx(0.695, abs=5e-4)
    assert first["links"]["crank"]["angle_deg"] == pytest.approx(60.0, abs=1e-12)
    # No centre of mass known for the output (bare joints, no mass) nor the ground.
    assert "acc_G_m_s2" not in first["links"]["output"] and "acc_G_m_s2" not in first["links"]["ground"]
    # 1 + 2 = 1.5 + 1.5: the seed's four-bar is a change-point linkage, flat at 180 deg.
    assert second["feasible"] is False and second["links"] == {}
    assert second["reason"].startswith("change point")
    text = capsys.readouterr().out
    assert "change-point, Barker III-2 SCRR" in text
    assert re.search(r"60\s+coupler\s+24\.7356\s+0\.408248\s+0\.459499\s+-0\.757733\s+-0\.605325", text)
    assert "180 deg: change point" in text
    assert not list(tmp_path.glob(".out.json.*"))  # the temporary file was renamed


def test_a_sweep_through_unreachable_angles_reports_them_and_never_writes_nan(tmp_path):
    text = SEED.replace("[[0.0, 0.0], [2.0, 0.0]]", "[[0.0, 0.0], [2.9, 0.0]]").replace(
        "input_angle_deg = [60.0, 180.0]", "input_angle_deg = {start = 0.0, stop = 359.0, num = 360}"
    )
    out = tmp_path / "sweep.json"
    out.write_text("old contents")
    assert main(["analyze", str(scene_file(tmp_path, text)), "--json", str(out)]) == 0
    positions = read_json(out)["positions"]
    assert len(positions) == 360
    infeasible = [p for p in positions if not p["feasible"]]
    assert infeasible and len(infeasible) < 360
    assert all(p["links"] == {} and p["reason"].startswith(("unreachable", "toggle")) for p in infeasible)
    values = [v for p in positions for link in p["links"].values() for v in link.values()]
    flat = [x for v in values for x in (v if isinstance(v, list) else [v])]
    assert all(math.isfinite(x) for x in flat)
    assert all(0.0 <= p["links"]["output"]["angle_deg"] < 360.0 for p in positions if p["feasible"])


def test_an_analysis_table_without_kinematics_leaves_the_link_data_out(tmp_path):
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene_file(tmp_path, SEED + "\n[analysis]\nstations = 11\n")), "--json", str(out)]) == 0
    assert [p["links"] for p in read_json(out)["positions"]] == [{}, {}]


def test_a_slider_crank_driven_by_a_function_of_time_reports_its_stroke_and_rates(tmp_path, capsys):
    out = tmp_path / "engine.json"
    path = scene_file(tmp_path, """
        [links.crank]
        joints = [[0.0, 0.0], [0.05, 0.0]]
        [links.rod]
        joints = [[0.0, 0.0], [0.2, 0.0]]
        [links.piston]
        joints = [[0.0, 0.0]]
        mass = 0.5
        inertia = 0.0
        center_of_mass = [0.0, 0.0]
        [links.block]
        joints = [[0.0, 0.0], [1.0, 0.0]]
        [mechanisms.engine]
        type = "slider-crank"
        crank = "crank"
        coupler = "rod"
        ground = "block"
        slider = "piston"
        [motion]
        input_angle_deg = {expression = "360*t", t = {start = 0.0, stop = 0.5, num = 3}}
    """)
    assert main(["analyze", str(path), "--json", str(out)]) == 0
    assert "stroke 0.1 m" in capsys.readouterr().out
    positions = read_json(out)["positions"]
    assert [p["input_angle_deg"] for p in positions] == [0.0, 90.0, 180.0]
    crank = positions[0]["links"]["crank"]
    assert crank["omega_rad_s"] == pytest.approx(2 * math.pi) and crank["alpha_rad_s2"] == 0.0
    # Top dead centre at 0 deg: the piston stops; its acceleration is -a w^2 (1 + a / b) along x.
    piston = positions[0]["links"]["piston"]
    assert piston["acc_G_m_s2"] == pytest.approx([-0.05 * (2 * math.pi) ** 2 * 1.25, 0.0], abs=1e-12)


BAD_SCENES = [
    (SEED.replace("mass = 471.0", "mas = 471.0"), "links.crank.mas: unknown key; allowed keys are: sketch,"),
    (SEED.replace('coupler = "coupler"', 'coupler = "couple"'), "mechanisms.main.coupler: no link named 'couple'"),
    (SEED.replace("joints = [[0.0, 0.0], [1.0, 0.0]]", "joints = [[0.0, 0.0]]"),
     "mechanisms.main.crank: link 'crank' has 1 joint(s); a crank needs two"),
    (SEED.replace("[[0.0, 0.0], [2.0, 0.0]]", "[[0.0, 0.0], [20.0, 0.0]]"),
     "mechanisms.main: these lengths can never assemble"),
]


@pytest.mark.parametrize("text, message", BAD_SCENES)
def test_a_bad_scene_exits_2_with_the_key_and_what_to_do(tmp_path, capsys, text, message):
    assert main(["analyze", str(scene_file(tmp_path, text))]) == 2
    err = capsys.readouterr().err
    assert err.startswith("linkstress: error: scene.toml: ")
    assert message in err


def test_the_console_exits_2_without_a_traceback(tmp_path):
    path = scene_file(tmp_path, BAD_SCENES[0][0])
    result = subprocess.run([sys.executable, "-m", "linkstress", "analyze", str(path)], capture_output=True, text=True)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert result.stderr.count("\n") == 1 and BAD_SCENES[0][1] in result.stderr


def test_json_into_a_missing_folder_exits_2_before_any_work(tmp_path, capsys):
    path = scene_file(tmp_path, SEED)
    assert main(["analyze", str(path), "--json", str(tmp_path / "no" / "out.json")]) == 2
    assert "--json: folder" in capsys.readouterr().err


def nortons_scene() -> str:
    """The Norton example of docs/scenes.md."""
    text = (REPO / "docs" / "scenes.md").read_text()
    section = text.split("## Example: Norton's four-bar", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```toml\n(.+?)\n```", section, re.S)[0]


def test_the_norton_example_scene_runs_as_documented(tmp_path, capsys):
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene_file(tmp_path, nortons_scene())), "--json", str(out)]) == 0
    first = read_json(out)["positions"][0]
    # Norton's problem 4-1 g, open branch: theta4 = 7.23605 deg, omega4 = 146.870417 rad/s.
    assert first["input_angle_deg"] == 25.0
    assert first["links"]["output"]["angle_deg"] == pytest.approx(7.23605, abs=5e-6)
    assert first["links"]["output"]["omega_rad_s"] == pytest.approx(146.870417, abs=5e-7)
    assert "Grashof" in capsys.readouterr().out
