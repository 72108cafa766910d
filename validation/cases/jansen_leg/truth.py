"""Independent truth for Jansen's leg (NOTES.md): positions from his published lengths by circle
intersections, rates by finite differences, forces by Newton-Euler, checked by the power balance.

Run ``python truth.py`` in this folder: it writes ``truth.json`` and prints a summary.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from linkage_support.geometry import circle_circle, unit  # noqa: E402
from linkage_support.truth import linked, run, summary  # noqa: E402

CM = 0.01
"""Jansen gives his lengths in centimetres."""
LENGTHS = {k: v * CM for k, v in dict(a=38.0, b=41.5, c=39.3, d=40.1, e=55.8, f=39.4, g=36.7, h=65.7,
                                        i=49.0, j=50.0, k=61.9, l=7.8, m=15.0).items()}
"""Theo Jansen's lengths [m]: a and l place the frame's pivot B from the crank's axle O (a to the
left, l down), m is the crank, b..k the links (NOTES.md names their joints)."""
O = np.array([0.0, 0.0])
B = np.array([-LENGTHS["a"], -LENGTHS["l"]])
DRAWN_INPUT = math.radians(0.0)
STEP = 5e-3
"""The finite differences' step in the crank angle [rad]."""
LINKS = {
    "frame": ("B", "O"),
    "crank": ("O", "A"),
    "upper_rod": ("C", "A"),
    "lower_rod": ("D", "A"),
    "hip": ("E", "B", "C"),
    "rocker": ("B", "D"),
    "thigh": ("E", "F"),
    "shin": ("F", "G", "D"),
}
"""Each link's joints in the drawing's order (x, then y, as drawn): the upper triangle BCE is the
hip, the lower triangle DFG (G the foot) the shin."""


def points(theta: np.ndarray) -> dict[str, np.ndarray]:
    """Every joint (P, 2) [m] at crank angles ``theta`` (P,) [rad], in the walking assembly."""
    L = LENGTHS
    n = len(theta)
    o, b = np.tile(O, (n, 1)), np.tile(B, (n, 1))
    a = o + L["m"] * unit(theta)
    c = circle_circle(a, L["j"], b, L["b"], -1)  # above: right of A -> B
    d = circle_circle(a, L["k"], b, L["c"], +1)  # below: left of A -> B
    e = circle_circle(b, L["d"], c, L["e"], +1)  # out to the left of B -> C
    f = circle_circle(e, L["f"], d, L["g"], -1)  # out to the left: right of E -> D
    g = circle_circle(d, L["i"], f, L["h"], +1)  # down: left of D -> F
    return {"O": o, "B": b, "A": a, "C": c, "D": d, "E": e, "F": f, "G": g}


place = linked(points, LINKS)


def main() -> None:
    print(summary(run(HERE, place, STEP)))


if __name__ == "__main__":
    main()
