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

from linkstress.analysis import plan_for, run_analysis
from linkstress.cli import main
from linkstress.report import html as report_html
from linkstress.report import detail_tables, peak_text
from linkstress.report.figures import (
    LABEL_ZORDER,
    TICK_GAP_PX,
    mechanism_figure,
    mechanism_sweep_figure,
    plt,
    spread_x_ticks,
    stress_along_figure,
    sweep_figure,
    x_tick_gaps,
)
from linkstress.scene.reader import load_scene

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
    # Nothing is fetched: the only address is the SVG namespace's name, which the view's script passes
    # to createElementNS; its scripts are inline.
    assert set(re.findall(r"https?://[^\s\"'<>)]+", text)) == {"http://www.w3.org/2000/svg"}
    assert re.findall(r"<script[^>]*>", text) == ['<script type="application/json" id="view-data">', "<script>"]
    assert "<link" not in text and "<iframe" not in text and "url(" not in text
    for heading in ("Mechanism, position by position", "Loads applied", "Mechanism", "Accelerations", "Joint forces and driving torque",
                    "Section stresses (beam theory)", "Versions"):
        assert f"<h2>{heading}</h2>" in text
    assert re.search(r"couple on output at joint 0 \[N m, ccw\]</td><td[^>]*>2</td>", text)
    assert "scikit-fem" in text and "gmsh" in text


def test_every_embedded_figure_is_a_real_picture(seed_report):
    images = embedded_images(seed_report.read_text())
    # the mechanism, the stresses along crank, coupler and output, and for the two links whose model
    # is the FEA peaks (crank and output: couples through their pivots) the peak over the sweep and its field
    assert len(images) == 4 + 2 * 2
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


# --- what a reader hit in the figures and tables ---------------------------------------------------

SIX_BAR = REPO / "validation" / "cases" / "six_bar" / "scene.toml"


@pytest.fixture(scope="module")
def six_bar():
    return run_analysis(load_scene(SIX_BAR))


def report_figures(result):
    """Every figure the analysis report draws, by name."""
    ok = np.flatnonzero(result.feasible)
    figures = {
        "mechanism": mechanism_figure(result, int(ok[3])),
        "mechanism over the sweep": mechanism_sweep_figure(result, ok[::3].tolist()),
        "sweep plots": sweep_figure(result),
    }
    figures.update({f"stresses along {name}": stress_along_figure(result, name, int(ok[3])) for name in result.stresses})
    return figures


def drawn_axes(fig):
    fig.canvas.draw()
    return fig.canvas.get_renderer(), [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]


def test_no_legend_covers_the_plotted_area(six_bar):
    for name, fig in report_figures(six_bar).items():
        renderer, axes = drawn_axes(fig)
        for ax in axes:
            legend = ax.get_legend()
            if legend is not None:
                inside = legend.get_window_extent(renderer).overlaps(ax.get_window_extent(renderer))
                assert not inside, f"{name}: the legend sits on the plot"
        plt.close(fig)


def test_x_tick_labels_that_would_run_together_are_thinned_out():
    # Matplotlib's own count allows about three characters a label: on a 4 inch axis from -0.025 to
    # 0.15 it gives ten ticks 0.025 apart, and "-0.050-0.025" reads as one number.
    fig, ax = plt.subplots(figsize=(4.0, 2.0), layout="constrained")
    ax.plot([-0.025, 0.15], [0.0, 1.0])
    fig.set_dpi(110)
    fig.canvas.draw()
    before = x_tick_gaps(ax, fig.canvas.get_renderer())
    assert len(before) == 7 and min(before) < 0
    spread_x_ticks(fig)
    after = x_tick_gaps(ax, fig.canvas.get_renderer())
    assert 2 <= len(after) < 7 and min(after) >= TICK_GAP_PX
    plt.close(fig)


def test_no_figure_of_the_report_has_x_tick_labels_closer_than_a_few_pixels(six_bar):
    for name, fig in report_figures(six_bar).items():
        spread_x_ticks(fig)
        renderer, axes = drawn_axes(fig)
        for ax in axes:
            assert min(x_tick_gaps(ax, renderer), default=np.inf) >= TICK_GAP_PX, name
        plt.close(fig)


def label_sits_above_everything(ax, label) -> bool:
    """The annotation is drawn after every line and fill of the axes, on an opaque box."""
    others = [*ax.lines, *ax.collections, *ax.patches]
    box = label.get_bbox_patch()
    return label.get_zorder() > max(a.get_zorder() for a in others) and box is not None and box.get_alpha() >= 0.9


def test_the_mechanism_figures_marked_maxima_are_labelled_above_the_links_and_arrows(six_bar):
    fig = mechanism_figure(six_bar, int(np.flatnonzero(six_bar.feasible)[3]))
    ax = fig.axes[0]
    labels = [t for t in ax.texts if t.get_text().startswith("max ")]
    assert len(labels) == len(six_bar.stresses)
    assert all(label_sits_above_everything(ax, label) for label in labels)
    assert all(t.get_zorder() == LABEL_ZORDER for t in labels)
    plt.close(fig)


def test_the_fea_peak_label_is_not_hidden_by_the_comparison_cuts():
    from dataclasses import replace

    from linkstress.validation.report import fea_contour_figure
    from linkstress.validation.validate_scene import validate_scene

    scene = load_scene(SEED)
    result = validate_scene(scene, replace(plan_for(scene), validate=("coupler",)), positions=1, levels=1)
    fig = fea_contour_figure(result.comparisons["coupler"], 0, 60.0)
    ax = fig.axes[0]
    cuts = [line for line in ax.lines if line.get_color() == "white"]
    (label,) = [t for t in ax.texts if t.get_text().startswith("peak ")]
    assert cuts and label_sits_above_everything(ax, label)
    renderer, _ = drawn_axes(fig)
    assert ax.get_window_extent(renderer).contains(*label.get_window_extent(renderer).p1)  # inside the plot
    plt.close(fig)


POINT_COLUMN = re.compile(r"\(x, y\) \[m\], (ground|member|drawing) frame")


def test_every_column_giving_a_point_names_its_frame(seed_report, capsys):
    headers = [*report_html.STRESS_HEADERS, *detail_tables.STRESS_HEADERS, *peak_text.PEAK_HEADERS]
    points = [h for h in headers if "(x, y)" in h]
    assert len(points) == 4 and all(POINT_COLUMN.search(h) for h in points)
    assert main(["analyze", str(SEED), "--details"]) == 0
    for page in (seed_report.read_text(), capsys.readouterr().out):
        assert page.count("(x, y)") == len(POINT_COLUMN.findall(page)) > 0
