"""Independent truth for the crank-shaper quick-return (NOTES.md): the slotted lever along the line
from its pivot through the crank pin, the ram's pin where the rod's circle meets the ram's guide
line; rates by finite differences, forces by Newton-Euler, checked by the power balance.

Run ``python truth.py`` in this folder: it writes ``truth.json`` and prints a summary.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from linkage_support.geometry import circle_line, placed, unit  # noqa: E402
from linkage_support.truth import linked, run, summary  # noqa: E402

O4, O2 = np.array([0.0, 0.0]), np.array([0.0, 0.30])
"""The slotted lever's pivot and the crank's centre [m]: c = |O2 O4| = 0.30 m."""
CRANK = 0.10
"""r = |O2 A| [m]; r / c = 1/3."""
LEVER, ROD = 0.56, 0.20
"""O4T (the lever's pin for the rod) and TR (the rod to the ram's pin) [m]."""
GUIDE = (np.array([-0.20, 0.60]), np.array([0.20, 0.60]))
"""Two points of the ram's guide line, on the frame [m]: horizontal, 0.60 m above O4."""
DRAWN_INPUT = math.radians(30.0)
STEP = 1e-2
"""The finite differences' step in the crank angle [rad]."""
LINKS = {
    "frame": ("G1", "O4", "O2", "G2"),
    "crank": ("O2", "A"),
    "collar": ("A",),
    "lever": ("O4", "T"),
    "rod": ("T", "R"),
    "ram": ("R",),
}
"""Each link's joints in the drawing's order (x, then y, as drawn)."""


def points(theta: np.ndarray) -> dict[str, np.ndarray]:
    """Every joint (P, 2) [m] at crank angles ``theta`` (P,) [rad]."""
    n = len(theta)
    fixed = {name: np.tile(p, (n, 1)) for name, p in (("O4", O4), ("O2", O2), ("G1", GUIDE[0]), ("G2", GUIDE[1]))}
    a = fixed["O2"] + CRANK * unit(theta)
    t = placed(fixed["O4"], a, LEVER, 0.0)  # the lever runs from O4 through the crank pin
    along = np.tile(unit(0.0), (n, 1))
    r = circle_line(t, ROD, fixed["G1"], along, +1)  # the ram's pin ahead of T
    return {**fixed, "A": a, "T": t, "R": r}


place = linked(points, LINKS)


def main() -> None:
    print(summary(run(HERE, place, STEP)))


if __name__ == "__main__":
    main()
