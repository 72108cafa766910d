"""``linkstress import --plot``: the overview names every link inside its outline, legends and titles
keep off the geometry, a narrow link's tick labels stay apart, and a 91-part sheet draws as one
overview of bounded size. Checked on the figure's artists after a draw, in window pixels."""

from __future__ import annotations

import itertools

import ezdxf
import pytest
from shapely.geometry import Point

from linkstress.importers import read_sketch
from linkstress.importers.figure import DPI, MAX_LINK_PANELS, MAX_WIDTH_IN, sketch_figure, sketch_png
from linkstress.validation.bench.plot import png_pixels, sheet_drawing
from test_import_cli import SEED


def drawn(sketch):
    fig = sketch_figure(sketch)
    fig.canvas.draw()
    return fig, fig.canvas.get_renderer()


def test_the_overview_names_every_link_at_a_point_inside_its_outline_and_marks_holes_and_joints():
    sketch = read_sketch(SEED)
    overview = sketch_figure(sketch).axes[0]
    names = {text.get_text(): Point(text.get_position()) for text in overview.texts}
    assert set(names) == {"crank", "coupler", "output", "ground"}
    for link in sketch.links:
        # Inside the material, clear of the outline: each bar is 0.5 m wide with 20 mm holes.
        assert link.outline.contains(names[link.name])
        assert link.outline.exterior.distance(names[link.name]) > 0.1
    outlines, holes = overview.collections
    joints, = overview.lines
    # Four bars, two 20 mm pin holes each, a POINT at each hole's centre.
    assert len(outlines.get_paths()) == 4 and len(holes.get_segments()) == 8 and len(joints.get_xdata()) == 8
    assert [t.get_text() for t in overview.get_legend().get_texts()] == ["outline", "holes", "joints"]


def test_a_row_per_link_follows_the_overview_up_to_the_panel_limit():
    fig = sketch_figure(read_sketch(SEED))
    # The overview, then per link its outline (sketch frame) and its U(x), L(x) (member frame).
    assert len(fig.axes) == 1 + 2 * 4
    assert [ax.get_title() for ax in fig.axes[1:3]] == [
        "crank: sketch frame [m]", "crank: bounding functions, member frame [m]"]


def test_legends_and_titles_keep_off_every_axes():
    fig, renderer = drawn(read_sketch(SEED))
    boxes = [ax.get_window_extent(renderer) for ax in fig.axes]
    furniture = [ax.get_legend() for ax in fig.axes] + [ax.title for ax in fig.axes]
    assert all(artist is not None for artist in furniture)
    for artist, box in itertools.product(furniture, boxes):
        assert not artist.get_window_extent(renderer).overlaps(box), artist


def upright_strip(tmp_path):
    """A link 10 x 200 mm, upright at x = 320..330 mm, with 4 mm pin holes and POINTs 10 mm from its
    ends: with an equal aspect that shrinks the box, its x ticks 0.325, 0.330 ran together."""
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(320, 0), (330, 0), (330, 200), (320, 200)], close=True)
    for y in (10, 190):
        msp.add_circle((325, y), 2)
        msp.add_point((325, y))
    path = tmp_path / "strip.dxf"
    doc.saveas(path)
    return read_sketch(path)


def visible_labels(ax, axis: str):
    """The tick labels of ``axis`` ("x" or "y") at ticks inside the view."""
    lo, hi = sorted(getattr(ax, f"get_{axis}lim")())
    ticks, labels = getattr(ax, f"get_{axis}ticks")(), getattr(ax, f"get_{axis}ticklabels")()
    return [label for tick, label in zip(ticks, labels) if lo <= tick <= hi and label.get_text()]


def test_the_tick_labels_of_a_narrow_link_do_not_run_together(tmp_path):
    fig, renderer = drawn(upright_strip(tmp_path))
    assert len(fig.axes) == 2  # one link: no overview, its row only
    for ax in fig.axes:
        for axis, (start, end) in (("x", ("x0", "x1")), ("y", ("y0", "y1"))):
            labels = visible_labels(ax, axis)
            assert len(labels) >= 3, (ax.get_title(), axis)
            extents = sorted((label.get_window_extent(renderer) for label in labels), key=lambda b: getattr(b, start))
            for a, b in zip(extents, extents[1:]):
                assert getattr(a, end) < getattr(b, start), (ax.get_title(), axis, [t.get_text() for t in labels])


def test_a_91_part_sheet_draws_one_overview_as_a_png_of_bounded_size(tmp_path):
    sheet_drawing(tmp_path / "sheet.dxf", 91)
    sketch = read_sketch(tmp_path / "sheet.dxf")
    fig = sketch_figure(sketch)
    assert len(sketch.links) == 91 > MAX_LINK_PANELS and len(fig.axes) == 1
    assert {text.get_text() for text in fig.axes[0].texts} == {f"part-{k:02d}" for k in range(1, 92)}
    assert "91 links: overview only" in fig.get_suptitle()
    png = sketch_png(sketch)
    assert png.startswith(b"\x89PNG\r\n\x1a\n")
    # At most MAX_WIDTH_IN wide and 0.6 of that tall (plus the title), where a row per link made
    # 1100 x 29120 px and 3.6 MB; mostly white, it compresses to well under 1 MB.
    width, height = png_pixels(png)
    assert width <= MAX_WIDTH_IN * DPI and height <= (0.6 * MAX_WIDTH_IN + 0.6) * DPI
    assert len(png) < 1e6


@pytest.mark.parametrize("links", [1, MAX_LINK_PANELS, MAX_LINK_PANELS + 1])
def test_the_rows_stop_beyond_the_panel_limit(tmp_path, links):
    sheet_drawing(tmp_path / "sheet.dxf", links)
    fig = sketch_figure(read_sketch(tmp_path / "sheet.dxf"))
    overview = links > 1
    rows = links if links <= MAX_LINK_PANELS else 0
    assert len(fig.axes) == overview + 2 * rows
    assert ("overview only" in fig.get_suptitle()) == (rows == 0)
