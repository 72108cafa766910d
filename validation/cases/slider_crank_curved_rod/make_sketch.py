"""Writes ``curved_rod.dxf``: a slider-crank's crank (50 mm) and curved connecting rod (200 mm
between pins, its centre line an arc bulging 25 mm, 24 mm wide), in millimetres, layers ``crank``
and ``rod``. Run ``python make_sketch.py`` in this folder; the output is byte-for-byte reproducible.
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
    straight_link(msp, "crank", [(0, 0), (50, 0)], 20, hole=8)
    doc.layers.add("rod")
    curved_link(msp, "rod", (0, 60), 200, sag=25, width=24, hole=8)
    save(doc, path)


if __name__ == "__main__":
    write(Path(__file__).with_name("curved_rod.dxf"))
