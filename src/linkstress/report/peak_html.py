"""The HTML report's FEA peaks and fatigue (``analyze --peaks``).

Per link: the sweep's summary (``peak_records.peak_summaries``, the figures of the text report's
table), the FEA peak along the sweep beside the beam's nominal maximum, and the von Mises field at
the worst position drawn on the peak mesh in the ground frame, with the peak and the fatigue
critical point marked. Stresses in MPa.
"""

from __future__ import annotations

import html

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator, MultipleLocator
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.report.cells import mpa, point
from linkstress.report.figures import field_colour_bar, field_scale, plt  # pyplot on the reports' Agg backend
from linkstress.report.html import figure_tag, table_html
from linkstress.report.peak_records import peak_summaries
from linkstress.stress_state import von_mises

CRITERION_NAMES = {"goodman": "Goodman", "gerber": "Gerber", "asme-elliptic": "ASME-elliptic"}
SUBTRIANGLES = np.array([[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]])
"""A 6-node triangle's four linear ones, as rows of its element dofs. skfem's ElementTriP2 numbers
the vertices 0-2, then the mid-edge nodes of edges (0, 1), (1, 2) and (0, 2) as 3, 4 and 5: the
three corner triangles keep the parent's orientation, and so does the middle one (the parent turned
by 180 deg)."""
LOG_SCALE_RATIO = 10.0
"""Above this ratio of the FEA peak to the beam's maximum, the sweep figure's stress axis is
logarithmic, so that the smaller values keep their shape (the field figure: ``figures.field_scale``)."""
FIGURE_SIZE = (6.0, 4.0)
WITHHELD = "withheld: the FEA peak is NOT converged (see the notes)"


def peak_sections(result: AnalysisResult) -> list[str]:
    """The section "FEA peak stresses and fatigue": per link with peaks, its table and notes, its peak
    over the sweep and its von Mises field at the worst position."""
    sections = [
        "<h2>FEA peak stresses and fatigue</h2>",
        '<p class="note">Plane-stress FEA of each link on a refined mesh, its unit load cases superposed at every '
        "feasible position: the von Mises peak anywhere in the link (pin holes, fillets, curved crowns), beside the "
        "beam's largest nominal section value. The peak's convergence is its change at its worst position over the "
        "last two mesh refinements; a peak that has not settled gives no safety factor. Fatigue: per point, the "
        "alternating and mean of the signed von Mises over the sweep, against the Marin-corrected endurance limit "
        "(docs/fatigue.md). Stresses in MPa.</p>",
    ]
    for name, summary in peak_summaries(result).items():
        sections += [
            f"<h3>{html.escape(name)}</h3>",
            table_html(("quantity", "value"), peak_rows(summary)),
            _notes_html(summary),
            figure_tag(peak_sweep_figure(result, name), f"FEA peak of {name} over the sweep"),
            figure_tag(peak_field_figure(result, name), f"von Mises in {name} at its worst position"),
        ]
    return sections


def peak_rows(summary: dict[str, object]) -> list[tuple[str, str]]:
    """A link's summary record (``peak_summaries``) as (quantity, value) text rows (stresses in MPa
    and factors to 3 significant digits, as the report's other tables)."""
    s = summary
    peak, beam = s["peak_max_von_mises_pa"], s.get("beam_max_von_mises_pa")
    status = "converged" if s["peak_converged"] else "NOT converged"
    rows = [
        ("FEA peak von Mises, largest over the sweep [MPa]", mpa(peak)),
        ("at input angle [deg]", f"{s['peak_max_input_angle_deg']:.6g}"),
        ("at (x, y) [m], ground frame", _point(s["peak_max_at_m"])),
        ("beam maximum, section von Mises (nominal), same positions [MPa]", "-" if beam is None else mpa(beam)),
        ("FEA peak / beam maximum", "-" if not beam else f"{peak / beam:.3g}"),
        ("peak convergence: change over the last mesh refinement, over the one before",
         f"{s['peak_change_pct']:.3g} %, {s['peak_previous_change_pct']:.3g} % (limit {s['peak_change_limit_pct']:g} % "
         f"each): {status}"),
        ("yield safety factor, from the FEA peak", _yield_factor(s)),
        (f"fatigue safety factor ({CRITERION_NAMES[s['fatigue_criterion']]}), other criteria beside it",
         _fatigue_factors(s)),
    ]
    if "fatigue_alternating_pa" in s:
        rows += [
            ("alternating stress sigma_a at the critical point [MPa]", mpa(s["fatigue_alternating_pa"])),
            ("mean stress sigma_m at the critical point [MPa]", mpa(s["fatigue_mean_pa"])),
            ("corrected endurance limit S_e [MPa]", mpa(s["fatigue_endurance_limit_pa"])),
            ("fatigue critical point (x, y) [m], drawing frame (the sketch's coordinates)",
             _point(s["fatigue_critical_at_m"])),
        ]
    mesh = s["peak_mesh"]
    solves = (f"{mesh['unit_load_cases']} unit load cases (bearing every {mesh['direction_step_deg']:g} deg)"
              if mesh["unit_load_cases"] else f"a direct solve at each of {mesh['direct_solves']} positions")
    rows.append(("FEA mesh", f"{mesh['dofs']} dofs, P{mesh['element_order']} triangles, {solves}"))
    return rows


def _notes_html(summary: dict[str, object]) -> str:
    """The link's notes under its table, as the text report gives them: why a factor is withheld,
    what the fatigue covers or why there is none."""
    notes = [(label, summary[key]) for label, key in (("FEA peak", "peak_note"), ("fatigue", "fatigue_note")) if summary[key]]
    if not notes:
        return ""
    items = "".join(f"<li>{label}: {html.escape(text)}</li>" for label, text in notes)
    return f'<p class="note">Notes:</p><ul class="note">{items}</ul>'


def _point(xy) -> str:
    return point(xy)


def _yield_factor(s: dict[str, object]) -> str:
    if "peak_yield_safety_factor" not in s:
        return "- (the material gives no yield_strength)"
    if not s["peak_converged"]:
        return WITHHELD
    factor = s["peak_yield_safety_factor"]
    return "- (no stress)" if factor is None else f"{factor:.3g}"


def _fatigue_factors(s: dict[str, object]) -> str:
    if "fatigue_safety_factors" not in s:
        return "- (no fatigue check: see the notes)"
    if not s["peak_converged"]:
        return WITHHELD
    criterion = s["fatigue_criterion"]
    factors = s["fatigue_safety_factors"]

    def text(value: float | None) -> str:
        # None on a converged peak: nothing cycles at the critical point, an infinite factor.
        return "- (nothing cycles)" if value is None else f"{value:.3g}"

    others = ", ".join(f"{CRITERION_NAMES[k]} {text(v)}" for k, v in factors.items() if k != criterion)
    return f"{text(factors[criterion])} ({CRITERION_NAMES[criterion]})" + (f"; {others}" if others else "")


def peak_sweep_figure(result: AnalysisResult, name: str) -> Figure:
    """Link ``name``'s FEA peak [MPa] over the input angle beside the beam's largest section von
    Mises, with the worst position marked; infeasible positions are gaps."""
    peaks = result.peaks[name]
    angle = result.scene.motion.angle_deg
    fea = peaks.peak / 1e6
    fig, ax = plt.subplots(figsize=FIGURE_SIZE, layout="constrained")
    ax.plot(angle, fea, ".-", ms=4, color="#d62728", label="FEA peak, anywhere in the link")
    # A link with peaks has section stresses (Plan.with_peaks); they hold values at infeasible positions.
    beam = np.where(result.feasible, result.stresses[name].max_von_mises, np.nan) / 1e6
    ax.plot(angle, beam, ".-", ms=4, color="#1f77b4", label="beam, largest section von Mises (nominal)")
    largest_beam = float(np.nanmax(beam))
    worst = peaks.worst_position
    ax.plot(angle[worst], fea[worst], "o", ms=11, mfc="none", mec="k", mew=1.5,
            label=f"worst: {fea[worst]:.4g} MPa at input {angle[worst]:.4g} deg")
    logarithmic = largest_beam > 0 and fea[worst] > LOG_SCALE_RATIO * largest_beam
    if logarithmic:
        ax.set_yscale("log")
    ax.set_xlabel("input angle [deg]")
    ax.set_ylabel("von Mises [MPa]" + (", log scale" if logarithmic else ""))
    ax.set_title(f"{name}: FEA peak and beam maximum over the sweep", fontsize=10)
    ax.grid(alpha=0.3, which="both" if logarithmic else "major")
    fig.legend(loc="outside lower center", ncol=2, fontsize=8, frameon=False)
    return fig


def peak_field_figure(result: AnalysisResult, name: str) -> Figure:
    """Link ``name``'s recovered von Mises [MPa] at its worst position on the peak mesh, in the ground
    frame at that position, with the peak and the fatigue critical point (if any) marked."""
    peaks = result.peaks[name]
    cases = peaks.sweep.cases
    worst = peaks.worst_position
    nodes = cases.nodes

    def ground(local: NDArray[np.float64]) -> NDArray[np.float64]:
        return result.to_ground(name, local, np.full(len(local), worst))

    xy = ground(nodes)
    stress = von_mises(peaks.sweep.worst_stress) / 1e6
    # A peak concentrated at a hole would leave the rest of the link one colour on a linear scale.
    scale = field_scale(stress)
    fig, ax = plt.subplots(figsize=FIGURE_SIZE, layout="constrained")
    field = ax.tripcolor(xy[:, 0], xy[:, 1], linear_triangles(cases.element_dofs), stress,
                         shading="gouraud", cmap="viridis", norm=scale.norm)
    field_colour_bar(fig, ax, field, scale.label)
    peak_at = ground(peaks.sweep.peak_at[peaks.sweep.worst:peaks.sweep.worst + 1])[0]
    ax.plot(*peak_at, "*", ms=15, mfc="white", mec="k", label=f"FEA peak {peaks.peak_max / 1e6:.4g} MPa")
    if peaks.fatigue is not None:
        critical = ground(nodes[peaks.fatigue.critical_node:peaks.fatigue.critical_node + 1])[0]
        ax.plot(*critical, "D", ms=9, mfc="none", mec="#e377c2", mew=2,
                label=f"fatigue critical point (lowest {CRITERION_NAMES[peaks.fatigue_criterion]} factor)")
    ax.set_aspect("equal")
    _same_ticks(ax, xy)
    ax.set_xlabel("x [m], ground frame")
    ax.set_ylabel("y [m], ground frame")
    ax.set_title(f"{name} at input {result.scene.motion.angle_deg[worst]:.4g} deg: von Mises", fontsize=10)
    fig.legend(loc="outside lower center", ncol=2, fontsize=8, frameon=False)
    return fig


def _same_ticks(ax, xy: NDArray[np.float64]) -> None:
    """One tick spacing on both axes of an equal-aspect drawing of the points ``xy`` (n, 2), about five
    ticks along its longer side: the shorter side then gets fewer ticks, not crowded labels."""
    ticks = MaxNLocator(5).tick_values(0.0, float(np.ptp(xy, axis=0).max()))
    step = float(ticks[1] - ticks[0])
    ax.xaxis.set_major_locator(MultipleLocator(step))
    ax.yaxis.set_major_locator(MultipleLocator(step))


def linear_triangles(element_dofs: NDArray[np.intp]) -> NDArray[np.intp]:
    """(T', 3) linear triangles of the nodes of a mesh's scalar space, from its element dofs (3, T)
    (P1: the elements themselves) or (6, T) (P2: each split into four, ``SUBTRIANGLES``)."""
    dofs = np.asarray(element_dofs)
    if len(dofs) == 3:
        return dofs.T
    return dofs[SUBTRIANGLES].transpose(2, 0, 1).reshape(-1, 3)
