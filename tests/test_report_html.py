"""The HTML report: one self-contained file whose figures render in a real (headless) browser."""

from __future__ import annotations

import base64
import io
import os
import re
import shutil
import subprocess
from pathlib import Path

import matplotlib.image as mpimg
import numpy as np
import pytest

from linkstress.cli import main

REPO = Path(__file__).resolve().parents[1]
SEED = REPO / "validation" / "cases" / "seed_ansys_fourbar" / "scene.toml"
CHROMIUM_FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
)


def embedded_images(text: str) -> list[np.ndarray]:
    return [
        mpimg.imread(io.BytesIO(base64.b64decode(data)), format="png")
        for data in re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
    ]


@pytest.fixture(scope="module")
def seed_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "seed.html"
    assert main(["analyze", str(SEED), "--html", str(out)]) == 0
    return out


def test_report_is_self_contained_and_states_loads_and_versions(seed_report):
    text = seed_report.read_text()
    assert "http://" not in text and "https://" not in text and "<script" not in text
    for heading in ("Loads applied", "Mechanism", "Accelerations", "Joint forces and driving torque",
                    "Section stresses (beam theory)", "Versions"):
        assert f"<h2>{heading}</h2>" in text
    assert re.search(r"couple on output at joint 0 \[N m, ccw\]</td><td[^>]*>2</td>", text)
    assert "scikit-fem" in text and "gmsh" in text


def test_every_embedded_figure_is_a_real_picture(seed_report):
    images = embedded_images(seed_report.read_text())
    assert len(images) == 4  # the mechanism and the stresses along crank, coupler and output
    for image in images:
        assert image.shape[0] > 200 and image.shape[1] > 200
        assert image[..., :3].std() > 0.05  # not a blank canvas


def find_chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


def test_report_renders_in_headless_chromium_with_its_figures(seed_report, tmp_path):
    browser = find_chromium()
    if browser is None:
        if os.environ.get("LINKSTRESS_REQUIRE_BROWSER"):
            pytest.fail("chromium is required here (LINKSTRESS_REQUIRE_BROWSER is set) but not installed")
        pytest.skip("no chromium on this machine; .ci/run installs Debian's chromium")
    shot = tmp_path / "shot.png"
    subprocess.run(
        [browser, *CHROMIUM_FLAGS, f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1100,3000",
         f"--screenshot={shot}", seed_report.as_uri()],
        check=True, capture_output=True, timeout=120,
    )
    picture = mpimg.imread(shot)[..., :3]
    assert picture.shape[:2] == (3000, 1100)
    # Figures are wide bands of colour among white text: plenty of non-white, non-grey pixels.
    coloured = (picture.max(axis=2) - picture.min(axis=2)) > 0.2
    assert coloured.mean() > 0.003
    rows_with_colour = coloured.any(axis=1)
    assert rows_with_colour.mean() > 0.2  # figures spread down the page, not one blob


def test_a_sweep_report_draws_the_mechanism_over_the_sweep_and_plots_against_the_input(tmp_path):
    out = tmp_path / "six.html"
    assert main(["analyze", str(REPO / "validation" / "cases" / "six_bar" / "scene.toml"), "--html", str(out)]) == 0
    text = out.read_text()
    assert 'alt="mechanism over the sweep"' in text and 'alt="sweep plots"' in text
    assert all(image[..., :3].std() > 0.05 for image in embedded_images(text))
