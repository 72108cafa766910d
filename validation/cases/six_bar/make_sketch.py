"""Writes ``six_bar.dxf``: a two-loop machine (six bars) in millimetres, links 6 mm steel plates.

Main loop: crank 40, coupler 120, rocker 100 on a 100 mm ground (a crank-rocker). The rocker is a
ternary link: it carries the main loop's B and, 50 mm beyond its pivot, the crank pin of the
second loop (rod 140, output 90, ground 150), which it drives rigidly. Each link on its own layer,
drawn apart from the others with its first joint where it is drawn. Run ``python make_sketch.py``
in this folder; the output is byte-for-byte reproducible.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from drawing import new_drawing, save, straight_link  # noqa: E402


def write(path: Path) -> None:
    doc = new_drawing(units=4)  # millimetres
    msp = doc.modelspace()
    links = {
        "crank": ([(0, 0), (40, 0)], 16),
        "coupler": ([(0, 60), (120, 60)], 20),
        "rocker": ([(-50, 120), (0, 120), (100, 120)], 20),
        "rod2": ([(0, 180), (140, 180)], 16),
        "out2": ([(0, 240), (90, 240)], 16),
    }
    for layer, (joints, width) in links.items():
        doc.layers.add(layer)
        straight_link(msp, layer, joints, width, hole=6)
    save(doc, path)


if __name__ == "__main__":
    write(Path(__file__).with_name("six_bar.dxf"))
