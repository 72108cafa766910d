"""Reports of a validation: docs/design.md's ``validate`` JSON, terminal text, and HTML sections.

Each report starts with the verdict (``validation.verdict``: what governs each link, where, how safe,
how far to trust it), then the scene's warnings, then the comparison. The FEA peak over the beam's
maximum is no error of the beam: it is the stress raiser at the holes (or a fillet) that beam theory
does not model, and the reports call it that; "check" is kept for what is checked (support reactions
and section resultants). The text is short by default: a compact table per link; ``details`` adds
each link's paragraph (every pin hole, member and convergence figure).

Errors are percentages; a link's scalar values are the worst over the compared positions, with the
per-position values beside them. Each maximum is given with the input angle [deg] and the place
[m, member frame] where it is, in the JSON, the table and the text alike.

``"converged"`` is true only when every compared quantity converged over the refinement study:
the section resultants, the nominal stresses (where a nominal station exists) and the FEA peak,
each judged by its change between the two finest meshes against its own limit (the peak over the
refinement before too; ``"convergence"`` gives each); null with one mesh, where nothing was checked. The yield safety factor against the
FEA peak is given only for a converged peak: with one mesh or an unconverged peak it is null and
``"fea_yield_safety_factor_reason"`` says why.
"""

from __future__ import annotations

import html
from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.tri import Triangulation
from numpy.typing import NDArray

from linkstress.report.figures import LABEL_ZORDER, boxed_label, field_colour_bar, field_scale, stress_along_figure
from linkstress.report.cells import mpa, point, text_table, without_noise
from linkstress.report.html import (
    analysis_sections, figure_tag, page, report_title, table_html, verdict_html, warnings_html,
)
from linkstress.report.places import joint_names
from linkstress.report.text import KT_WORDS, warnings_text
from linkstress.report.verdict import Verdict, analysis_places
from linkstress.safety import finite_or_none, yield_factor
from linkstress.validation.compare import HolePeak, LinkComparison, MemberComparison
from linkstress.validation.fea.convergence import CONVERGED_CHANGE, PEAK_CONVERGED_CHANGE, RESULTANT_CONVERGED_CHANGE
from linkstress.validation.validate_scene import RESULTANT_LIMIT, ValidationResult
from linkstress.validation.verdict import validation_verdict

NOTE = (
    "Beam sections are compared with plane-stress FEA of the same link under the same loads: pin "
    "forces as cosine bearing pressure on the loaded half of each hole, a driving torque as a uniform "
    "shear on its pin's hole, the d'Alembert body force, applied couples. Resultants: N, V, M over FEA "
    "cuts. Nominal: von Mises at the beam's critical fibre of stations at least one section depth from "
    "every pin. FEA peak / beam maximum: the FEA's largest anywhere over the beam's largest, the stress "
    "raiser at the holes (or a fillet) that beam theory does not model; not an error of the beam."
)
LEGEND = (
    "resultants: N, V, M over FEA cuts against the beam's (checked: within {limit:g} %); nominal: von Mises at "
    "stations a section depth or more from every pin, against the beam's; FEA peak / beam max: the stress raiser "
    "at the holes (or a fillet) that the beam does not model, not an error of the beam (the verdict takes the FEA "
    "peak)"
)
DETAILS_HINT = "each link's pin holes, members and convergence: add --details"


def link_record(result: ValidationResult, name: str) -> dict:
    """The ``validate`` JSON entry of one link (worst values over the compared positions, each
    maximum with the input angle [deg] and place [m, member frame] where it is)."""
    if name in result.errors:
        return {"error": result.errors[name]}
    c = result.comparisons[name]
    angles = input_angles(result)
    beam, fea = beam_maximum(result, name), fea_peak(c, angles)
    factor, reason = fea_safety_factor(result, name, c)
    k = int(np.argmax(c.peak_error))
    return {
        "beam_max_von_mises_pa": beam.value,
        "beam_max_input_angle_deg": beam.angle_deg,
        "beam_max_at_member_m": beam.at,
        "fea_max_von_mises_pa": fea.value,
        "fea_max_input_angle_deg": fea.angle_deg,
        "fea_max_at_member_m": fea.at,
        "nominal_error_pct": None if c.nominal_error is None else float(100 * c.nominal_error.max()),
        "nominal_note": nominal_note(c),
        "peak_error_pct": float(100 * c.peak_error.max()),
        "fea_peak_over_beam_max": float(c.fea_peak[k] / c.beam_max[k]) if c.beam_max[k] > 0 else None,
        "fea_max_where": fea_where(result, name, c),
        "resultant_error_pct": None if c.resultant_error is None else float(100 * c.resultant_error.max()),
        "not_compared": [s.note for s in c.skipped],
        "dofs": int(c.fea.dofs),
        "beam_seconds": float(c.beam_seconds),
        "fea_seconds": float(c.fea_seconds),
        "elements": int(c.fea.n_elements),
        "mesh_size_m": float(c.fea.plane.settings.size),
        "hole_size_m": float(c.fea.plane.settings.hole_size),
        "mesh_levels": 1 if c.study is None else len(c.study.dofs),
        "converged": c.converged,
        "convergence": convergence_record(c),
        "discretisation_error_pct": None if c.study is None or not c.study.has_nominal else float(100 * c.discretisation_error.max()),
        "reaction_ratio": float(c.fea.reaction_ratio.max()),
        "pin_estimate_max_pa": pin_estimate(c),
        "pin_holes": [pin_hole_record(h, angles) for h in c.hole_peaks],
        "fea_yield_safety_factor": factor,
        "fea_yield_safety_factor_reason": reason,
        "members": [member_record(m) for m in c.members],
        "stations_m": c.stations.tolist(),
        "stations_note": c.station_note or None,
        "nominal_stations_m": c.stations[c.away].tolist(),
        "positions": {
            "input_angle_deg": angles.tolist(),
            "beam_max_von_mises_pa": result.analysis.stresses[name].max_von_mises[result.positions].tolist(),
            "fea_max_von_mises_pa": c.fea_peak.tolist(),
            "fea_max_at_m": _ground(result, name, c.fea.von_mises_peak_at).tolist(),
            "nominal_error_pct": None if c.nominal_error is None else (100 * c.nominal_error).tolist(),
            "peak_error_pct": (100 * c.peak_error).tolist(),
            "resultant_error_pct": None if c.resultant_error is None else (100 * c.resultant_error).tolist(),
        },
    }


def fea_where(result: ValidationResult, name: str, c: LinkComparison) -> str:
    """Where on link ``name`` the FEA's largest von Mises is, in words ("pin hole O2 (crank-ground)")."""
    places = analysis_places(result.analysis, name)
    return places.name(c.fea.von_mises_peak_at[int(np.argmax(c.fea_peak))], beam=False)


def member_record(m: MemberComparison) -> dict:
    """The ``validate`` JSON entry of one member of a link (worst values over the compared positions)."""
    return {
        "joints": list(m.joints),
        "beam_max_von_mises_pa": float(m.beam_max.max()),
        "nominal_error_pct": None if m.nominal_error is None else float(100 * m.nominal_error.max()),
        "resultant_error_pct": float(100 * m.resultant_error.max()),
    }


def member_words(m: MemberComparison) -> str:
    """One member's comparison in a line: its joints, the beam's largest and the worst errors."""
    record = member_record(m)
    nominal = record["nominal_error_pct"]
    return (
        f"member joints {m.joints[0]}-{m.joints[1]}: beam maximum {record['beam_max_von_mises_pa'] / 1e6:.4g} MPa, "
        f"resultants within {record['resultant_error_pct']:.3g} %, "
        + ("no nominal station (every one near a pin or a junction)" if nominal is None else f"nominal within {nominal:.3g} %")
    )


@dataclass(frozen=True)
class Maximum:
    """A stress ``value`` [Pa] at input angle ``angle_deg`` [deg], at ``at`` [x, y] [m, member frame]."""

    value: float
    angle_deg: float
    at: list[float]

    def words(self) -> str:
        return f"{mpa(self.value)} MPa at input angle {self.angle_deg:.4g} deg, {point(self.at)} m (member frame)"


def input_angles(result: ValidationResult) -> NDArray[np.float64]:
    """Input angle [deg] of each compared position."""
    return np.asarray(result.analysis.scene.motion.angle_deg, float)[result.positions]


def beam_maximum(result: ValidationResult, name: str) -> Maximum:
    """The analysis's largest section von Mises of link ``name`` over the compared positions (the
    table's "beam max"): value, input angle and place."""
    stress = result.analysis.stresses[name]
    k = result.positions[int(np.argmax(stress.max_von_mises[result.positions]))]
    return Maximum(float(stress.max_von_mises[k]), float(result.analysis.scene.motion.angle_deg[k]), stress.max_at[k].tolist())


def fea_peak(c: LinkComparison, angles: NDArray[np.float64]) -> Maximum:
    """The FEA's largest von Mises over the compared positions of input ``angles`` [deg] (the
    table's "FEA peak")."""
    k = int(np.argmax(c.fea_peak))
    return Maximum(float(c.fea_peak[k]), float(angles[k]), c.fea.von_mises_peak_at[k].tolist())


def convergence_record(c: LinkComparison) -> dict:
    """Per compared quantity (``resultants``, ``nominal``, ``peak``): ``change_pct`` over the last
    refinement (worst over the positions), ``previous_change_pct`` over the one before where it is
    judged too (the peak; else null), ``limit_pct``, ``converged`` and ``status`` ("converged",
    "NOT converged", "not checked" with one mesh, "not compared" for nominal on a link without a
    nominal station)."""
    limits = {"resultants": RESULTANT_CONVERGED_CHANGE, "nominal": CONVERGED_CHANGE, "peak": PEAK_CONVERGED_CHANGE}
    study = c.convergence
    record = {}
    for quantity, limit in limits.items():
        q = None if study is None else study[quantity]
        status = "not checked" if study is None else "not compared" if q is None else (
            "converged" if q.converged else "NOT converged")
        record[quantity] = {
            "change_pct": None if q is None else float(100 * q.change.max()),
            "previous_change_pct": None if q is None or q.previous is None else float(100 * q.previous.max()),
            "limit_pct": 100 * limit,
            "converged": None if q is None else q.converged,
            "status": status,
        }
    return record


def fea_safety_factor(result: ValidationResult, name: str, c: LinkComparison) -> tuple[float | None, str | None]:
    """The link material's yield strength over the FEA peak, or None and why: no yield strength, no
    stress, a peak that changed more than PEAK_CONVERGED_CHANGE over the last refinement, or one
    mesh (the peak's convergence not checked: a coarse mesh tends to underestimate a hole's peak)."""
    material = result.analysis.scene.links[name].material
    if material is None or material.yield_strength is None:
        return None, "the material has no yield_strength"
    convergence = c.convergence
    if convergence is None:
        return None, ("one mesh (--mesh-levels 1): the FEA peak's convergence was not checked; run a "
                      "refinement study (--mesh-levels 3) for a safety factor")
    peak = convergence["peak"]
    if not peak.converged:
        return None, f"the FEA peak is NOT converged ({peak.words()}), so no safety factor is taken from it"
    factor = finite_or_none(yield_factor(material.yield_strength, np.array([float(c.fea_peak.max())])))[0]
    return factor, None if factor is not None else "no stress"


def pin_estimate(c: LinkComparison) -> float | None:
    """The largest Kt x nominal estimate inside the Kt tables at the link's pin holes over the compared positions."""
    values = [e for e in (h.largest(slice(None)) for h in c.beam.pin_holes) if e is not None]
    return max(values) if values else None


def pin_hole_record(h: HolePeak, angles: NDArray[np.float64]) -> dict:
    """One pin hole's estimate against the FEA at the same hole, at the position of its largest FEA
    peak among those where the estimate is inside the Kt tables (where it is nowhere: the FEA's
    largest, no estimate, and why)."""
    inside = np.flatnonzero(h.inside)
    candidates = inside if inside.size else np.arange(len(h.fea))
    k = int(candidates[np.argmax(h.fea[candidates])])
    return {
        "joint": h.joint,
        "diameter_m": h.diameter,
        "centre_member_m": h.centre.tolist(),
        "input_angle_deg": float(angles[k]),
        "estimate_pa": float(h.estimate[k]) if inside.size else None,
        "fea_peak_pa": float(h.fea[k]),
        "fea_peak_at_member_m": h.fea_at[k].tolist(),
        "error_pct": float(100 * h.error[k]) if inside.size else None,
        "kt_outside_table": not inside.size,
        "kt_outside_reason": None if inside.size else h.reasons[k],
    }


def _ground(result: ValidationResult, name: str, local: np.ndarray) -> np.ndarray:
    """Member-frame points (Pc, 2) at the compared positions, in the ground frame."""
    motion = result.analysis.kinematics.links[name]
    k = result.positions
    c, s = np.cos(motion.angle[k]), np.sin(motion.angle[k])
    return motion.origin[k] + np.column_stack([c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]])


def validation_json(result: ValidationResult, verdict: Verdict | None = None) -> dict:
    """docs/design.md's ``validate`` JSON, with the ``verdict`` (made here when not given) and the
    scene's ``warnings``."""
    return {
        "links": {name: link_record(result, name) for name in result.analysis.plan.validate},
        "positions_compared": result.positions.tolist(),
        "failures": result.failures(),
        "not_converged": result.unconverged(),
        "verdict": (verdict or validation_verdict(result)).record(),
        "warnings": list(result.analysis.scene.warnings),
        "not_compared": result.not_compared(),
        "not_validated": [{"link": name, "reason": why} for name, why in result.skipped.items()],
    }


HEADERS = ("link", "beam max [MPa]", "FEA peak [MPa]", "FEA peak / beam max", "FEA peak at", "resultants [%]",
           "nominal [%]", "dofs", "converged")


def table_rows(result: ValidationResult, reasons: bool = False) -> list[tuple]:
    """The summary table: each maximum beside its input angle, errors worst over the positions; a
    link whose FEA failed says so (with the reason when ``reasons``)."""
    rows = []
    for name in result.analysis.plan.validate:
        r = link_record(result, name)
        if "error" in r:
            rows.append((name, "FEA failed" + (": " + r["error"] if reasons else ""), "", "", "", "", "", "", ""))
            continue
        ratio = r["fea_peak_over_beam_max"]
        rows.append((
            name, mpa(r["beam_max_von_mises_pa"]), mpa(r["fea_max_von_mises_pa"]),
            "-" if ratio is None else f"{ratio:.3g} x", r["fea_max_where"],
            "-" if r["resultant_error_pct"] is None else f"{r['resultant_error_pct']:.2g}",
            "-" if r["nominal_error_pct"] is None else f"{r['nominal_error_pct']:.2g}", str(r["dofs"]),
            converged_word(r["convergence"]),
        ))
    return rows


def converged_word(convergence: dict) -> str:
    """"yes", "not checked", or "NO (" the quantities that did not converge ")"."""
    statuses = {q: v["status"] for q, v in convergence.items()}
    if "not checked" in statuses.values():
        return "not checked"
    failed = [q for q, status in statuses.items() if status == "NOT converged"]
    return f"NO ({', '.join(failed)})" if failed else "yes"


def check_line(result: ValidationResult) -> str:
    """The check's verdict, what it checked, and beside it what did not converge (not part of it)."""
    failures = result.failures()
    verdict = "passed" if not failures else "FAILED"
    line = f"check: {verdict} ({result.checked()})"
    if result.not_compared():
        line += ("; not compared, so not checked: " + ", ".join(result.not_compared_names())
                 + " (every cut through a hole: see each link)")
    if result.skipped:
        line += "; not validated: " + "; ".join(f"{name} ({why})" for name, why in result.skipped.items())
    unconverged = result.unconverged()
    if unconverged:
        line += "; reported beside this check, not part of it: " + "; ".join(unconverged)
        if any(": peak NOT converged" in u for u in unconverged):
            line += " (no safety factor is taken from a peak that is not converged)"
    elif result.comparisons and all(c.study is None for c in result.comparisons.values()):
        line += "; convergence not checked (one mesh)"
    if failures:
        line += "\n  " + "\n  ".join(failures)
    return line


def validation_text(result: ValidationResult, details: bool = False, verdict: Verdict | None = None) -> str:
    """The terminal report: the ``verdict`` (made here when not given), the scene's warnings, a
    compact comparison per link and the check; with ``details`` each link's paragraph."""
    parts = [(verdict or validation_verdict(result)).text()]
    if result.analysis.scene.warnings:
        parts.append(warnings_text(result.analysis.scene.warnings))
    lines = [
        f"beam sections against FEA at {len(result.positions)} position(s) (worst over them; MPa, %)",
        text_table(HEADERS, table_rows(result)),
        LEGEND.format(limit=100 * RESULTANT_LIMIT),
        KT_WORDS,
    ]
    lines += [f"  {name}: FEA failed: {message}" for name, message in result.errors.items()]
    lines.append(check_line(result))
    parts.append("\n".join(lines))
    if details:
        parts.append("\n".join(f"  {name}: {part}" for name, c in result.comparisons.items() for part in link_lines(result, name, c)))
    elif result.comparisons:
        parts.append(DETAILS_HINT)
    return "\n\n".join(parts)


def link_lines(result: ValidationResult, name: str, c: LinkComparison) -> list[str]:
    """What the comparison of one link says, one statement each, every figure with its input angle
    and place."""
    angles = input_angles(result)
    lines = [
        f"beam maximum {beam_maximum(result, name).words()}; FEA peak {fea_peak(c, angles).words()}",
        peak_words(c, angles, fea_where(result, name, c)),
        nominal_words(c, angles),
    ]
    if c.station_note and c.frame_compared:
        lines.append(c.station_note)
    lines += [s.note for s in c.skipped]
    if len(c.members) > 1:
        lines += [member_words(m) for m in c.members]
        lines += [f"member joints {m.joints[0]}-{m.joints[1]}: {m.beam.note}" for m in c.members if m.beam.note]
    labels = joint_names(result.analysis.scene)[name]
    lines += [pin_hole_words(h, angles, labels[h.joint].words()) for h in c.hole_peaks]
    bend = curvature_note(c)
    if bend:
        lines.append(bend)
    lines.append(convergence_words(convergence_record(c)))
    factor, reason = fea_safety_factor(result, name, c)
    if factor is not None:
        lines.append(f"yield safety factor {factor:.3g} against the FEA peak")
    elif reason is not None and not reason.startswith("the material has no"):
        lines.append(f"no yield safety factor: {reason}")
    return lines


def peak_words(c: LinkComparison, angles: NDArray[np.float64], where: str = "") -> str:
    """The FEA peak over the beam's largest (the stress raiser the beam does not model), at its input
    angle and place (``where``), with the two values it compares."""
    k = int(np.argmax(c.peak_error))
    ratio = f"{c.fea_peak[k] / c.beam_max[k]:.3g} x" if c.beam_max[k] > 0 else "- (no beam stress)"
    at = f", at {where}" if where else ""
    return (
        f"FEA peak / beam maximum = {ratio}{at} - the stress raiser the beam does not model; see the verdict "
        f"(at input angle {angles[k]:.4g} deg: the FEA peak {mpa(c.fea_peak[k])} MPa, the beam's largest at the "
        f"comparison stations {mpa(c.beam_max[k])} MPa)"
    )


def nominal_note(c: LinkComparison) -> str | None:
    """Why no nominal comparison is possible on this link, or None when it is made."""
    if c.nominal_error is not None:
        return None
    if not c.frame_compared:
        return ("no nominal comparison: no compared member has a station a section depth from every pin and junction"
                if c.members else "no nominal comparison: no member of the link could be compared")
    depth = c.beam.sections.top - c.beam.sections.bottom
    centres = c.fea.link.frame(*c.fea.frame_joints).to_local(c.fea.link.holes[0])[:, 0]
    gap = np.abs(c.stations[:, None] - centres).min(axis=1, initial=np.inf)
    k = int(np.argmax(gap - depth))
    # a station at a joint's abscissa may carry round-off (x = 1.4e-17): against the link's size it is 0
    x = float(without_noise(c.stations, float(np.abs(c.stations).max() + depth.max()))[k])
    return (
        f"no nominal comparison: no station is a section depth from every pin (at x = {x:.4g} m, "
        f"member frame, the section is {depth[k]:.4g} m deep and the nearest pin {gap[k]:.4g} m away), and within a "
        "section depth of a pin beam theory does not hold"
    )


def nominal_words(c: LinkComparison, angles: NDArray[np.float64]) -> str:
    """The nominal comparison at its worst, or why there is none."""
    if c.nominal_error is None:
        return nominal_note(c)
    k = int(np.argmax(c.nominal_error))
    if not c.members:
        diff = c.fea_von_mises[k, c.away] - c.beam.von_mises[k, c.away]
        s = int(np.argmax(np.abs(diff)))
        where = f"x = {c.stations[c.away][s]:.4g} m, member frame"
    else:
        m = max((m for m in c.members if m.nominal_error is not None), key=lambda m: m.nominal_error[k])
        away = m.beam.away
        s = int(np.argmax(np.abs(m.fea_von_mises[k, away] - m.beam.von_mises[k, away])))
        x, y = m.beam.cuts.origin[away][s]
        where = f"s = {m.beam.cuts.s[away][s]:.4g} m along member joints {m.joints[0]}-{m.joints[1]}, {point((x, y))} m member frame"
    return f"nominal stresses within {100 * c.nominal_error[k]:.3g} % (worst at input angle {angles[k]:.4g} deg, {where})"


def pin_hole_words(h: HolePeak, angles: NDArray[np.float64], name: str = "") -> str:
    """A pin hole's Kt x nominal estimate against the FEA's peak at the same hole and position; the
    hole named ``name`` (its joint's, default "joint k")."""
    r = pin_hole_record(h, angles)
    hole = f"pin hole {name or f'at joint {h.joint}'} (d = {h.diameter:.4g} m, centre {point(h.centre)} m, member frame)"
    if r["estimate_pa"] is None:
        return (
            f"{hole}: the FEA's peak there is {mpa(r['fea_peak_pa'])} MPa at input angle {r['input_angle_deg']:.4g} deg; "
            f"no Kt x nominal estimate at the compared positions, outside the Kt tables: {r['kt_outside_reason']}"
        )
    return (
        f"{hole}: Kt x nominal estimate {mpa(r['estimate_pa'])} MPa against the FEA's {mpa(r['fea_peak_pa'])} MPa "
        f"at that hole, at input angle {r['input_angle_deg']:.4g} deg ({r['error_pct']:+.3g} %)"
    )


def convergence_words(record: dict) -> str:
    """Each quantity's change over the last refinement against its limit, or "not checked"."""
    if all(q["status"] == "not checked" for q in record.values()):
        return "convergence not checked (one mesh, --mesh-levels 1)"
    parts = []
    for quantity, q in record.items():
        if q["change_pct"] is None:
            parts.append(f"{quantity} {q['status']}")
        else:
            before = "" if q["previous_change_pct"] is None else f", {q['previous_change_pct']:.3g} % the refinement before"
            parts.append(f"{quantity} {q['status']} ({q['change_pct']:.3g} %{before}, limit {q['limit_pct']:g} %)")
    return "change over the last refinement: " + ", ".join(parts)


def curvature_note(c: LinkComparison) -> str:
    """How a curved link is sectioned (normal to its centreline, with curved-beam normal stress), or
    "" for a straight one."""
    if c.beam.curved is None:
        return ""
    return (
        "the link is curved: its sections are cut normal to its centreline and take the curved-beam "
        "(Winkler-Bach) normal stress, which the FEA checks over the same cuts"
    )


def fea_contour_figure(c: LinkComparison, k: int, angle_deg: float) -> Figure:
    """FEA von Mises over the link (member frame) at compared position ``k`` (input angle
    ``angle_deg`` [deg]), peak marked."""
    mesh = c.fea.plane.mesh
    corners = mesh.nvertices  # the P2 mesh lists its corner nodes first
    values = c.fea.nodal_von_mises[k, c.fea.model.scalar.nodal_dofs[0][:corners]] / 1e6
    fig, ax = plt.subplots(figsize=(7.5, 3.8), layout="constrained")
    triangles = Triangulation(mesh.p[0, :corners], mesh.p[1, :corners], mesh.t.T)
    # A pin's peak can be a hundred times the rest: a log scale keeps the link's own field in view.
    scale = field_scale(values)
    shading = ax.tripcolor(triangles, values, shading="gouraud", cmap="viridis", norm=scale.norm)
    field_colour_bar(fig, ax, shading, scale.label)
    peak = c.fea.von_mises_peak_at[k]
    for x in c.stations:
        ax.axvline(x, color="white", lw=0.4, alpha=0.6)
    ax.plot(*peak, marker="*", color="red", ms=14, zorder=LABEL_ZORDER - 1)
    # Offset toward the link's middle: at a pin near the end the label would leave the axes.
    side = 1 if peak[0] <= float(np.mean(ax.get_xlim())) else -1
    boxed_label(ax, f"peak {c.fea_peak[k] / 1e6:.4g} MPa", peak, offset=(10 * side, 10), color="red",
                ha="left" if side > 0 else "right")
    ax.set_aspect("equal")
    ax.set_xlabel("x along the member [m], member frame")
    ax.set_ylabel("y [m], member frame")
    ax.set_title(f"{c.name} at input angle {angle_deg:.4g} deg: FEA von Mises (white lines: comparison cuts)")
    return fig


def validation_html(result: ValidationResult, verdict: Verdict | None = None) -> str:
    """The HTML report: the ``verdict`` (made here when not given) first, the analysis, then the
    comparison of every link."""
    top = verdict_html(verdict or validation_verdict(result)) + warnings_html(result.analysis)
    sections = analysis_sections(result.analysis, top)
    sections.insert(-2, "<h2>Beam against FEA</h2>")
    body = [f'<p class="note">{html.escape(NOTE)}</p>', table_html(HEADERS, table_rows(result, reasons=True))]
    verdict, *failures = check_line(result).split("\n")
    body.append(f"<p><b>{html.escape(verdict)}</b></p>")
    body += [f"<p>{html.escape(line.strip())}</p>" for line in failures]
    angles = input_angles(result)
    for name, c in result.comparisons.items():
        k = int(np.argmax(c.peak_error))
        position = int(result.positions[k])
        body.append(f"<h3>{html.escape(name)}</h3>")
        body += [f"<p>{html.escape(line)}</p>" for line in link_lines(result, name, c)]
        body.append(f"<p>Figures at input angle {angles[k]:.4g} deg, the position of the largest FEA peak over the beam's "
                    "maximum.</p>")
        body.append(figure_tag(fea_contour_figure(c, k, angles[k]), f"FEA contour of {name}"))
        if name in result.analysis.stresses:
            body.append(figure_tag(
                stress_along_figure(result.analysis, name, position, c.stations, c.fea_von_mises[k]),
                f"beam and FEA along {name} at input angle {angles[k]:.4g} deg",
            ))
        if c.study is not None:
            study_rows = [
                (int(d), float(h), mpa(float(p)), float(t))
                for d, h, p, t in zip(c.study.dofs, c.study.spacing, c.study.peaks.max(axis=1), c.study.seconds)
            ]
            body.append(table_html(("dofs", "element spacing [m]", "FEA peak [MPa]", "time [s]"), study_rows))
            if c.study.has_nominal:
                body.append(
                    f"<p>Richardson estimate of the finest mesh's error at the nominal points "
                    f"{100 * c.discretisation_error.max():.3g} %.</p>"
                )
    sections[-2:-2] = body
    return page(report_title(result.analysis.scene, "validate"), sections)
