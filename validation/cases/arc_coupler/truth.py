"""Truth figures for curved couplers (NOTES.md): the arc coupler at its crown and at two other
radial cuts, and the banana coupler (``../banana_coupler``) at its crown. At each cut the hand N, V,
M from the pin forces linkstress computes, the straight-beam and Winkler-Bach hoop stresses at the
inner and outer fibre, and the converged plane-stress FEA there; at the two positions of the
sweep where the hand crown moment is largest and smallest (signed).

Run ``python truth.py`` in this folder (about 10 s). Conventions: ``../hand_sections.py``;
here s points along the centre line toward the coupler's joint B (decreasing polar angle), so
n is the outward radial direction: y = r - R, and M > 0 puts the outer fibre in tension.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from hand_sections import (  # noqa: E402
    base_mesh, converged_fea, hand_resultants, radial_cut, straight_fibres, winkler_bach_fibres,
)

from linkstress.analysis import plan_for, run_analysis  # noqa: E402
from linkstress.scene import load_scene  # noqa: E402

CASES = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class ArcCoupler:
    """A case's curved coupler as its make_sketch.py draws it, member frame A -> B [m]: the centre
    line's centre and radius, the bar's depth, the pin holes' diameter, the cuts' polar angles [deg]."""

    case: str
    centre: tuple[float, float]
    radius: float
    depth: float
    hole: float
    cuts_deg: tuple[float, ...]


ARC = ArcCoupler("arc_coupler", (0.06, 0.0), 0.06, 0.02, 0.01, (90.0, 45.0, 135.0))
# Chord 180 mm, sag 40 mm: R = (90^2 + 40^2) / (2 x 40) = 121.25 mm, centre 40 - 121.25 mm below the chord.
BANANA = ArcCoupler("banana_coupler", (0.09, 0.04 - 0.12125), 0.12125, 0.03, 0.008, (90.0,))


def report(coupler: ArcCoupler) -> None:
    """Print the case's table."""
    scene = load_scene(CASES / coupler.case / "scene.toml")
    analysis = run_analysis(scene, plan_for(scene))
    link = scene.links["coupler"].profile
    loads = analysis.forces.link_loads["coupler"]
    if tuple(loads.frame_joints) != (0, 1):
        raise RuntimeError(f"{coupler.case}: the coupler's frame is {loads.frame_joints}, not A -> B (0, 1)")
    cuts = [radial_cut(f"{a:g} deg", coupler.centre, coupler.radius, a, -1, coupler.depth) for a in coupler.cuts_deg]
    crown = hand_resultants(link, loads, cuts[0]).moment
    feasible = np.flatnonzero(analysis.feasible)
    positions = feasible[[np.argmax(crown[feasible]), np.argmin(crown[feasible])]]
    loads = loads.at(positions)
    fea = converged_fea(link, loads, cuts, {}, base_mesh(coupler.depth, coupler.hole))
    inputs = np.degrees(analysis.kinematics.input_angle[positions])
    inner, outer = coupler.radius - coupler.depth / 2, coupler.radius + coupler.depth / 2
    print(f"{coupler.case}: R = {1e3 * coupler.radius:g} mm, h = {1e3 * coupler.depth:g} mm (R/h = "
          f"{coupler.radius / coupler.depth:.3g}), t = {1e3 * link.thickness:g} mm; Winkler-Bach r_n = "
          f"{1e3 * coupler.depth / np.log(outer / inner):.4f} mm; cuts at polar angles {coupler.cuts_deg} deg "
          f"about ({1e3 * coupler.centre[0]:g}, {1e3 * coupler.centre[1]:g}) mm, member frame A -> B (90 deg: the crown)")
    print(f"FEA P2 converged over {len(fea.dofs)} meshes, dofs {fea.dofs}, largest change of a fibre von "
          f"Mises per refinement {[f'{100 * c:.3g} %' for c in fea.change[1:]]}")
    for k, p in enumerate(positions):
        print(f"\ninput {inputs[k]:g} deg")
        print("  cut      hand N [N]  FEA N [N]  hand V [N]  hand M [N m]  FEA M [N m]  fibre  straight [MPa]"
              "  Winkler-Bach [MPa]  FEA hoop [MPa]  FEA vM [MPa]  straight/FEA-1 [%]  W-B/FEA-1 [%]")
        for cut in cuts:
            hand = hand_resultants(link, loads, cut)
            straight = straight_fibres(hand, cut.depth, link.thickness)[k]
            curved = winkler_bach_fibres(hand, coupler.radius, cut.depth, link.thickness)[k]
            at = fea.cuts[cut.name]
            for i, fibre in enumerate(("inner", "outer")):
                lead = (f"  {cut.name:<7}  {hand.normal[k]:10.2f}  {at.resultants.normal[k]:9.2f}  {hand.shear[k]:10.2f}"
                        f"  {hand.moment[k]:12.4f}  {at.resultants.moment[k]:11.4f}") if i == 0 else " " * 69
                hoop = at.sigma[k, i]
                print(f"{lead}  {fibre}  {straight[i] / 1e6:14.3f}  {curved[i] / 1e6:18.3f}  {hoop / 1e6:14.3f}"
                      f"  {at.von_mises[k, i] / 1e6:12.3f}  {100 * (straight[i] / hoop - 1):18.2f}"
                      f"  {100 * (curved[i] / hoop - 1):13.2f}")
    print()


if __name__ == "__main__":
    report(ARC)
    report(BANANA)
