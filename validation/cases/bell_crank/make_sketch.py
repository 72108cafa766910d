"""Writes ``bell_crank.dxf``: a two-loop machine in millimetres whose middle link is an L-shaped
bell crank, links 10 mm steel plates, 12 mm pin holes.

Main loop: crank 50 (30 wide), coupler 200 (25 wide), bell crank arm O4 -> B 150 on a 200 mm
ground (a crank-rocker). The bell crank has three pins: its pivot O4 at the corner, B at the end of
one arm and C at the end of the other, 150 mm from O4 at 90 degrees clockwise of O4 -> B; arms
35 mm wide with a 10 mm fillet at the inner corner and a round boss about O4 at the outer one. C is
the crank pin of the second loop (rod 150, 25 wide; output 120, 30 wide), which the bell crank
drives rigidly. Each link on its own layer, drawn apart from the others. Run ``python
make_sketch.py`` in this folder; the output is byte-for-byte reproducible.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from drawing import bent_link, new_drawing, save, straight_link  # noqa: E402

HOLE = 12


def write(path: Path) -> None:
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    straight = {
        "crank": ([(0, 0), (50, 0)], 30),
        "coupler": ([(0, 60), (200, 60)], 25),
        "rod2": ([(0, 380), (150, 380)], 25),
        "out2": ([(0, 440), (120, 440)], 30),
    }
    for layer, (joints, width) in straight.items():
        doc.layers.add(layer)
        straight_link(msp, layer, joints, width, hole=HOLE)
    # Joints sorted by x then y: 0 = C (0, 170), 1 = O4 (0, 320), 2 = B (150, 320).
    doc.layers.add("bellcrank")
    bent_link(msp, "bellcrank", (0, 320), ((150, 320), (0, 170)), width=35, fillet=10, hole=HOLE)
    save(doc, path)


if __name__ == "__main__":
    write(Path(__file__).with_name("bell_crank.dxf"))
