"""Generates the pin-loaded hole stress concentration tables of ``linkstress.dynamics.pin_holes``.

A plate lug of width H and thickness t, two holes of diameter d (close-fitting pins) 5 H apart,
pulled apart by pin forces +-P along the axis (cosine bearing pressure on the loaded half of each
hole, as everywhere in linkstress). Two end shapes:

- square: the lug is a rectangle, each hole an end distance e from its square end;
- round: each end is a disc of diameter H concentric with its hole (e = H / 2) on a shank of width
  w <= H (w = H is the plain round-ended lug, w < H a boss on a narrower shank).

Kt is the FEA's peak von Mises over the net-section stress P / ((H - d) t), from a three-level
refinement study. A hole far from every edge (the open plate: d/H = 0.1, pulled or pushed, whichever
is higher) gets one more value; run ``python -m linkstress.validation.fea.pin_hole_kt`` to reproduce the tables (it
prints them as the Python literals ``pin_holes.py`` holds).
"""

from __future__ import annotations

import math

import numpy as np
from shapely.geometry import Polygon, box

from linkstress.geometry.curves import arc_points, circle_points
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.geometry.profile import LinkProfile
from linkstress.validation.fea.convergence import convergence_study
from linkstress.validation.fea.mesh import MeshSettings

RATIOS = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7)
END_DISTANCES = (0.5, 0.75, 1.0, 1.5)
SHANKS = (0.5, 0.75, 1.0)
HEIGHT, THICKNESS, FORCE, SPACING = 0.1, 0.01, 1000.0, 0.5
SAGITTA = 1e-6


def square_lug(d_over_h: float, e_over_h: float) -> LinkProfile:
    """The square-ended lug: d = ``d_over_h`` H, each hole ``e_over_h`` H from its end."""
    e = e_over_h * HEIGHT
    return _lug(box(-e, -HEIGHT / 2, SPACING + e, HEIGHT / 2), d_over_h * HEIGHT)


def round_lug(d_over_h: float, shank_over_h: float = 1.0) -> LinkProfile:
    """The round-ended lug: ends of diameter H concentric with the holes, shank ``shank_over_h`` H wide."""
    # The shank's sides meet each disc at +-(pi - a) from the far end's axis.
    a = math.asin(shank_over_h)
    right = arc_points((SPACING, 0.0), HEIGHT / 2, a - math.pi, math.pi - a, SAGITTA)
    left = arc_points((0.0, 0.0), HEIGHT / 2, a, 2 * math.pi - a, SAGITTA)
    return _lug(Polygon(np.vstack([right, left])), d_over_h * HEIGHT)


def _lug(shell: Polygon, d: float) -> LinkProfile:
    holes = [circle_points(c, d / 2, SAGITTA)[::-1] for c in ((0.0, 0.0), (SPACING, 0.0))]
    outline = Polygon(shell.exterior.coords, holes)
    return LinkProfile(outline, np.array([[0.0, 0.0], [SPACING, 0.0]]), THICKNESS, STRUCTURAL_STEEL, "lug")


def axial_pull(sense: float = 1.0) -> LinkLoadCase:
    """+-FORCE [N] pulling the two pins apart along the lug (member frame of joints 0, 1); ``sense``
    -1 pushes them together."""
    return LinkLoadCase(
        frame_joints=(0, 1),
        pin_forces=sense * np.array([[[-FORCE, 0.0], [FORCE, 0.0]]]),
        joint_couples=np.zeros((1, 2)),
        omega=np.zeros(1), alpha=np.zeros(1), origin_acceleration=np.zeros((1, 2)), gravity=np.zeros((1, 2)),
    )


def lug_kt(lug: LinkProfile, levels: int = 3, sense: float = 1.0) -> tuple[float, float]:
    """(Kt, relative change of the hole's rim stress between the two finest meshes) of ``lug`` pulled
    (``sense`` 1) or pushed (-1) by ``axial_pull``."""
    d = 2 * float(np.sqrt(lug.holes[1][0] / np.pi))
    settings = MeshSettings(size=HEIGHT / 5, hole_size=d / 16, stations=(SPACING / 2,))
    # A pulled lug peaks on the hole's rim at +-90 degrees from the load, a pushed one where the pin
    # bears: watch those points converge.
    points = np.array([[0.0, d / 2], [0.0, -d / 2], [sense * d / 2, 0.0]])
    study = convergence_study(lug, axial_pull(sense), settings, points, levels=levels)
    nominal = FORCE / ((HEIGHT - d) * THICKNESS)
    return float(study.finest.von_mises_peak[0] / nominal), float(study.change.max())


def square_table() -> tuple[tuple[float, ...], ...]:
    """Kt of the square end, one row per d/H of RATIOS, one column per e/H of END_DISTANCES."""
    return tuple(tuple(round(lug_kt(square_lug(r, e))[0], 3) for e in END_DISTANCES) for r in RATIOS)


def round_table() -> tuple[tuple[float, ...], ...]:
    """Kt of the round end, one row per d/H of RATIOS, one column per shank w/H of SHANKS."""
    return tuple(tuple(round(lug_kt(round_lug(r, w))[0], 3) for w in SHANKS) for r in RATIOS)


def open_plate_kt() -> float:
    """Kt of a hole far from the edges (none within 3 d ahead of the pin, 5 d beside it): the largest
    of the square lug with d/H = 0.1 pulled with its end 3 d or 10 d ahead and pushed along its
    shank (the pushed one, which bears on the long shank)."""
    cases = [lug_kt(square_lug(RATIOS[0], 0.3)), lug_kt(square_lug(RATIOS[0], 1.0)),
             lug_kt(square_lug(RATIOS[0], 1.0), sense=-1.0)]
    return round(max(kt for kt, _ in cases), 3)


def main() -> None:
    for name, table in (("SQUARE_KT", square_table()), ("ROUND_KT", round_table())):
        print(f"{name} = (")
        for row in table:
            print("    (" + ", ".join(f"{kt:.3f}" for kt in row) + "),")
        print(")")
    print(f"OPEN_KT = {open_plate_kt():.3f}")


if __name__ == "__main__":
    main()
