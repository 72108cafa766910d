"""Peak stress at pin holes, estimated: Kt x the net-section stress of the pin force.

Beam theory does not hold within a section depth of a pin; there the engine reports nominal
section stresses and, separately, this estimate. It is an estimate for a close-fitting pin whose
force pulls along a straight lug, labelled as such wherever it is shown.

Source of the Kt curve: linkstress's own plane-stress FEA (``python -m
linkstress.validation.pin_hole_kt`` reproduces it): a plate lug of depth H with a hole of
diameter d one depth from its end, the pin force P as a cosine bearing pressure on the loaded half
of the hole, Kt = peak von Mises / (P / ((H - d) t)), each value from a three-level refinement study
(finest meshes within 1.2 %). It follows the classical photoelastic measurements of pin-loaded
plates (Frocht and Hill, 1940, reproduced in Peterson's Stress Concentration Factors): Kt falls
from above 10 for small holes in deep lugs to about 2 as d approaches H. For d/H up to 0.3 it is
the bearing asymptote Kt = 1.45 (H - d) / d within 3 %, which extends the table to smaller holes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.loads import LinkLoadCase, hole_at
from linkstress.profile import LinkProfile
from linkstress.sections import cut_extent

KT_TABLE = (
    (0.05, 28.424), (0.10, 13.328), (0.20, 5.808), (0.30, 3.347),
    (0.40, 2.684), (0.50, 2.321), (0.60, 2.111), (0.70, 1.989),
)
"""(d/H, Kt) from ``linkstress.validation.pin_hole_kt``."""
BEARING_FACTOR = KT_TABLE[0][1] * KT_TABLE[0][0] / (1 - KT_TABLE[0][0])
"""Kt (d/H) / (1 - d/H) at the table's smallest hole: the peak over the bearing stress P / (d t)."""
SOURCE = (
    "estimate: Kt x P / ((H - d) t) for a close-fitting pin pulling along a straight lug; Kt from "
    "linkstress plane-stress FEA of pin-loaded lugs (validation/pin_hole_kt.py), in line with Frocht "
    "and Hill (1940); a couple carried through the pin (a keyed shaft) is not included"
)


def pin_hole_kt(d_over_h: float) -> float | None:
    """Kt of a pin-loaded hole with diameter ``d_over_h`` times the lug depth; None beyond the table."""
    ratios, kts = np.array(KT_TABLE).T
    if d_over_h <= 0 or d_over_h > ratios[-1]:
        return None
    if d_over_h < ratios[0]:
        return BEARING_FACTOR * (1 - d_over_h) / d_over_h
    # Linear in log-log: monotone like the table, and close to the power law of the small-hole end.
    return float(np.exp(np.interp(np.log(d_over_h), np.log(ratios), np.log(kts))))


@dataclass(frozen=True)
class PinHoleEstimate:
    """At joint ``joint`` (a pin hole of diameter ``diameter`` [m] in a section ``depth`` [m] deep):
    the net-section stress ``nominal`` (P,) [Pa] of its pin force and ``estimate`` = Kt x nominal
    (None where d/H is beyond the table)."""

    joint: int
    diameter: float
    depth: float
    kt: float | None
    nominal: NDArray[np.float64]
    estimate: NDArray[np.float64] | None
    source: str = SOURCE


def pin_hole_estimates(link: LinkProfile, loads: LinkLoadCase) -> tuple[PinHoleEstimate, ...]:
    """The estimate at every joint of ``link`` that is the centre of a pin hole, of the force its pin
    bears: the pin force plus any point force given in that hole (a pin's load given as a force)."""
    holed = [(j, hole) for j, hole in enumerate(link.joint_holes) if hole is not None]
    if not holed:
        return ()
    joints = link.frame(*loads.frame_joints).to_local(link.joints)
    # The section through each pin's centre spans the lug's full depth H (its top and bottom fibres).
    bottom, top = cut_extent(link.boundary(*loads.frame_joints), joints[[j for j, _ in holed], 0])
    areas = link.holes[1]
    borne = _borne_forces(link, loads)
    estimates = []
    for k, (j, hole) in enumerate(holed):
        diameter = 2 * float(np.sqrt(areas[hole] / np.pi))
        depth = float(top[k] - bottom[k])
        net = max(depth - diameter, 1e-300) * link.thickness
        nominal = np.hypot(*(loads.pin_forces[:, j] + borne.get(hole, 0.0)).T) / net
        kt = pin_hole_kt(diameter / depth) if depth > 0 else None
        estimates.append(PinHoleEstimate(j, diameter, depth, kt, nominal, None if kt is None else kt * nominal))
    return tuple(estimates)



def _borne_forces(link: LinkProfile, loads: LinkLoadCase) -> dict[int, NDArray[np.float64]]:
    """Per hole (its index in the outline), the sum (P, 2) [N, member frame] of the point forces
    given inside it."""
    outline = link.local_outline(*loads.frame_joints)
    borne: dict[int, NDArray[np.float64]] = {}
    for point in loads.point_forces:
        hole = hole_at(outline, point.at)
        if hole is not None:
            borne[hole] = borne.get(hole, 0.0) + np.asarray(point.force, float)
    return borne
