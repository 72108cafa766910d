"""Generates the pin-loaded hole stress concentration table of ``linkstress.dynamics.pin_holes``.

A straight plate lug of height H and thickness t, two holes of diameter d (close-fitting pins) 5 H
apart, each H from its end, pulled apart by pin forces +-P along the axis (cosine bearing pressure on
the loaded half of each hole, as everywhere in linkstress). Kt is the FEA's peak von Mises over the
net-section stress P / ((H - d) t), from a three-level refinement study; run
``python -m linkstress.validation.pin_hole_kt`` to reproduce the table (it prints it).
"""

from __future__ import annotations

import numpy as np

from linkstress.builders import straight_bar
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.validation.convergence import convergence_study
from linkstress.validation.mesh import MeshSettings

RATIOS = (0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7)
HEIGHT, THICKNESS, FORCE = 0.1, 0.01, 1000.0


def lug_kt(d_over_h: float, levels: int = 3) -> tuple[float, float]:
    """(Kt, relative change between the two finest meshes) for a hole of d = ``d_over_h`` H."""
    d = d_over_h * HEIGHT
    bar = straight_bar(5 * HEIGHT, HEIGHT, HEIGHT, THICKNESS, STRUCTURAL_STEEL, hole_diameter=d, name="lug")
    loads = LinkLoadCase(
        frame_joints=(0, 1),
        pin_forces=np.array([[[-FORCE, 0.0], [FORCE, 0.0]]]),
        joint_couples=np.zeros((1, 2)),
        omega=np.zeros(1), alpha=np.zeros(1), origin_acceleration=np.zeros((1, 2)), gravity=np.zeros((1, 2)),
    )
    settings = MeshSettings(size=HEIGHT / 5, hole_size=d / 16, stations=(2.5 * HEIGHT,))
    # The peak lies on the hole's rim at +-90 degrees from the load: watch those points converge.
    points = np.array([[0.0, d / 2], [0.0, -d / 2]])
    study = convergence_study(bar, loads, settings, points, levels=levels)
    nominal = FORCE / ((HEIGHT - d) * THICKNESS)
    return float(study.finest.von_mises_peak[0] / nominal), float(study.change.max())


def main() -> None:
    print("d/H      Kt  (mesh change between the two finest levels)")
    for ratio in RATIOS:
        kt, change = lug_kt(ratio)
        print(f"{ratio:4.2f}  {kt:6.3f}  ({100 * change:.2f} %)")


if __name__ == "__main__":
    main()
