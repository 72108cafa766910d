"""Writes ``arc_coupler.dxf``: a four-bar's crank (40 mm, 24 wide), circular-arc coupler and output
(100 mm, 24 wide), 10 mm pin holes, in millimetres. The coupler's centre line is a half circle of
radius 60 mm between its pins (120 mm apart), the bar 20 mm deep (radius over depth 3), with a
30 mm round lug about each pin joined to the bar's edges by 5 mm fillets. Run ``python
make_sketch.py`` in this folder; the output is byte-for-byte reproducible.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from drawing import arc_link, new_drawing, save, straight_link  # noqa: E402

HOLE = 10


def write(path: Path) -> None:
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    doc.layers.add("crank")
    straight_link(msp, "crank", [(0, 0), (40, 0)], 24, hole=HOLE)
    doc.layers.add("coupler")
    arc_link(msp, "coupler", (60, 60), 60, 0, 180, depth=20, lug=30, fillet=5, hole=HOLE)
    doc.layers.add("output")
    straight_link(msp, "output", [(0, 160), (100, 160)], 24, hole=HOLE)
    save(doc, path)


if __name__ == "__main__":
    write(Path(__file__).with_name("arc_coupler.dxf"))
