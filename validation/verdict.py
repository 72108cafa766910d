"""The verdict of a validation (``linkstress.report.verdict``): per validated link, the stress that
governs it, now with the FEA of ``validate`` at its compared positions.

A converged FEA peak governs, with its yield safety factor; taken over fewer positions than the
sweep's feasible ones it says so beside the factor ("at 4 of 361 positions"), and a higher stress the
run computed elsewhere (the beam's maximum, a pin-hole estimate, at a position the FEA did not
compare) is named in the reason. A peak that did not converge, or that no refinement study checked
(one mesh), gives no factor: the larger of the beam's maximum and the pin-hole estimates governs
then, unless that peak is larger still (a lower bound, shown without a factor). A link whose FEA
failed keeps the analysis's row, its trust saying so. ``validate`` computes no fatigue: the row
points to ``analyze --peaks`` where the material has fatigue data.
"""

from __future__ import annotations

import numpy as np

from linkstress.report.cells import mpa
from linkstress.report.places import LinkPlaces, joint_names
from linkstress.report.verdict import (
    FEA_PEAK,
    Factor,
    Stress,
    Verdict,
    VerdictRow,
    analysis_places,
    beam_stress,
    higher_words,
    hole_covers,
    holes_words,
    percent,
    positions_words,
    yield_factor,
)
from linkstress.validation.compare import LinkComparison
from linkstress.validation.validate_scene import ValidationResult


def validation_verdict(result: ValidationResult) -> Verdict:
    """The verdict of ``result``, a row per link its plan validates."""
    analysis = result.analysis
    ok = analysis.feasible
    positions = positions_words(ok)
    if not ok.any():
        return Verdict((), positions=positions)
    names = joint_names(analysis.scene)
    rows = []
    for name in analysis.plan.validate:
        places = analysis_places(analysis, name, names)
        comparison = result.comparisons.get(name)
        rows.append(_row(result, name, places, comparison, result.errors.get(name, "")))
    return Verdict(tuple(rows), _next_step(result, tuple(rows)), positions)


def fea_peak_stress(result: ValidationResult, name: str, places: LinkPlaces, c: LinkComparison) -> Stress:
    """The FEA's largest von Mises of link ``name`` over the compared positions, where on the link."""
    k = int(np.argmax(c.fea_peak))
    angle = float(np.asarray(result.analysis.scene.motion.angle_deg, float)[result.positions[k]])
    return Stress(FEA_PEAK, float(c.fea_peak[k]), angle, places.name(c.fea.von_mises_peak_at[k], beam=False))


def _row(result: ValidationResult, name: str, places: LinkPlaces, c: LinkComparison | None, error: str) -> VerdictRow:
    analysis = result.analysis
    ok = analysis.feasible
    count = int(ok.sum())
    material = analysis.scene.links[name].material
    strength = material.yield_strength
    beam = beam_stress(analysis, name, places, ok)
    covers = hole_covers(analysis, name, places, ok)
    missing = [cover for cover in covers if not cover.covered]
    estimates = [cover.largest for cover in covers if cover.largest is not None]
    best = max([beam, *estimates], key=lambda s: s.value)
    fatigue = Factor(None, "analyze --peaks" if material.fatigue_strength is not None else "")
    uncovered = tuple(cover.name for cover in missing)
    if c is None:
        note = "sections only" if best is beam and missing else ""
        return VerdictRow(name, "beam+Kt" if covers else "beam", best, yield_factor(strength, best.value, note), fatigue,
                          "FEA failed", error.split(";")[0], uncovered)
    fea = fea_peak_stress(result, name, places, c)
    compared = len(result.positions)
    share = "" if compared == count else f"at {compared} of {count} positions"
    convergence = c.convergence
    peak = None if convergence is None else convergence["peak"]
    if peak is not None and peak.converged:
        reason = f"converged {percent(float(peak.change.max()))}"
        if best.value > fea.value:
            where = "" if _compared(result, best.input_angle_deg) else f" (input {best.input_angle_deg:.6g} deg, not compared)"
            reason += f"; {higher_words(best, where)}"
        return VerdictRow(name, "fea", fea, yield_factor(strength, fea.value, share), fatigue, "FEA", reason)
    if peak is None:
        trust, change = "one mesh", "convergence not checked (--mesh-levels 1)"
    else:
        trust = "NOT converged"
        worst = max(float(peak.change.max()), float(peak.previous.max()) if peak.previous is not None else 0.0)
        change = f"{percent(worst)} over a mesh refinement (limit {100 * peak.limit:g} %)"
    withheld = Factor(None, f"withheld: FEA {trust}")
    if fea.value >= best.value:
        return VerdictRow(name, "fea", fea, withheld, fatigue, trust, f"{change}: a lower bound, no safety factor",
                          uncovered)
    note = "sections only" if best is beam and missing else ""
    reason = f"the FEA peak {mpa(fea.value)} MPa: {change}; the {best.governing} governs"
    if missing:
        reason += f"; {holes_words(missing)} outside the Kt tables"
    return VerdictRow(name, "fea", best, yield_factor(strength, best.value, note), fatigue, trust, reason, uncovered)


def _compared(result: ValidationResult, angle_deg: float) -> bool:
    angles = np.asarray(result.analysis.scene.motion.angle_deg, float)[result.positions]
    return bool(np.any(angles == angle_deg))


def _next_step(result: ValidationResult, rows: tuple[VerdictRow, ...]) -> str:
    """What to run when the FEA left something uncovered: more positions, a finer mesh, a study."""
    scene = result.analysis.scene.path
    parts = []
    count = int(result.analysis.feasible.sum())
    if len(result.positions) < count and any(row.trust == "FEA" for row in rows):
        parts.append(
            f"validate compared {len(result.positions)} of {count} positions: `linkstress analyze {scene} --peaks` "
            "gives the FEA peak at every position"
        )
    unsettled = [row.link for row in rows if row.trust == "NOT converged"]
    if unsettled:
        parts.append(
            f"the FEA peak of {', '.join(unsettled)} did not converge: round the sharp corner in the drawing or give a "
            "finer --mesh-size"
        )
    if any(row.trust == "one mesh" for row in rows):
        parts.append(f"run `linkstress validate {scene}` with --mesh-levels 3 or more for a safety factor")
    failed = [row.link for row in rows if row.trust == "FEA failed"]
    if failed:
        parts.append(f"the FEA of {', '.join(failed)} failed: see why under the comparison")
    return "; ".join(parts)
