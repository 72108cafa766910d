"""Independent truth for the six-bar with a triad (NOTES.md): the crank by its angle, the triad by
one scalar unknown (the rocker O4C's angle) found by bracketing so that the output O6D closes, the
rest by circle intersections; rates by finite differences, forces by Newton-Euler, checked by the
power balance.

Run ``python truth.py`` in this folder: it writes ``truth.json`` and prints a summary.
"""

from __future__ import annotations

import math
import sys
from functools import cache
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from linkage_support.geometry import circle_circle, distance, placed, unit  # noqa: E402
from linkage_support.roots import continued_root, root_table  # noqa: E402
from linkage_support.truth import linked, run, summary  # noqa: E402

O2, O4, O6 = np.array([0.0, 0.0]), np.array([0.36, 0.0]), np.array([0.45, 0.27])
"""The fixed pivots [m]: O2 and O4 as in the Acimep paper's four-bar (Table 6), O6 the third binary's."""
CRANK, COUPLER, ROCKER = 0.06, 0.40, 0.18
"""O2A, AB and O4C [m]: the Acimep paper's crank, coupler and rocker (Table 6: 60, 400, 180)."""
BC, CD = 0.15, 0.20
"""The ternary's sides from C [m]; D is 90 deg clockwise of C -> B, so BD = 0.25 m."""
OUTPUT = 0.20
"""O6D [m]."""
DRAWN_INPUT = math.radians(70.0)
"""The crank angle of the drawing [rad]: the Acimep paper's input angle (Table 6)."""
DRAWN_ROCKER = math.radians(118.0)
"""Near the rocker O4C's angle in the drawn assembly [rad]: where the continuation starts."""
TABLE_STEP = math.radians(0.5)
"""The continuation table's step in the crank angle [rad]."""
HALF_WIDTH = 0.02
"""Brackets about the continued root [rad]."""
STEP = 1e-2
"""The finite differences' step in the crank angle [rad]."""
LINKS = {
    "frame": ("O2", "O4", "O6"),
    "crank": ("O2", "A"),
    "coupler": ("A", "B"),
    "ternary": ("C", "B", "D"),
    "rocker": ("C", "O4"),
    "output": ("O6", "D"),
}
"""Each link's joints in the drawing's order (x, then y, as drawn)."""


def _triad(theta: np.ndarray, phi: np.ndarray) -> dict[str, np.ndarray]:
    """A, B, C, D with the rocker O4C at ``phi`` [rad]: B at COUPLER from A and BC from C (left of
    A -> C), D on the ternary, 90 deg clockwise of C -> B."""
    a = O2 + CRANK * unit(theta)
    c = O4 + ROCKER * unit(phi)
    b = circle_circle(a, COUPLER, c, BC, +1)
    return {"A": a, "B": b, "C": c, "D": placed(c, b, 0.0, -CD)}


def residual(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """|O6 D| - OUTPUT [m]: zero where the triad closes."""
    return distance(O6, _triad(theta, phi)["D"]) - OUTPUT


@cache
def _table() -> tuple[np.ndarray, np.ndarray]:
    """The rocker's angle over one turn of the crank from the drawn angle, in TABLE_STEP steps."""
    path = DRAWN_INPUT + np.arange(0.0, 2 * math.pi + TABLE_STEP / 2, TABLE_STEP)
    return path, root_table(residual, path, DRAWN_ROCKER, HALF_WIDTH)


def points(theta: np.ndarray) -> dict[str, np.ndarray]:
    """Every joint (P, 2) [m] at crank angles ``theta`` (P,) [rad], in the drawn assembly."""
    path, roots = _table()
    phi = continued_root(residual, theta, path, roots, HALF_WIDTH, period=2 * math.pi)
    n = len(theta)
    fixed = {name: np.tile(p, (n, 1)) for name, p in (("O2", O2), ("O4", O4), ("O6", O6))}
    return {**fixed, **_triad(theta, phi)}


place = linked(points, LINKS)


def main() -> None:
    print(summary(run(HERE, place, STEP)))


if __name__ == "__main__":
    main()
