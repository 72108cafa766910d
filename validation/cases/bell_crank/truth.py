"""Truth figures for the bell crank (NOTES.md): per arm, at its root and mid-arm, the hand
straight-beam N, V, M and fibre stresses from the pin forces linkstress computes, against the
converged plane-stress FEA at the same fibres; and the FEA's peaks at the pin holes and the fillet.

Run ``python truth.py`` in this folder (about 10 s). Hand and FEA conventions:
``validation/cases/hand_sections.py``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from hand_sections import base_mesh, converged_fea, hand_resultants, straight_cut, straight_fibres  # noqa: E402

from linkstress.analysis import plan_for, run_analysis  # noqa: E402
from linkstress.scene import load_scene  # noqa: E402

LINK = "bellcrank"
INPUTS_DEG = (0.0, 120.0, 240.0)
WIDTH, FILLET, HOLE = 0.035, 0.010, 0.012
"""The arms' width, the inner fillet's radius and the pin holes' diameter [m] (make_sketch.py)."""
ARM_LENGTH = 0.15
PIN_NAMES = {0: "C", 1: "O4", 2: "B"}
"""The bell crank's joints as the sketch numbers them (by x, then y)."""


def main() -> None:
    scene = load_scene(Path(__file__).with_name("scene.toml"))
    analysis = run_analysis(scene, plan_for(scene))
    inputs = np.degrees(analysis.kinematics.input_angle)
    positions = np.array([int(np.argmin(np.abs(inputs - a))) for a in INPUTS_DEG])
    link = scene.links[LINK].profile
    loads = analysis.forces.link_loads[LINK].at(positions)
    joints = link.frame(*loads.frame_joints).to_local(link.joints)
    o4, c, b = joints[1], joints[0], joints[2]
    cuts = [
        straight_cut(f"{arm} {where}", o4, end, distance, WIDTH)
        for arm, end in (("O4->B", b), ("O4->C", c))
        for where, distance in (("root", WIDTH), ("mid", ARM_LENGTH / 2))
    ]
    u_b, u_c = (b - o4) / np.hypot(*(b - o4)), (c - o4) / np.hypot(*(c - o4))
    fillet_centre = o4 + (WIDTH / 2 + FILLET) * (u_b + u_c)
    regions = {f"hole {PIN_NAMES[k]}": _near(joints[k], HOLE) for k in PIN_NAMES}
    regions["inner fillet"] = _near(fillet_centre, 2 * FILLET)
    regions["anywhere"] = lambda nodes: np.ones(len(nodes), bool)
    fea = converged_fea(link, loads, cuts, regions, base_mesh(WIDTH, HOLE))

    angle = analysis.kinematics.links[LINK].angle[positions]
    print(f"bell crank: FEA P2 converged over {len(fea.dofs)} meshes, dofs {fea.dofs}, "
          f"largest change of a reported figure per refinement {[f'{100 * c:.3g} %' for c in fea.change[1:]]}")
    print(f"member frame: origin O4, +x toward B; arm O4->C along {np.round(u_c, 6).tolist()}")
    for k, p in enumerate(positions):
        print(f"\ninput {inputs[p]:g} deg (bell crank O4->B at {np.degrees(angle[k]):.4g} deg)")
        rotation = np.array([[np.cos(angle[k]), -np.sin(angle[k])], [np.sin(angle[k]), np.cos(angle[k])]])
        for j, name in PIN_NAMES.items():
            f = rotation @ loads.pin_forces[k, j]
            print(f"  pin force on the bell crank at {name}: ({f[0]:.2f}, {f[1]:.2f}) N, ground frame")
        print("  cut          hand N [N]  FEA N [N]  hand V [N]  hand M [N m]  FEA M [N m]"
              "  fibre           hand sigma [MPa]  FEA sigma [MPa]  hand vM [MPa]  FEA vM [MPa]  vM diff [%]")
        for cut in cuts:
            hand = hand_resultants(link, loads, cut)
            sigma = straight_fibres(hand, cut.depth, link.thickness)[k]
            at = fea.cuts[cut.name]
            # The inner fibre is the one on the fillet's side of the arm.
            ends = cut.points(np.array([-cut.depth / 2, cut.depth / 2]))
            inner = int(np.argmin(np.hypot(*(ends - fillet_centre).T)))
            for i in range(2):
                fibre = f"{'inner' if i == inner else 'outer'} (y={'-+'[i]}h/2)"
                lead = (f"  {cut.name:<11}  {hand.normal[k]:10.2f}  {at.resultants.normal[k]:9.2f}  {hand.shear[k]:10.2f}"
                        f"  {hand.moment[k]:12.4f}  {at.resultants.moment[k]:11.4f}") if i == 0 else " " * 73
                diff = 100 * (abs(sigma[i]) / at.von_mises[k, i] - 1)
                print(f"{lead}  {fibre:<14}  {sigma[i] / 1e6:16.3f}  {at.sigma[k, i] / 1e6:15.3f}"
                      f"  {abs(sigma[i]) / 1e6:13.3f}  {at.von_mises[k, i] / 1e6:12.3f}  {diff:11.2f}")
        for name, peak in fea.peaks.items():
            x, y = peak.at[k]
            print(f"  FEA peak von Mises, {name}: {peak.value[k] / 1e6:.2f} MPa at "
                  f"({1e3 * x:.2f}, {1e3 * y:.2f}) mm, member frame")


def _near(centre: np.ndarray, radius: float):
    """The nodes within ``radius`` [m] of ``centre`` (member frame)."""
    return lambda nodes: np.hypot(*(nodes - centre).T) <= radius


if __name__ == "__main__":
    main()
