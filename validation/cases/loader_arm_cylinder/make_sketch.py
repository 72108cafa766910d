"""Writes ``loader_arm_cylinder.dxf``: the loader arm and its lift cylinder drawn assembled at a
stroke of 1.20 m (NOTES.md), in millimetres, each link on its own layer.

The frame (the loader's tower plate) with 40 mm bores for the arm's pivot P0 and the cylinder's
base pin Q; the arm, a 180 mm deep plate bent 30 deg down at the cylinder's pin K, with a 40 mm
inner fillet and 40 mm pin holes at P0, K and the bucket pin T; the cylinder's barrel, 110 mm
across, round about its base pin Q and square at its head, with a POINT on its axis 950 mm from Q
(the line the rod slides on); the rod, an 80 mm eye about K tapering to 50 mm, reaching 850 mm back
into the barrel. The joints are where ``truth.py`` places them. Run ``python make_sketch.py`` in
this folder; the output is byte-for-byte reproducible.
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from drawing import bent_link, new_drawing, save  # noqa: E402
from linkage_support.plates import capsule, joints, pin_holes, rounded_plate  # noqa: E402

PIN = 40.0
"""Every pin's hole [mm]."""
BARREL = (110.0, 960.0)
"""The barrel's outer diameter and its length from the base pin to the head's face [mm]."""
ROD = (40.0, 25.0, 850.0)
"""The rod's eye radius, its own radius and its length from the eye back into the barrel [mm]."""


def write(path: Path) -> None:
    truth = runpy.run_path(str(HERE / "truth.py"))
    at = {name: 1000.0 * p[0] for name, p in truth["points"](np.array([truth["DRAWN_INPUT"]])).items()}  # mm
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    for layer in ("frame", "arm", "barrel", "rod"):
        doc.layers.add(layer)

    rounded_plate(msp, "frame", [(at["P0"], 70.0), (at["Q"], 60.0)])
    pin_holes(msp, "frame", [at["P0"], at["Q"]], PIN)

    bent_link(msp, "arm", tuple(at["K"]), (tuple(at["P0"]), tuple(at["T"])), width=180.0, fillet=40.0, hole=PIN)

    axis = (at["K"] - at["Q"]) / np.hypot(*(at["K"] - at["Q"]))
    diameter, length = BARREL
    capsule(msp, "barrel", at["Q"], at["Q"] + length * axis, diameter, round_start=True, round_end=False)
    pin_holes(msp, "barrel", [at["Q"]], PIN)
    joints(msp, "barrel", [at["H"]])

    eye, radius, reach = ROD
    rounded_plate(msp, "rod", [(at["K"], eye), (at["K"] - reach * axis, radius)])
    pin_holes(msp, "rod", [at["K"]], PIN)
    save(doc, path)


if __name__ == "__main__":
    write(HERE / "loader_arm_cylinder.dxf")
