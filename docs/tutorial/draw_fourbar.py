"""Draws the tutorial's four-bar, assembled, into ``fourbar.dxf`` beside this script.

A crank-rocker in millimetres: ground pivots O2 = (0, 0) and O4 = (110, 0), crank 35, coupler 120,
rocker 95, drawn with the crank at 60 deg on the open branch. Each link is a round-ended bar 14 mm
wide with 6 mm pin holes, on its own layer (ground, crank, coupler, rocker), drawn as a CAD program
would: LINEs and ARCs for the outline, a CIRCLE per pin hole. Run ``python docs/tutorial/draw_fourbar.py``.
"""

from __future__ import annotations

import math
from pathlib import Path

import ezdxf

WIDTH, HOLE = 14.0, 6.0


def bar(msp, layer: str, start: tuple[float, float], end: tuple[float, float]) -> None:
    """A stadium from ``start`` to ``end`` with a pin hole at each end."""
    angle = math.degrees(math.atan2(end[1] - start[1], end[0] - start[0]))
    nx, ny = -math.sin(math.radians(angle)) * WIDTH / 2, math.cos(math.radians(angle)) * WIDTH / 2
    attrs = {"layer": layer}
    msp.add_line((start[0] - nx, start[1] - ny), (end[0] - nx, end[1] - ny), dxfattribs=attrs)
    msp.add_arc(end, WIDTH / 2, angle - 90, angle + 90, dxfattribs=attrs)
    msp.add_line((end[0] + nx, end[1] + ny), (start[0] + nx, start[1] + ny), dxfattribs=attrs)
    msp.add_arc(start, WIDTH / 2, angle + 90, angle + 270, dxfattribs=attrs)
    for centre in (start, end):
        msp.add_circle(centre, HOLE / 2, dxfattribs=attrs)


def open_branch_b(a: tuple[float, float], o4: tuple[float, float], coupler: float, rocker: float) -> tuple[float, float]:
    """The coupler-rocker pin B: the intersection of the two circles above the line A -> O4."""
    dx, dy = o4[0] - a[0], o4[1] - a[1]
    d = math.hypot(dx, dy)
    along = (coupler**2 - rocker**2 + d**2) / (2 * d)
    across = math.sqrt(coupler**2 - along**2)
    return (a[0] + (along * dx - across * dy) / d, a[1] + (along * dy + across * dx) / d)


def main() -> None:
    ezdxf.options.write_fixed_meta_data_for_testing = True
    doc = ezdxf.new("R2013", units=4)  # $INSUNITS 4: millimetres
    msp = doc.modelspace()
    o2, o4 = (0.0, 0.0), (110.0, 0.0)
    a = (35.0 * math.cos(math.radians(60.0)), 35.0 * math.sin(math.radians(60.0)))
    b = open_branch_b(a, o4, 120.0, 95.0)
    for layer in ("ground", "crank", "coupler", "rocker"):
        doc.layers.add(layer)
    bar(msp, "ground", o2, o4)
    bar(msp, "crank", o2, a)
    bar(msp, "coupler", a, b)
    bar(msp, "rocker", o4, b)
    # CLASS entries sorted (ezdxf orders them by hash), so that the file is the same on every run.
    doc.classes.add_required_classes(doc.dxfversion)
    doc.classes.classes = dict(sorted(doc.classes.classes.items()))
    doc.saveas(Path(__file__).with_name("fourbar.dxf"))


if __name__ == "__main__":
    main()
