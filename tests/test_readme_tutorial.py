"""The README's tutorial runs as written: import the drawing into a scene, edit it as shown, analyze
with peaks, validate, make it a regression case and regress it; the figures the tutorial quotes are
the ones the run gives."""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from linkstress.cli import main
from linkstress.validation.bench.tutorial import edit_scene

REPO = Path(__file__).resolve().parents[1]


def tutorial() -> str:
    text = (REPO / "README.md").read_text()
    return text.split("## Tutorial", 1)[1].split("\n## ", 1)[0]


def shell_lines() -> list[str]:
    """Every shell command of the tutorial, in order."""
    return re.findall(r"```sh\n(.+?)\n```", tutorial(), re.S)


def commands() -> list[list[str]]:
    """The tutorial's linkstress commands up to its regression step, without the venv's path."""
    words = [shlex.split(line) for line in shell_lines()]
    words = [w for w in words if w[0] == ".venv/bin/linkstress" and w[1] != "regress"]
    return [w[1:] for w in words]


def regress_step() -> list[str]:
    """Step 6's shell commands, as written."""
    step = tutorial().split("**6.", 1)[1]
    return re.findall(r"```sh\n(.+?)\n```", step, re.S)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tutorial")
    (folder / "docs").symlink_to(REPO / "docs")
    steps = commands()
    assert [s[0] for s in steps] == ["import", "analyze", "validate"]
    here = os.getcwd()
    os.chdir(folder)
    try:
        assert main(steps[0]) == 0
        edits = re.findall(r"```toml\n(.+?)\n```", tutorial(), re.S)[0]
        scene = folder / "fourbar.toml"
        scene.write_text(edit_scene(scene.read_text(), edits))
        analyze = steps[1] + ["--json", "analysis.json"]
        with contextlib.redirect_stdout(io.StringIO()) as printed:
            assert main(analyze) == 0
        (folder / "analyze.txt").write_text(printed.getvalue())
        validate = steps[2] + ["--json", "check.json"]
        with contextlib.redirect_stdout(io.StringIO()) as printed:
            code = main(validate)
        (folder / "validate.txt").write_text(printed.getvalue())
    finally:
        os.chdir(here)
    return folder, code


def test_the_written_and_edited_scene_is_the_scene_the_tutorial_describes(run):
    folder, _ = run
    scene = tomllib.loads((folder / "fourbar.toml").read_text())
    assert {link["thickness"] for link in scene["links"].values()} == {0.006}
    assert scene["motion"]["input_speed_rad_s"] == 100.0
    assert scene["loads"]["couples"] == {"rocker": 5.0}
    assert (folder / "fourbar.png").stat().st_size > 10_000


def test_the_figures_the_tutorial_quotes_are_those_of_the_run(run):
    folder, _ = run
    analysis = json.loads((folder / "analysis.json").read_text())
    links, positions = analysis["links"], analysis["positions"]
    rocker = links["rocker"]
    beam = max(p["links"]["rocker"]["max_von_mises_pa"] for p in positions)
    beam_factor = min(p["links"]["rocker"]["yield_safety_factor"] for p in positions)
    text = tutorial()
    quoted = re.search(r"beam maximum is (\d+) MPa but its FEA peak, at the pin hole, is (\d+) MPa", text)
    factors = re.search(r"yield safety factor is ([\d.]+), not the ([\d.]+)", text)
    assert round(beam / 1e6) == int(quoted.group(1))
    assert round(rocker["peak_max_von_mises_pa"] / 1e6) == int(quoted.group(2))
    assert rocker["peak_converged"]
    assert round(rocker["peak_yield_safety_factor"], 1) == float(factors.group(1))
    assert round(beam_factor, 1) == float(factors.group(2))
    assert rocker["fatigue_safety_factor"] is not None


def test_the_tutorial_analyze_prints_its_verdict_first_as_the_readme_quotes_it(run):
    from test_verdict import assert_verdict_is_the_jsons

    folder, _ = run
    text = (folder / "analyze.txt").read_text()
    lines = text.splitlines()
    heading = next(k for k, line in enumerate(lines) if line.startswith("verdict:"))
    end = lines.index("", heading)
    assert end <= 25  # the verdict and its next step within the first 25 lines of the terminal
    assert_verdict_is_the_jsons(text, json.loads((folder / "analysis.json").read_text())["verdict"])
    quoted = re.search(r"```text\n(verdict: .+?)\n```", tutorial(), re.S).group(1)
    assert quoted == "\n".join(lines[heading:end])


def test_the_tutorial_validate_prints_its_verdict_first_over_the_positions_it_compared(run):
    from test_verdict import assert_verdict_is_the_jsons

    folder, _ = run
    text = (folder / "validate.txt").read_text()
    data = json.loads((folder / "check.json").read_text())
    assert text.startswith("verdict:") and text.splitlines().index("") <= 25
    assert_verdict_is_the_jsons(text, data["verdict"])
    for row in data["verdict"]["rows"]:
        if row["governing"] == "FEA peak":
            assert row["yield_safety_factor_note"] == "at 4 of 361 positions"


def test_the_regress_step_runs_as_written_stores_a_reference_and_passes(run):
    # Step 6 in a shell, in the tutorial's folder after steps 1-5, with the README's
    # .venv/bin/linkstress being this interpreter's linkstress.
    folder, _ = run
    lines = regress_step()
    assert len(lines) == 4 and lines[-2:] == [".venv/bin/linkstress regress cases --update", ".venv/bin/linkstress regress cases"]
    linkstress = f"{shlex.quote(sys.executable)} -m linkstress"
    outputs = []
    for line in lines:
        done = subprocess.run(["bash", "-c", line.replace(".venv/bin/linkstress", linkstress)], cwd=folder,
                              capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, (line, done.stdout, done.stderr)
        outputs.append(done.stdout)
    case = folder / "cases" / "fourbar"
    assert tomllib.loads((case / "scene.toml").read_text())["links"]["rocker"]["sketch"] == "fourbar.dxf"
    stored = json.loads((case / "reference.json").read_text())
    assert set(stored["validation"]["links"]) == {"crank", "coupler", "rocker"}
    assert outputs[2].strip() == "fourbar: reference rewritten"
    assert "1 of 1 cases passed" in outputs[3]


def test_the_tutorial_validate_passes(run):
    folder, code = run
    assert code == 0
    report = json.loads((folder / "check.json").read_text())
    assert set(report["links"]) == {"crank", "coupler", "rocker"}


def test_the_tutorial_pictures_are_in_the_repository():
    for path in re.findall(r"\]\((docs/images/[^)]+\.png)\)", tutorial()):
        assert (REPO / path).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", path
    assert len(re.findall(r"\]\((docs/images/[^)]+\.png)\)", tutorial())) == 2


def test_the_tutorial_drawing_is_what_its_script_draws(tmp_path):
    import runpy
    import shutil

    shutil.copy(REPO / "docs" / "tutorial" / "draw_fourbar.py", tmp_path)
    runpy.run_path(str(tmp_path / "draw_fourbar.py"), run_name="__main__")
    assert (tmp_path / "fourbar.dxf").read_bytes() == (REPO / "docs" / "tutorial" / "fourbar.dxf").read_bytes()
