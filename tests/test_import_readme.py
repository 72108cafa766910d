"""docs/importing.md's examples run as written."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def section() -> str:
    return (REPO / "docs" / "importing.md").read_text()


def test_the_readme_import_commands_run(tmp_path):
    commands = [line for block in re.findall(r"```sh\n(.+?)\n```", section(), re.S) for line in block.splitlines()]
    assert len(commands) == 3
    for name in ("validation", "cad_scripts"):
        (tmp_path / name).symlink_to(REPO / name)
    for command in commands:
        program, *args = shlex.split(command)
        assert program == "linkstress"
        result = subprocess.run([sys.executable, "-m", "linkstress", *args], cwd=tmp_path, capture_output=True, text=True)
        assert result.returncode == 0, result.stderr
        assert "link" in result.stdout
    assert (tmp_path / "links.json").exists() and (tmp_path / "links.png").exists()
    assert 'type = "linkage"' in (tmp_path / "press.toml").read_text()


def test_the_readme_python_example_runs_and_gives_the_stated_mass():
    code = re.findall(r"```python\n(.+?)\n```", section(), re.S)[0]
    check = "\nassert round(profile.mass, 3) == 470.507, profile.mass\nassert crank.joint_rules == ('point', 'point')\n"
    result = subprocess.run([sys.executable, "-c", code + check], cwd=REPO, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
