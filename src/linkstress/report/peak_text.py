"""The terminal report's FEA peaks and fatigue (``analyze --peaks --details``): one row per link, then
what each figure means and why a factor is withheld. Stresses in MPa."""

from __future__ import annotations

from linkstress.analysis import AnalysisResult
from linkstress.report.cells import mpa, point, significant, text_table
from linkstress.report.peak_records import peak_summaries

PEAK_HEADERS = (
    "link", "FEA peak [MPa]", "at input [deg]", "at (x, y) [m], ground frame", "beam max [MPa]", "FEA peak / beam max",
    "peak convergence", "yield safety factor (FEA peak)", "fatigue safety factor", "critical point (x, y) [m], drawing frame",
)


def peaks_table(result: AnalysisResult) -> str:
    """Per link: the FEA peak over the sweep (where and when), the beam's largest nominal value
    beside it, the peak's convergence, and the yield and fatigue safety factors taken from the FEA."""
    summaries = peak_summaries(result)
    rows, notes = [], []
    for name, s in summaries.items():
        beam = s.get("beam_max_von_mises_pa")
        at = s["peak_max_at_m"]
        fatigue = s["fatigue_safety_factor"]
        where = s.get("fatigue_critical_at_m")
        rows.append((
            name, mpa(s["peak_max_von_mises_pa"]), f"{s['peak_max_input_angle_deg']:.6g}", point(at),
            "-" if beam is None else mpa(beam),
            "-" if not beam else f"{s['peak_max_von_mises_pa'] / beam:.3g}",
            f"{s['peak_change_pct']:.2g} %, {s['peak_previous_change_pct']:.2g} %"
            + ("" if s["peak_converged"] else " NOT converged"),
            _factor(s.get("peak_yield_safety_factor"), "peak_yield_safety_factor" in s),
            "-" if fatigue is None else f"{significant(fatigue)} ({s['fatigue_criterion']})",
            "-" if fatigue is None or where is None else point(where),
        ))
        mesh = s["peak_mesh"]
        line = f"  {name}: {mesh['dofs']} dofs, " + (
            f"{mesh['unit_load_cases']} unit load cases (bearing every {mesh['direction_step_deg']:g} deg)"
            if mesh["unit_load_cases"] else f"a direct solve at each of {mesh['direct_solves']} positions (a block slides along it)"
        )
        if "fatigue_alternating_pa" in s:
            factors = ", ".join(f"{k} {'-' if v is None else significant(v)}" for k, v in s["fatigue_safety_factors"].items())
            line += (
                f"; fatigue at the critical point: sigma_a {mpa(s['fatigue_alternating_pa'])} MPa, sigma_m "
                f"{mpa(s['fatigue_mean_pa'])} MPa, S_e {mpa(s['fatigue_endurance_limit_pa'])} MPa; {factors}"
            )
        notes.append(line)
        notes += [f"  {name}: {text}" for text in (s["peak_note"], s["fatigue_note"]) if text]
    return "\n".join([
        "FEA peak stresses over the sweep (plane-stress FEA of each link, its unit load cases superposed at every "
        "position; von Mises anywhere in the link: pin holes, fillets, curved crowns)",
        text_table(PEAK_HEADERS, rows),
        *notes,
        "peak convergence: the peak's change at its worst position over the last two mesh refinements (limit 5 % "
        "each); a peak that has not settled gives no safety factor. fatigue: over the sweep, per point, the "
        "alternating and mean of the signed von Mises (sign of the larger principal stress), Marin-corrected "
        "endurance limit (docs/fatigue.md)",
    ])


def _factor(value: float | None, given: bool) -> str:
    if not given:
        return "-"
    return "- (withheld)" if value is None else significant(value)
