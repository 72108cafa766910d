"""``docs/benchmarks.md`` from one ``linkstress bench`` run: the run's JSON figures as Markdown.

The page is a function of the JSON alone (``bench_json``), so that a page and the figures it was
written from can be checked against each other: ``linkstress bench --markdown docs/benchmarks.md
--json docs/benchmarks.json`` writes both from the same run. Times are milliseconds or seconds as
the headers say, errors percentages.
"""

from __future__ import annotations

from collections.abc import Sequence

GENERATED = "<!-- Written by `linkstress bench --markdown`: rerun it to update this page, do not edit by hand. -->"

WHAT_IS_MEASURED = """\
Every stress method is timed the same way: wall time after imports, from the link profiles and their
joint loads to the stresses of all compared links (the joint-force solve they share is timed apart).
A run under a second is repeated for a second and the best kept; a longer one is timed once. The
error is that of the nominal von Mises stress at validate's comparison stations along every member
of each link (sections square to the member's axis, a section depth or more from every pin and
junction), at the beam's critical fibre, worst over members, links and positions, against the
Richardson extrapolation of the three finest P2 meshes. The strip sums are the original program's
method (strips between U(x) and L(x), joint forces translated along the link); they cut along a
link's frame axis, so they are measured on links that are one straight member only. Times move with
the machine and its load; the ratios are what one run measured."""

SCRIPTS = """\
Benchmarks outside `linkstress bench` are scripts that print figures (these machines are shared and
noisy: compare the ratios measured in one run, never a time against a bound):

```sh
python -m linkstress.validation.bench.profile        # section tables, mass properties, strip sums (--full: dx = 1e-4 m)
python -m linkstress.validation.bench.kinematics     # four-bar sweeps against reference loops; four chained loops
python -m linkstress.validation.bench.dynamics       # forces and section stresses, seed case and a 3,600-position sweep
python -m linkstress.validation.bench.fea            # FEA: converged single position, 360-position sweep, memory
python -m linkstress.validation.bench.sketch_import --ezdxf  # sketch import
python -m linkstress.validation.bench.plot           # the import plot of a many-part sheet
python -m linkstress.validation.bench.memory         # analyze's peak memory at 1e4, 1e5, 1e6 positions
python -m linkstress.validation.bench.startup        # start-up of analyze against a bare import of numpy
python -m linkstress.validation.fea.verification     # the FEA's analytic verification suite
python -m linkstress.validation.bench.cluster        # regression cases on a Dask cluster of 1 and 2 local workers
python -m linkstress.validation.bench.blocks         # validate of one link's long sweep, whole and in blocks on 2 workers
python -m linkstress.validation.bench.first_solve    # one link's unit-load set phase by phase; analyze --peaks cold and with its cache warm
```"""


def number(value: object) -> str:
    """A figure as a reader wants it: 3 significant digits, thousands separated, '-' for none."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else ""
    if isinstance(value, int):
        return f"{value:,}"
    if isinstance(value, float):
        if value != value:
            return "-"
        if abs(value) >= 1000:
            return f"{value:,.0f}"
        return f"{value:.3g}"
    return str(value)


def table(headers: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """A Markdown pipe table; numbers right-aligned."""
    right = [bool(rows) and all(isinstance(row[k], (int, float)) and not isinstance(row[k], bool) or row[k] is None
                                for row in rows) for k in range(len(headers))]
    lines = ["| " + " | ".join(headers) + " |", "|" + "|".join("---:" if r else "---" for r in right) + "|"]
    lines += ["| " + " | ".join(number(v).replace("|", "/") for v in row) + " |" for row in rows]
    return "\n".join(lines)


def machine_line(figures: dict) -> str:
    machine = figures["machine"]
    return (f"One `linkstress bench` run ({figures['mode']}, {figures['seconds']:.0f} s) on "
            + ", ".join(f"{key} {value}" for key, value in machine.items()) + ".")


def case_section(name: str, case: dict, stations: int) -> list[str]:
    reference = ", ".join(f"{link} {dofs:,} dofs" for link, dofs in case["reference_dofs"].items())
    estimates = [e for e in case["reference_error_pct"].values() if e is not None]
    rows = [(m["method"], m["label"], m["size"], 1e3 * m["seconds"], m["nominal_error_pct"], m["peak_error_pct"],
             m["resultant_error_pct"], "yes" if m["pareto"] else "") for m in case["methods"]]
    lines = [
        f"### {case['title']} (`{name}`)", "",
        f"Links {', '.join(case['links'])} at {case['positions']} position(s). Reference: Richardson on the three "
        f"finest P2 meshes ({reference})"
        + (f", its own error estimate {max(estimates):.2g} %" if estimates else "")
        + f". Joint forces {1e3 * case['kinetics_seconds']:.2g} ms.", "",
        table(("method", "setting", "stations / strips / dofs", "time [ms]", "nominal error [%]", "peak error [%]",
               "resultant error [%]", "Pareto"), rows),
    ]
    members = member_rows(case, stations)
    if members:
        lines += ["", f"Along every member, the beam at {stations} stations (the default) and validate's converged mesh:", "",
                  table(("link", "member", "curved", "beam nominal error [%]", "beam resultant error [%]",
                         "converged FEA nominal error [%]"), members)]
    if case["note"]:
        lines += ["", case["note"]]
    return lines


def member_rows(case: dict, stations: int) -> list[tuple]:
    """Per member: the default beam's and validate's converged FEA's errors (the methods the page's
    tables mark as default and converged)."""
    beam = next((m for m in case["methods"] if m["method"] == "beam" and m["setting"] == f"{stations} stations"), None)
    fea = next((m for m in case["methods"] if m["method"] == "FEA P2" and "converged" in m["label"]), None)
    if beam is None:
        return []
    rows = []
    for link, errors in beam["links"].items():
        for member, values in errors["members"].items():
            converged = fea["links"][link]["members"][member]["nominal_error_pct"] if fea else None
            rows.append((link, member, "yes" if link in case["curved_links"] else "", values["nominal_error_pct"],
                         values["resultant_error_pct"], converged))
    return rows


def must_show_lines(figures: dict) -> list[str]:
    m = figures["must_show"]
    return [
        f"- **Beam against converged FEA on the seed.** The beam engine ({m['beam_stations']} stations) is "
        f"{m['beam_nominal_error_pct']:.3g} % from the reference in {1e3 * m['beam_seconds']:.3g} ms for the three "
        f"links; validate's converged FEA is {m['fea_nominal_error_pct']:.3g} % in {m['fea_seconds']:.3g} s for one solve, "
        f"{m['fea_study_seconds']:.3g} s for the three-level study that shows it converged: "
        f"**{m['speedup']:,.0f} x** and **{m['study_speedup']:,.0f} x** ({'met' if m['met'] else 'NOT met'}: within the "
        "bound, at least 1,000 x).",
    ]


def superposition_section(figures: dict) -> list[str]:
    s = figures["superposition"]
    speed = s["speed"]
    rows = [(case, link, f["unit_cases"], f["dofs"], f["sweep_positions"],
             1e3 * (f["mesh_seconds"] + f["unit_solve_seconds"]), f["superposition_ms_per_position"], f["compared_positions"],
             f["direct_ms_per_position"], f["peak_error_pct"], f["field_error_pct"])
            for case, study in s["cases"].items() for link, f in study["links"].items()]
    return [
        f"FEA peaks over a sweep by superposition of unit loads ({s['setting']}) against the direct FEA of the same "
        f"loads on the same mesh at validate's compared positions: peak von Mises error (bound {s['peak_bound_pct']:g} %) "
        f"and rms error of the nodal von Mises field (bound {s['field_bound_pct']:g} %), worst over those positions.", "",
        table(("case", "link", "unit cases", "dofs", "feasible positions", "mesh + unit solves [ms]",
               "superposition [ms per position]", "compared positions", "direct FEA [ms per position]",
               "peak error [%]", "field rms error [%]"), rows), "",
        f"- **A sweep with peaks against one validate.** The seed's {speed['sweep_positions']} input angles with FEA peaks "
        f"for {', '.join(speed['links'])}: {speed['sweep_with_peaks_seconds']:.3g} s; one `validate` at one position "
        f"(three meshes): {speed['validate_one_position_seconds']:.3g} s (best of {speed['repeat']}, alternated): ratio "
        f"**{speed['ratio']:.3g}** (target below {speed['ratio_target']:g}); superposition "
        f"{speed['superposition_ms_per_link_position']:.3g} ms per link and position (target at most "
        f"{speed['superposition_target_ms']:g} ms): {'met' if speed['met'] else 'NOT met'}.",
    ]


def strip_rows(figures: dict) -> list[tuple]:
    rows = []
    for name, case in figures["cases"].items():
        for m in case["methods"]:
            if m["mass_errors_pct"]:
                worst = [max(e[key] for e in m["mass_errors_pct"].values()) for key in ("area", "centroid_over_length", "polar_moment")]
                rows.append((name, m["setting"], 1e3 * m["seconds"], *worst))
    return rows


def stability_rows(figures: dict) -> list[tuple]:
    return [
        (case["case"], r["link"], round(r["input_angle_deg"], 4), "yes" if r["feasible"] else "no",
         r["transmission_angle_deg"], r["nominal_error_pct"], r["near_hole_error_pct"], r["resultant_error_pct"],
         "; ".join(r["flags"]) if r["flags"] else ("-" if r["feasible"] else "infeasible"))
        for case in figures["stability"] for r in case["rows"]
    ]


def analyze_runs_section(figures: dict) -> list[str]:
    """``analyze`` of the README tutorial's scene and the seed: first run, cached run, models."""
    runs = figures.get("analyze_runs", [])
    rows = [(r["case"], r["positions"], ", ".join(f"{k} {v}" for k, v in r["models"].items()), r["first_seconds"],
             r["cached_seconds"]) for r in runs]
    repeat = runs[0]["repeat"] if runs else 0
    return [
        "Each stressed link takes the model that answers its governing stress within the default 5 % (beam, beam+Kt "
        "or the FEA peaks; docs/numbers.md); the first run has an empty disk cache, the cached run is the same command "
        f"again. Whole processes, bytecode compiled, best of {repeat}, alternated.", "",
        table(("scene", "positions", "models", "first run [s]", "cached run [s]"), rows),
    ]


def bench_markdown(figures: dict) -> str:
    """The benchmarks page from one run's ``bench_json`` figures."""
    lines = [GENERATED, "", "# Speed against error, and the benchmarks", "", machine_line(figures), "",
             "## Speed against error", "", WHAT_IS_MEASURED, ""]
    for name, case in figures["cases"].items():
        lines += [*case_section(name, case, figures["must_show"]["beam_stations"]), ""]
    lines += ["## What the run shows", "", *must_show_lines(figures), *(f"- {line}" for line in figures["defaults"]), ""]
    strips = strip_rows(figures)
    if strips:
        lines += ["## The original program's strip sums", "",
                  "Their mass properties against the exact (Green's theorem) values, worst link; the strips miss the holes.", "",
                  table(("case", "strip width", "time incl. stresses [ms]", "area [%]", "centroid / length [%]",
                         "polar moment [%]"), strips), ""]
    lines += ["## Throughput", "",
              table(("case", "stage", "positions", "time [ms]", "positions per second", "what"),
                    [(r["case"], r["stage"], r["positions"], 1e3 * r["seconds"], r["positions_per_second"], r["detail"])
                     for r in figures["throughput"]]), "",
              "## FEA peak memory (a fresh process per row)", "",
              table(("case", "link", "elements", "dofs", "time [s]", "before [MB]", "peak [MB]"),
                    [(m["case"], m["link"], f"P{m['order']}", m["dofs"], m["seconds"], m["baseline_mb"], m["peak_mb"])
                     for m in figures["memory"]]), "",
              "## Hard cases", "",
              "The beam against FEA where beam theory is strained; the flags are what the engine itself says.", "",
              table(("case", "link", "input [deg]", "feasible", "transmission [deg]", "nominal [%]", "near holes [%]",
                     "resultants [%]", "flags"), stability_rows(figures)), "",
              "## FEA peaks by superposition", "", *superposition_section(figures), "",
              "## analyze as a whole process", "", *analyze_runs_section(figures), "",
              "## Checks", "",
              "Errors only, never times: " + ("all passed." if not figures["failures"]
                                              else "FAILED: " + "; ".join(figures["failures"]) + "."), "",
              "## Other benchmarks", "", SCRIPTS, ""]
    return "\n".join(lines)


def readme_summary(figures: dict) -> str:
    """The README's paragraph of figures, from the same run as the page (a test holds them equal)."""
    must = figures["must_show"]
    beams = {name: next(m for m in case["methods"] if m["method"] == "beam" and m["setting"] == f"{must['beam_stations']} stations")
             for name, case in figures["cases"].items()}
    others = [beam["nominal_error_pct"] for name, beam in beams.items() if name != "seed_ansys_fourbar"]
    rates = {(r["case"], r["stage"]): r for r in figures["throughput"]}
    kinematics, whole = rates[("seed_ansys_fourbar", "kinematics")], rates[("seed_ansys_fourbar", "whole analysis")]
    speed = figures["superposition"]["speed"]
    runs = {r["case"]: r for r in figures.get("analyze_runs", [])}
    tutorial = runs.get("tutorial")
    analyze = "" if tutorial is None else (
        f" The tutorial's `analyze` ({tutorial['positions']} positions, FEA peaks where the model choice puts them: "
        f"{', '.join(k for k, v in tutorial['models'].items() if v == 'fea-peaks') or 'none'}) takes "
        f"{tutorial['first_seconds']:.2g} s the first time and {tutorial['cached_seconds']:.2g} s again with its cache warm."
    )
    machine = figures["machine"]
    load = next((value for key, value in machine.items() if key.startswith("load")), "not measured")
    return (
        f"on the seed four-bar the beam engine's nominal von Mises is {must['beam_nominal_error_pct']:.2g} % from "
        f"converged FEA, in {1e3 * must['beam_seconds']:.2g} ms for three links: {must['speedup']:,.0f} x faster than one "
        f"solve on validate's converged mesh. On the curved couplers and the bell crank the worst member is "
        f"{max(others):.2g} % off. A whole turn of {speed['sweep_positions']} positions with FEA peaks takes "
        f"{speed['ratio']:.2g} x the time of one `validate` at one position.{analyze} Over a sweep of "
        f"{kinematics['positions']:,} positions of the seed, kinematics runs at {kinematics['positions_per_second']:,.0f} "
        f"positions per second and the whole analysis (kinematics, forces, stresses of three links) at "
        f"{whole['positions_per_second']:,.0f}. Measured on {machine['cpu']}, {machine['cores']} cores shared with "
        f"other work (load average {load}), Python {machine['python']}, in a {figures['seconds']:.0f} s run."
    )
