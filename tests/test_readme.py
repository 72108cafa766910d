"""The README's two set-up commands stay true: CI runs the test command verbatim."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def readme_commands() -> list[str]:
    text = (REPO / "README.md").read_text()
    section = text.split("## Set up and run", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```sh\n(.+?)\n```", section)


def test_readme_has_exactly_two_setup_commands():
    commands = readme_commands()
    assert len(commands) == 2
    assert all(c.startswith("python3 -m venv .venv && ") for c in commands)


def test_ci_runs_the_readme_test_command():
    test_command = readme_commands()[1]
    assert "pytest" in test_command
    assert test_command in (REPO / ".ci" / "run").read_text().splitlines()


def test_readme_main_job_runs_as_written_and_its_report_renders_in_chromium(tmp_path, monkeypatch):
    import shlex

    from linkstress.cli import main
    from test_report_html import CHROMIUM_FLAGS, embedded_images, find_chromium

    command = readme_commands()[0].split("&&")[-1]
    words = shlex.split(command)
    assert words[0] == ".venv/bin/linkstress"
    args = words[1:]
    report = tmp_path / args[args.index("--html") + 1]
    args[args.index("--html") + 1] = str(report)
    monkeypatch.chdir(REPO)
    assert main(args) == 0
    text = report.read_text()
    images = embedded_images(text)
    assert len(images) >= 10  # mechanism, 3 stress plots, 3 contours, 3 beam-and-FEA plots
    assert all(image[..., :3].std() > 0.05 for image in images)
    browser = find_chromium()
    if browser is None:
        import os

        if os.environ.get("LINKSTRESS_REQUIRE_BROWSER"):
            raise AssertionError("chromium is required here (LINKSTRESS_REQUIRE_BROWSER is set) but not installed")
        pytest.skip("no chromium here to render the report in (CI installs it)")
    import subprocess

    import matplotlib.image as mpimg

    shot = tmp_path / "shot.png"
    subprocess.run(
        [browser, *CHROMIUM_FLAGS, f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1100,12000",
         f"--screenshot={shot}", report.as_uri()],
        check=True, capture_output=True, timeout=180,
    )
    picture = mpimg.imread(shot)[..., :3]
    coloured = (picture.max(axis=2) - picture.min(axis=2)) > 0.2
    # every figure drawn: coloured rows spread over most of the long page
    assert coloured.any(axis=1).mean() > 0.25
