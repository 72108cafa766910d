"""The terminal report of an analysis: the verdict first, then the mechanism, each link's largest
stresses and the notes that qualify them; with ``--details`` the tables position by position.

Short by default: a designer reads the verdict (``report.verdict``: what governs each link, where,
how safe, how far to trust it), the scene's warnings, a summary of each mechanism and per-link maxima.
``--details`` adds the motion, the joint forces (named by the links they act between) and the
section stresses at every position (at most ``MAX_ROWS`` positions per table, evenly spaced, said
so), and the FEA peak details; the JSON and HTML carry every position either way. Stresses are in MPa
to 3 significant digits, forces in N to 4, and round-off noise is written 0 (``report.cells``).
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
from linkstress.report.cells import mpa, significant, text_table, without_noise
from linkstress.report.linkage_summary import describe_linkage
from linkstress.report.detail_tables import MAX_ROWS, estimate_cell, forces_table, motion_table, stress_table
from linkstress.report.peak_text import peaks_table
from linkstress.report.verdict import Verdict, analysis_verdict
from linkstress.scene import Scene

SHORT_LIST = 5
"""Warnings and infeasible positions listed in the short report before "and N more"."""
KT_WORDS = (
    "Kt: the stress concentration factor of a pin hole (peak over the net-section stress); e/H: the hole's "
    "end distance over the link's width across the pin force; d/H: the hole's diameter over that width "
    "(docs/numbers.md, pin holes)"
)
"""Said once per report, wherever pin-hole estimates appear."""
DETAILS_HINT = (
    "position by position (motion, joint forces, section stresses) and the FEA peak details: add --details; "
    "--json and --html carry every position"
)


def report(result: AnalysisResult, details: bool = False, verdict: Verdict | None = None) -> str:
    """The text printed on stdout: the verdict (``verdict``, made here when not given), the scene's
    warnings, the mechanisms, per-link maxima and notes; with ``details`` the position-by-position
    tables too."""
    scene = result.scene
    parts = [header(result)]
    if result.stresses:
        parts.append((verdict or analysis_verdict(result)).text())
    if scene.warnings:
        parts.append(warnings_text(scene.warnings))
    parts += [describe_loop(scene, loop.name, result) for loop in scene.machine.loops]
    if scene.linkage is not None:
        parts.append(describe_linkage(scene.linkage))
    if result.stresses:
        parts.append(maxima_table(result))
    parts += curved_warnings(result)
    parts += transmission_warnings(result)
    parts += crossing_warnings(result, None if details else SHORT_LIST)
    parts += infeasible_lines(result, None if details else SHORT_LIST)
    if details:
        analysis = scene.analysis
        if analysis is None or analysis.kinematics:
            parts.append(motion_table(result))
        if result.forces is not None:
            parts.append(forces_table(result))
        if result.stresses:
            parts.append(stress_table(result))
        if result.peaks:
            parts.append(peaks_table(result))
    else:
        parts.append(DETAILS_HINT)
    return "\n\n".join(parts)


def header(result: AnalysisResult) -> str:
    """"scene NAME: N positions (input A to B deg), M feasible"."""
    scene = result.scene
    feasible = result.feasible
    angles = scene.motion.angle_deg
    span = f" (input {angles.min():.6g} to {angles.max():.6g} deg)" if len(angles) > 1 else f" (input {angles[0]:.6g} deg)"
    count = len(feasible)
    return f"scene {scene.path.name}: {count} position{'s' if count > 1 else ''}{span}, {int(feasible.sum())} feasible"


def warnings_text(warnings: tuple[str, ...]) -> str:
    """The scene's warnings (implausible values, a unit slip most likely), one line each."""
    return "\n".join(f"warning: {line}" for line in warnings)


def infeasible_lines(result: AnalysisResult, most: int | None) -> list[str]:
    """The infeasible positions and why, at most ``most`` of them (None: all) then a count."""
    scene = result.scene
    bad = [(a, r) for a, r, ok in zip(scene.motion.angle_deg.tolist(), result.reasons, result.feasible) if not ok]
    if not bad:
        return []
    shown = bad if most is None else bad[:most]
    lines = [f"  {a:.6g} deg: {r}" for a, r in shown]
    if len(shown) < len(bad):
        lines.append(f"  and {len(bad) - len(shown)} more (--details lists every one, --json has them)")
    return [f"infeasible positions ({len(bad)}):\n" + "\n".join(lines)]


def describe_loop(scene: Scene, name: str, result: AnalysisResult | None = None) -> str:
    """A mechanism's links and lengths, class, toggles, feasible input range, limit positions and,
    from ``result`` where it has joint forces, the range of its driving torque or force."""
    loop = scene.machine.loop(name)
    linkage = scene.machine.geometry(loop)
    drive = "" if loop.driven_by is None else f", driven by {loop.driven_by.loop}.{loop.driven_by.role}"
    lines = [f"mechanism {name}: {loop.kind}, {loop.branch} branch{drive}"]

    def role(word: str) -> str:
        link = getattr(loop, word).link
        return word if link == word else f"{word} ({link})"

    if isinstance(linkage, FourBar):
        a, b, c, d = linkage.lengths
        kind = classify(linkage)
        lines.append(f"  {role('crank')} {a:.6g} m, {role('coupler')} {b:.6g} m, {role('output')} {c:.6g} m, "
                     f"{role('ground')} {d:.6g} m")
        lines.append(f"  {kind.grashof}, Barker {kind.barker_class} {kind.code}: {kind.description}")
        toggles, ranges = toggle_angles(linkage), feasible_input_ranges(linkage)
        limits = output_limits(linkage)
        limit_what = "output"
    else:
        lines.append(
            f"  {role('crank')} {linkage.crank:.6g} m, rod{'' if loop.coupler.link == 'rod' else f' ({loop.coupler.link})'} "
            f"{linkage.rod:.6g} m, offset "
            f"{linkage.offset:.6g} m, slider line at {math.degrees(linkage.slider_angle):.6g} deg; stroke {stroke(linkage):.6g} m"
        )
        toggles, ranges = slider_toggle_angles(linkage), slider_feasible_input_ranges(linkage)
        limits = slider_limits(linkage)
        limit_what = "slider"
    listed = ", ".join(f"{_deg360(t):.6g}" for t in toggles)
    lines.append(("  toggles at input " + listed + " deg" if toggles else "  toggles: none") + "; feasible input: "
                 + "; ".join(_range_text(lo, hi) for lo, hi in ranges))
    for lim in limits:
        value = f"{_deg360(lim.output):.6g} deg" if limit_what == "output" else f"{lim.output:.6g} m"
        lines.append(f"  {limit_what} limit ({lim.kind}) at input {_deg360(lim.input_angle):.6g} deg: {value}")
    if result is not None and result.forces is not None and result.feasible.any():
        lines.append(_drive_range(result, name))
    return "\n".join(line for line in lines if line)


def _drive_range(result: AnalysisResult, name: str) -> str:
    """"  driving torque T12 on crank: -1.23 to 4.56 N m" over the feasible positions ("" when nothing drives the loop)."""
    mech = result.forces.mechanisms[name]
    ok = result.feasible
    loop = result.scene.machine.loop(name)
    if mech.driving_torque is not None:
        kind = "driving" if mech.torque_name in ("T12", "T14") else "coupling"
        values, what, unit = mech.driving_torque[ok], f"{kind} torque {mech.torque_name}", "N m"
    elif mech.driving_force is not None:
        values, what, unit = mech.driving_force[ok], f"driving force P14 on {loop.slider.link}", "N"
    else:
        return ""
    low, high = without_noise(np.array([values.min(), values.max()]), float(np.abs(values).max()))
    return f"  {what}: {significant(float(low), 4)} to {significant(float(high), 4)} {unit} over the sweep"


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


def crossing_warnings(result: AnalysisResult, most: int | None = None) -> list[str]:
    """One block with a warning per step that passed a loop's toggle or change point between
    feasible positions (at most ``most``, default MAX_ROWS, then a count; --json has each on its position)."""
    most = MAX_ROWS if most is None else most
    crossings = result.kinematics.crossings
    lines = [f"warning: {message}" for _, message in crossings[:most]]
    if len(crossings) > most:
        more = len(crossings) - most
        lines.append(f"warning: {more} more crossings of toggles or change points; --details lists up to {MAX_ROWS}, --json has every one")
    return ["\n".join(lines)] if lines else []


def maxima_table(result: AnalysisResult) -> str:
    """Per stressed link over the sweep: the beam's largest section von Mises and away from holes,
    the largest pin-hole estimate and, with peaks, the FEA peak; MPa."""
    ok = result.feasible
    if not ok.any():
        return "link maxima: no feasible position"
    rows = []
    for name, stress in result.stresses.items():
        k = int(np.flatnonzero(ok)[np.argmax(stress.max_von_mises[ok])])
        away = stress.max_away_from_holes
        row = [
            name, mpa(float(stress.max_von_mises[k])), f"{result.scene.motion.angle_deg[k]:.6g}",
            "-" if away is None else mpa(float(away[ok].max())), estimate_cell(result, name),
        ]
        if result.peaks:
            peaks = result.peaks.get(name)
            row += ["-", "-"] if peaks is None else [mpa(peaks.peak_max), f"{peaks.peak_max / float(stress.max_von_mises[k]):.3g}"
                                                      if stress.max_von_mises[k] > 0 else "-"]
        rows.append(row)
    headers = ["link", "beam max [MPa]", "at input [deg]", "away from holes [MPa]", "pin-hole estimate [MPa]"]
    if result.peaks:
        headers += ["FEA peak [MPa]", "FEA peak / beam max"]
    return "\n".join([
        "link maxima over the sweep (beam theory along each member, nominal within a section depth of a pin or "
        "junction; the pin-hole estimate is Kt x the net-section stress, where the Kt tables cover the hole's geometry)",
        text_table(headers, rows),
        KT_WORDS,
    ])
