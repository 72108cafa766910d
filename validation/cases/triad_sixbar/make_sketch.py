"""Writes ``triad_sixbar.dxf``: the six-bar with a triad drawn assembled at crank angle 70 deg
(NOTES.md), in millimetres, each link on its own layer.

Plates: an 8 mm steel frame plate with 25 mm bosses about O2, O4 and O6; a crank with a 25 mm
boss about its 20 mm shaft; bars 30 mm wide (coupler, rocker, output); the floating ternary link
(B, C, D) a triangular plate with 20 mm corners. 14 mm pin holes elsewhere. The joints are where
``truth.py`` places them. Run ``python make_sketch.py`` in this folder; the output is byte-for-byte
reproducible.
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

PIN, SHAFT = 14.0, 20.0
"""Pin hole and crank shaft diameters [mm]."""
PLATES = {
    "frame": (("O2", 25.0), ("O4", 25.0), ("O6", 25.0)),
    "crank": (("O2", 25.0), ("A", 15.0)),
    "coupler": (("A", 15.0), ("B", 15.0)),
    "ternary": (("B", 20.0), ("C", 20.0), ("D", 20.0)),
    "rocker": (("C", 15.0), ("O4", 15.0)),
    "output": (("O6", 15.0), ("D", 15.0)),
}
"""Each plate: the circles (joint, radius [mm]) whose hull is its outline; a pin hole at each."""


def write(path: Path) -> None:
    truth = runpy.run_path(str(HERE / "truth.py"))
    at = {name: 1000.0 * p[0] for name, p in truth["points"](np.array([truth["DRAWN_INPUT"]])).items()}  # mm
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    for layer, circles in PLATES.items():
        doc.layers.add(layer)
        rounded_plate(msp, layer, [(at[name], radius) for name, radius in circles])
        for name, _ in circles:
            pin_holes(msp, layer, [at[name]], SHAFT if name == "O2" else PIN)
    save(doc, path)


if __name__ == "__main__":
    write(HERE / "triad_sixbar.dxf")
