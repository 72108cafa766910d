"""A sketch's links as text tables and as the JSON of docs/design.md (``linkstress import``).

Areas and moments are per unit thickness, in the sketch frame; each profile U(x), L(x) is in the
member frame of the link's first two joints (origin at joint 0, +x toward joint 1).
"""

from __future__ import annotations

import math

import numpy as np
from shapely.geometry import Polygon

from linkstress.importers.plausibility import unit_warnings
from linkstress.importers.problems import (
    ANNOTATION_LAYER, MAX_LISTED, Skipped, SketchProblem, by_kind, counted, skipped_counted,
)
from linkstress.importers.sketch import ImportedLink, Sketch
from linkstress.report.cells import without_noise
from linkstress.tables import format_table

MAX_PRINTED = MAX_LISTED
"""Problems of each kind, and skipped items of each kind, the text spells out; the rest are counted (all are
in the JSON)."""

NO_PROFILE = "a profile U(x), L(x) needs a member frame, which needs two joints; this link has {n}"


def link_json(link: ImportedLink) -> dict:
    """One link: docs/design.md's keys (area_m2, centroid_m, polar_moment_area_m4, joints_m, holes, profile)
    plus layer, joint_rules, largest_gap_m and the member frame of the profile."""
    profile = link.profile(1.0)
    props = profile.area_properties
    holes = []
    for ring, diameter, rule in zip(link.outline.interiors, link.hole_diameters_m, link.hole_rules):
        hole = Polygon(ring)
        holes.append({
            "centroid_m": [hole.centroid.x, hole.centroid.y],
            "area_m2": hole.area,
            "diameter_m": diameter,
            "circle_rule": rule,
        })
    out = {
        "name": link.name,
        "layer": link.layer,
        "area_m2": props.area,
        "centroid_m": list(props.centroid),
        "polar_moment_area_m4": props.polar,
        "joints_m": link.joints.tolist(),
        "joint_rules": list(link.joint_rules),
        "holes": holes,
        "largest_gap_m": link.largest_gap_m,
    }
    if len(link.joints) >= 2:
        x, upper, lower = profile.bounds(0, 1).polyline()
        frame = profile.frame(0, 1)
        out["member_frame"] = {"origin_m": list(frame.origin), "angle_deg": math.degrees(frame.angle)}
        out["profile"] = {"x_m": x.tolist(), "upper_m": upper.tolist(), "lower_m": lower.tolist()}
    else:
        out["profile"] = None
        out["profile_note"] = NO_PROFILE.format(n=len(link.joints))
    return out


def sketch_json(sketch: Sketch, refused: str | None = None) -> dict:
    """``{"links": [...]}`` of docs/design.md, with what was read, assumed, ignored, fixed and left out
    (``problems``: kind, layer, ``at`` in drawing units, entities, problem, fix), what was skipped as no
    part (``skipped``), the layers taken as holes, the unit warnings and, for a refused import, why
    (``refused``)."""
    data = {
        "sketch": str(sketch.path),
        "format": sketch.format,
        "units": sketch.units,
        "units_source": sketch.units_source,
        "gap_tolerance_m": sketch.gap_tolerance_m,
        "links": [link_json(link) for link in sketch.links],
        "ignored": dict(sketch.ignored),
        "fixes": list(sketch.fixes),
        "problems": [problem.json() for problem in sketch.problems],
        "skipped": [item.json() for item in sketch.skipped],
        "hole_layers": list(sketch.hole_layers),
        "warnings": list(unit_warnings(sketch)),
    }
    if refused is not None:
        data["refused"] = refused
    return data


def sketch_text(sketch: Sketch) -> str:
    """The headline (links that are parts, what was skipped, problems), the unit warnings, the problems
    grouped by kind and what was skipped as no part (a few of each, counted), then a table per link
    (area, centroid, polar moment, joints and their rule, holes, largest gap) and what was ignored and
    fixed."""
    units = f"units {sketch.units} ({sketch.units_source})"
    head = f"{sketch.path.name}: {sketch.format}, {units}, {len(sketch.links)} link(s)"
    skipped = sum(item.count for item in sketch.skipped if item.kind != ANNOTATION_LAYER)
    if skipped:
        head += f", {skipped} outline(s) skipped as no part"
    layers = sum(item.count for item in sketch.skipped if item.kind == ANNOTATION_LAYER)
    if layers:
        head += f", {layers} annotation layer(s) not read"
    if sketch.problems:
        head += f", {len(sketch.problems)} problem(s)"
    parts = [head]
    warnings = unit_warnings(sketch)
    if warnings:
        parts.append("\n".join(f"warning: {line}" for line in warnings))
    if sketch.problems:
        parts.append(problems_text(sketch.problems))
    if sketch.skipped:
        parts.append(skipped_text(sketch.skipped))
    for link in sketch.links:
        props = link.profile(1.0).area_properties
        size = float(np.abs(link.outline.bounds).max())  # round-off of coordinates is against this
        rows = [
            ("area per unit thickness [m^2]", props.area),
            ("centroid [m]", _pair(props.centroid, size)),
            ("polar moment of area about centroid [m^4]", props.polar),
        ]
        rows += [(f"joint {k} [m]", f"{_pair(p, size)} ({rule})") for k, (p, rule) in enumerate(zip(link.joints, link.joint_rules))]
        if not len(link.joints):
            rows.append(("joints", "none: no POINTs and no circular holes"))
        rows.append(("holes", _holes(link)))
        rows.append(("largest gap closed [m]", float(without_noise([link.largest_gap_m], size)[0])))
        layer = f" (layer {link.layer})" if link.layer else ""
        parts.append(f"link {link.name}{layer}\n" + format_table(("property", "value"), rows))
    if sketch.ignored:
        parts.append("ignored: " + ", ".join(f"{n} {kind}" for kind, n in sorted(sketch.ignored.items())))
    if sketch.fixes:
        parts.append("fixed:\n" + "\n".join(f"- {fix}" for fix in sketch.fixes))
    return "\n\n".join(parts)


def problems_text(problems: tuple[SketchProblem, ...]) -> str:
    """The problems grouped by kind, largest group first: a line with each group's count, then its first
    few problems."""
    lines = [f"problems ({len(problems)}, left out of the links below; every one in --json):"]
    for kind, group in by_kind(problems).items():
        first = f": first {MAX_PRINTED} of {len(group)}" if len(group) > MAX_PRINTED else ""
        lines.append(f"- {counted(len(group), kind)}{first}")
        lines += [f"  - {problem.text}" for problem in group[:MAX_PRINTED]]
    return "\n".join(lines)


def skipped_text(skipped: tuple[Skipped, ...]) -> str:
    """What was skipped as no part, grouped by kind: each group's count, then its first few notes."""
    lines = ["skipped, not parts (every one in --json):"]
    groups: dict[str, list[Skipped]] = {}
    for item in skipped:
        groups.setdefault(item.kind, []).append(item)
    for kind, group in groups.items():
        first = f": first {MAX_PRINTED} of {len(group)}" if len(group) > MAX_PRINTED else ""
        lines.append(f"- {skipped_counted(sum(item.count for item in group), kind)}{first}")
        lines += [f"  - {item.note}" for item in group[:MAX_PRINTED]]
    return "\n".join(lines)


def _pair(p, size: float) -> str:
    """"(x, y)" [m], a coordinate within round-off of 0 against the link's ``size`` [m] written 0."""
    x, y = without_noise(np.asarray(p, float)[:2], size)
    return f"({x:.6g}, {y:.6g})"


def _holes(link: ImportedLink) -> str:
    n = len(link.hole_diameters_m)
    if not n:
        return "0"
    circular = [(d, rule) for d, rule in zip(link.hole_diameters_m, link.hole_rules) if d is not None]
    text = f"{n}"
    if circular:
        listed = ", ".join(f"{d:.6g} m ({rule})" for d, rule in circular)
        text += f" ({len(circular)} circular, diameter {listed})"
    return text


def finite(data) -> bool:
    """True when every number in ``data`` (nested lists/dicts) is finite."""
    if isinstance(data, dict):
        return all(finite(v) for v in data.values())
    if isinstance(data, (list, tuple)):
        return all(finite(v) for v in data)
    if isinstance(data, float):
        return math.isfinite(data)
    return not isinstance(data, np.floating) or bool(np.isfinite(data))
