"""Independent truth for the Watt II six-bar (NOTES.md): positions from its lengths by circle
intersections, rates by finite differences, forces by Newton-Euler, checked by the power balance.

Run ``python truth.py`` in this folder: it writes ``truth.json`` and prints a summary.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from linkage_support.geometry import circle_circle, placed, unit  # noqa: E402
from linkage_support.truth import linked, run, summary  # noqa: E402

O2, O4, O6 = np.array([0.0, 0.0]), np.array([0.2, 0.0]), np.array([0.22, -0.1])
"""The fixed pivots [m]: the crank's, the bell crank's, the output's."""
CRANK, COUPLER, ARM, ROD, OUTPUT = 0.05, 0.2, 0.15, 0.15, 0.12
"""O2A, AB, O4B = O4C (the bell crank's arms, C 90 deg clockwise of B about O4), CD, O6D [m]."""
DRAWN_INPUT = 0.0
"""The crank angle of the drawing [rad]."""
STEP = 1e-2
"""The finite differences' step in the crank angle [rad]."""
LINKS = {
    "frame": ("O2", "O4", "O6"),
    "crank": ("O2", "A"),
    "coupler": ("A", "B"),
    "bellcrank": ("B", "O4", "C"),
    "rod": ("D", "C"),
    "output": ("O6", "D"),
}
"""Each link's joints in the drawing's order (x, then y, as drawn)."""


def points(theta: np.ndarray) -> dict[str, np.ndarray]:
    """Every joint (P, 2) [m] at crank angles ``theta`` (P,) [rad], open assembly of both loops."""
    n = len(theta)
    fixed = {name: np.tile(p, (n, 1)) for name, p in (("O2", O2), ("O4", O4), ("O6", O6))}
    a = fixed["O2"] + CRANK * unit(theta)
    b = circle_circle(a, COUPLER, fixed["O4"], ARM, +1)  # B left of A -> O4
    c = placed(fixed["O4"], b, 0.0, -ARM)  # 90 deg clockwise of O4 -> B
    d = circle_circle(c, ROD, fixed["O6"], OUTPUT, +1)  # D left of C -> O6
    return {**fixed, "A": a, "B": b, "C": c, "D": d}


place = linked(points, LINKS)


def main() -> None:
    print(summary(run(HERE, place, STEP)))


if __name__ == "__main__":
    main()
