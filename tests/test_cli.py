"""The console script: help, version, and the exit-code contract."""

from __future__ import annotations

import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from linkstress import __version__
from linkstress.cli import build_parser, main

REPO = Path(__file__).resolve().parents[1]


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "linkstress", *args], capture_output=True, text=True)


def test_version_prints_the_package_version():
    result = run_cli("--version")
    assert result.returncode == 0
    assert result.stdout.strip() == f"linkstress {__version__}"


def test_the_command_line_and_an_analysis_without_a_report_leave_matplotlib_unloaded(tmp_path):
    # matplotlib takes about half a second to import: only --html and the figures need it
    scene = "validation/cases/seed_ansys_fourbar/scene.toml"
    code = (
        "import sys\n"
        "from linkstress.cli import main\n"
        f"assert main(['analyze', {scene!r}, '--json', {str(tmp_path / 'out.json')!r}]) == 0\n"
        "print('matplotlib' in sys.modules)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().splitlines()[-1] == "False"


def test_help_lists_the_commands():
    result = run_cli("--help")
    assert result.returncode == 0
    assert "sections" in result.stdout


COMMANDS = ("import", "analyze", "validate", "sections", "regress", "bench")
INPUTS = ("scene", "sketch", "cases")
"""The arguments that name files a command reads (its outputs need not exist yet)."""


def help_text(capsys, *argv: str) -> str:
    with pytest.raises(SystemExit) as stop:
        main([*argv, "--help"])
    assert stop.value.code == 0
    return capsys.readouterr().out


def closing_examples(text: str) -> list[str]:
    """The command lines of a help's last paragraph: a heading starting "example", then the lines."""
    lines = text.rstrip().split("\n\n")[-1].splitlines()
    assert lines[0].startswith("example"), lines[0]
    first = next(k for k, line in enumerate(lines) if line.startswith("  linkstress "))
    assert all(line.startswith("  linkstress ") for line in lines[first:]), lines
    return [line.strip() for line in lines[first:]]


@pytest.mark.parametrize("command", [(), *((name,) for name in COMMANDS)], ids=["linkstress", *COMMANDS])
def test_every_help_ends_with_examples_the_parser_takes_on_files_that_exist(capsys, command):
    examples = closing_examples(help_text(capsys, *command))
    assert examples
    for line in examples:
        argv = shlex.split(line)[1:]
        if command:
            assert argv[0] == command[0], line
        args = build_parser().parse_args(argv)  # exits 2 on a flag or value the command does not take
        assert hasattr(args, "run"), line
        for name in INPUTS:
            if getattr(args, name, None) is not None:
                assert (REPO / getattr(args, name)).exists(), line


def test_the_main_path_runs_import_then_analyze_then_validate(capsys):
    assert [line.split()[1] for line in closing_examples(help_text(capsys))] == ["import", "analyze", "validate"]


def test_analyze_help_says_a_sweep_includes_its_stop(capsys):
    text = " ".join(help_text(capsys, "analyze").split())
    assert "{start, stop, num} is num angles from start to stop, both included" in text


def test_console_script_is_installed_beside_the_interpreter():
    script = Path(sys.executable).parent / "linkstress"
    assert script.is_file(), f"no console script at {script}: is linkstress installed in this environment?"
    result = subprocess.run([str(script), "--version"], capture_output=True, text=True)
    assert result.returncode == 0 and result.stdout.strip() == f"linkstress {__version__}"


def test_sections_prints_the_seed_crank_bar(capsys):
    # The seed's ANSYS crank: 1.0 m between 20 mm pin holes, 1.2 x 0.5 x 0.1 m, steel 7850 kg/m^3.
    assert main(["sections", "--bar", "1.0", "0.5", "0.1", "0.1", "--hole", "0.02", "--stations", "3"]) == 0
    out = capsys.readouterr().out
    # m = 7850 x 0.1 x (1.2 x 0.5 - 2 pi 0.01^2) = 470.507 kg (flattened holes: within 1e-6)
    assert "470.507" in out
    assert "0.00104167" in out  # I = t h^3 / 12 away from the holes


def test_bad_input_exits_2_with_one_message_and_no_traceback():
    result = run_cli("sections", "--bar", "1.0", "0.5", "0.1", "-0.1")
    assert result.returncode == 2
    assert result.stderr.strip() == "linkstress: error: link 'bar': thickness must be > 0 m, got -0.1"
    assert "Traceback" not in result.stderr
