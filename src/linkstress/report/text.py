"""The terminal report of an analysis: mechanisms, motion, joint forces and section stresses.

Long sweeps are shown at most ``MAX_ROWS`` positions per table (evenly spaced, the table says so);
the JSON output carries every position.
"""

from __future__ import annotations

import math

import numpy as np

from linkstress.analysis import AnalysisResult
from linkstress.kinematics.fourbar import FourBar
from linkstress.kinematics.linkage_class import (
    classify,
    feasible_input_ranges,
    output_limits,
    slider_feasible_input_ranges,
    slider_limits,
    slider_toggle_angles,
    stroke,
    toggle_angles,
)
from linkstress.report.linkage_summary import describe_linkage
from linkstress.report.maxima import LinkFigures, link_figures
from linkstress.report.peak_text import peaks_table
from linkstress.report.records import link_columns
from linkstress.safety import link_safety_factors, uncovered_pin_holes
from linkstress.scene import Scene
from linkstress.tables import format_table

MAX_ROWS = 40
STRESS_HEADERS = ("link", "max von Mises [Pa]", "at input [deg]", "at (x, y) [m], ground frame", "away from holes [Pa]",
                  "pin hole estimate [Pa]", "equilibrium check")


def report(result: AnalysisResult) -> str:
    """The text printed on stdout."""
    scene = result.scene
    feasible = result.feasible
    parts = [f"scene {scene.path.name}: {len(feasible)} positions, {int(feasible.sum())} feasible"]
    parts += [describe_loop(scene, loop.name) for loop in scene.machine.loops]
    if scene.linkage is not None:
        parts.append(describe_linkage(scene.linkage))
    analysis = scene.analysis
    if analysis is None or analysis.kinematics:
        parts.append(motion_table(result))
    if result.forces is not None:
        parts.append(forces_table(result))
    if result.stresses:
        parts.append(stress_table(result))
    if result.peaks:
        parts.append(peaks_table(result))
    parts += curved_warnings(result)
    parts += transmission_warnings(result)
    parts += crossing_warnings(result)
    bad = [(a, r) for a, r, ok in zip(scene.motion.angle_deg.tolist(), result.reasons, feasible) if not ok]
    if bad:
        parts.append("infeasible positions:\n" + "\n".join(f"  {a:.6g} deg: {r}" for a, r in bad))
    return "\n\n".join(parts)


def describe_loop(scene: Scene, name: str) -> str:
    """A mechanism's geometry, class, toggles, feasible input range and limit positions."""
    loop = scene.machine.loop(name)
    linkage = scene.machine.geometry(loop)
    drive = "" if loop.driven_by is None else f", driven by {loop.driven_by.loop}.{loop.driven_by.role}"
    lines = [f"mechanism {name}: {loop.kind}, {loop.branch} branch{drive}"]
    if isinstance(linkage, FourBar):
        a, b, c, d = linkage.lengths
        kind = classify(linkage)
        lines.append(f"  crank {a:.6g} m, coupler {b:.6g} m, output {c:.6g} m, ground {d:.6g} m")
        lines.append(f"  {kind.grashof}, Barker {kind.barker_class} {kind.code}: {kind.description}")
        toggles, ranges = toggle_angles(linkage), feasible_input_ranges(linkage)
        limits = output_limits(linkage)
        limit_what = "output"
    else:
        lines.append(
            f"  crank {linkage.crank:.6g} m, rod {linkage.rod:.6g} m, offset {linkage.offset:.6g} m, "
            f"slider line at {math.degrees(linkage.slider_angle):.6g} deg; stroke {stroke(linkage):.6g} m"
        )
        toggles, ranges = slider_toggle_angles(linkage), slider_feasible_input_ranges(linkage)
        limits = slider_limits(linkage)
        limit_what = "slider"
    listed = ", ".join(f"{_deg360(t):.6g}" for t in toggles)
    lines.append(f"  toggles at input {listed} deg" if toggles else "  toggles: none")
    lines.append("  feasible input: " + "; ".join(_range_text(lo, hi) for lo, hi in ranges))
    for lim in limits:
        value = f"{_deg360(lim.output):.6g} deg" if limit_what == "output" else f"{lim.output:.6g} m"
        lines.append(f"  {limit_what} limit ({lim.kind}) at input {_deg360(lim.input_angle):.6g} deg: {value}")
    return "\n".join(lines)


def _range_text(lo: float, hi: float) -> str:
    if hi - lo >= 2 * math.pi - 1e-12:
        return "full turn"
    return f"{_deg360(lo):.6g} to {_deg360(lo) + math.degrees(hi - lo):.6g} deg"


def _deg360(angle: float) -> float:
    """An angle [rad] in degrees in [0, 360)."""
    value = math.degrees(angle) % 360.0
    return 0.0 if value >= 360.0 else value + 0.0


LOW_TRANSMISSION_DEG = 30.0
"""Below this transmission angle (Norton recommends at least 40 deg) forces climb toward a toggle."""


def transmission_warnings(result: AnalysisResult) -> list[str]:
    """A warning per loop whose transmission angle falls below LOW_TRANSMISSION_DEG."""
    ok = result.feasible
    lines = []
    for name, loop in result.kinematics.loops.items():
        angle = np.degrees(loop.transmission_angle)
        low = ok & (angle < LOW_TRANSMISSION_DEG)
        if low.any():
            k = int(np.flatnonzero(ok)[np.argmin(angle[ok])])
            lines.append(
                f"warning: mechanism {name}'s transmission angle falls to {angle[k]:.3g} deg at input "
                f"{result.scene.motion.angle_deg[k]:.6g} deg (below {LOW_TRANSMISSION_DEG:g} deg at {int(low.sum())} "
                "position(s)): joint forces and stresses climb steeply toward the toggle and beam theory "
                "loses accuracy there; check those positions with linkstress validate"
            )
    return lines


def curved_warnings(result: AnalysisResult) -> list[str]:
    """A note per curved member: how curved, and the theory its sections took."""
    lines = []
    for name, stress in result.stresses.items():
        for m in stress.members:
            if not m.member.curved:
                continue
            theory = (
                "curved-beam (Winkler-Bach) normal stress where its radius is under ten section depths"
                if m.theory == "curved" else "straight-beam stresses (its radius is over ten section depths)"
            )
            lines.append(
                f"note: link {name}, member {list(m.joints)} is curved (its centreline strays {m.member.wander:.2g} "
                f"section depths from the line through its joints): sectioned square to its centreline, {theory}"
            )
    return lines


def crossing_warnings(result: AnalysisResult) -> list[str]:
    """One block with a warning per step that passed a loop's toggle or change point between
    feasible positions (at most MAX_ROWS, then a count; --json has each on its position)."""
    crossings = result.kinematics.crossings
    lines = [f"warning: {message}" for _, message in crossings[:MAX_ROWS]]
    if len(crossings) > MAX_ROWS:
        more = len(crossings) - MAX_ROWS
        lines.append(f"warning: {more} more crossings of toggles or change points; --json has every one")
    return ["\n".join(lines)] if lines else []


def shown_positions(result: AnalysisResult) -> tuple[np.ndarray, str]:
    """Feasible positions to tabulate (at most MAX_ROWS, evenly spaced) and a note when thinned."""
    ok = np.flatnonzero(result.feasible)
    if len(ok) <= MAX_ROWS:
        return ok, ""
    pick = ok[np.linspace(0, len(ok) - 1, MAX_ROWS).round().astype(int)]
    return pick, f"({MAX_ROWS} of {len(ok)} feasible positions shown; --json has all)"


def motion_table(result: AnalysisResult) -> str:
    columns = link_columns(result)
    rows = []
    shown, note = shown_positions(result)
    for k in shown:
        angle = float(result.scene.motion.angle_deg[k])
        for name, c in columns.items():
            acc = ("", "") if c.acc_g is None else (float(c.acc_g[k, 0]), float(c.acc_g[k, 1]))
            rows.append((angle, name, float(c.angle_deg[k]), float(c.omega[k]), float(c.alpha[k]), *acc))
    headers = ("input [deg]", "link", "angle [deg]", "omega [rad/s]", "alpha [rad/s^2]", "a_Gx [m/s^2]", "a_Gy [m/s^2]")
    return "\n".join(filter(None, ["motion", format_table(headers, rows), note]))


def forces_table(result: AnalysisResult) -> str:
    """Joint forces (Fij: force of link i on link j, ground frame) and the driving torque or force."""
    rows = []
    shown, note = shown_positions(result)
    for k in shown:
        angle = float(result.scene.motion.angle_deg[k])
        for name, mech in result.forces.mechanisms.items():
            for label, force in mech.forces.items():
                rows.append((angle, name, label, float(force[k, 0]), float(force[k, 1]), float(np.hypot(*force[k]))))
            if mech.driving_torque is not None:
                rows.append((angle, name, f"{mech.torque_name} [N m]", float(mech.driving_torque[k]), "", ""))
            if mech.driving_force is not None:
                rows.append((angle, name, f"{mech.force_name} [N]", float(mech.driving_force[k]), "", ""))
    headers = ("input [deg]", "mechanism", "force", "x [N]", "y [N]", "|F| [N]")
    return "\n".join(filter(None, ["joint forces (Fij: of link i on link j) and driving torque", format_table(headers, rows), note]))


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
        row = [
            name, peak.value, peak.input_angle_deg, f"({peak.at[0]:.4g}, {peak.at[1]:.4g})",
            "-" if figures.away_from_holes is None else figures.away_from_holes.value,
            _pin_hole_cell(figures, stress), float(stress.mismatch[ok].max()),
        ]
        if factors:
            row += _factor_cells(factors.get(name), ok)
            uncovered = uncovered_pin_holes(stress, ok)
            if name in factors and uncovered:
                joints = ", ".join(str(joint) for joint, _ in uncovered)
                row[-1] = f"{row[-1]} (joint {joints}: no estimate *)"
                uncovered_notes.append(_uncovered_note(name, uncovered, int(ok.sum()), name in result.peaks))
        rows.append(tuple(row))
        where += [f"  {name}: {line}" for line in figure_lines(figures)]
    headers = list(STRESS_HEADERS)
    if factors:
        headers += ["yield safety factor", "at pin holes (estimate)"]
    lines = [
        "section stresses (beam theory along every member of a link; within one section depth of a pin hole "
        "or of another member's axis the value is nominal)",
        format_table(tuple(headers), rows),
    ]
    if where:
        lines += ["where each figure comes from (its input angle; its point in the ground frame at that input):", *where]
    lines.append(
        "pin hole estimate: Kt x the net-section stress of the pin force, an ESTIMATE for a close-fitting pin "
        "(Kt from linkstress FEA of pin-loaded lugs, see dynamics/pin_holes.py); linkstress validate gives the FEA peak"
    )
    if factors:
        lines.append(
            "yield safety factor: the material's yield_strength over the largest stress of the sweep (section "
            "von Mises; pin hole estimate); '-' where the material gives no yield_strength"
        )
    lines += uncovered_notes
    return "\n".join(lines)


def uncovered_text(holes: list[tuple[int, int]], feasible: int) -> str:
    """The pin holes no factor covers (``uncovered_pin_holes``), in words: where and how often."""
    return ", ".join(f"joint {joint} (at {count} of {feasible} positions)" for joint, count in holes)


def _uncovered_note(name: str, holes: list[tuple[int, int]], feasible: int, peaks: bool) -> str:
    """Why a link's yield safety factor covers its sections only, and where the holes' stress is."""
    listed = uncovered_text(holes, feasible)
    where = ("the FEA peak table below gives the stress there, holes included" if peaks
             else "run analyze --peaks (or validate) for the FEA peak there, holes included")
    return (f"* {name}: no yield safety factor covers the pin holes at {listed}: they are outside the Kt tables, "
            f"so no estimate covers them, and beam theory is silent at a hole; {where}")


def figure_lines(figures: LinkFigures) -> list[str]:
    """One line per figure of a link: value (stresses as in the table, factors to 3 digits), input
    angle, location and frame."""
    listed = [
        (figures.max_von_mises, " Pa", 6), (figures.away_from_holes, " Pa", 6), (figures.pin_hole, " Pa", 6),
        (figures.section_factor, "", 3), (figures.pin_hole_factor, "", 3),
        *((member, " Pa", 6) for member in figures.members),
    ]
    return [figure.describe(unit, digits) for figure, unit, digits in listed if figure is not None]


def _pin_hole_cell(figures, stress) -> float | str:
    """The largest pin-hole estimate, or why there is none."""
    if figures.pin_hole is not None:
        return figures.pin_hole.value
    return "- (outside the Kt tables)" if stress.pin_holes else "-"


def _factor_cells(factors, ok) -> list[str]:
    """The sweep's lowest yield safety factors of one link, '-' without a yield strength."""
    if factors is None:
        return ["-", "-"]
    sections, pin_holes = factors.lowest(ok)
    return [
        _factor_text(sections),
        "-" if pin_holes is None else _factor_text(pin_holes),
    ]


def _factor_text(factor: float) -> str:
    return f"{factor:.3g}" if np.isfinite(factor) else "- (no stress)"
