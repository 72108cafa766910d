"""Writes ``watt2_sixbar.dxf``: the Watt II six-bar of ``../bell_crank`` drawn assembled, in
millimetres, at crank angle 0 (NOTES.md), each link on its own layer.

The plates are bell_crank's: 10 mm steel, 12 mm pin holes; crank 30 wide, coupler and rod 25,
output 30; the L-shaped bell crank 35 wide with a 10 mm inner fillet and a round boss about its
pivot O4; the frame a ternary plate with 20 mm bosses about O2, O4 and O6. The joints are where
``truth.py`` places them from the lengths. Run ``python make_sketch.py`` in this folder; the output
is byte-for-byte reproducible.
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from drawing import bent_link, new_drawing, save  # noqa: E402
from linkage_support.plates import pin_holes, rounded_plate  # noqa: E402

HOLE = 12.0
BARS = {"crank": (("O2", "A"), 30.0), "coupler": (("A", "B"), 25.0), "rod": (("C", "D"), 25.0), "output": (("O6", "D"), 30.0)}
"""Straight links: their pins and width [mm]."""


def write(path: Path) -> None:
    truth = runpy.run_path(str(HERE / "truth.py"))
    at = {name: 1000.0 * p[0] for name, p in truth["points"](np.array([truth["DRAWN_INPUT"]])).items()}  # mm
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    doc.layers.add("frame")
    rounded_plate(msp, "frame", [(at[name], 20.0) for name in ("O2", "O4", "O6")])
    pin_holes(msp, "frame", [at[name] for name in ("O2", "O4", "O6")], HOLE)
    for layer, (pins, width) in BARS.items():
        doc.layers.add(layer)
        rounded_plate(msp, layer, [(at[name], width / 2) for name in pins])
        pin_holes(msp, layer, [at[name] for name in pins], HOLE)
    doc.layers.add("bellcrank")
    bent_link(msp, "bellcrank", tuple(at["O4"]), (tuple(at["B"]), tuple(at["C"])), width=35.0, fillet=10.0, hole=HOLE)
    save(doc, path)


if __name__ == "__main__":
    write(HERE / "watt2_sixbar.dxf")
