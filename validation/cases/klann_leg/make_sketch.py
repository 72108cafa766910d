"""Writes ``klann_leg.dxf``: the Klann leg of the patent's example, 250 mm per patent unit, drawn
assembled at crank angle 30 deg (NOTES.md), in millimetres, each link on its own layer.

6 mm aluminium plates: a ternary frame plate about the crank's shaft O and the rockers' axles U and
L (25 mm bosses, 16 mm bore for the shaft); a crank with a 25 mm boss; the connecting rod bent
12.8 deg at its elbow E and the leg bent 30 deg at its knee K (25 and 30 mm wide, 8 and 10 mm inner
fillets); two 25 mm rockers. 8 mm pin holes; the foot F has an 8 mm hole for its pad. The joints
are where ``truth.py`` places them. Run ``python make_sketch.py`` in this folder; the output is
byte-for-byte reproducible.
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

PIN, SHAFT = 8.0, 16.0
"""Pin hole and crank shaft diameters [mm]."""
PLATES = {
    "frame": (("L", 25.0), ("U", 25.0), ("O", 25.0)),
    "crank": (("O", 25.0), ("A", 12.5)),
    "lower_rocker": (("L", 12.5), ("E", 12.5)),
    "upper_rocker": (("H", 12.5), ("U", 12.5)),
}
"""Rounded plates: the circles (joint, radius [mm]) whose hull is the outline; a hole at each."""
BENT = {"connecting_rod": ("E", ("A", "K"), 25.0, 8.0), "leg": ("K", ("H", "F"), 30.0, 10.0)}
"""Bent links: the corner joint, the arms' ends, the width and the inner fillet [mm]."""


def write(path: Path) -> None:
    truth = runpy.run_path(str(HERE / "truth.py"))
    at = {name: 1000.0 * p[0] for name, p in truth["points"](np.array([truth["DRAWN_INPUT"]])).items()}  # mm
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    for layer, circles in PLATES.items():
        doc.layers.add(layer)
        rounded_plate(msp, layer, [(at[name], radius) for name, radius in circles])
        for name, _ in circles:
            pin_holes(msp, layer, [at[name]], SHAFT if name == "O" else PIN)
    for layer, (corner, ends, width, fillet) in BENT.items():
        doc.layers.add(layer)
        bent_link(msp, layer, tuple(at[corner]), tuple(tuple(at[e]) for e in ends), width=width, fillet=fillet, hole=PIN)
    save(doc, path)


if __name__ == "__main__":
    write(HERE / "klann_leg.dxf")
