"""Writes ``stephenson3_press.dxf``: the Stephenson III press drive drawn assembled at crank angle
60 deg (NOTES.md), in millimetres, each link on its own layer.

Plates a designer would cut for it: a 15 mm frame plate with 30 mm bosses about the three fixed
pivots; a crank with a 30 mm boss about its 25 mm shaft; a ternary coupler plate (A, P, B) with
20 mm corners; a rocker with a boss at its pivot; the dyad's link; an output lever with a 28 mm
boss at its pivot O6 tapering to a 20 mm eye at the tool end T. 16 mm pin holes elsewhere. The
joints are where ``truth.py`` places them from the lengths. Run ``python make_sketch.py`` in this
folder; the output is byte-for-byte reproducible.
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

PIN, SHAFT = 16.0, 25.0
"""Pin hole and crank shaft diameters [mm]."""
PLATES = {
    "frame": ((("O2", 30.0), ("O4", 30.0), ("O6", 30.0)), ("O2", "O4", "O6")),
    "crank": ((("O2", 30.0), ("A", 18.0)), ("O2", "A")),
    "coupler": ((("A", 20.0), ("P", 20.0), ("B", 20.0)), ("A", "P", "B")),
    "rocker": ((("B", 18.0), ("O4", 22.0)), ("B", "O4")),
    "link": ((("P", 16.0), ("Q", 16.0)), ("P", "Q")),
    "lever": ((("O6", 28.0), ("T", 20.0)), ("O6", "Q", "T")),
}
"""Each plate: the circles (joint, radius [mm]) whose hull is its outline, and its pin holes."""


def write(path: Path) -> None:
    truth = runpy.run_path(str(HERE / "truth.py"))
    at = {name: 1000.0 * p[0] for name, p in truth["points"](np.array([truth["DRAWN_INPUT"]])).items()}  # mm
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    for layer, (circles, holes) in PLATES.items():
        doc.layers.add(layer)
        rounded_plate(msp, layer, [(at[name], radius) for name, radius in circles])
        pin_holes(msp, layer, [at[name] for name in holes if name != "O2"], PIN)
        if "O2" in holes:
            pin_holes(msp, layer, [at["O2"]], SHAFT)
    save(doc, path)


if __name__ == "__main__":
    write(HERE / "stephenson3_press.dxf")
