"""Reports of a validation: DESIGN.md's ``validate`` JSON, terminal text, and HTML sections.

Errors are percentages; a link's scalar values are the worst over the compared positions, with the
per-position values beside them.
"""

from __future__ import annotations

import html

import matplotlib.pyplot as plt
import numpy as np
from numpy.typing import NDArray
from matplotlib.figure import Figure
from matplotlib.tri import Triangulation

from linkstress.report.figures import stress_along_figure
from linkstress.report.html import analysis_sections, figure_tag, page, table_html
from linkstress.safety import finite_or_none, yield_factor
from linkstress.sections import SectionTable
from linkstress.tables import format_table
from linkstress.validation.compare import LinkComparison
from linkstress.validation.validate_scene import REACTION_LIMIT, RESULTANT_LIMIT, ValidationResult

NOTE = (
    "Beam sections are checked against plane-stress FEA of the same link under the same loads: pin "
    "forces as cosine bearing pressure on the loaded half of each hole, a driving torque as a uniform "
    "shear on its pin's hole, the d'Alembert body force, applied couples. Resultants: N, V, M over FEA "
    "cuts. Nominal: von Mises at the beam's critical fibre of stations at least one section depth from "
    "every pin. Peak: the FEA's largest anywhere, which beam theory does not see near holes."
)


def link_record(result: ValidationResult, name: str) -> dict:
    """The ``validate`` JSON entry of one link."""
    if name in result.errors:
        return {"error": result.errors[name]}
    c = result.comparisons[name]
    analysis_beam = result.analysis.stresses[name].max_von_mises[result.positions]
    record = {
        "beam_max_von_mises_pa": float(analysis_beam.max()),
        "fea_max_von_mises_pa": float(c.fea_peak.max()),
        "nominal_error_pct": None if c.nominal_error is None else float(100 * c.nominal_error.max()),
        "peak_error_pct": float(100 * c.peak_error.max()),
        "resultant_error_pct": float(100 * c.resultant_error.max()),
        "dofs": int(c.fea.dofs),
        "beam_seconds": float(c.beam_seconds),
        "fea_seconds": float(c.fea_seconds),
        "elements": int(c.fea.n_elements),
        "mesh_size_m": float(c.fea.plane.settings.size),
        "hole_size_m": float(c.fea.plane.settings.hole_size),
        "mesh_levels": 1 if c.study is None else len(c.study.dofs),
        "converged": None if c.study is None else bool(c.study.converged),
        "discretisation_error_pct": None if c.study is None else float(100 * c.discretisation_error.max()),
        "reaction_ratio": float(c.fea.reaction_ratio.max()),
        "pin_estimate_max_pa": pin_estimate(c),
        "fea_yield_safety_factor": fea_safety_factor(result, name, float(c.fea_peak.max())),
        "stations_m": c.stations.tolist(),
        "nominal_stations_m": c.stations[c.away].tolist(),
        "positions": {
            "input_angle_deg": result.analysis.scene.motion.angle_deg[result.positions].tolist(),
            "beam_max_von_mises_pa": analysis_beam.tolist(),
            "fea_max_von_mises_pa": c.fea_peak.tolist(),
            "fea_max_at_m": _ground(result, name, c.fea.von_mises_peak_at).tolist(),
            "nominal_error_pct": None if c.nominal_error is None else (100 * c.nominal_error).tolist(),
            "peak_error_pct": (100 * c.peak_error).tolist(),
            "resultant_error_pct": (100 * c.resultant_error).tolist(),
        },
    }
    return record


def fea_safety_factor(result: ValidationResult, name: str, fea_peak: float) -> float | None:
    """The link material's yield strength over the FEA peak (the stress to trust near the pins), or
    None without a yield strength or without stress."""
    material = result.analysis.scene.links[name].material
    if material is None or material.yield_strength is None:
        return None
    return finite_or_none(yield_factor(material.yield_strength, np.array([fea_peak])))[0]


def pin_estimate(c: LinkComparison) -> float | None:
    """The largest Kt x nominal estimate inside the Kt tables at the link's pin holes over the compared positions."""
    values = [e for e in (h.largest(slice(None)) for h in c.beam.pin_holes) if e is not None]
    return max(values) if values else None


def _ground(result: ValidationResult, name: str, local: np.ndarray) -> np.ndarray:
    """Member-frame points (Pc, 2) at the compared positions, in the ground frame."""
    motion = result.analysis.kinematics.links[name]
    k = result.positions
    c, s = np.cos(motion.angle[k]), np.sin(motion.angle[k])
    return motion.origin[k] + np.column_stack([c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]])


def validation_json(result: ValidationResult) -> dict:
    return {
        "links": {name: link_record(result, name) for name in result.analysis.plan.validate},
        "positions_compared": result.positions.tolist(),
        "failures": result.failures(),
    }


def validation_text(result: ValidationResult) -> str:
    rows, records = [], {}
    for name in result.analysis.plan.validate:
        if name in result.errors:
            rows.append((name, "FEA failed", "", "", "", "", "", ""))
            continue
        r = records[name] = link_record(result, name)
        nominal = "-" if r["nominal_error_pct"] is None else r["nominal_error_pct"]
        converged = "-" if r["converged"] is None else ("yes" if r["converged"] else "NO")
        rows.append((
            name, r["beam_max_von_mises_pa"], r["fea_max_von_mises_pa"], r["resultant_error_pct"], nominal,
            r["peak_error_pct"], r["dofs"], converged,
        ))
    headers = ("link", "beam max [Pa]", "FEA peak [Pa]", "resultants [%]", "nominal [%]", "peak [%]", "dofs", "converged")
    lines = [
        f"beam sections against FEA at {len(result.positions)} position(s) (worst over them)",
        format_table(headers, rows),
        "resultants: N, V, M over FEA cuts; nominal: von Mises at stations one section depth or more from "
        "every pin; peak: the FEA's largest anywhere (beam theory misses it near holes).",
    ]
    lines += [f"  {name}: {message}" for name, message in result.errors.items()]
    for name, c in result.comparisons.items():
        lines.append(f"  {name}: {shortfall(c)}")
        factor = records[name]["fea_yield_safety_factor"]
        if factor is not None:
            lines.append(f"  {name}: yield safety factor {factor:.3g} against the FEA peak")
    failures = result.failures()
    lines.append("check: " + ("passed" if not failures else "FAILED\n  " + "\n  ".join(failures)))
    return "\n".join(lines)


def shortfall(c: LinkComparison) -> str:
    """Where beam theory falls short on this link, in words."""
    worst = int(np.argmax(c.peak_error))
    parts = [
        f"FEA peak {c.fea_peak[worst]:.4g} Pa at ({c.fea.von_mises_peak_at[worst][0]:.4g}, "
        f"{c.fea.von_mises_peak_at[worst][1]:.4g}) m (member frame) against a beam maximum of "
        f"{c.beam_max[worst]:.4g} Pa"
    ]
    if c.nominal_error is None:
        parts.append("no station is a section depth from every pin: the link is all near-hole region")
    else:
        k = int(np.argmax(c.nominal_error))
        diff = c.fea_von_mises[k, c.away] - c.beam.von_mises[k, c.away]
        s = int(np.argmax(np.abs(diff)))
        parts.append(
            f"nominal stresses within {100 * c.nominal_error.max():.3g} % (largest at x = "
            f"{c.stations[c.away][s]:.4g} m)"
        )
    estimate = pin_estimate(c)
    if estimate is not None:
        parts.append(
            f"the Kt x nominal estimate at its pins is {estimate:.4g} Pa "
            f"({100 * (estimate / c.fea_peak.max() - 1):+.3g} % of the FEA peak; it leaves out any couple "
            "carried through a pin)"
        )
    bend = curvature_note(c)
    if bend:
        parts.append(bend)
    if c.study is not None and not c.study.converged:
        parts.append("the FEA did not converge to 0.5 % over the refinement study")
    return "; ".join(parts)


CURVED = 0.1
"""A link whose neutral axis wanders more than this fraction of its depth off the member axis."""


def neutral_axis_wander(table: SectionTable, near_hole: NDArray[np.bool_]) -> tuple[float, float] | None:
    """How far the neutral axis wanders across the member axis [m], and the smallest section depth
    [m], over the solid stations clear of holes (a hole moves the neutral axis of a straight bar
    too); None with fewer than two such stations."""
    plain = (table.n_chords == 1) & ~near_hole
    if plain.sum() < 2:
        return None
    return float(np.ptp(table.neutral_axis[plain])), float((table.top - table.bottom)[plain].min())


def is_curved(table: SectionTable, near_hole: NDArray[np.bool_]) -> bool:
    """A link whose neutral axis wanders more than CURVED section depths: straight sections fall short."""
    wander = neutral_axis_wander(table, near_hole)
    return wander is not None and wander[0] > CURVED * wander[1]


def curvature_note(c: LinkComparison) -> str:
    """Why straight-beam sections fall short on a curved link, or "" for a straight one."""
    if not is_curved(c.beam.sections, c.beam.near_hole):
        return ""
    wander, depth = neutral_axis_wander(c.beam.sections, c.beam.near_hole)
    return (
        f"the link is curved (its neutral axis wanders {wander:.3g} m across the member axis, "
        f"{wander / depth:.2g} section depths): straight-beam sections cut the curved bar at an angle and "
        "sigma = N/A + M y/I misses the curvature's shift of the neutral axis (Winkler-Bach), so the FEA is "
        "the value to trust there"
    )


def fea_contour_figure(c: LinkComparison, k: int) -> Figure:
    """FEA von Mises over the link (member frame) at compared position ``k``, peak marked."""
    mesh = c.fea.plane.mesh
    corners = mesh.nvertices  # the P2 mesh lists its corner nodes first
    values = c.fea.nodal_von_mises[k, c.fea.model.scalar.nodal_dofs[0][:corners]] / 1e6
    fig, ax = plt.subplots(figsize=(7.5, 3.8))
    triangles = Triangulation(mesh.p[0, :corners], mesh.p[1, :corners], mesh.t.T)
    # A pin's peak can be a hundred times the rest: cap the scale so the link's own field shows.
    shading = ax.tripcolor(triangles, values, shading="gouraud", cmap="viridis", vmax=float(np.percentile(values, 99)))
    fig.colorbar(shading, ax=ax, label="von Mises [MPa] (capped at the 99th percentile)", extend="max")
    peak = c.fea.von_mises_peak_at[k]
    ax.plot(*peak, marker="*", color="red", ms=14)
    ax.annotate(f"peak {c.fea_peak[k] / 1e6:.4g} MPa", peak, textcoords="offset points", xytext=(8, 8), color="red")
    for x in c.stations:
        ax.axvline(x, color="white", lw=0.4, alpha=0.6)
    ax.set_aspect("equal")
    ax.set_xlabel("x along the member [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{c.name}: FEA von Mises (white lines: comparison cuts)")
    fig.tight_layout()
    return fig


def validation_html(result: ValidationResult) -> str:
    sections = analysis_sections(result.analysis)
    sections.insert(-2, "<h2>Beam against FEA</h2>")
    body = [f'<p class="note">{html.escape(NOTE)}</p>']
    rows = []
    for name in result.analysis.plan.validate:
        r = link_record(result, name)
        if "error" in r:
            rows.append((name, "FEA failed: " + r["error"], "", "", "", "", "", "", ""))
            continue
        rows.append((
            name, r["beam_max_von_mises_pa"], r["fea_max_von_mises_pa"], r["resultant_error_pct"],
            "-" if r["nominal_error_pct"] is None else r["nominal_error_pct"], r["peak_error_pct"],
            r["dofs"], r["beam_seconds"], r["fea_seconds"],
        ))
    body.append(table_html(
        ("link", "beam max [Pa]", "FEA peak [Pa]", "resultants err [%]", "nominal err [%]", "peak err [%]",
         "dofs", "beam [s]", "FEA [s]"), rows,
    ))
    failures = result.failures()
    body.append(f"<p><b>Check: {'passed' if not failures else 'FAILED'}</b> (support reactions below "
                f"{REACTION_LIMIT:g} of the load, resultants within {100 * RESULTANT_LIMIT:g} %)</p>")
    body += [f"<p>{html.escape(line)}</p>" for line in failures]
    for name, c in result.comparisons.items():
        k = int(np.argmax(c.peak_error))
        position = int(result.positions[k])
        body.append(f"<h3>{html.escape(name)}</h3><p>{html.escape(shortfall(c))}</p>")
        body.append(figure_tag(fea_contour_figure(c, k), f"FEA contour of {name}"))
        if name in result.analysis.stresses:
            body.append(figure_tag(
                stress_along_figure(result.analysis, name, position, c.stations, c.fea_von_mises[k]),
                f"beam and FEA along {name}",
            ))
        if c.study is not None:
            study_rows = [(int(d), float(s), float(t)) for d, s, t in zip(c.study.dofs, c.study.spacing, c.study.seconds)]
            body.append(table_html(("dofs", "element spacing [m]", "time [s]"), study_rows))
            body.append(
                f"<p>Refinement study: change between the two finest meshes {100 * c.study.change.max():.3g} % "
                f"({'converged' if c.study.converged else 'NOT converged'} at 0.5 %); Richardson estimate of "
                f"the finest mesh's error {100 * c.discretisation_error.max():.3g} %.</p>"
            )
    sections[-2:-2] = body
    return page(f"linkstress validate: {result.analysis.scene.title}", sections)
