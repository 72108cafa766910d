"""No two labels of a report's figures overlap.

The six-bar's mechanism figure put each joint force's label at the tail of its arrow, so the two
loops' forces on their shared pivot printed on top of each other, and the links' "max" labels on
the forces'. The boxes are measured as matplotlib's renderer draws them, at the resolution the
reports save at, on every figure the six-bar's analysis report draws, at every position of its sweep.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from linkstress.analysis import plan_for, run_analysis
from linkstress.report.figures import mechanism_figure, mechanism_sweep_figure, plt, spread_x_ticks, stress_along_figure, sweep_figure
from linkstress.report.labels import PLACEMENT_DPI, LabelPlacer
from linkstress.scene import load_scene

SIX_BAR = Path(__file__).resolve().parents[1] / "validation" / "cases" / "six_bar" / "scene.toml"


def label_boxes(fig) -> list[tuple[str, Bbox]]:
    """Every label drawn in the figure's axes (texts and annotations with text), with the box in
    pixels of its text (and white box; not its leader line), drawn as ``figures.png_bytes`` saves it."""
    spread_x_ticks(fig, PLACEMENT_DPI)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = []
    for ax in fig.axes:
        for text in ax.texts:
            if not text.get_visible() or not text.get_text():
                continue
            parts = [Text.get_window_extent(text, renderer)]
            if text.get_bbox_patch() is not None:
                parts.append(text.get_bbox_patch().get_window_extent(renderer))
            boxes.append((text.get_text(), Bbox.union(parts)))
    return boxes


def overlapping(boxes: list[tuple[str, Bbox]]) -> list[tuple[str, str]]:
    return [(a, b) for (a, box_a), (b, box_b) in itertools.combinations(boxes, 2) if box_a.overlaps(box_b)]


@pytest.fixture(scope="module")
def six_bar():
    scene = load_scene(SIX_BAR)
    return run_analysis(scene, plan_for(scene))


def test_no_two_labels_of_the_six_bars_mechanism_overlap_at_any_position(six_bar):
    positions = np.flatnonzero(six_bar.feasible)
    assert len(positions) == 36
    for k in positions.tolist():
        fig = mechanism_figure(six_bar, k)
        boxes = label_boxes(fig)
        names = [text for text, _ in boxes]
        shown = sum(text.startswith("max ") for text in names)
        legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        # five stressed links' maxima and 8 joint forces, each on the drawing or else in the legend
        assert shown + sum("(no room on the drawing)" in t and t.startswith("max ") for t in legend) == 5
        forces = sum(" N" in t for t in names) + sum("(no room on the drawing)" in t and " N " in t for t in legend)
        assert forces == 8, k
        assert overlapping(boxes) == [], f"position {k}"
        plt.close(fig)


def test_the_six_bars_other_report_figures_have_no_overlapping_labels(six_bar):
    ok = np.flatnonzero(six_bar.feasible)
    figures = [mechanism_sweep_figure(six_bar, ok[::3].tolist()), sweep_figure(six_bar)]
    figures += [stress_along_figure(six_bar, name, int(ok[3])) for name in six_bar.stresses]
    for fig in figures:
        assert overlapping(label_boxes(fig)) == []
        plt.close(fig)


def test_labels_crowding_one_point_each_take_their_own_place_or_are_returned():
    # Thirty labels on one point of a small plot: the first goes up and to the right, the others
    # around it at growing distances with leader lines, none overlapping; those with no room left
    # inside the axes are not drawn but returned.
    fig, ax = plt.subplots(figsize=(3.0, 2.0), layout="constrained")
    ax.plot([0.0, 1.0], [0.0, 1.0])
    labels = LabelPlacer(ax)
    texts = [f"label number {k}" for k in range(30)]
    for text in texts:
        labels.add(text, (0.5, 0.5), fontsize=8)
    left_off = labels.place()
    boxes = label_boxes(fig)
    assert overlapping(boxes) == []
    assert sorted([t for t, _ in boxes] + left_off) == sorted(texts)
    assert boxes[0][0] == "label number 0" and 0 < len(left_off) < 30
    frame = ax.get_window_extent()
    assert all(frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1) for _, box in boxes)
    plt.close(fig)
