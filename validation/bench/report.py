"""Reports of ``linkstress bench``: terminal text, JSON and a self-contained HTML page.

Errors are percentages and times milliseconds in the text; the JSON keeps seconds and fractions
under names that say so.
"""

from __future__ import annotations

import html

import matplotlib.pyplot as plt
import numpy as np

from linkstress.analysis import DEFAULT_STATIONS
from linkstress.report.figures import boxed_label, outside_legend  # selects Agg
from linkstress.report.html import figure_tag, page, table_html, versions_html
from linkstress.tables import format_table
from linkstress.validation.bench.peaks import FIELD_BOUND, PEAK_BOUND, RATIO_TARGET, SETTING, SUPERPOSITION_TARGET
from linkstress.validation.bench.suite import NOMINAL_BOUND, SPEEDUP, BenchResult, converged_setting
from linkstress.validation.bench.speed_error import RATIO, VALIDATE_LEVELS, CaseStudy

PLOT_FLOOR = 1e-4
"""Smallest error [%] drawn on the log axis (a method that matches the reference to rounding)."""
STYLES = {"beam": ("o", "tab:blue"), "strip sums": ("s", "tab:gray"), "FEA P1": ("^", "tab:orange"), "FEA P2": ("D", "tab:green")}


def _pct(value) -> object:
    return "-" if value is None else 100 * value


def label(case: CaseStudy, method) -> str:
    """The setting in words: FEA levels say their refinement and role."""
    if not method.method.startswith("FEA"):
        return method.setting
    k = int(method.setting.split("=")[1])
    size = f"element size x {RATIO**-k:.3g}"
    return size + (" (validate's converged mesh)" if method.method == "FEA P2" and k == VALIDATE_LEVELS[-1] else "")


def case_rows(case: CaseStudy) -> list[tuple]:
    front = set(case.pareto())
    return [
        (m.method, label(case, m), m.size, 1e3 * m.seconds, 100 * m.nominal_error, _pct(m.peak_error),
         _pct(m.resultant_error), "yes" if k in front else "", m.note)
        for k, m in enumerate(case.methods)
    ]


CASE_HEADERS = ("method", "setting", "stations / strips / dofs", "time [ms]", "nominal error [%]", "peak error [%]",
                "resultant error [%]", "Pareto", "note")


def member_rows(case: CaseStudy) -> list[tuple]:
    """The beam at the default stations and validate's converged FEA on every member, against the reference."""
    beam = case.find("beam", f"{DEFAULT_STATIONS} stations")
    fea = case.find("FEA P2", converged_setting())
    return [
        (link, member, "yes" if link in case.curved else "", _pct(nominal), _pct(resultants),
         _pct(fea.member_errors[link][member][0]))
        for link, members in beam.member_errors.items()
        for member, (nominal, resultants) in members.items()
    ]


MEMBER_HEADERS = ("link", "member", "curved link", f"beam ({DEFAULT_STATIONS} stations) nominal error [%]",
                  "beam resultant error [%]", "converged FEA nominal error [%]")


def reference_estimate(case: CaseStudy) -> float:
    """The Richardson estimate of the reference's own error [-], worst over the links that have one."""
    return max(e for e in case.reference_error.values() if e is not None)


def stations_needed(case: CaseStudy, tolerance: float = 5e-4) -> int | None:
    """The fewest beam stations whose nominal error is within ``tolerance`` of the most stations' error."""
    beams = [(int(m.setting.split()[0]), m.nominal_error) for m in case.methods if m.method == "beam"]
    best = min(beams, key=lambda b: -b[0])[1]
    within = [count for count, error in beams if error <= best + tolerance]
    return min(within) if within else None


def coarsest_converged(case: CaseStudy, bound: float = 0.005):
    """The fastest P2 level within ``bound`` of the reference."""
    levels = [m for m in case.methods if m.method == "FEA P2" and m.nominal_error < bound]
    return min(levels, key=lambda m: m.seconds) if levels else None


def defaults_lines(result: BenchResult) -> list[str]:
    lines = []
    for case in result.cases:
        default = case.find("beam", f"{DEFAULT_STATIONS} stations")
        needed = stations_needed(case)
        coarse = coarsest_converged(case)
        fea = case.find("FEA P2", converged_setting())
        lines.append(
            f"{case.name}: beam stations: {needed} reach the error of the most stations measured (within 0.05 "
            f"points); the default {DEFAULT_STATIONS} give {100 * default.nominal_error:.3g} % in {1e3 * default.seconds:.3g} ms. "
            f"FEA: validate's converged mesh {100 * fea.nominal_error:.3g} % ({fea.size} dofs, {fea.seconds:.3g} s); "
            + (f"the fastest P2 mesh under 0.5 % is {label(case, coarse)} ({coarse.size} dofs, {coarse.seconds:.3g} s)"
               if coarse else "no P2 mesh measured is under 0.5 %")
        )
    return lines


def must_show_lines(result: BenchResult) -> list[str]:
    m = result.must_show
    verdict = "met" if m.met else "NOT met"
    return [
        f"seed case: beam engine ({DEFAULT_STATIONS} stations) nominal error {100 * m.beam_error:.3g} % "
        f"(bound {100 * NOMINAL_BOUND:g} %) in {1e3 * m.beam_seconds:.3g} ms for its three links; validate's converged "
        f"FEA {100 * m.fea_error:.3g} % in {m.fea_seconds:.3g} s (one solve on its finest mesh), {m.study_seconds:.3g} s "
        "for the three-level study that shows it converged",
        f"speed-up: {m.speedup:,.0f} x over the one solve, {m.study_speedup:,.0f} x over the study "
        f"(must show >= {SPEEDUP:,.0f} x over the converged FEA: {verdict})",
        *sweep_speedup_lines(result),
    ]


def sweep_speedup_lines(result: BenchResult) -> list[str]:
    """Per link and position over a sweep: the seed's section stresses against one link's FEA sweep."""
    rates = {(r.case, r.stage): r for r in result.rates}
    beam, fea = rates.get(("seed_ansys_fourbar", "section stresses")), rates.get(("seed_ansys_fourbar", "FEA (one link)"))
    if beam is None or fea is None:
        return []
    links = len(result.cases[0].links)
    beam_each, fea_each = beam.seconds / (beam.positions * links), fea.seconds / fea.positions
    return [
        f"over a sweep (throughput below): {1e6 * beam_each:.3g} us per link and position for the beam, "
        f"{1e3 * fea_each:.3g} ms for the FEA on validate's converged mesh: {fea_each / beam_each:,.0f} x"
    ]


def superposition_rows(result: BenchResult) -> list[tuple]:
    """One row per case and link: the superposed FEA's size, times and errors against direct FEA."""
    return [
        ("superposed FEA", study.name, link.name, link.unit_cases, link.dofs, link.sweep_positions,
         1e3 * (link.mesh_seconds + link.unit_solve_seconds), 1e3 * link.superposition_per_position, 1e3 * link.sweep_seconds,
         link.compared, 1e3 * link.direct_per_position, 100 * link.peak_error, 100 * link.field_error)
        for study in result.peaks for link in study.links
    ]


SUPERPOSITION_HEADERS = ("method", "case", "link", "unit cases", "dofs", "feasible positions", "mesh + unit solves [ms]",
                         "superposition [ms per position]", "whole sweep [ms]", "compared positions",
                         "direct FEA [ms per position]", "peak error [%]", "field rms error [%]")


def superposition_lines(result: BenchResult) -> list[str]:
    """What the superposed FEA's table measures, and the seed's sweep with peaks against one validate."""
    s = result.peaks_speed
    verdict = "met" if s.met else "NOT met"
    return [
        f"FEA peaks over a sweep by superposition of unit loads ({SETTING}) against the direct FEA of the same loads on "
        f"the same mesh at validate's compared positions: peak von Mises error (bound {100 * PEAK_BOUND:g} %) and rms "
        f"error of the nodal von Mises field (bound {100 * FIELD_BOUND:g} %), worst over those positions; the whole sweep "
        "is the mesh, the unit solves and the superposition of every feasible position; the direct FEA's time per "
        "position shares its mesh and factorisation among the compared positions",
        f"seed: a whole turn of {s.sweep_positions} input angles analysed with FEA peaks for {', '.join(s.links)} in "
        f"{s.sweep_seconds:.3g} s, one validate at one position (three mesh levels) {s.validate_seconds:.3g} s (best of "
        f"{s.repeat}, alternated): ratio {s.ratio:.3g} (target < {RATIO_TARGET:g}); superposition "
        f"{1e3 * s.superposition_per_link_position:.3g} ms per link and position (target <= {1e3 * SUPERPOSITION_TARGET:g} ms): "
        f"{verdict}",
    ]


def bench_text(result: BenchResult) -> str:
    lines = [f"linkstress bench ({result.settings.name}), {result.seconds:.0f} s; machine: "
             + ", ".join(f"{k} {v}" for k, v in result.machine.items())]
    for case in result.cases:
        lines += ["", f"{case.title} ({case.name}): {', '.join(case.links)} at {case.positions} position(s); "
                  f"reference: Richardson on the three finest P2 meshes ({', '.join(f'{k} {v} dofs' for k, v in case.reference_dofs.items())}), "
                  f"its own error estimate {100 * reference_estimate(case):.2g} %; joint forces {1e3 * case.kinetics_seconds:.2g} ms",
                  format_table(CASE_HEADERS, case_rows(case)),
                  "per member (a member whose every compared station is near a hole or a junction has no nominal error: -)",
                  format_table(MEMBER_HEADERS, member_rows(case))]
        if case.curved:
            lines.append(f"curved: {', '.join(case.curved)} (a member sectioned square to its centreline, Winkler-Bach stresses)")
        if case.note:
            lines.append(case.note)
    lines += ["", *must_show_lines(result), "", "defaults:", *(f"  {line}" for line in defaults_lines(result))]
    lines += ["", "strip sums' mass properties against the exact (Green) values (worst link)", format_table(*strip_mass_table(result))]
    lines += ["", "throughput", format_table(*rates_table(result)), "", "FEA peak memory (fresh process)", format_table(*memory_table(result))]
    lines += ["", "hard cases (errors of the beam against FEA; flags are what the engine says)", format_table(*stability_table(result))]
    for case in result.stability:
        lines += [f"  {case.name}: {flag}" for flag in case.flags]
    lines += ["", "superposed FEA peaks against direct FEA", *superposition_lines(result),
              format_table(SUPERPOSITION_HEADERS, superposition_rows(result))]
    lines += ["", "analyze as a whole process (first run: an empty disk cache; cached: the same command again)",
              format_table(*analyze_runs_table(result))]
    failures = result.failures()
    lines += ["", "checks (errors only): " + ("passed" if not failures else "FAILED\n  " + "\n  ".join(failures))]
    return "\n".join(lines)


def analyze_runs_table(result: BenchResult):
    rows = [(r.case, r.positions, ", ".join(f"{k} {v}" for k, v in r.models.items()), r.first, r.cached)
            for r in result.analyze_runs]
    return ("scene", "positions", "models", "first run [s]", "cached run [s]"), rows


def strip_mass_table(result: BenchResult):
    rows = []
    for case in result.cases:
        for m in case.methods:
            if m.mass_errors:
                worst = np.max(np.array(list(m.mass_errors.values())), axis=0)
                rows.append((case.name, m.setting, 1e3 * m.seconds, *(100 * worst)))
    return ("case", "strip width", "time incl. stresses [ms]", "area [%]", "centroid / length [%]", "polar moment [%]"), rows


def rates_table(result: BenchResult):
    rows = [(r.case, r.stage, r.positions, 1e3 * r.seconds, round(r.per_second), r.detail) for r in result.rates]
    return ("case", "stage", "positions", "time [ms]", "positions per second", "what"), rows


def memory_table(result: BenchResult):
    rows = [(m.case, m.link, f"P{m.order}", m.dofs, m.seconds, m.baseline_mb, m.peak_mb, m.peak_mb - m.baseline_mb)
            for m in result.memory]
    return ("case", "link", "elements", "dofs", "time [s]", "before [MB]", "peak [MB]", "FEA's share [MB]"), rows


def stability_table(result: BenchResult):
    rows = []
    for case in result.stability:
        for r in case.rows:
            rows.append((
                case.name, r.link, round(r.input_angle_deg, 4), "yes" if r.feasible else "no: " + r.reason.split(":")[0],
                "-" if r.transmission_deg is None else r.transmission_deg, _pct(r.nominal), _pct(r.near_hole),
                _pct(r.resultants), "; ".join(r.flags) if r.flags else ("-" if r.feasible else "infeasible"),
            ))
    return ("case", "link", "input [deg]", "feasible", "transmission [deg]", "nominal [%]", "near holes [%]",
            "resultants [%]", "position flags"), rows


def bench_json(result: BenchResult) -> dict:
    def method(case, k, m):
        return {
            "method": m.method, "setting": m.setting, "label": label(case, m), "size": m.size, "seconds": m.seconds,
            "nominal_error_pct": 100 * m.nominal_error, "peak_error_pct": _none_pct(m.peak_error),
            "resultant_error_pct": _none_pct(m.resultant_error), "pareto": k in case.pareto(),
            "links": {n: {**dict(zip(("nominal_error_pct", "peak_error_pct", "resultant_error_pct"), map(_none_pct, e))),
                          "members": {member: dict(zip(("nominal_error_pct", "resultant_error_pct"), map(_none_pct, errors)))
                                      for member, errors in m.member_errors.get(n, {}).items()}}
                      for n, e in m.link_errors.items()},
            "note": m.note,
            "mass_errors_pct": None if m.mass_errors is None else {
                n: dict(zip(("area", "centroid_over_length", "polar_moment"), (100 * v for v in e))) for n, e in m.mass_errors.items()
            },
        }

    ms = result.must_show
    return {
        "mode": result.settings.name, "seconds": result.seconds, "machine": result.machine,
        "cases": {c.name: {
            "title": c.title, "links": list(c.links), "members": {n: list(v) for n, v in c.members.items()},
            "positions": c.positions, "curved_links": list(c.curved), "note": c.note,
            "kinetics_seconds": c.kinetics_seconds, "reference_dofs": c.reference_dofs,
            "reference_error_pct": {n: _none_pct(e) for n, e in c.reference_error.items()},
            "methods": [method(c, k, m) for k, m in enumerate(c.methods)],
        } for c in result.cases},
        "must_show": {
            "beam_stations": DEFAULT_STATIONS, "beam_nominal_error_pct": 100 * ms.beam_error, "beam_seconds": ms.beam_seconds,
            "fea_nominal_error_pct": 100 * ms.fea_error, "fea_seconds": ms.fea_seconds, "fea_study_seconds": ms.study_seconds,
            "speedup": ms.speedup, "study_speedup": ms.study_speedup, "met": ms.met,
        },
        "defaults": defaults_lines(result),
        "throughput": [{"case": r.case, "stage": r.stage, "positions": r.positions, "seconds": r.seconds,
                        "positions_per_second": r.per_second, "detail": r.detail} for r in result.rates],
        "memory": [m.__dict__ for m in result.memory],
        "stability": [{"case": c.name, "description": c.description, "flags": list(c.flags),
                       "rows": [_stability_row(r) for r in c.rows]} for c in result.stability],
        "checks": [c.__dict__ for c in result.checks],
        "failures": result.failures(),
        "superposition": superposition_json(result),
        "analyze_runs": [r.record() for r in result.analyze_runs],
    }


def superposition_json(result: BenchResult) -> dict:
    s = result.peaks_speed
    return {
        "setting": SETTING, "peak_bound_pct": 100 * PEAK_BOUND, "field_bound_pct": 100 * FIELD_BOUND,
        "cases": {study.name: {
            "title": study.title, "positions": study.positions,
            "peak_error_pct": 100 * study.peak_error, "field_error_pct": 100 * study.field_error,
            "links": {link.name: {
                "unit_cases": link.unit_cases, "dofs": link.dofs, "sweep_positions": link.sweep_positions,
                "mesh_seconds": link.mesh_seconds, "unit_solve_seconds": link.unit_solve_seconds,
                "superposition_seconds": link.superposition_seconds,
                "superposition_ms_per_position": 1e3 * link.superposition_per_position, "sweep_seconds": link.sweep_seconds,
                "compared_positions": link.compared, "direct_seconds": link.direct_seconds,
                "direct_ms_per_position": 1e3 * link.direct_per_position,
                "peak_error_pct": 100 * link.peak_error, "field_error_pct": 100 * link.field_error,
            } for link in study.links},
        } for study in result.peaks},
        "speed": {
            "case": s.study.name, "sweep_positions": s.sweep_positions, "links": list(s.links), "repeat": s.repeat,
            "sweep_with_peaks_seconds": s.sweep_seconds, "validate_one_position_seconds": s.validate_seconds,
            "ratio": s.ratio, "ratio_target": RATIO_TARGET,
            "superposition_ms_per_link_position": 1e3 * s.superposition_per_link_position,
            "superposition_target_ms": 1e3 * SUPERPOSITION_TARGET, "met": s.met,
        },
    }


def _stability_row(r) -> dict:
    return {
        "link": r.link, "input_angle_deg": r.input_angle_deg, "feasible": r.feasible, "reason": r.reason,
        "transmission_angle_deg": r.transmission_deg, "nominal_error_pct": _none_pct(r.nominal),
        "near_hole_error_pct": _none_pct(r.near_hole), "resultant_error_pct": _none_pct(r.resultants),
        "fea_peak_over_beam_max": r.peak_ratio, "equilibrium_mismatch": r.equilibrium, "reaction_ratio": r.reaction,
        "flags": list(r.flags), "trusted": r.trusted,
    }


def _none_pct(value):
    return None if value is None else 100 * value


def speed_error_figure(case: CaseStudy):
    """Log-log time against nominal error, one marker per method and setting, the Pareto front joined."""
    fig, ax = plt.subplots(figsize=(7.5, 5.0), layout="constrained")
    for family, (marker, colour) in STYLES.items():
        points = [(m.seconds, max(100 * m.nominal_error, PLOT_FLOOR)) for m in case.methods if m.method == family]
        if points:
            ax.plot(*zip(*points), marker=marker, color=colour, ls=":", lw=0.8, label=family)
    front = [case.methods[k] for k in case.pareto()]
    xs = [m.seconds for m in front]
    ys = [max(100 * m.nominal_error, PLOT_FLOOR) for m in front]
    ax.step(xs, ys, where="post", color="black", lw=1.2, label="Pareto front")
    ax.plot(xs, ys, "o", mfc="none", mec="black", ms=12)
    default = case.find("beam", f"{DEFAULT_STATIONS} stations")
    converged = case.find("FEA P2", converged_setting())
    for m, text, side in ((default, f"beam, {DEFAULT_STATIONS} stations (default)", 1), (converged, "validate's converged FEA", -1)):
        if m is not None:
            boxed_label(ax, text, (m.seconds, max(100 * m.nominal_error, PLOT_FLOOR)), offset=(6 * side, 6),
                        ha="left" if side > 0 else "right", fontsize=8)
    ax.axhline(100 * NOMINAL_BOUND, color="tab:red", lw=0.8, ls="--", label=f"{100 * NOMINAL_BOUND:g} %")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time [s] (all compared links, best of several runs)")
    ax.set_ylabel("nominal von Mises error against the reference [%]")
    ax.set_title(f"{case.title}: speed against error")
    ax.grid(True, which="both", lw=0.3)
    outside_legend(ax)
    return fig


def bench_html(result: BenchResult) -> str:
    sections = [
        "<p>Every stress method of linkstress timed the same way (wall time after imports, from the link profiles and "
        "their joint loads to the stresses; where a run is cheap, the best of as many runs as fill a window of a second in the full run) and compared with one reference: "
        "the Richardson extrapolation of the three finest P2 meshes. The quantity is the nominal von Mises stress at "
        "validate's comparison stations along every member of each link (sections square to the member's axis), at "
        "the beam's critical fibre.</p>",
        "<h2>Machine</h2>", table_html(("", ""), list(result.machine.items())),
        "<h2>What must show</h2>", *(f"<p>{html.escape(line)}</p>" for line in must_show_lines(result)),
    ]
    for case in result.cases:
        sections += [
            f"<h2>{html.escape(case.title)}</h2>",
            f"<p>{html.escape(', '.join(case.links))} at {case.positions} position(s); reference error estimate "
            f"{100 * reference_estimate(case):.2g} %.{' ' + html.escape(case.note) if case.note else ''}</p>",
            figure_tag(speed_error_figure(case), f"time against error, {case.name}"),
            table_html(CASE_HEADERS, case_rows(case)),
            "<p>Per member (a member whose every compared station is near a hole or a junction has no nominal error: -)</p>",
            table_html(MEMBER_HEADERS, member_rows(case)),
        ]
    sections += ["<h2>Defaults</h2>", *(f"<p>{html.escape(line)}</p>" for line in defaults_lines(result))]
    sections += ["<h2>Strip sums: mass properties</h2>", table_html(*strip_mass_table(result))]
    sections += ["<h2>Throughput</h2>", table_html(*rates_table(result)), "<h2>FEA memory</h2>", table_html(*memory_table(result))]
    sections += ["<h2>Hard cases</h2>", table_html(*stability_table(result))]
    for case in result.stability:
        sections.append(f"<p><b>{html.escape(case.name)}</b>: {html.escape(case.description)}</p>")
        sections += [f'<p class="note">{html.escape(flag)}</p>' for flag in case.flags]
    sections += ["<h2>Superposed FEA peaks</h2>", *(f"<p>{html.escape(line)}</p>" for line in superposition_lines(result)),
                 table_html(SUPERPOSITION_HEADERS, superposition_rows(result))]
    rows = [(c.name, "passed" if c.passed else "FAILED", "-" if c.value is None else 100 * c.value,
             "-" if c.bound is None else 100 * c.bound) for c in result.checks]
    sections += ["<h2>Checks (errors only, never times)</h2>", table_html(("check", "result", "value [%]", "bound [%]"), rows)]
    sections += ["<h2>Versions</h2>", versions_html()]
    return page(f"linkstress bench ({result.settings.name}): speed against error", sections)
