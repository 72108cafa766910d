"""Independent truth for the Klann leg (NOTES.md): positions from the patent's example leg by
circle intersections, rates by finite differences, forces by Newton-Euler, checked by the power
balance.

Run ``python truth.py`` in this folder: it writes ``truth.json`` and prints a summary.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from linkage_support.geometry import circle_circle, distance, unit  # noqa: E402
from linkage_support.truth import linked, run, summary  # noqa: E402

PATENT = {
    "U": (1.366, 1.366),  # 9, the upper rocker's axle
    "L": (1.009, 0.574),  # 11, the lower rocker's axle
    "O": (1.599, 0.750),  # 15, the crank's shaft
    "E": (1.277, 0.750),  # 27, the elbow: connecting rod and lower rocker
    "A": (1.867, 0.750),  # 29, the crank pin
    "F": (1.000, 0.000),  # 33, the foot
    "K": (0.768, 0.866),  # 35, the knee: connecting rod and leg
    "H": (1.000, 1.732),  # 37, the hip: leg and upper rocker
}
"""The example leg of Klann's US patent 6,260,862 (NOTES.md): its points (patent numbers in the
comments), in its units, at crank angle 0 (the crank pin straight ahead of the shaft)."""
SCALE = 0.25
"""Metres per patent unit: a leg 433 mm from hip to foot."""
DRAWN_INPUT = math.radians(30.0)
STEP = 1e-2
"""The finite differences' step in the crank angle [rad]."""
LINKS = {
    "frame": ("L", "U", "O"),
    "crank": ("O", "A"),
    "connecting_rod": ("K", "E", "A"),
    "lower_rocker": ("L", "E"),
    "upper_rocker": ("H", "U"),
    "leg": ("K", "H", "F"),
}
"""Each link's joints in the drawing's order (x, then y, as drawn at 30 deg)."""


def _at(name: str) -> np.ndarray:
    """A patent point [m], the crank's shaft at the origin."""
    return SCALE * (np.array(PATENT[name]) - np.array(PATENT["O"]))


def _length(p: str, q: str) -> float:
    return float(distance(_at(p), _at(q)))


def points(theta: np.ndarray) -> dict[str, np.ndarray]:
    """Every joint (P, 2) [m] at crank angles ``theta`` (P,) [rad], in the patent's assembly."""
    n = len(theta)
    fixed = {name: np.tile(_at(name), (n, 1)) for name in ("O", "U", "L")}
    a = fixed["O"] + _length("O", "A") * unit(theta)
    e = circle_circle(a, _length("A", "E"), fixed["L"], _length("L", "E"), -1)  # elbow below A -> L
    k = circle_circle(a, _length("A", "K"), e, _length("E", "K"), -1)  # the rod's 12.8 deg bend, up
    h = circle_circle(k, _length("K", "H"), fixed["U"], _length("U", "H"), +1)  # hip left of K -> U
    f = circle_circle(k, _length("K", "F"), h, _length("H", "F"), -1)  # foot right of K -> H
    return {**fixed, "A": a, "E": e, "K": k, "H": h, "F": f}


place = linked(points, LINKS)


def main() -> None:
    print(summary(run(HERE, place, STEP)))


if __name__ == "__main__":
    main()
