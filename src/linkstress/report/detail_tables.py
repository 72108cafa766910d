"""The position-by-position tables of ``analyze --details`` (motion, joint forces named by the links
they act between, section stresses with where each figure comes from), and the pin-hole estimate's
cell shared with the short report. At most ``MAX_ROWS`` positions per table, evenly spaced, said so;
the JSON and HTML carry every position. Stresses in MPa, forces in N to 4 significant digits,
round-off noise written 0 (``report.cells``).
"""

from __future__ import annotations

import numpy as np

from linkstress.analysis import AnalysisResult
from linkstress.report.cells import column_cells, mpa, point, significant, text_table
from linkstress.report.maxima import LinkFigures, link_figures
from linkstress.report.places import force_names, joint_names
from linkstress.report.records import link_columns
from linkstress.safety import link_safety_factors, uncovered_pin_holes

MAX_ROWS = 40


def shown_positions(result: AnalysisResult) -> tuple[np.ndarray, str]:
    """Feasible positions to tabulate (at most MAX_ROWS, evenly spaced) and a note when thinned."""
    ok = np.flatnonzero(result.feasible)
    if len(ok) <= MAX_ROWS:
        return ok, ""
    pick = ok[np.linspace(0, len(ok) - 1, MAX_ROWS).round().astype(int)]
    return pick, f"({MAX_ROWS} of {len(ok)} feasible positions shown; --json has all)"


def motion_table(result: AnalysisResult) -> str:
    """Each link's angle, angular velocity and acceleration and its centre of mass's acceleration
    (ground frame), 6 significant digits, round-off noise written 0."""
    columns = link_columns(result)
    rows = []
    shown, note = shown_positions(result)
    for k in shown:
        angle = float(result.scene.motion.angle_deg[k])
        for name, c in columns.items():
            acc = ("", "") if c.acc_g is None else (float(c.acc_g[k, 0]), float(c.acc_g[k, 1]))
            rows.append((angle, name, float(c.angle_deg[k]), float(c.omega[k]), float(c.alpha[k]), *acc))
    headers = ("input [deg]", "link", "angle [deg]", "omega [rad/s]", "alpha [rad/s^2]", "a_Gx [m/s^2]", "a_Gy [m/s^2]")
    cells = column_cells(rows, (6, None, 6, 6, 6, 6, 6))
    return "\n".join(filter(None, ["motion", text_table(headers, cells), note]))


def forces_table(result: AnalysisResult) -> str:
    """Joint forces, each named by the links it acts between (Fij: the force of link i on link j,
    ground frame) to 4 significant digits, and the driving torque or force."""
    rows = []
    shown, note = shown_positions(result)
    named = force_names(result.scene)
    for k in shown:
        angle = float(result.scene.motion.angle_deg[k])
        for name, mech in result.forces.mechanisms.items():
            for label, force in mech.forces.items():
                rows.append((angle, name, label, named[name].get(label, ""), float(force[k, 0]), float(force[k, 1]),
                             float(np.hypot(*force[k]))))
            if mech.driving_torque is not None:
                rows.append((angle, name, f"{mech.torque_name} [N m]", "driving torque", float(mech.driving_torque[k]), "", ""))
            if mech.driving_force is not None:
                rows.append((angle, name, f"{mech.force_name} [N]", "driving force", float(mech.driving_force[k]), "", ""))
    headers = ("input [deg]", "mechanism", "force", "of link on link, at", "x [N]", "y [N]", "|F| [N]")
    cells = column_cells(rows, (6, None, None, None, 4, 4, 4))
    title = "joint forces (Fij: the force of link i on link j, ground frame) and driving torque"
    return "\n".join(filter(None, [title, text_table(headers, cells), note]))


STRESS_HEADERS = ("link", "beam max [MPa]", "at input [deg]", "at (x, y) [m], ground frame", "away from holes [MPa]",
                  "pin-hole estimate [MPa]", "equilibrium check")

def estimate_cell(result: AnalysisResult, name: str) -> str:
    """Link ``name``'s largest pin-hole estimate [MPa] with its hole and how many loaded positions it
    covers, or why there is none."""
    ok = result.feasible
    figures = link_figures(result, name)
    stress = result.stresses[name]
    if figures is None or figures.pin_hole is None:
        return "- (outside the Kt tables)" if stress.pin_holes else "- (no pin hole)"
    hole = next(h for h in stress.pin_holes if h.joint == figures.pin_hole.joint)
    loaded = ok & (hole.nominal > 0)
    inside = int((loaded & ~hole.outside).sum())
    label = _joint_label(result, name, hole.joint)
    share = "" if inside == int(loaded.sum()) else f", at {inside} of {int(loaded.sum())} positions"
    return f"{mpa(figures.pin_hole.value)} at {label}{share}"


def _joint_label(result: AnalysisResult, name: str, joint: int) -> str:
    return joint_names(result.scene)[name][joint].label


def stress_table(result: AnalysisResult) -> str:
    """Per link, the largest section von Mises over the sweep, where, and the equilibrium check; the
    safety factors against yield where the material gives a yield strength; under the table, the
    input angle and the location of every figure."""
    rows = []
    ok = result.feasible
    factors = link_safety_factors(result)
    where, uncovered_notes = [], []
    for name, stress in result.stresses.items():
        figures = link_figures(result, name, factors.get(name))
        if figures is None:
            continue
        peak = figures.max_von_mises
        mismatch = float(stress.mismatch[ok].max())
        row = [
            name, mpa(peak.value), f"{peak.input_angle_deg:.6g}", point(peak.at),
            "-" if figures.away_from_holes is None else mpa(figures.away_from_holes.value),
            estimate_cell(result, name), "0" if mismatch <= 1e-9 else f"{mismatch:.2g}",
        ]
        if factors:
            row += _factor_cells(factors.get(name), ok)
            uncovered = uncovered_pin_holes(stress, ok)
            if name in factors and uncovered:
                uncovered_notes.append(_uncovered_note(result, name, uncovered, int(ok.sum()), name in result.peaks))
        rows.append(tuple(row))
        labels = tuple(j.label for j in joint_names(result.scene)[name])
        where += [f"  {name}: {line}" for line in figure_lines(figures, labels)]
    headers = list(STRESS_HEADERS)
    if factors:
        headers += ["yield safety factor, sections", "yield safety factor, pin-hole estimate"]
    lines = [
        "section stresses (beam theory along every member of a link; within one section depth of a pin hole "
        "or of another member's axis the value is nominal)",
        text_table(tuple(headers), rows),
    ]
    if where:
        lines += ["where each figure comes from (its input angle; its point in the ground frame at that input):", *where]
    lines.append(
        "pin-hole estimate: Kt x the net-section stress of the pin force, an ESTIMATE for a close-fitting pin "
        "(Kt from linkstress's FEA of pin-loaded lugs: docs/numbers.md); linkstress validate or analyze --peaks "
        "gives the FEA peak"
    )
    if factors:
        lines.append(
            "yield safety factor: the material's yield_strength over the largest stress of the sweep (section "
            "von Mises; pin-hole estimate where there is one); '-' where the material gives no yield_strength"
        )
    lines += uncovered_notes
    return "\n".join(lines)


def uncovered_text(holes: list[tuple[int, int]], feasible: int, labels=None) -> str:
    """The pin holes no factor covers (``uncovered_pin_holes``), in words: where and how often."""
    return ", ".join(
        f"{'joint ' + str(joint) if labels is None else labels[joint]} (at {count} of {feasible} positions)"
        for joint, count in holes
    )


def _uncovered_note(result: AnalysisResult, name: str, holes: list[tuple[int, int]], feasible: int, peaks: bool) -> str:
    """Why a link's yield safety factors leave some pin holes uncovered, and where their stress is."""
    labels = [j.label for j in joint_names(result.scene)[name]]
    listed = uncovered_text(holes, feasible, labels)
    where = ("the FEA peak table below gives the stress there, holes included" if peaks
             else "run analyze --peaks (or validate) for the FEA peak there, holes included")
    return (f"* {name}: no yield safety factor covers the pin holes {listed}: there their geometry is outside the Kt "
            f"tables, so no estimate covers them, and beam theory is silent at a hole; {where}")


def figure_lines(figures: LinkFigures, joint_labels: tuple[str, ...] | None = None) -> list[str]:
    """One line per figure of a link: value (stresses in MPa, factors to 3 digits), input angle,
    location and frame; pin holes named by ``joint_labels`` when given."""
    listed = [
        figures.max_von_mises, figures.away_from_holes, figures.pin_hole,
        figures.section_factor, figures.pin_hole_factor, *figures.members,
    ]
    return [figure.describe(joint_labels) for figure in listed if figure is not None]


def _factor_cells(factors, ok) -> list[str]:
    """The sweep's lowest yield safety factors of one link, '-' without a yield strength; a
    pin-hole factor says over how many positions an estimate exists when not all."""
    if factors is None:
        return ["-", "-"]
    sections, pin_holes = factors.lowest(ok)
    if pin_holes is None:
        return [_factor_text(sections), "-"]
    inside = int(factors.pin_hole_inside[ok].sum())
    share = "" if inside == int(ok.sum()) else f" (at {inside} of {int(ok.sum())} positions)"
    return [_factor_text(sections), _factor_text(pin_holes) + share]


def _factor_text(factor: float) -> str:
    return significant(factor) if np.isfinite(factor) else "- (no stress)"
