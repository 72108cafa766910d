"""Writes ``jansen_leg.dxf``: Theo Jansen's leg at his lengths, drawn assembled at crank angle 0
(NOTES.md), in millimetres, each link on its own layer.

8 mm aluminium plates a builder would laser-cut: 30 mm bars (the rods j and k, the rocker c, the
thigh f), the two triangles (hip B-C-E and shin D-F-G) with 25 mm corners, a crank with a 35 mm
boss about its 20 mm axle, a frame bar from the axle O to the pivot B with bosses. 12 mm pin holes;
a 10 mm hole at the foot G for its pad. The joints are where ``truth.py`` places them. Run
``python make_sketch.py`` in this folder; the output is byte-for-byte reproducible.
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from drawing import new_drawing, save  # noqa: E402
from linkage_support.plates import pin_holes, rounded_plate  # noqa: E402

HOLES = {"O": 20.0, "G": 10.0}
"""Hole diameters [mm] other than the 12 mm pins: the crank's axle and the foot pad's bolt."""
PLATES = {
    "frame": (("B", 30.0), ("O", 40.0)),
    "crank": (("O", 35.0), ("A", 20.0)),
    "upper_rod": (("A", 15.0), ("C", 15.0)),
    "lower_rod": (("A", 15.0), ("D", 15.0)),
    "hip": (("B", 25.0), ("C", 25.0), ("E", 25.0)),
    "rocker": (("B", 15.0), ("D", 15.0)),
    "thigh": (("E", 15.0), ("F", 15.0)),
    "shin": (("D", 25.0), ("F", 25.0), ("G", 25.0)),
}
"""Each plate: the circles (joint, radius [mm]) whose hull is its outline; a hole at each."""


def write(path: Path) -> None:
    truth = runpy.run_path(str(HERE / "truth.py"))
    at = {name: 1000.0 * p[0] for name, p in truth["points"](np.array([truth["DRAWN_INPUT"]])).items()}  # mm
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    for layer, circles in PLATES.items():
        doc.layers.add(layer)
        rounded_plate(msp, layer, [(at[name], radius) for name, radius in circles])
        for name, _ in circles:
            pin_holes(msp, layer, [at[name]], HOLES.get(name, 12.0))
    save(doc, path)


if __name__ == "__main__":
    write(HERE / "jansen_leg.dxf")
