"""Independent truth for the loader arm raised by a hydraulic cylinder (NOTES.md): the rod's eye
where the circle about the arm's pivot meets the circle of the cylinder's length about its base
pin; rates by finite differences in the stroke, forces by Newton-Euler, checked by the power
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

from linkage_support.geometry import circle_circle, placed  # noqa: E402
from linkage_support.truth import linked, run, summary  # noqa: E402

PIVOT, BASE = np.array([0.0, 0.0]), np.array([0.35, -0.90])
"""The arm's pivot on the frame and the cylinder's base pin [m]."""
EYE = 1.0
"""The arm's cylinder pin K from its pivot [m]."""
TIP = (EYE + 1.3 * math.cos(math.radians(30.0)), -1.3 * math.sin(math.radians(30.0)))
"""The bucket pin T in the arm's frame (pivot -> K) [m]: 1.3 m beyond K, bent 30 deg down."""
HEAD = 0.95
"""The barrel's head (its gland) from the base pin along the cylinder's axis [m]."""
DRAWN_INPUT = 1.20
"""The stroke (pin to pin, base to rod eye) of the drawing [m]."""
STEP = 5e-3
"""The finite differences' step in the stroke [m]."""
LINKS = {
    "frame": ("P0", "Q"),
    "arm": ("P0", "K", "T"),
    "barrel": ("Q", "H"),
    "rod": ("K",),
}
"""Each link's joints in the drawing's order (x, then y, as drawn)."""


def points(stroke: np.ndarray) -> dict[str, np.ndarray]:
    """Every joint (P, 2) [m] at strokes (P,) [m]: the cylinder's pin-to-pin length."""
    n = len(stroke)
    p0, q = np.tile(PIVOT, (n, 1)), np.tile(BASE, (n, 1))
    k = circle_circle(p0, EYE, q, stroke, +1)  # K left of P0 -> Q: ahead of the frame
    return {"P0": p0, "Q": q, "K": k, "T": placed(p0, k, *TIP), "H": placed(q, k, HEAD, 0.0)}


place = linked(points, LINKS)


def main() -> None:
    print(summary(run(HERE, place, STEP)))


if __name__ == "__main__":
    main()
