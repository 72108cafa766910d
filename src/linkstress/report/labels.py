"""Labels on a drawing placed so that no two overlap.

A mechanism's joint forces meet at shared pins (two loops' forces on one pivot) and its links' "max"
marks fall beside them: labels written at a fixed offset print on top of each other. Each label is
tried at offsets around its point, nearest first, in eight directions and at growing distances
(with a thin leader line past the first ring), and takes the first place where its box, as the
renderer measures it, stays inside the axes and clear of every label placed before it. A label
with no such place is left off the drawing and returned, for the caller to list beside it.

Boxes are measured once the figure's layout has settled at the resolution it will be saved at
(``PLACEMENT_DPI``); the labels keep out of the layout, so placing them moves nothing else.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from matplotlib.transforms import Bbox

from linkstress.report.figure_notes import figure_warnings

PLACEMENT_DPI = 110
"""The resolution the reports' figures are saved at (``figures.png_bytes``)."""
GAP_PX = 3.0
"""Space kept between two labels' boxes, and between a box and the axes' edge [pixels]."""
RINGS_PT = (8.0, 20.0, 34.0, 52.0, 74.0)
"""Distances [points] of the tried places from a label's point, nearest first."""
MARK_PX = 14.0
"""The size [pixels] of a marker labels keep off (a 12 pt star at PLACEMENT_DPI is about 18 px tip to tip)."""
DIRECTIONS = ((1, 1), (1, -1), (-1, 1), (-1, -1), (1, 0), (-1, 0), (0, 1), (0, -1))
"""Sides tried at each distance: up-right first, as a label is usually written."""


@dataclass
class LabelPlacer:
    """Labels to place on ``ax``: ``add`` each (most important first), then ``place``."""

    ax: object
    requests: list[tuple[str, tuple[float, float], dict]] = field(default_factory=list)
    marks: list[tuple[float, float]] = field(default_factory=list)

    def add(self, text: str, at, **style) -> None:
        """A label ``text`` for the point ``at`` (data coordinates) with text ``style`` (fontsize,
        color, bbox ...)."""
        self.requests.append((text, (float(at[0]), float(at[1])), style))

    def avoid(self, at) -> None:
        """Keep labels off a marker (MARK_PX across) at the point ``at`` (data coordinates)."""
        self.marks.append((float(at[0]), float(at[1])))

    def place(self) -> list[str]:
        """Place every label where it overlaps none placed before it; returns the texts left off."""
        fig = self.ax.figure
        fig.set_dpi(PLACEMENT_DPI)
        with figure_warnings():  # a glyph its font lacks: not onto the terminal
            fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        frame = self.ax.get_window_extent(renderer)
        scale = PLACEMENT_DPI / 72.0
        half = MARK_PX / 2
        placed = [Bbox.from_bounds(x - half, y - half, MARK_PX, MARK_PX)
                  for x, y in (self.ax.transData.transform(m) for m in self.marks)]
        left_off = []
        for text, at, style in self.requests:
            probe = self._annotation(text, at, (0.0, 0.0), style)
            width, height = _size(probe, renderer)
            probe.remove()
            anchor = self.ax.transData.transform(at)
            spot = _free_spot(anchor, width, height, frame, placed, scale)
            if spot is None:
                left_off.append(text)
                continue
            (x0, y0), ring = spot
            leader = dict(arrowstyle="-", lw=0.5, color=style.get("color", "k"), shrinkA=0.0, shrinkB=0.0)
            self._annotation(text, at, ((x0 - anchor[0]) / scale, (y0 - anchor[1]) / scale), style,
                             leader if ring > 0 else None)
            placed.append(Bbox.from_bounds(x0, y0, width, height))
        return left_off

    def _annotation(self, text: str, at, offset, style: dict, arrowprops: dict | None = None):
        """``text`` with its lower left ``offset`` points from ``at``, out of the figure's layout."""
        label = self.ax.annotate(
            text, at, textcoords="offset points", xytext=offset, ha="left", va="bottom",
            annotation_clip=False, arrowprops=arrowprops, **style,
        )
        label.set_in_layout(False)
        return label


def _size(label, renderer) -> tuple[float, float]:
    """Width and height [pixels] of ``label`` as drawn, its box (if any) included."""
    boxes = [label.get_window_extent(renderer)]
    patch = label.get_bbox_patch()
    if patch is not None:
        label.update_bbox_position_size(renderer)
        boxes.append(patch.get_window_extent(renderer))
    box = Bbox.union(boxes)
    return box.width, box.height


def _free_spot(anchor, width: float, height: float, frame: Bbox, placed: list[Bbox], scale: float):
    """The lower-left corner [pixels] of the first place around ``anchor`` where a ``width`` x
    ``height`` box stays GAP_PX inside ``frame`` and clear of ``placed``, with the index of its
    ring; None where there is none."""
    for ring, distance in enumerate(RINGS_PT):
        reach = distance * scale
        for dx, dy in DIRECTIONS:
            x0 = anchor[0] + (reach if dx > 0 else -reach - width if dx < 0 else -width / 2)
            y0 = anchor[1] + (reach if dy > 0 else -reach - height if dy < 0 else -height / 2)
            box = Bbox.from_bounds(x0, y0, width, height)
            if not _inside(box, frame):
                continue
            if any(_near(box, other) for other in placed):
                continue
            return (x0, y0), ring
    return None


def _inside(box: Bbox, frame: Bbox) -> bool:
    return (box.x0 >= frame.x0 + GAP_PX and box.x1 <= frame.x1 - GAP_PX
            and box.y0 >= frame.y0 + GAP_PX and box.y1 <= frame.y1 - GAP_PX)


def _near(box: Bbox, other: Bbox) -> bool:
    """Whether two boxes come within GAP_PX of each other."""
    return bool(np.all([box.x0 < other.x1 + GAP_PX, other.x0 < box.x1 + GAP_PX,
                        box.y0 < other.y1 + GAP_PX, other.y0 < box.y1 + GAP_PX]))
