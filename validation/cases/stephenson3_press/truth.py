"""Independent truth for the Stephenson III press drive (NOTES.md): positions from its lengths by
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

from linkage_support.geometry import circle_circle, placed, unit  # noqa: E402
from linkage_support.truth import linked, run, summary  # noqa: E402

O2, O4, O6 = np.array([0.0, 0.0]), np.array([0.25, 0.0]), np.array([0.08, 0.33])
"""The fixed pivots [m]: crank, rocker, output lever."""
CRANK, COUPLER, ROCKER = 0.06, 0.23, 0.16
"""O2A, AB, O4B [m]: a Grashof crank-rocker (60 + 250 <= 230 + 160)."""
COUPLER_POINT = (0.15 * math.cos(math.radians(50)), 0.15 * math.sin(math.radians(50)))
"""P on the coupler: 150 mm from A at 50 deg counter-clockwise of A -> B (along, across A -> B) [m]."""
LINK, LEVER, TOOL = 0.20, 0.16, 0.26
"""PQ (the dyad's link), O6Q and O6T (the output lever, T its tool end beyond Q) [m]."""
DRAWN_INPUT = math.radians(60.0)
STEP = 1e-2
"""The finite differences' step in the crank angle [rad]."""
LINKS = {
    "frame": ("O2", "O6", "O4"),
    "crank": ("O2", "A"),
    "coupler": ("A", "P", "B"),
    "rocker": ("B", "O4"),
    "link": ("P", "Q"),
    "lever": ("O6", "Q", "T"),
}
"""Each link's joints in the drawing's order (x, then y, as drawn)."""


def points(theta: np.ndarray) -> dict[str, np.ndarray]:
    """Every joint (P, 2) [m] at crank angles ``theta`` (P,) [rad], in the drawn assembly."""
    n = len(theta)
    fixed = {name: np.tile(p, (n, 1)) for name, p in (("O2", O2), ("O4", O4), ("O6", O6))}
    a = fixed["O2"] + CRANK * unit(theta)
    b = circle_circle(a, COUPLER, fixed["O4"], ROCKER, +1)  # B left of A -> O4: above
    p = placed(a, b, *COUPLER_POINT)
    q = circle_circle(p, LINK, fixed["O6"], LEVER, -1)  # Q right of P -> O6
    t = placed(fixed["O6"], q, TOOL, 0.0)
    return {**fixed, "A": a, "B": b, "P": p, "Q": q, "T": t}


place = linked(points, LINKS)


def main() -> None:
    print(summary(run(HERE, place, STEP)))


if __name__ == "__main__":
    main()
