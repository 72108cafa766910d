"""Writes ``banana_coupler.dxf``: a four-bar's crank (60 mm), banana coupler (180 mm between pins,
centre line bulging 40 mm, 30 mm wide) and output (150 mm), 8 mm pin holes, in millimetres.
Run ``python make_sketch.py`` in this folder; the output is byte-for-byte reproducible.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from drawing import curved_link, new_drawing, save, straight_link  # noqa: E402


def write(path: Path) -> None:
    doc = new_drawing(units=4)
    msp = doc.modelspace()
    doc.layers.add("crank")
    straight_link(msp, "crank", [(0, 0), (60, 0)], 20, hole=8)
    doc.layers.add("coupler")
    curved_link(msp, "coupler", (0, 80), 180, sag=40, width=30, hole=8)
    doc.layers.add("output")
    straight_link(msp, "output", [(0, 200), (150, 200)], 20, hole=8)
    save(doc, path)


if __name__ == "__main__":
    write(Path(__file__).with_name("banana_coupler.dxf"))
