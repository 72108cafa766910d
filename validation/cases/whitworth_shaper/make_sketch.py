"""Writes ``whitworth_shaper.dxf``: the crank-shaper quick-return drawn assembled at crank angle
30 deg (NOTES.md), in millimetres, each link on its own layer.

A frame plate (column) from the lever's pivot O4 up to the ram's guide, with a 40 mm bore for the
crank's shaft at O2 and a 30 mm one at O4, and two POINTs on the ram's guide line; the crank (the
bull gear's crank arm, a 60 mm boss about O2); the slotted lever (45 mm boss at O4, 35 mm eye at T,
a 36 mm slot from 150 to 450 mm along it); the collar, a 70 x 36 mm block in the slot on the crank
pin; the rod T -> R; the ram, a 650 x 100 mm block on its guide with its pin R. The joints are
where ``truth.py`` places them. Run ``python make_sketch.py`` in this folder; the output is
byte-for-byte reproducible.
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from drawing import new_drawing, save  # noqa: E402
from linkage_support.plates import joints, pin_holes, rectangle, rounded_plate, slot  # noqa: E402

PIN = 20.0
"""The pins' holes [mm]: crank pin, T, R."""
SLOT = (150.0, 450.0, 36.0)
"""The lever's slot: from and to [mm along O4 -> T], width [mm]."""
RAM = (-450.0, 200.0, 100.0)
"""The ram's ends behind and ahead of its pin R along the guide, and its depth [mm]."""


def write(path: Path) -> None:
    truth = runpy.run_path(str(HERE / "truth.py"))
    at = {name: 1000.0 * p[0] for name, p in truth["points"](np.array([truth["DRAWN_INPUT"]])).items()}  # mm
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    for layer in ("frame", "crank", "collar", "lever", "rod", "ram"):
        doc.layers.add(layer)

    rounded_plate(msp, "frame", [(at["G1"], 40.0), (at["G2"], 40.0), (at["O4"], 50.0)])
    pin_holes(msp, "frame", [at["O4"]], 30.0)
    pin_holes(msp, "frame", [at["O2"]], 40.0)
    joints(msp, "frame", [at["G1"], at["G2"]])

    rounded_plate(msp, "crank", [(at["O2"], 60.0), (at["A"], 22.0)])
    pin_holes(msp, "crank", [at["O2"]], 40.0)
    pin_holes(msp, "crank", [at["A"]], PIN)

    lever = (at["T"] - at["O4"]) / np.hypot(*(at["T"] - at["O4"]))
    rectangle(msp, "collar", at["A"], lever, 70.0, SLOT[2])
    pin_holes(msp, "collar", [at["A"]], PIN)

    rounded_plate(msp, "lever", [(at["O4"], 45.0), (at["T"], 35.0)])
    slot(msp, "lever", at["O4"] + SLOT[0] * lever, at["O4"] + SLOT[1] * lever, SLOT[2])
    pin_holes(msp, "lever", [at["O4"]], 30.0)
    pin_holes(msp, "lever", [at["T"]], PIN)

    rounded_plate(msp, "rod", [(at["T"], 22.0), (at["R"], 22.0)])
    pin_holes(msp, "rod", [at["T"], at["R"]], PIN)

    behind, ahead, depth = RAM
    rectangle(msp, "ram", at["R"] + np.array([(behind + ahead) / 2, 0.0]), (1.0, 0.0), ahead - behind, depth)
    pin_holes(msp, "ram", [at["R"]], PIN)
    save(doc, path)


if __name__ == "__main__":
    write(HERE / "whitworth_shaper.dxf")
