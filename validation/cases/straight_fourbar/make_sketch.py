"""Writes ``straight_fourbar.dxf``: a four-bar's coupler (500 mm between pins) and rocker (300 mm),
straight plates 44 mm deep with square ends 25 mm past 4 mm pin holes, in millimetres. Every pin
hole is more than 5 diameters from the plate's sides and 3 ahead of its end: the Kt tables' open
plate, whatever the direction of the pin force. Run ``python make_sketch.py`` in this folder; the
output is byte-for-byte reproducible.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from drawing import new_drawing, plate_link, save  # noqa: E402


def write(path: Path) -> None:
    doc = new_drawing(units=4)
    msp = doc.modelspace()
    doc.layers.add("coupler")
    plate_link(msp, "coupler", [(0, 0), (500, 0)], depth=44, end=25, hole=4)
    doc.layers.add("rocker")
    plate_link(msp, "rocker", [(0, 100), (300, 100)], depth=44, end=25, hole=4)
    save(doc, path)


if __name__ == "__main__":
    write(Path(__file__).with_name("straight_fourbar.dxf"))
