"""JSON records of the FEA peaks and fatigue of an analysis (``analyze --peaks``).

Per link and position (beside the beam's values): ``peak_von_mises_pa`` (the superposed FEA's
largest von Mises anywhere in the link), ``peak_at_m`` (ground frame) and, where the material gives
``yield_strength`` and the peak settled on its mesh, ``peak_yield_safety_factor``.

Per link over the sweep (the top-level ``links`` table): ``peak_max_von_mises_pa``,
``peak_max_input_angle_deg``, ``peak_max_at_m`` (ground frame), the beam's largest nominal value over
the same positions, the peak's check (``peak_converged``, ``peak_change_pct`` and
``peak_previous_change_pct`` over the last two mesh refinements at the worst position, the limit), the yield factor from the peak, the mesh and the time
it took; and the fatigue: ``fatigue_safety_factor`` of ``fatigue_criterion``, every criterion's
factor at the critical node (``fatigue_safety_factors``), its alternating and mean signed
equivalent stress, the corrected endurance limit, and where the critical node is:
``fatigue_critical_at_m`` in the link's drawing frame (a point of the link, which moves: the sketch's
coordinates find it on the drawing) and ``fatigue_critical_at_member_m`` in its member frame.
``peak_note`` and ``fatigue_note`` say why a factor is withheld or what it covers.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.safety import yield_factor


def peak_columns(result: AnalysisResult, name: str) -> dict[str, NDArray[np.float64]]:
    """Link ``name``'s per-position peak columns: ``peak_von_mises_pa`` (P,) [Pa] and ``peak_at_m``
    (P, 2) [m, ground frame]; nan at infeasible positions, which carry no link data. The yield
    factor from the peak: ``peak_yield_factors``."""
    peaks = result.peaks[name]
    return {"peak_von_mises_pa": peaks.peak, "peak_at_m": result.to_ground(name, peaks.peak_at)}


def peak_yield_factors(result: AnalysisResult, name: str) -> NDArray[np.float64] | None:
    """Link ``name``'s yield strength over its FEA peak at every position (P,): inf where the peak is
    zero, nan where infeasible; None where the material gives no ``yield_strength`` or the peak did
    not settle on its mesh (no factor is taken from it)."""
    peaks = result.peaks[name]
    strength = result.scene.links[name].material.yield_strength
    if strength is None or not peaks.trusted:
        return None
    peak = peaks.peak
    return np.where(np.isnan(peak), np.nan, yield_factor(strength, peak))


def peak_summaries(result: AnalysisResult) -> dict[str, dict[str, object]]:
    """Per link with peaks, the sweep's summary record (see the module's docstring)."""
    return {name: _summary(result, name) for name in result.peaks}


def _summary(result: AnalysisResult, name: str) -> dict[str, object]:
    peaks = result.peaks[name]
    link = result.scene.links[name]
    worst = peaks.worst_position
    cases = peaks.sweep.cases
    record: dict[str, object] = {
        "peak_max_von_mises_pa": peaks.peak_max,
        "peak_max_input_angle_deg": float(result.scene.motion.angle_deg[worst]),
        "peak_max_at_m": result.to_ground(name, peaks.peak_at[worst:worst + 1], np.array([worst]))[0].tolist(),
    }
    if name in result.stresses:
        beam = result.stresses[name].max_von_mises[peaks.sweep.positions]
        record["beam_max_von_mises_pa"] = float(beam.max())
    record |= {
        "peak_converged": peaks.trusted,
        "peak_change_pct": 100 * peaks.check.change,
        "peak_previous_change_pct": 100 * peaks.check.previous_change,
        "peak_change_limit_pct": 100 * peaks.check.limit,
        "peak_note": peaks.untrusted_reason,
    }
    strength = link.material.yield_strength
    if strength is not None:
        factor = float(yield_factor(strength, np.array(peaks.peak_max))) if peaks.trusted else np.inf
        record["peak_yield_safety_factor"] = factor if np.isfinite(factor) else None
    record["peak_mesh"] = {
        "dofs": cases.dofs,
        "unit_load_cases": cases.count,
        "direction_step_deg": float(np.rad2deg(cases.directions[1] - cases.directions[0])) if cases.count else None,
        "direct_solves": 0 if cases.count else len(peaks.sweep.positions),
        "element_size_m": peaks.mesh.size,
        "hole_size_m": peaks.mesh.hole_size,
        "element_order": peaks.mesh.order,
    }
    record["peak_seconds"] = {
        "mesh": cases.seconds["mesh"], "unit_solves": cases.seconds["solve"], "superposition": peaks.sweep.seconds,
        "check": peaks.check_seconds,
    }
    record |= _fatigue(result, name)
    return record


def _fatigue(result: AnalysisResult, name: str) -> dict[str, object]:
    peaks = result.peaks[name]
    record: dict[str, object] = {"fatigue_criterion": peaks.fatigue_criterion}
    fatigue = peaks.fatigue
    if fatigue is None:
        record |= {"fatigue_safety_factor": None, "fatigue_note": peaks.fatigue_note}
        return record
    node = peaks.sweep.cases.nodes[fatigue.critical_node]
    frame = result.scene.links[name].profile.frame(*peaks.sweep.cases.frame_joints)
    factor = fatigue.critical_factors[peaks.fatigue_criterion]
    note = peaks.fatigue_note
    if not peaks.trusted:
        note = f"withheld: {peaks.untrusted_reason}" + (f"; {note}" if note else "")
    strength = result.scene.links[name].material.fatigue_strength
    record |= {
        "fatigue_safety_factor": factor if peaks.trusted and np.isfinite(factor) else None,
        "fatigue_safety_factors": {k: (v if peaks.trusted and np.isfinite(v) else None) for k, v in fatigue.critical_factors.items()},
        "fatigue_critical_at_m": frame.to_global(node).tolist(),
        "fatigue_critical_at_member_m": node.tolist(),
        "fatigue_alternating_pa": fatigue.sigma_a,
        "fatigue_mean_pa": fatigue.sigma_m,
        "fatigue_endurance_limit_pa": strength.corrected_endurance_limit,
        "fatigue_note": note,
    }
    return record
