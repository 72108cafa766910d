"""A picture of a sketch's links (matplotlib, Agg, no screen).

First an overview of the whole sketch in its frame [m]: every link's outline, holes and joints in
place, its name inside its outline. Then, when the sketch holds at most ``MAX_LINK_PANELS`` links, a
row per link: the link with its numbered joints and member axis in the sketch frame [m], and U(x),
L(x) in its member frame [m]. Each kind of line (outlines, holes, joints) is one artist for all the
links it shows, so a sheet of a hundred parts draws in about a second.
"""

from __future__ import annotations

import io
from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PathCollection
from matplotlib.figure import Figure
from matplotlib.legend_handler import HandlerPolyCollection
from matplotlib.path import Path
from matplotlib.ticker import MaxNLocator
from numpy.typing import NDArray
from shapely.geometry import Polygon
from shapely.ops import polylabel

from linkstress.importers.sketch import ImportedLink, Sketch
from linkstress.importers.summary import NO_PROFILE
from linkstress.report.figure_notes import figure_warnings

MAX_LINK_PANELS = 12
"""A sketch of more links gets the overview only: a row per link of a 91-part sheet would be a PNG
29,000 pixels tall that took 24 s to draw."""
DPI = 100
ROW_HEIGHT_IN = 3.2
"""Height of one link's row of panels [in]."""
WIDTH_IN = 11.0
"""Width of a picture with per-link rows [in]; an overview alone is 2 sqrt(n) in wide for n links, up
to ``MAX_WIDTH_IN``: on a square sheet each part keeps about 2 in, room for its name."""
MAX_WIDTH_IN = 20.0
TICKS = 6
"""At most this many ticks per axis: coordinates such as 0.325 m need the room."""
NAME_POINTS = 7
ELONGATED = 2.0
"""A link whose oriented bounding box is longer than this many times its width carries its name
along its length."""
LEGEND = dict(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, fontsize=7,
              handler_map={PathCollection: HandlerPolyCollection()})
"""Legends sit outside their axes, on the right, so that they never hide geometry; the outlines'
collection shows as a filled box (the default handler draws scatter markers, of no size here)."""


def sketch_png(sketch: Sketch) -> bytes:
    """PNG bytes of ``sketch_figure(sketch)``."""
    buffer = io.BytesIO()
    with figure_warnings():  # a glyph its font lacks (a CJK layer name): not onto the terminal
        sketch_figure(sketch).savefig(buffer, format="png", dpi=DPI)
    return buffer.getvalue()


def sketch_figure(sketch: Sketch) -> Figure:
    """The overview of every link (sketch frame [m]) when there are several, then a row per link
    (sketch frame [m] on the left, U(x) and L(x) in its member frame [m] on the right) when there
    are at most ``MAX_LINK_PANELS``; the figure says when the rows are left out."""
    links = sketch.links
    rows = links if len(links) <= MAX_LINK_PANELS else ()
    width = WIDTH_IN if rows else float(np.clip(2.0 * np.sqrt(len(links)), WIDTH_IN, MAX_WIDTH_IN))
    heights = ([_overview_height(links, width)] if len(links) > 1 else []) + [ROW_HEIGHT_IN] * len(rows)
    # A bare Figure, not pyplot's: nothing global to close; its Agg canvas can draw to measure text.
    fig = Figure(figsize=(width, sum(heights) + 0.6), layout="constrained")
    FigureCanvasAgg(fig)
    grid = fig.add_gridspec(len(heights), 2, height_ratios=heights)
    title = f"{sketch.path.name}: {len(links)} link(s) ({sketch.units}, shown in m)"
    if len(links) > 1:
        _overview(fig.add_subplot(grid[0, :]), links)
    if len(links) > len(rows):
        title += (f"\n{len(links)} links: overview only (a row per link up to {MAX_LINK_PANELS} links); "
                  "every link's U(x), L(x) is in --json")
    for row, link in enumerate(rows, start=len(heights) - len(rows)):
        _link_panel(fig.add_subplot(grid[row, 0]), link)
        _bounds_panel(fig.add_subplot(grid[row, 1]), link)
    fig.suptitle(title, fontsize=10)
    return fig


def _overview_height(links: Sequence[ImportedLink], width: float) -> float:
    """Height [in] of the overview: the sketch's aspect at ``width`` less the legend's 1.5 in, from
    3 in to 0.6 ``width`` (a tall sketch is drawn narrower rather than as a tower)."""
    xmin, ymin, xmax, ymax = _box(links)
    aspect = (ymax - ymin) / (xmax - xmin)
    return float(np.clip((width - 1.5) * aspect, 3.0, 0.6 * width))


def _overview(ax: Axes, links: Sequence[ImportedLink]) -> None:
    _draw_links(ax, links)
    for link in links:
        _name(ax, link)
    ax.set_title("every link in place, sketch frame [m]", fontsize=9)
    ax.legend(**LEGEND)


def _link_panel(ax: Axes, link: ImportedLink) -> None:
    _draw_links(ax, [link])
    for k, (p, rule) in enumerate(zip(link.joints, link.joint_rules)):
        ax.annotate(f"{k} ({rule})", p, textcoords="offset points", xytext=(4, 4), fontsize=7)
    if len(link.joints) >= 2:
        profile = link.profile(1.0)
        lo, hi = profile.x_extent(0, 1)
        axis = profile.frame(0, 1).to_global(np.array([[lo, 0.0], [hi, 0.0]]))
        ax.plot(*axis.T, "--", color="tab:red", lw=0.8, zorder=4, label="member axis")
    ax.set_title(f"{link.name}: sketch frame [m]", fontsize=9)
    ax.legend(**LEGEND)


def _bounds_panel(ax: Axes, link: ImportedLink) -> None:
    if len(link.joints) < 2:
        ax.text(0.5, 0.5, NO_PROFILE.format(n=len(link.joints)), ha="center", va="center", wrap=True,
                fontsize=8, transform=ax.transAxes)
        ax.set_axis_off()
        return
    x, upper, lower = link.profile(1.0).bounds(0, 1).polyline()
    ax.fill_between(x, lower, upper, color="0.9")
    ax.plot(x, upper, color="tab:green", lw=1, label="U(x)")
    ax.plot(x, lower, color="tab:purple", lw=1, label="L(x)")
    ax.axhline(0.0, color="tab:red", ls="--", lw=0.8)
    ax.set_xlabel("x along joint 0 -> joint 1 [m]", fontsize=8)
    ax.set_title(f"{link.name}: bounding functions, member frame [m]", fontsize=9)
    _ticks(ax)
    ax.legend(**LEGEND)


def _draw_links(ax: Axes, links: Sequence[ImportedLink]) -> None:
    """Outlines filled (holes left open), hole rings and joints of ``links``, one artist per kind;
    equal aspect with the limits, not the box, stretched to it, so that a narrow link keeps a
    panel wide enough for its tick labels."""
    ax.add_collection(PathCollection([_path(link.outline) for link in links], facecolor="0.85",
                                     edgecolor="k", linewidth=0.8, zorder=1, label="outline"))
    holes = [np.asarray(ring.coords) for link in links for ring in link.outline.interiors]
    if holes:
        ax.add_collection(LineCollection(holes, colors="tab:blue", linewidths=0.8, zorder=2, label="holes"))
    joints = np.vstack([link.joints for link in links])
    if len(joints):
        ax.plot(*joints.T, "o", color="tab:red", ms=4, zorder=4, label="joints")
    xmin, ymin, xmax, ymax = _box(links)
    pad = 0.05 * max(xmax - xmin, ymax - ymin)
    # Data limits, not fixed limits: the equal aspect may then widen whichever side it needs.
    ax.update_datalim([(xmin - pad, ymin - pad), (xmax + pad, ymax + pad)])
    ax.margins(0.0)
    ax.set_aspect("equal", adjustable="datalim")
    _ticks(ax)


def _ticks(ax: Axes) -> None:
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(MaxNLocator(nbins=TICKS, steps=[1, 2, 2.5, 5, 10]))
    # Absolute coordinates: an offset ("+3.25e-1") would hide where the link is.
    ax.ticklabel_format(useOffset=False)
    ax.tick_params(labelsize=7)


def _path(outline: Polygon) -> Path:
    """The outline as one compound path: shell counter-clockwise and holes clockwise (as
    ``ImportedLink`` keeps them), so the non-zero fill leaves the holes open."""
    rings = [np.asarray(ring.coords) for ring in (outline.exterior, *outline.interiors)]
    codes = []
    for ring in rings:
        code = np.full(len(ring), Path.LINETO, dtype=Path.code_type)
        code[0], code[-1] = Path.MOVETO, Path.CLOSEPOLY
        codes.append(code)
    return Path(np.vstack(rings), np.concatenate(codes))


def _name(ax: Axes, link: ImportedLink) -> None:
    """The link's name at its pole of inaccessibility (the inside point farthest from the outline),
    along its length when it is elongated."""
    outline = link.outline
    xmin, ymin, xmax, ymax = outline.bounds
    where = polylabel(outline, tolerance=1e-3 * max(xmax - xmin, ymax - ymin))
    ax.text(where.x, where.y, link.name, fontsize=NAME_POINTS, ha="center", va="center",
            rotation=_long_side_deg(outline), rotation_mode="anchor", zorder=5,
            bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.7))


def _long_side_deg(outline: Polygon) -> float:
    """Direction of the outline's oriented bounding box's long side in (-89, 91] degrees, or 0 when
    the box is less than ``ELONGATED`` times longer than wide."""
    corners = np.asarray(outline.minimum_rotated_rectangle.exterior.coords)
    sides = np.diff(corners[:3], axis=0)
    lengths = np.hypot(*sides.T)
    if lengths.min() * ELONGATED > lengths.max():
        return 0.0
    dx, dy = sides[np.argmax(lengths)]
    angle = float(np.degrees(np.arctan2(dy, dx)) % 180.0)
    # Up to a degree past vertical still reads upward: rounding must not turn an upright name over.
    return angle - 180.0 if angle > 91.0 else angle


def _box(links: Sequence[ImportedLink]) -> NDArray[np.float64]:
    """(xmin, ymin, xmax, ymax) [m] of the links' outlines."""
    boxes = np.array([link.outline.bounds for link in links])
    return np.concatenate([boxes[:, :2].min(axis=0), boxes[:, 2:].max(axis=0)])
