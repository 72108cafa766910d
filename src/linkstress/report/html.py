"""One self-contained HTML file per run: figures inline (base64 PNG), the interactive view of the
mechanism inline (its data and script in the page), no network.

The page states the exact loads that were applied and the versions that produced it, so that
everything in it can be reproduced from the scene file alone.
"""

from __future__ import annotations

import base64
import html
from importlib import metadata

import numpy as np
from matplotlib.figure import Figure

from linkstress import __version__
from linkstress.analysis import AnalysisResult
from linkstress.report.cells import column_cells, mpa, point, significant
from linkstress.report.figures import (
    mechanism_figure,
    mechanism_sweep_figure,
    png_bytes,
    stress_along_figure,
    sweep_figure,
)
from linkstress.report.maxima import link_figures, worst_position
from linkstress.report.linkage_summary import describe_linkage
from linkstress.report.mechanism_view import view_html
from linkstress.report.places import force_names, joint_names
from linkstress.report.records import link_columns
from linkstress.report.detail_tables import figure_lines, uncovered_text
from linkstress.report.text import KT_WORDS, crossing_warnings, curved_warnings, transmission_warnings
from linkstress.report.verdict import HEADERS as VERDICT_HEADERS
from linkstress.report.verdict import Verdict, analysis_verdict
from linkstress.safety import link_safety_factors, uncovered_pin_holes

DEPENDENCIES = ("numpy", "scipy", "shapely", "ezdxf", "scikit-fem", "gmsh", "meshio", "matplotlib")
MAX_DRAWN_POSITIONS = 4
STRESS_HEADERS = ("link", "max von Mises [MPa]", "at input [deg]", "at (x, y) [m], ground frame", "away from holes [MPa]",
                  "pin-hole estimate [MPa]", "curved")
PIN_HOLE_NOTE = (
    "Estimate: Kt x P / ((H - d) t), H the link's width across the pin force through the hole's centre (at most 10 d; "
    "a round end's diameter), for a close-fitting pin; Kt from linkstress's plane-stress FEA of pin-loaded lugs with "
    "square ends, round ends concentric with the hole and holes far from the edges, read per position by the direction "
    "of the pin force (docs/numbers.md). A pin that carries a couple (a driving torque, a keyed shaft) is outside the "
    "tables."
)

STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1000px; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; margin: 0.5em 0; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: right; }
th { background: #f2f2f2; } td.text, th.text { text-align: left; }
img { max-width: 100%; display: block; margin: 0.5em 0; }
.note { color: #555; font-size: 0.9em; }
.view-controls { display: flex; align-items: center; gap: 0.6em; margin: 0.5em 0; }
#view-slider { flex: 1; }
"""


def figure_tag(fig: Figure, alt: str) -> str:
    """The figure as an inline PNG <img>; the figure is closed."""
    data = base64.b64encode(png_bytes(fig)).decode("ascii")
    return f'<img alt="{html.escape(alt)}" src="data:image/png;base64,{data}">'


def table_html(headers, rows) -> str:
    """A table of ``rows`` under ``headers``: floats to 6 significant digits; numbers, and text that
    reads as one, right-aligned, other text left."""
    def cell(value, tag):
        text = f"{value:.6g}" if isinstance(value, float) else html.escape(str(value))
        kind = "" if isinstance(value, (int, float)) or _reads_as_number(str(value)) else ' class="text"'
        return f"<{tag}{kind}>{text}</{tag}>"

    head = "".join(cell(h, "th") for h in headers)
    body = "".join("<tr>" + "".join(cell(v, "td") for v in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _reads_as_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def versions_html() -> str:
    rows = [("linkstress", __version__)]
    for name in DEPENDENCIES:
        try:
            rows.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            rows.append((name, "not installed"))
    return table_html(("package", "version"), rows)


def page(title: str, sections: list[str]) -> str:
    body = "\n".join(sections)
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        f"<title>{html.escape(title)}</title><style>{STYLE}</style></head>\n"
        f"<body><h1>{html.escape(title)}</h1>\n{body}\n</body></html>\n"
    )


def drawn_positions(result: AnalysisResult) -> list[int]:
    """Positions worth drawing: each link's worst stress and the largest driving torque, or all
    feasible positions when there are few."""
    ok = np.flatnonzero(result.feasible)
    if len(ok) <= MAX_DRAWN_POSITIONS:
        return ok.tolist()
    picks = []
    for stress in result.stresses.values():
        picks.append(int(ok[np.argmax(stress.max_von_mises[ok])]))
    if result.forces is not None:
        for mech in result.forces.mechanisms.values():
            if mech.driving_torque is not None:
                picks.append(int(ok[np.argmax(np.abs(mech.driving_torque[ok]))]))
    picks.append(int(ok[0]))
    return sorted(dict.fromkeys(picks))[:MAX_DRAWN_POSITIONS]


def loads_html(result: AnalysisResult) -> str:
    """The exact loads and motion applied."""
    scene = result.scene
    motion = scene.motion
    rows = [
        ("input angles", f"{len(motion.angle_deg)} from {motion.angle_deg.min():.6g} to {motion.angle_deg.max():.6g} deg"),
        ("input speed [rad/s]", _span(motion.speed)),
        ("input acceleration [rad/s^2]", _span(motion.acceleration)),
        ("actuator (unknown driving torque)", scene.actuator),
        ("gravity [m/s^2]", f"({scene.loads.gravity[0]:.6g}, {scene.loads.gravity[1]:.6g})"),
    ]
    rows += [(f"couple on {c.link} at joint {c.at_joint} [N m, ccw]", f"{c.value:.6g}") for c in scene.loads.couples]
    rows += [
        (f"force on {f.link} at ({f.at[0]:.6g}, {f.at[1]:.6g}) m, member frame [N]", f"({f.force[0]:.6g}, {f.force[1]:.6g})")
        for f in scene.loads.forces
    ]
    rows += [(f"Coulomb friction on the slider of {name}", f"{mu:.6g}") for name, mu in scene.loads.friction.items()]
    for name in scene.moving_links:
        data = scene.links[name].mass_data
        if data is not None:
            rows.append((f"{name}: mass [kg], inertia about G [kg m^2], G (member frame) [m]",
                         f"{data.mass:.6g}, {data.inertia:.6g}, ({data.center_of_mass[0]:.6g}, {data.center_of_mass[1]:.6g})"))
    return table_html(("load", "value"), rows)


def _span(values) -> str:
    lo, hi = float(np.min(values)), float(np.max(values))
    return f"{lo:.6g}" if lo == hi else f"{lo:.6g} to {hi:.6g}"


def verdict_html(verdict: Verdict) -> list[str]:
    """The verdict as the report's first section: its table and the next step (``report.verdict``)."""
    unanalysed = "".join(f"<li><b>{html.escape(line)}</b></li>" for line in verdict.unanalysed_lines())
    unanalysed = [f"<ul>{unanalysed}</ul>"] if unanalysed else []
    if not verdict.rows:
        return ["<h2>Verdict</h2>", "<p>No link has section stresses at a feasible position.</p>", *unanalysed]
    rows = [row.cells() for row in verdict.rows]
    sections = ["<h2>Verdict</h2>", f'<p class="note">{html.escape(verdict.heading())}.</p>',
                table_html(VERDICT_HEADERS, rows), *unanalysed]
    if verdict.next_step:
        sections.append(f"<p><b>Next:</b> {html.escape(verdict.next_step)}</p>")
    if verdict.models:
        items = "".join(f"<li>{html.escape(line)}</li>" for line in verdict.models_lines())
        sections.append(f'<p class="note">{html.escape(verdict.models_heading())}:</p><ul>{items}</ul>')
    return sections


def warnings_html(result: AnalysisResult) -> list[str]:
    """The scene's warnings (implausible values, a unit slip most likely), right after the verdict."""
    return [f'<p><b>warning: {html.escape(line)}</b></p>' for line in result.scene.warnings]


def analysis_sections(result: AnalysisResult, top: list[str] | None = None) -> list[str]:
    """The sections every report of an analysis has, after ``top`` (default: the analysis's verdict
    and the scene's warnings; ``validate`` gives its own verdict and adds its sections after these)."""
    scene = result.scene
    feasible = result.feasible
    if top is None:
        top = verdict_html(analysis_verdict(result)) + warnings_html(result)
    sections = [
        f'<p>Scene <code>{html.escape(str(scene.path))}</code>: {len(feasible)} position{"s" if len(feasible) > 1 else ""}, '
        f"{int(feasible.sum())} feasible. Ground frame, SI units; Fij is the force of link i on link j.</p>",
        *top,
        *(f'<p class="note">{html.escape(note)}</p>' for note in scene.notes),
        *(f"<p><b>{html.escape(line)}</b></p>" for line in _warning_lines(result)),
        "<h2>Mechanism, position by position</h2>", view_html(result),
        "<h2>Loads applied</h2>", loads_html(result),
        "<h2>Mechanism</h2>",
    ]
    if scene.linkage is not None:
        sections.append(f"<pre>{html.escape(describe_linkage(scene.linkage))}</pre>")
    for k in drawn_positions(result):
        sections.append(figure_tag(mechanism_figure(result, k), f"mechanism at position {k}"))
    if int(feasible.sum()) > MAX_DRAWN_POSITIONS:
        sections.append(figure_tag(mechanism_sweep_figure(result, _shown(result)[::2]), "mechanism over the sweep"))
    if len(feasible) > 1:
        sections += ["<h2>Over the sweep</h2>", figure_tag(sweep_figure(result), "sweep plots")]
    sections += ["<h2>Accelerations</h2>", _accelerations_table(result)]
    if result.forces is not None:
        sections += ["<h2>Joint forces and driving torque</h2>", _forces_table(result)]
    if result.stresses:
        sections.append("<h2>Section stresses (beam theory)</h2>")
        sections.append(
            '<p class="note">Largest von Mises over each section: sigma = N/A + M y/I, Jourawski shear, '
            "at the same fibre. Within one section depth of a pin hole the value is nominal; the FEA "
            "check (linkstress validate) gives the peak there.</p>"
        )
        sections.append(_stress_table(result))
        for name, stress in result.stresses.items():
            if feasible.any():
                k = worst_position(stress.max_von_mises, feasible)
                sections.append(figure_tag(stress_along_figure(result, name, k), f"stresses along {name}"))
        sections.append(_pin_holes_table(result))
        sections.append(_safety_table(result))
    if result.peaks:
        # Imported here: peak_html builds on this module's tables and figure tags.
        from linkstress.report.peak_html import peak_sections

        sections += peak_sections(result)
    if result.seconds:
        rows = [(stage, 1e3 * seconds) for stage, seconds in result.seconds.items()]
        sections += ["<h2>Timings</h2>", table_html(("stage", "time [ms]"), rows)]
    sections += ["<h2>Versions</h2>", versions_html()]
    return sections


def report_title(scene, command: str) -> str:
    """The page's title: the scene's ``title``, or where it gives none its file's name (with its
    folder's when the file is a case's ``scene.toml``), then the command that wrote it."""
    path = scene.path
    if scene.title != path.stem:
        name = scene.title
    elif path.stem == "scene" and path.parent.name:
        name = f"{path.parent.name}/{path.name}"
    else:
        name = path.name
    return f"{name}: linkstress {command}"


def analysis_html(result: AnalysisResult, verdict: Verdict | None = None) -> str:
    """The analysis's HTML report, its ``verdict`` (made here when not given) first."""
    top = verdict_html(verdict or analysis_verdict(result)) + warnings_html(result)
    return page(report_title(result.scene, "analyze"), analysis_sections(result, top))


def _shown(result: AnalysisResult) -> list[int]:
    ok = np.flatnonzero(result.feasible)
    if len(ok) <= 24:
        return ok.tolist()
    return ok[np.linspace(0, len(ok) - 1, 24).round().astype(int)].tolist()


def _accelerations_table(result: AnalysisResult) -> str:
    columns = link_columns(result)
    rows = []
    for k in _shown(result):
        angle = float(result.scene.motion.angle_deg[k])
        for name, c in columns.items():
            acc = ("", "") if c.acc_g is None else (float(c.acc_g[k, 0]), float(c.acc_g[k, 1]))
            rows.append((angle, name, float(c.angle_deg[k]), float(c.omega[k]), float(c.alpha[k]), *acc))
    return table_html(
        ("input [deg]", "link", "angle [deg]", "omega [rad/s]", "alpha [rad/s^2]", "a_Gx [m/s^2]", "a_Gy [m/s^2]"),
        column_cells(rows, (6, None, 6, 6, 6, 6, 6)),
    )


def _stress_table(result: AnalysisResult) -> str:
    """Per link, the sweep's largest section von Mises, away from holes and pin-hole estimate, and
    under the table the input angle and ground-frame point of each."""
    factors = link_safety_factors(result)
    rows, where = [], []
    for name in result.stresses:
        figures = link_figures(result, name, factors.get(name))
        if figures is None:
            continue
        peak = figures.max_von_mises
        rows.append((
            name, mpa(peak.value), peak.input_angle_deg, point(peak.at),
            "-" if figures.away_from_holes is None else mpa(figures.away_from_holes.value),
            "-" if figures.pin_hole is None else mpa(figures.pin_hole.value),
            "yes" if result.curved(name) else "no",
        ))
        lines = figure_lines(figures, tuple(j.label for j in joint_names(result.scene)[name]))
        where += [f"{name}: {line}" for line in lines]
    if not rows:
        return ""
    items = "".join(f"<li>{html.escape(line)}</li>" for line in where)
    return (
        "<h3>Largest stresses over the sweep</h3>" + table_html(STRESS_HEADERS, rows)
        + '<p class="note">Where each figure comes from (its input angle; its point in the ground frame at that '
        f"input):</p><ul class=\"note\">{items}</ul>"
    )


def _pin_holes_table(result: AnalysisResult) -> str:
    """Kt x nominal at every pin hole, largest over the feasible positions and the input angle it
    comes from: an estimate, said so."""
    ok = result.feasible
    rows = []
    names = joint_names(result.scene)
    for name, stress in result.stresses.items():
        for hole in stress.pin_holes:
            if not ok.any():
                continue
            largest = hole.largest(ok)
            loaded = ok & (hole.nominal > 0)
            inside = int((loaded & ~hole.outside).sum())
            if largest is None:
                k = worst_position(hole.nominal, ok)
                estimate = "- (outside the Kt tables)"
            else:
                k = worst_position(np.where(hole.outside, -1.0, hole.estimate), ok)
                estimate = mpa(largest)
            rows.append((name, names[name][hole.joint].words(), hole.diameter, hole.depth,
                         "-" if hole.kt is None else significant(hole.kt), mpa(float(hole.nominal[k])), estimate,
                         f"{inside} of {int(loaded.sum())}", float(result.scene.motion.angle_deg[k])))
    if not rows:
        return ""
    headers = ("link", "pin hole", "hole d [m]", "depth H [m]", "Kt", "net-section stress [MPa]", "Kt x nominal [MPa]",
               "loaded positions inside the Kt tables", "at input [deg]")
    return (
        "<h3>Pin holes: peak stress ESTIMATES</h3>"
        + table_html(headers, rows)
        + f'<p class="note">{html.escape(PIN_HOLE_NOTE)} {html.escape(KT_WORDS)}. Each row: the largest over the '
        "sweep, at the input angle given.</p>"
    )


def _safety_table(result: AnalysisResult) -> str:
    """Per link whose material gives a yield strength, the sweep's lowest safety factors against it,
    each with the input angle it comes from (and the joint of the pin hole)."""
    rows = []
    ok = result.feasible
    for name, factors in link_safety_factors(result).items():
        figures = link_figures(result, name, factors)
        if figures is None:
            return ""
        section, pin = figures.section_factor, figures.pin_hole_factor
        uncovered = uncovered_pin_holes(result.stresses[name], ok)
        labels = [j.label for j in joint_names(result.scene)[name]]
        rows.append((
            name, mpa(factors.yield_strength),
            _finite(section.value),
            "-" if section is None else section.input_angle_deg,
            "-" if pin is None else _finite(pin.value),
            "-" if pin is None else pin.input_angle_deg,
            "-" if pin is None else labels[pin.joint],
            uncovered_text(uncovered, int(ok.sum()), labels) or "-",
        ))
    if not rows:
        return ""
    headers = ("link", "yield strength [MPa]", "lowest, sections", "at input [deg]", "lowest, pin holes (ESTIMATE)",
               "at input [deg]", "at the pin hole", "pin holes NO factor covers")
    return (
        "<h3>Safety factors against yield</h3>"
        + table_html(headers, rows)
        + '<p class="note">The material\'s yield_strength over the largest section von Mises (beam theory, nominal '
        "near pin holes and junctions, curved-beam on curved members) and over the largest pin-hole estimate Kt x "
        "nominal, each at the input angle given. A loaded pin hole outside the Kt tables has no estimate, and beam theory "
        "is silent at a hole: no factor here covers it (last column); "
        + ("the FEA peaks below give the stress there." if result.peaks else "analyze --peaks gives the FEA peak there.")
        + "</p>"
    )


def _finite(value) -> str:
    return significant(float(value)) if np.isfinite(value) else "- (no stress)"


def _forces_table(result: AnalysisResult) -> str:
    """Joint forces by position, each named by the links it acts between; driving torque or force."""
    rows = []
    named = force_names(result.scene)
    for k in _shown(result):
        angle = float(result.scene.motion.angle_deg[k])
        for name, mech in result.forces.mechanisms.items():
            for label, force in mech.forces.items():
                rows.append((angle, name, label, named[name].get(label, ""), float(force[k, 0]), float(force[k, 1])))
            if mech.driving_torque is not None:
                rows.append((angle, name, f"{mech.torque_name} [N m]", "driving torque", float(mech.driving_torque[k]), ""))
            if mech.driving_force is not None:
                rows.append((angle, name, f"{mech.force_name} [N]", "driving force", float(mech.driving_force[k]), ""))
    headers = ("input [deg]", "mechanism", "force", "of link on link, at", "x [N]", "y [N]")
    return table_html(headers, column_cells(rows, (6, None, None, None, 4, 4)))


def _warning_lines(result: AnalysisResult) -> list[str]:
    """The text report's warnings, a paragraph each: curved links, low transmission angles and
    steps that crossed a toggle or change point."""
    blocks = curved_warnings(result) + transmission_warnings(result) + crossing_warnings(result)
    return [line for block in blocks for line in block.splitlines()]
