"""Hostile scenes, flags and output paths: one ``linkstress: error:`` line naming the key, flag or file
and what to do, exit 2, no traceback, no nan or inf printed, no output file, in bounded time.

Every input is generated here: bare-joint four-bars (fast), and bars drawn with ezdxf for the links
the FEA needs. The four-bar: crank 0.1 m, coupler 0.3 m, output 0.25 m, ground 0.3 m (Grashof).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import textwrap
import time
import tomllib
from pathlib import Path

import ezdxf
import pytest

from linkstress.analysis import plan_for
from linkstress.cli import main
from linkstress.commands.analyze import MEMORY_LIMIT, memory_estimate
from linkstress.inputs import SCENE_BYTES, SKETCH_BYTES, InputFileError, read_bounded
from linkstress import executors
from linkstress.messages import capped
from linkstress.scene import load_scene

REPO = Path(__file__).resolve().parents[1]
BARS = {"crank": 0.1, "coupler": 0.3, "output": 0.25}

BARE = """
[links.crank]
joints = [[0.0, 0.0], [0.1, 0.0]]
mass = 0.5
inertia = 0.001
center_of_mass = [0.05, 0.0]

[links.coupler]
joints = [[0.0, 0.0], [0.3, 0.0]]
mass = 1.0
inertia = 0.01
center_of_mass = [0.15, 0.0]

[links.output]
joints = [[0.0, 0.0], [0.25, 0.0]]
mass = 0.8
inertia = 0.005
center_of_mass = [0.125, 0.0]

[links.ground]
joints = [[0.0, 0.0], [0.3, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = [30.0, 120.0]
input_speed_rad_s = 10.0
"""

DRAWN = """
[materials.steel]
density = 7850.0
youngs_modulus = 200e9
poisson_ratio = 0.3

[links.crank]
sketch = "bars.dxf"
layer = "crank"
thickness = 0.01
material = "steel"

[links.coupler]
sketch = "bars.dxf"
layer = "coupler"
thickness = 0.01
material = "steel"

[links.output]
sketch = "bars.dxf"
layer = "output"
thickness = 0.01
material = "steel"

[links.ground]
joints = [[0.0, 0.0], [0.3, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = [30.0, 120.0]
input_speed_rad_s = 10.0
"""


def draw_bars(path: Path, height: float = 0.04, overhang: float = 0.03, hole: float = 0.01) -> Path:
    """Straight bars (metres, one layer each) with a pin hole and a joint point at each end."""
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    for k, (name, length) in enumerate(BARS.items()):
        y, h = 0.5 * k, height / 2
        corners = [(-overhang, y - h), (length + overhang, y - h), (length + overhang, y + h), (-overhang, y + h)]
        msp.add_lwpolyline(corners, close=True, dxfattribs={"layer": name})
        for x in (0.0, length):
            msp.add_circle((x, y), hole / 2, dxfattribs={"layer": name})
            msp.add_point((x, y), dxfattribs={"layer": name})
    doc.saveas(path)
    return path


def write_scene(folder: Path, text: str, name: str = "scene.toml") -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(text))
    if "bars.dxf" in text and not (folder / "bars.dxf").exists():
        draw_bars(folder / "bars.dxf")
    return path


def edited(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def refused(capsys, argv: list[str], *expected: str, seconds: float = 30.0) -> str:
    """Run ``linkstress argv`` in this process: exit 2, one error line holding every ``expected``
    text, nothing but that on stderr, no nan or inf on stdout, within ``seconds``."""
    start = time.perf_counter()
    code = main(argv)
    elapsed = time.perf_counter() - start
    out, err = capsys.readouterr()
    assert code == 2, (code, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkstress: error: "), err
    for text in expected:
        assert text in lines[0], (text, lines[0])
    assert not re.search(r"\b(nan|inf)\b", out, re.IGNORECASE), out
    assert elapsed < seconds, elapsed
    return lines[0]


def run_cli(*args: str, cwd: Path, limit_file_bytes: int | None = None) -> subprocess.CompletedProcess:
    """``python -m linkstress args`` in a subprocess (to see its stderr and warnings whole), optionally
    under a file-size limit (RLIMIT_FSIZE) as a full disk or a quota would impose."""
    code = "import runpy, sys\n"
    if limit_file_bytes is not None:
        code += f"import resource\nresource.setrlimit(resource.RLIMIT_FSIZE, ({limit_file_bytes}, {limit_file_bytes}))\n"
    code += "sys.argv = ['linkstress', *sys.argv[1:]]\nrunpy.run_module('linkstress', run_name='__main__')\n"
    # no bytecode written: under the file-size limit a .pyc write could end the process before linkstress runs
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"}
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, cwd=cwd, timeout=120, env=env)


def assert_one_error(result: subprocess.CompletedProcess, *expected: str) -> None:
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr and "Warning" not in result.stderr, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkstress: error: "), result.stderr
    for text in expected:
        assert text in lines[0], (text, lines[0])


# --- physical quantities out of any sane range are refused by key -------------------------------

@pytest.mark.parametrize(
    ("old", "new", "key", "limit"),
    [
        ("input_speed_rad_s = 10.0", "input_speed_rad_s = 1e200", "motion.input_speed_rad_s", "at most 100000 rad/s"),
        ("input_speed_rad_s = 10.0", "input_speed_rad_s = 10.0\ninput_acceleration_rad_s2 = -1e300",
         "motion.input_acceleration_rad_s2", "at most 1e+09 rad/s^2"),
        ("mass = 0.5", "mass = 1e300", "links.crank.mass", "at most 1e+09 kg"),
        ("mass = 0.5", "mass = 1e-300", "links.crank.mass", "at least 1e-09 kg"),
        ("inertia = 0.001", "inertia = 1e300", "links.crank.inertia", "at most 1e+09 kg m^2"),
        ("center_of_mass = [0.05, 0.0]", "center_of_mass = [0.05, 1e300]", "links.crank.center_of_mass[1]", "at most 1000 m"),
        ("joints = [[0.0, 0.0], [0.1, 0.0]]", "joints = [[0.0, 0.0], [1e300, 0.0]]", "links.crank.joints[1]", "at most 1000 m"),
        ("joints = [[0.0, 0.0], [0.1, 0.0]]", "joints = [[0.0, 0.0], [0.1, 0.0]]\nthickness = 1e-300",
         "links.crank.thickness", "at least 1e-06 m"),
        ("input_angle_deg = [30.0, 120.0]", "input_angle_deg = [30.0, 1e300]", "motion.input_angle_deg[1]", "at most 1e+07 deg"),
        ("input_speed_rad_s = 10.0", "input_speed_rad_s = 10.0\n[loads]\ngravity_m_s2 = [0, 1e300]",
         "loads.gravity_m_s2[1]", "at most 1e+06 m/s^2"),
        ("input_speed_rad_s = 10.0", "input_speed_rad_s = 10.0\n[loads.couples]\noutput = -1e300",
         "loads.couples.output", "at most 1e+12 N m"),
        ("input_speed_rad_s = 10.0",
         "input_speed_rad_s = 10.0\n[[loads.forces]]\nlink = \"coupler\"\nat_m = [0.1, 0.0]\nforce_n = [1e300, 0.0]",
         "loads.forces[0].force_n[0]", "at most 1e+12 N"),
        ("[links.crank]", "[materials.steel]\ndensity = 1e300\n\n[links.crank]", "materials.steel.density", "at most 100000 kg/m^3"),
        ("[links.crank]", "[materials.steel]\ndensity = 7850.0\nyoungs_modulus = 1e300\n\n[links.crank]",
         "materials.steel.youngs_modulus", "at most 1e+13 Pa"),
    ],
    ids=lambda v: v if isinstance(v, str) and "." in v and " " not in v else None,
)
def test_a_physical_quantity_outside_its_stated_range_is_refused_naming_the_key(tmp_path, capsys, old, new, key, limit):
    scene = write_scene(tmp_path, edited(BARE, old, new))
    refused(capsys, ["analyze", str(scene), "--json", str(tmp_path / "out.json")], f"scene.toml: {key}: must be {limit}",
            "check the unit")
    assert not (tmp_path / "out.json").exists()


def test_the_ranges_still_take_a_real_machine(tmp_path, capsys):
    # 2,000 rpm, a 5 kN m couple, 1 g: well inside every range
    text = edited(BARE, "input_speed_rad_s = 10.0", "input_speed_rad_s = 209.4\n[loads]\ngravity_m_s2 = [0.0, -9.81]\n"
                  "[loads.couples]\noutput = 5000.0")
    assert main(["analyze", str(write_scene(tmp_path, text))]) == 0


def test_sections_refuses_a_bar_of_1e300_metres(capsys):
    refused(capsys, ["sections", "--bar", "1e300", "0.5", "0.1", "0.1"], "--bar SPACING: must be at most 1000 m")


def test_sections_refuses_a_density_of_1e300(capsys):
    refused(capsys, ["sections", "--bar", "1", "0.5", "0.1", "0.1", "--density", "1e300"], "--density: must be at most 100000 kg/m^3")


def test_a_huge_motion_expression_is_one_error_naming_its_key_and_no_numpy_warning(tmp_path):
    # 1e200 deg/s: held to the ranges of plain values, it stops before anything squares it
    text = edited(BARE, "input_angle_deg = [30.0, 120.0]\ninput_speed_rad_s = 10.0",
                  'input_angle_deg = {expression = "1e200*t", t = [0.0, 0.5]}')
    write_scene(tmp_path, text)
    result = run_cli("analyze", "scene.toml", "--json", "out.json", cwd=tmp_path)
    assert_one_error(result, "scene.toml: motion.input_angle_deg.expression: '1e200*t' gives", "check the unit")
    assert not re.search(r"\b(nan|inf)\b", result.stdout, re.IGNORECASE)
    assert not (tmp_path / "out.json").exists()


@pytest.mark.parametrize(
    ("expression", "times", "message"),
    [
        # theta = 1e17 t deg: 1e17 deg at t = 1 s, past the 1e7 deg of a plain input_angle_deg
        ("1e17*t", "[0.0, 1.0]", "gives an input angle of 1e+17 deg at t = 1 s, more than the 1e+07 deg"),
        # theta = 1e8 t deg: dtheta/dt = 1e8 deg/s = 1e8 pi / 180 = 1.74533e6 rad/s, past 1e5 rad/s
        ("1e8*t", "[0.0, 0.05]", "gives an input speed (its time derivative) of 1.74533e+06 rad/s at t = 0 s, more than "
         "the 100000 rad/s"),
        # theta = cos(1e6 t) deg: d2theta/dt2 = -1e12 cos(1e6 t) deg/s^2 = -1.74533e10 rad/s^2 at t = 0
        ("cos(1e6*t)", "[0.0]", "gives an input acceleration (its second time derivative) of -1.74533e+10 rad/s^2 at "
         "t = 0 s, more than the 1e+09 rad/s^2"),
    ],
)
def test_a_motion_expression_is_held_to_the_ranges_of_plain_values(tmp_path, capsys, expression, times, message):
    text = edited(BARE, "input_angle_deg = [30.0, 120.0]\ninput_speed_rad_s = 10.0",
                  f'input_angle_deg = {{expression = "{expression}", t = {times}}}')
    refused(capsys, ["analyze", str(write_scene(tmp_path, text))],
            f"scene.toml: motion.input_angle_deg.expression: {expression!r} {message}")


@pytest.mark.parametrize(
    ("expression", "passes"),
    [
        # 1e7 deg, the largest plain angle, and just past it
        ("1e7 + 0*t", True), ("1.0000001e7 + 0*t", False),
        # 1e5 rad/s = 1e5 x 180 / pi = 5,729,577.95 deg/s
        ("5729577.9*t", True), ("5729578.0*t", False),
    ],
)
def test_an_expression_on_the_bound_of_a_range_runs(tmp_path, capsys, expression, passes):
    text = edited(BARE, "input_angle_deg = [30.0, 120.0]\ninput_speed_rad_s = 10.0",
                  f'input_angle_deg = {{expression = "{expression}", t = [0.0, 0.001]}}')
    code = main(["analyze", str(write_scene(tmp_path, text))])
    assert code == (0 if passes else 2), capsys.readouterr().err


def test_a_long_expression_is_quoted_cut_in_its_message(tmp_path, capsys):
    expression = "t + " + "abc" * 300
    text = edited(BARE, "input_angle_deg = [30.0, 120.0]\ninput_speed_rad_s = 10.0",
                  f'input_angle_deg = {{expression = "{expression}", t = [0.0, 1.0]}}')
    line = refused(capsys, ["analyze", str(write_scene(tmp_path, text))], "'abcabc", "...", "' in 't + abcabc")
    assert len(line) < 400


# --- work beyond a stated limit is refused before it is done ------------------------------------

def test_sections_refuses_a_hundred_million_stations(capsys):
    refused(capsys, ["sections", "--bar", "1", "0.5", "0.1", "0.1", "--stations", "100000000"],
            "--stations: must be at most 100000", seconds=5)


@pytest.mark.parametrize(("value", "message"), [
    ("1000000000", "analysis.stations: must be <= 100000, got 1000000000"),
    ("1e9", "analysis.stations: must be a whole number, got 1000000000.0"),
])
def test_analysis_stations_beyond_the_limit_are_refused(tmp_path, capsys, value, message):
    scene = write_scene(tmp_path, DRAWN + f"\n[analysis]\nstresses = true\nstations = {value}\n")
    refused(capsys, ["analyze", str(scene)], message, seconds=10)


def test_a_sweep_longer_than_the_schema_allows_is_refused(tmp_path, capsys):
    text = edited(BARE, "input_angle_deg = [30.0, 120.0]", "input_angle_deg = {start = 0.0, stop = 360.0, num = 10000001}")
    refused(capsys, ["analyze", str(write_scene(tmp_path, text))], "motion.input_angle_deg.num: must be <= 10000000", seconds=10)


def test_ten_million_positions_of_joint_forces_are_refused_stating_the_memory_limit(tmp_path, capsys):
    # 10^7 positions x 4 links x (110 + 230) B = 13.6 GB of arrays against the 6 GB limit
    text = edited(BARE, "input_angle_deg = [30.0, 120.0]", "input_angle_deg = {start = 0.0, stop = 360.0, num = 10000000}")
    refused(capsys, ["analyze", str(write_scene(tmp_path, text))],
            "10000000 positions of 4 links need about 13.6 GB of memory, more than the 6 GB limit", seconds=20)


def test_ten_million_positions_of_kinematics_alone_still_fit(tmp_path):
    # the schema's 10^7 positions stay usable: 10^7 x 4 links x 110 B = 4.4 GB < 6 GB
    text = edited(BARE, "input_angle_deg = [30.0, 120.0]", "input_angle_deg = {start = 0.0, stop = 360.0, num = 10000000}")
    scene = load_scene(write_scene(tmp_path, text + "\n[analysis]\nkinematics = true\n"))
    assert memory_estimate(scene, plan_for(scene)) == pytest.approx(4.4e9)
    assert memory_estimate(scene, plan_for(scene)) < MEMORY_LIMIT


def test_a_million_seed_positions_with_stresses_fit_as_json_too(tmp_path):
    # The JSON is streamed a block of positions at a time, so the estimate does not depend on it:
    # 10^6 x (4 links x (110 + 230) B + 3 stressed links x 60 B) = 1.54 GB, under the 6 GB limit
    # (measured: 1.36 GB peak with --json, validation/bench/memory.py).
    seed = REPO / "validation" / "cases" / "seed_ansys_fourbar"
    shutil.copy(seed / "ansys_four_bars.dxf", tmp_path)
    text = (seed / "scene.toml").read_text().replace(
        "input_angle_deg = 60.0", "input_angle_deg = {start = 0.0, stop = 360.0, num = 1000000}")
    scene = load_scene(write_scene(tmp_path, text))
    assert memory_estimate(scene, plan_for(scene)) == pytest.approx(1.54e9)
    assert memory_estimate(scene, plan_for(scene)) < MEMORY_LIMIT


@pytest.mark.parametrize(("flags", "message"), [
    (["--mesh-size", "1e-7"], "would need about 1.4e+12 elements of 1e-07 m on its finest mesh, more than the 1e+06"),
    (["--mesh-size", "inf"], "--mesh-size: must be a finite size > 0 m, got inf"),
    (["--mesh-size", "nan"], "--mesh-size: must be a finite size > 0 m, got nan"),
    (["--mesh-size", "1.0"], "1 m is larger than the depth of link 'crank', 0.04 m"),
    (["--positions", "1000000000000"], "--positions: must be 1 to 3600"),
    (["--positions", "0"], "--positions: must be 1 to 3600"),
    (["--mesh-levels", "1000"], "--mesh-levels: use 1 (one mesh) or 3 to 6"),
    (["--jobs", "100000"], "--jobs: must be 1 to"),
    (["--jobs", "0"], "--jobs: must be 1 to"),
])
def test_validate_refuses_work_beyond_its_stated_limits_before_meshing(tmp_path, capsys, flags, message):
    # the crank bar: 0.16 m x 0.04 m less two 10 mm holes = 6.24e-3 m^2; an equilateral triangle of
    # side 1e-7 m covers 4.33e-15 m^2: about 1.4e12 elements, refused before gmsh starts
    scene = write_scene(tmp_path, DRAWN)
    refused(capsys, ["validate", str(scene), "--mesh-levels", "1", *flags, "--json", str(tmp_path / "v.json")], message,
            seconds=20)
    assert not (tmp_path / "v.json").exists()


def test_validate_refuses_a_mesh_size_in_the_scene_beyond_the_limit(tmp_path, capsys):
    scene = write_scene(tmp_path, DRAWN + "\n[analysis]\nvalidate = [\"crank\"]\nmesh_size_m = 1e-6\n")
    refused(capsys, ["validate", str(scene), "--mesh-levels", "1"], "link 'crank'", "more than the 1e+06", seconds=20)


def test_regress_refuses_a_hundred_thousand_jobs(capsys):
    refused(capsys, ["regress", "--jobs", "100000"], "--jobs: must be 1 to", seconds=5)


# --- validate: bad input is exit 2, not a failed check ------------------------------------------

def test_validate_without_youngs_modulus_is_bad_input_not_a_failed_check(tmp_path, capsys):
    scene = write_scene(tmp_path, edited(DRAWN, "youngs_modulus = 200e9\n", ""))
    line = refused(capsys, ["validate", str(scene), "--mesh-levels", "1"],
                   "materials.steel.youngs_modulus: missing; the FEA of link 'crank' needs it")
    assert "FAILED" not in line


# --- output paths -------------------------------------------------------------------------------

@pytest.mark.parametrize("command", ["analyze", "validate"])
@pytest.mark.parametrize("flag", ["--json", "--html"])
def test_an_output_path_that_is_a_folder_is_refused_before_any_work(tmp_path, capsys, command, flag):
    scene = write_scene(tmp_path, DRAWN)
    (tmp_path / "out").mkdir()
    refused(capsys, [command, str(scene), flag, str(tmp_path / "out")], f"{flag}: ", "is a folder; give a file name")
    assert list((tmp_path / "out").iterdir()) == []


def test_an_import_plot_path_that_is_a_folder_is_refused(tmp_path, capsys):
    draw_bars(tmp_path / "bars.dxf")
    (tmp_path / "plot").mkdir()
    refused(capsys, ["import", str(tmp_path / "bars.dxf"), "--plot", str(tmp_path / "plot")], "--plot: ", "is a folder")


def test_a_json_pointing_at_the_scene_is_refused_and_the_scene_kept(tmp_path, capsys):
    scene = write_scene(tmp_path, BARE)
    refused(capsys, ["analyze", str(scene), "--json", str(scene)], "--json: ", "is an input", "would overwrite it")
    assert tomllib.loads(scene.read_text())["motion"]["input_speed_rad_s"] == 10.0


def test_a_json_pointing_at_the_scene_s_sketch_is_refused_and_the_sketch_kept(tmp_path, capsys):
    scene = write_scene(tmp_path, DRAWN)
    sketch = tmp_path / "bars.dxf"
    before = sketch.read_bytes()
    refused(capsys, ["analyze", str(scene), "--json", str(sketch)], "--json: ", "bars.dxf", "would overwrite it")
    assert sketch.read_bytes() == before


def test_json_and_html_on_the_same_file_are_refused_before_any_work(tmp_path, capsys):
    scene = write_scene(tmp_path, BARE)
    same = str(tmp_path / "report.out")
    refused(capsys, ["analyze", str(scene), "--json", same, "--html", same], "--json and --html name the same file", seconds=5)
    assert not Path(same).exists()


def test_a_write_beyond_the_file_size_limit_is_one_error_and_leaves_no_file(tmp_path):
    # 20 kB lets the JSON through (about 3 kB) but not the HTML (its figures): neither may be left
    write_scene(tmp_path, BARE)
    result = run_cli("analyze", "scene.toml", "--json", "out.json", "--html", "out.html", cwd=tmp_path,
                     limit_file_bytes=20_000)
    assert_one_error(result, "cannot write 'out.html'", "File too large", "nothing written")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]


# --- scene files --------------------------------------------------------------------------------

def test_a_sketch_path_of_5000_characters_is_one_error_naming_the_key(tmp_path, capsys):
    scene = write_scene(tmp_path, edited(DRAWN, 'sketch = "bars.dxf"', f'sketch = "{"a" * 5000}.dxf"'))
    refused(capsys, ["analyze", str(scene)], "links.crank.sketch: cannot use this path (File name too long)")


def test_toml_nested_5000_deep_is_one_error(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text("x = " + "[" * 5000 + "]" * 5000 + "\n")
    refused(capsys, ["analyze", str(scene)], "scene.toml: arrays or inline tables nested too deep to read")


def test_a_scene_with_a_utf8_byte_order_mark_reads_like_one_without(tmp_path):
    plain = write_scene(tmp_path, BARE, "plain.toml")
    marked = tmp_path / "marked.toml"
    marked.write_bytes(b"\xef\xbb\xbf" + plain.read_bytes())
    assert main(["analyze", str(plain), "--json", str(tmp_path / "plain.json")]) == 0
    assert main(["analyze", str(marked), "--json", str(tmp_path / "marked.json")]) == 0
    assert json.loads((tmp_path / "plain.json").read_text()) == json.loads((tmp_path / "marked.json").read_text())


def test_a_scene_that_is_a_folder_is_one_error(tmp_path, capsys):
    (tmp_path / "scene.toml").mkdir()
    refused(capsys, ["analyze", str(tmp_path / "scene.toml")], "is a folder; give the .toml file inside it")


def test_a_scene_that_is_not_utf8_is_one_error(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_bytes('title = "Gel\u00e4nde"\n'.encode("latin-1") + BARE.encode())
    refused(capsys, ["analyze", str(scene)], "scene.toml: not UTF-8 text", "save the scene file as UTF-8")


def test_an_empty_scene_is_one_error(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text("\n  \n")
    refused(capsys, ["analyze", str(scene)], "scene.toml: the scene file is empty")


@pytest.mark.parametrize(("stored", "message"), [
    ("{not json", "case seed: reference.json: not valid JSON"),
    ("[1, 2, 3]", "case seed: reference.json: must be a JSON object {...}, got list"),
])
def test_regress_with_a_broken_reference_is_one_error_naming_the_case_and_file(tmp_path, capsys, stored, message):
    case = tmp_path / "cases" / "seed"
    case.mkdir(parents=True)
    write_scene(case, BARE)
    (case / "reference.json").write_text(stored)
    refused(capsys, ["regress", str(tmp_path / "cases")], message, "delete it and run regress --update")


# --- a wrong type for every key -----------------------------------------------------------------

FULL = DRAWN + """
[loads]
gravity_m_s2 = [0.0, -9.81]

[loads.couples]
output = 2.0
coupler = {value = 1.0, at_joint = 1}

[[loads.forces]]
link = "coupler"
at_m = [0.1, 0.0]
force_n = [10.0, 0.0]

[analysis]
kinematics = true
forces = true
stresses = true
stations = 21
validate = ["crank"]
mesh_size_m = 0.01
element_order = 2
body_load_near_holes = false
"""
FULL = edited(FULL, "[materials.steel]", 'title = "hostile"\nnotes = ["n"]\nunits = "m"\n\n[materials.steel]')
FULL = edited(FULL, "[links.ground]\njoints = [[0.0, 0.0], [0.3, 0.0]]",
              "[links.ground]\njoints = [[0.0, 0.0], [0.3, 0.0]]\nmass = 1.0\ninertia = 0.1\ncenter_of_mass = [0.1, 0.0]")
FULL = edited(FULL, 'ground = "ground"', 'ground = "ground"\nbranch = "open"')
FULL = edited(FULL, "input_speed_rad_s = 10.0", 'input_speed_rad_s = 10.0\ninput_acceleration_rad_s2 = 0.0\nactuator = "crank"')


def toml_value(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()) + "}"


def leaves(data: dict, path: tuple = ()):
    """(path, value) of every key whose value is not a table of further keys."""
    for key, value in data.items():
        if isinstance(value, dict):
            yield from leaves(value, (*path, key))
        else:
            yield (*path, key), value


def wrong_types(value: object) -> list[object]:
    """Values of every other TOML type: a string where a number goes, a table where a list goes,
    booleans for numbers (true is not 1) and numbers for booleans."""
    if isinstance(value, bool):
        return [1, "true"]
    if isinstance(value, (int, float)):
        return ["1", True, {"a": 1}]
    if isinstance(value, str):
        return [1, True, ["x"]]
    if isinstance(value, list):
        return [{"a": 1}, "x", True]
    return [1, "x"]


def wrong_type_cases():
    data = tomllib.loads(textwrap.dedent(FULL))
    for path, value in leaves(data):
        for wrong in wrong_types(value):
            if path == ("notes",) and isinstance(wrong, str):
                continue  # notes may be one string
            yield pytest.param(path, wrong, id=f"{'.'.join(path)}={toml_value(wrong)}")


def with_value(data: dict, path: tuple, value: object) -> dict:
    copy = json.loads(json.dumps(data))
    node = copy
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return copy


def test_the_full_scene_is_valid(tmp_path):
    assert main(["analyze", str(write_scene(tmp_path, FULL)), "--explain"]) == 0


@pytest.mark.parametrize(("path", "wrong"), list(wrong_type_cases()))
def test_a_wrong_type_for_any_key_is_one_message_naming_it(tmp_path, capsys, path, wrong):
    data = with_value(tomllib.loads(textwrap.dedent(FULL)), path, wrong)
    draw_bars(tmp_path / "bars.dxf")
    scene = tmp_path / "scene.toml"
    scene.write_text("".join(f"{json.dumps(k)} = {toml_value(v)}\n" for k, v in data.items()))
    refused(capsys, ["analyze", str(scene), "--explain"], f"scene.toml: {'.'.join(path)}")


# --- inputs that are not files, and files past their size limit -----------------------------------

@contextlib.contextmanager
def special_file(kind: str, folder: Path, suffix: str):
    """A path in ``folder`` that is ``kind``: a FIFO, a socket, a folder, or the device /dev/zero."""
    if kind == "/dev/zero":
        yield Path("/dev/zero")
        return
    path = folder / f"input{suffix}"
    if kind == "FIFO":
        os.mkfifo(path)
        yield path
    elif kind == "socket":
        # a Unix socket's path may hold about 100 bytes: a short folder of its own
        short = Path(tempfile.mkdtemp(prefix="ls"))
        path = short / f"s{suffix}"
        server = socket.socket(socket.AF_UNIX)
        server.bind(str(path))
        try:
            yield path
        finally:
            server.close()
            shutil.rmtree(short)
    else:
        path.mkdir()
        yield path


@contextlib.contextmanager
def within(seconds: float):
    """Fail instead of hanging: a read of a FIFO waits for a writer forever."""
    def alarm(signum, frame):
        raise TimeoutError(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


SPECIAL = {"FIFO": "a FIFO (named pipe)", "/dev/zero": "a character device", "socket": "a socket", "folder": "a folder"}


@pytest.mark.parametrize("kind", list(SPECIAL))
def test_a_sketch_that_is_not_a_file_is_refused_by_what_it_is_before_reading(tmp_path, capsys, kind):
    with special_file(kind, tmp_path, ".dxf") as path, within(10):
        refused(capsys, ["import", str(path), "--units", "mm"], f"the sketch {str(path)!r} is {SPECIAL[kind]}, not a file")


@pytest.mark.parametrize("kind", ["FIFO", "/dev/zero", "socket"])
def test_a_scene_that_is_not_a_file_is_refused_by_what_it_is_before_reading(tmp_path, capsys, kind):
    with special_file(kind, tmp_path, ".toml") as path, within(10):
        refused(capsys, ["analyze", str(path)], f"the scene file {str(path)!r} is {SPECIAL[kind]}, not a file")


@pytest.mark.parametrize("kind", list(SPECIAL))
def test_a_scene_s_sketch_that_is_not_a_file_is_refused_naming_the_key(tmp_path, capsys, kind):
    with special_file(kind, tmp_path, ".dxf") as path, within(10):
        scene = write_scene(tmp_path, DRAWN.replace('sketch = "bars.dxf"', f'sketch = "{path}"', 1))
        refused(capsys, ["analyze", str(scene)], "scene.toml: links.crank.sketch: the sketch", f"is {SPECIAL[kind]}")


def test_a_scene_file_past_16_mib_is_refused_with_its_size_before_reading(tmp_path, capsys):
    # a sparse file: its size is there, its bytes are not (nothing to read if the size were not checked first)
    path = tmp_path / "scene.toml"
    with path.open("wb") as stream:
        stream.truncate(SCENE_BYTES + 1)
    refused(capsys, ["analyze", str(path)],
            f"the scene file {str(path)!r} is 16,777,217 bytes (16.0 MiB), more than the 16 MiB a scene file may be",
            seconds=5)


def test_a_scene_file_of_16_mib_is_read(tmp_path, capsys):
    # exactly the limit: read and parsed (and refused for what it lacks)
    path = tmp_path / "scene.toml"
    path.write_bytes(b"#" + b" " * (SCENE_BYTES - 2) + b"\n")
    refused(capsys, ["analyze", str(path)], "scene.toml: links: missing table")


def test_a_sketch_past_256_mib_is_refused_with_its_size_before_reading(tmp_path, capsys):
    path = tmp_path / "sheet.dxf"
    with path.open("wb") as stream:
        stream.truncate(SKETCH_BYTES + 1)
    refused(capsys, ["import", str(path)], "is 268,435,457 bytes (256.0 MiB), more than the 256 MiB a sketch may be",
            seconds=5)


def test_a_file_that_grows_past_its_limit_while_read_is_refused(tmp_path, monkeypatch):
    # the size the file system gave was within the limit; the bytes read were not
    path = tmp_path / "scene.toml"
    path.write_bytes(b"x" * 11)
    real = os.fstat
    monkeypatch.setattr(os, "fstat", lambda fd: os.stat_result((*real(fd)[:6], 5, *real(fd)[7:])))
    with pytest.raises(InputFileError, match=r"is at least 11 bytes \(0.0 MiB\), more than the 0 MiB"):
        read_bounded(path, 10, "scene file")
    assert read_bounded(path, 11, "scene file") == b"x" * 11


# --- a valid case with nothing to carry -----------------------------------------------------------

def test_a_zero_load_case_with_peaks_gives_zeros_and_no_nan(tmp_path, capsys):
    # no loads, no speed, no gravity: every force, stress and FEA peak is exactly 0, and a factor
    # against 0 is no factor (null), never inf or nan
    text = DRAWN.replace("poisson_ratio = 0.3", "poisson_ratio = 0.3\nyield_strength = 250e6\nendurance_limit = 200e6\n"
                         "ultimate_strength = 400e6").replace("input_speed_rad_s = 10.0\n", "")
    scene = write_scene(tmp_path, text)
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene), "--peaks", "--json", str(out)]) == 0
    stdout = capsys.readouterr().out
    assert not re.search(r"\b(nan|inf)\b", stdout, re.IGNORECASE)
    data = json.loads(out.read_text(), parse_constant=lambda c: pytest.fail(f"the JSON holds {c}"))
    for position in data["positions"]:
        for name in BARS:
            link = position["links"][name]
            assert link["max_von_mises_pa"] == 0.0 and link["peak_von_mises_pa"] == 0.0
            assert link["peak_yield_safety_factor"] is None and link["yield_safety_factor"] is None
    for name in BARS:
        summary = data["links"][name]
        assert summary["peak_max_von_mises_pa"] == 0.0 and summary["peak_change_pct"] == 0.0
        assert summary["peak_yield_safety_factor"] is None and summary["fatigue_safety_factor"] is None
        assert summary["fatigue_alternating_pa"] == 0.0 and summary["fatigue_mean_pa"] == 0.0


# --- messages that list things list five ---------------------------------------------------------

def test_capped_lists_five_and_counts_them_all():
    assert capped([]) == ""
    assert capped("abcde") == "a, b, c, d, e"
    assert capped("abcdef") == "a, b, c, d, e (first 5 of 6)"
    assert capped(range(100), 2, "; ") == "0; 1 (first 2 of 100)"


def test_an_import_scene_refusal_of_150_outlines_lists_five(tmp_path, capsys):
    # 150 squares with a hole each (one joint, no mechanism): the refusal listed all 150 twice
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for k in range(150):
        x, y = (k % 15) * 20, (k // 15) * 20
        msp.add_lwpolyline([(x, y), (x + 8, y), (x + 8, y + 8), (x, y + 8)], close=True, dxfattribs={"layer": f"glyph_{k}"})
        msp.add_circle((x + 4, y + 4), 1, dxfattribs={"layer": f"glyph_{k}"})
    doc.saveas(tmp_path / "sheet.dxf")
    line = refused(capsys, ["import", str(tmp_path / "sheet.dxf"), "--scene", str(tmp_path / "scene.toml")],
                   "no two of the links ('glyph_0', 'glyph_15', 'glyph_30', 'glyph_45', 'glyph_60' (first 5 of 150))",
                   "links with fewer than two joints: 'glyph_0' (1), ", "(1) (first 5 of 150)")
    assert len(line) < 600
    assert not (tmp_path / "scene.toml").exists()


def test_a_scene_naming_an_unknown_material_among_forty_lists_five(tmp_path, capsys):
    materials = "".join(f"[materials.m{k:02d}]\ndensity = 7850.0\n" for k in range(40))
    text = materials + edited(BARE, "[links.crank]\n", "[links.crank]\nmaterial = \"steel\"\n")
    line = refused(capsys, ["analyze", str(write_scene(tmp_path, text))],
                   "links.crank.material: no material named 'steel'; materials are: m00, m01, m02, m03, m04 (first 5 of 40)")
    assert len(line) < 300


def test_a_key_path_of_5000_characters_is_cut_in_its_message(tmp_path, capsys):
    name = "x" * 5000
    text = BARE + f"\n[links.{name}]\njoints = [[0.0, 0.0], [0.1, 0.0]]\n"
    line = refused(capsys, ["analyze", str(write_scene(tmp_path, text))], "scene.toml: links.xxx", "x...x",
                   "x: no mechanism uses this link")
    assert len(line) < 400


# --- a scheduler address with a control character ------------------------------------------------

CONTROLLED = ["tcp://10.0.0.5:8786\n", "tcp://10.0.0.5:8786\r", "\ttcp://10.0.0.5:8786", "tcp://10.0.0.5:8786\x1b[31m",
              "tcp://10.0.0.5:87\x0086", "tcp://10.0.0.5:8786\u202e", "tcp://10.0.\u200b0.5:8786", "local\n"]
"""A final newline (which ``$`` let through), a carriage return, a tab, an escape sequence, a NUL, a
right-to-left override and a zero-width space (format characters), and ``local`` with a newline."""


@pytest.mark.parametrize("address", CONTROLLED, ids=repr)
@pytest.mark.parametrize("command", ["analyze", "validate", "regress"])
def test_a_scheduler_option_holding_a_control_character_is_refused_at_once_quoted(tmp_path, capsys, address, command):
    scene = write_scene(tmp_path, DRAWN)
    argv = {"analyze": ["analyze", str(scene), "--peaks"], "validate": ["validate", str(scene)],
            "regress": ["regress", str(REPO / "validation" / "cases" / "textbook_fourbar")]}[command]
    control = next(c for c in address if not c.isprintable() or c in "\u202e\u200b")
    refused(capsys, [*argv, "--scheduler", address], f"--scheduler: {address!r} holds the control character {control!r}",
            seconds=5)


@pytest.mark.parametrize("address", [a for a in CONTROLLED if "\x00" not in a], ids=repr)
def test_a_scheduler_variable_holding_a_control_character_is_refused_at_once_quoted(capsys, monkeypatch, address):
    # an environment variable cannot hold a NUL
    monkeypatch.setenv("LINKSTRESS_SCHEDULER", address)
    refused(capsys, ["regress", str(REPO / "validation" / "cases" / "textbook_fourbar")],
            f"LINKSTRESS_SCHEDULER: {address!r} holds the control character", seconds=5)


def test_a_scheduler_address_of_100000_characters_is_quoted_cut(capsys):
    address = "tcp://" + "a" * 100_000 + ":8786"
    line = refused(capsys, ["regress", "--scheduler", address], "--scheduler: 'tcp://aaa", "...", "aaa:8786' is not a scheduler")
    assert len(line) < 400


@pytest.mark.parametrize("host", ["a" * 64, ".".join(["a" * 63] * 4) + "aa", "a..b", ".a", "[" + "1" * 46 + "]"])
def test_a_scheduler_host_dns_cannot_hold_is_refused_before_connecting(capsys, host):
    # DNS: labels of at most 63 characters, names of at most 253 (RFC 1035 2.3.4); a 64-character
    # label made the socket module's IDNA codec raise UnicodeError, a traceback
    refused(capsys, ["regress", "--scheduler", f"tcp://{host}:8786"], "is not a scheduler address", seconds=5)


@pytest.mark.parametrize("host", ["a" * 63, ".".join(["a" * 63] * 4)[:253], "10.0.0.5", "[::1]", "node-7.cluster_a.example"])
def test_a_scheduler_host_dns_can_hold_passes_the_check(host):
    executors.check_address(f"tcp://{host}:8786")
