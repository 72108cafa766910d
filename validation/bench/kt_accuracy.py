"""How close the pin-hole estimate Kt x nominal is to the converged FEA, inside the Kt tables.

The model choice (``linkstress.model_choice``) leaves a link on the pin-hole estimates only where
they answer within the accuracy asked; it needs what the tables are worth against FEA, measured,
not guessed. This measures it: lugs whose geometry is inside the tables but between their points
(square ends over d/H and e/H, round ends and bosses over d/H and w/H), pulled along their axis and
with the pin force turned 2.5-10 deg off it (the tables take forces up to 10 deg off the shank), each
estimate against ``validate``'s converged FEA peak within one hole diameter of the hole (a
three-level refinement study). It prints each lug's FEA / estimate - 1 (> 0: the FEA is higher, the
estimate unconservative) and, per tilt, the largest over the lugs: the envelope that
``model_choice.KT_ERROR_BY_TILT`` holds.

    python -m linkstress.validation.bench.kt_accuracy
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from shapely.geometry import Point, Polygon, box

from linkstress.dynamics.pin_holes import pin_hole_estimates
from linkstress.geometry.builders import stadium
from linkstress.geometry.curves import arc_points
from linkstress.geometry.profile import LinkProfile
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.validation.compare import compare_link

H, SPACING, T, P = 0.04, 0.2, 0.005, 1000.0
"""The lugs: H = 40 mm wide, pins 200 mm apart, 5 mm steel, pulled by 1 kN."""
TILTS_DEG = (0.0, 2.5, 5.0, 7.5, 10.0)
SQUARE_LUGS = ((0.15, 0.6), (0.25, 0.9), (0.35, 0.8), (0.45, 1.2), (0.55, 0.6), (0.65, 1.4))
"""(d/H, e/H) of the square-ended lugs, between the table's points."""
ROUND_LUGS = ((0.15, 1.0), (0.25, 0.8), (0.32, 0.6), (0.5, 1.0), (0.45, 0.9), (0.65, 0.7), (0.7, 0.5))
"""(d/H, w/H) of the round-ended lugs (w < 1: a boss on a narrower shank)."""
TILTED = (("round", 0.5, 1.0), ("round", 0.32, 0.6), ("round", 0.25, 1.0), ("round", 0.65, 0.7), ("round", 0.7, 0.5),
          ("square", 0.35, 0.8), ("square", 0.15, 1.0))
"""The lugs also pulled off their axis at every tilt of TILTS_DEG."""


def _lug(shell: Polygon, d: float) -> LinkProfile:
    holes = [Point(c).buffer(d / 2, 64).exterior.coords[::-1] for c in ((0.0, 0.0), (SPACING, 0.0))]
    return LinkProfile(Polygon(shell.exterior.coords, holes), np.array([[0.0, 0.0], [SPACING, 0.0]]), T,
                       STRUCTURAL_STEEL, "lug")


def square_lug(d_over_h: float, e_over_h: float) -> LinkProfile:
    """A square-ended lug, each hole e = ``e_over_h`` H from its end."""
    e = e_over_h * H
    return _lug(box(-e, -H / 2, SPACING + e, H / 2), d_over_h * H)


def round_lug(d_over_h: float, w_over_h: float) -> LinkProfile:
    """Ends of diameter H concentric with the holes on a shank ``w_over_h`` H wide."""
    d = d_over_h * H
    if w_over_h == 1.0:
        return stadium(SPACING, H, T, STRUCTURAL_STEEL, hole_diameter=d, name="lug")
    a = math.asin(w_over_h)
    right = arc_points((SPACING, 0.0), H / 2, a - math.pi, math.pi - a, 1e-7)
    left = arc_points((0.0, 0.0), H / 2, a, 2 * math.pi - a, 1e-7)
    return _lug(Polygon(np.vstack([right, left])), d)


def tilted_pull(degrees: float) -> LinkLoadCase:
    """The pull P on joint 0 turned ``degrees`` off the lug's axis, its opposite on joint 1, and the
    couple at joint 1 that balances the two offset forces."""
    a = math.radians(180.0 - degrees)
    fx, fy = P * math.cos(a), P * math.sin(a)
    return LinkLoadCase((0, 1), np.array([[[fx, fy], [-fx, -fy]]]), np.array([[0.0, SPACING * fy]]), np.zeros(1),
                        np.zeros(1), np.zeros((1, 2)), np.zeros((1, 2)))


def fea_peak_at_hole(link: LinkProfile, loads: LinkLoadCase) -> float:
    """[Pa]: validate's converged FEA peak von Mises within one hole diameter of joint 0."""
    comparison = compare_link("lug", link, loads, np.array([0]))
    d = 2 * math.sqrt(link.holes[1][0] / math.pi)
    near = np.hypot(*comparison.fea.nodes.T) < d
    return float(comparison.fea.nodal_von_mises[0, near].max())


@dataclass(frozen=True)
class KtComparison:
    """One lug at one tilt: the estimate [Pa], the FEA peak at the hole [Pa], and whether the
    geometry the force sees is inside the tables."""

    name: str
    tilt_deg: float
    estimate: float
    fea: float
    inside: bool

    @property
    def excess(self) -> float:
        """[-]: FEA / estimate - 1 (> 0: the estimate is below the FEA)."""
        return self.fea / self.estimate - 1.0


def compare(name: str, link: LinkProfile, tilt_deg: float) -> KtComparison:
    loads = tilted_pull(tilt_deg)
    (hole, _) = pin_hole_estimates(link, loads)
    return KtComparison(name, tilt_deg, float(hole.estimate[0]), fea_peak_at_hole(link, loads), not bool(hole.outside[0]))


def lugs() -> list[tuple[str, LinkProfile, tuple[float, ...]]]:
    """Every lug measured, with the tilts it is measured at."""
    tilted = {(shape, r, c) for shape, r, c in TILTED}
    out = []
    for r, e in SQUARE_LUGS:
        tilts = TILTS_DEG if ("square", r, e) in tilted else (0.0,)
        out.append((f"square d/H {r} e/H {e}", square_lug(r, e), tilts))
    for shape, r, c in TILTED:
        if shape == "square" and (r, c) not in SQUARE_LUGS:
            out.append((f"square d/H {r} e/H {c}", square_lug(r, c), TILTS_DEG))
    for r, w in ROUND_LUGS:
        tilts = TILTS_DEG if ("round", r, w) in tilted else (0.0,)
        out.append((f"round d/H {r} w/H {w}", round_lug(r, w), tilts))
    for shape, r, c in TILTED:
        if shape == "round" and (r, c) not in ROUND_LUGS:
            out.append((f"round d/H {r} w/H {c}", round_lug(r, c), TILTS_DEG))
    return out


def envelope(comparisons: list[KtComparison]) -> dict[float, float]:
    """Per tilt [deg], the largest excess over the lugs inside the tables there."""
    tilts = sorted({c.tilt_deg for c in comparisons})
    return {t: max(c.excess for c in comparisons if c.tilt_deg == t and c.inside) for t in tilts}


def main() -> None:
    comparisons = []
    for name, link, tilts in lugs():
        for tilt in tilts:
            c = compare(name, link, tilt)
            comparisons.append(c)
            inside = "inside" if c.inside else "OUTSIDE the tables"
            print(f"{name:24s} tilt {tilt:4.1f} deg  estimate {c.estimate / 1e6:8.4g} MPa  FEA {c.fea / 1e6:8.4g} MPa  "
                  f"FEA/estimate - 1 {100 * c.excess:+6.2f} %  {inside}", flush=True)
    print("envelope: the largest FEA/estimate - 1 over the lugs inside the tables, per tilt")
    for tilt, excess in envelope(comparisons).items():
        print(f"  {tilt:4.1f} deg: {100 * excess:+.2f} %")


if __name__ == "__main__":
    main()
