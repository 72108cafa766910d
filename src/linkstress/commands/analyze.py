"""``linkstress analyze SCENE [--json OUT]``: what every link of a scene's machine does at every position.

stdout: each mechanism's class (Grashof, Barker), toggles, feasible input range and limit positions,
then a table of every link's angle, angular velocity and acceleration and its centre of mass's
acceleration at each feasible position, then the infeasible positions and why.

JSON (DESIGN.md's ``analyze`` shape): ``{"positions": [{"input_angle_deg", "feasible", "reason",
"links": {NAME: {"angle_deg", "omega_rad_s", "alpha_rad_s2", "acc_G_m_s2"}}}]}``; ``acc_G_m_s2``
only where the link's centre of mass is known; an infeasible position has empty ``links``.
Angles in [0, 360) degrees, counter-clockwise from the ground frame's +x; ground frame, SI.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import tempfile
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import InputError
from linkstress.kinematics import MachineMotion, solve_machine
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
from linkstress.scene import Scene, load_scene
from linkstress.tables import format_table


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "analyze",
        help="kinematics of a scene's machine over its input motion",
        description=(
            "Read a scene file (TOML) and report, at every input angle, each link's angle, angular "
            "velocity and acceleration and its centre of mass's acceleration (ground frame, SI), with "
            "each mechanism's Grashof class, toggles and limit positions."
        ),
    )
    parser.add_argument("scene", type=Path, metavar="SCENE", help="scene file (TOML)")
    parser.add_argument("--json", type=Path, metavar="OUT", help="also write the results as JSON to OUT")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.json is not None and not args.json.parent.resolve().is_dir():
        raise InputError(f"--json: folder {str(args.json.parent)!r} does not exist")
    result = analyze(load_scene(args.scene))
    print(report(result))
    if args.json is not None:
        write_json(args.json, {"positions": position_records(result)})
    return 0


@dataclass(frozen=True)
class AnalyzeResult:
    """A scene and its machine's motion over the scene's input positions."""

    scene: Scene
    kinematics: MachineMotion

    @cached_property
    def columns(self) -> dict[str, LinkColumns]:
        """Every link's reported values, in the scene's order."""
        return link_columns(self)


@dataclass(frozen=True)
class LinkColumns:
    """One link's reported values at every position: angle_deg in [0, 360), omega [rad/s],
    alpha [rad/s^2], acc_g (P, 2) [m/s^2] or None when its centre of mass is unknown."""

    angle_deg: NDArray[np.float64]
    omega: NDArray[np.float64]
    alpha: NDArray[np.float64]
    acc_g: NDArray[np.float64] | None


def analyze(scene: Scene) -> AnalyzeResult:
    return AnalyzeResult(scene, solve_machine(scene.machine, scene.motion))


def link_columns(result: AnalyzeResult) -> dict[str, LinkColumns]:
    """Every link's columns, in the scene's order."""
    columns = {}
    for name, link in result.scene.links.items():
        motion = result.kinematics.links[name]
        com = link.center_of_mass
        acc_g = None if com is None else motion.point(com)[2]
        angle = np.mod(np.rad2deg(motion.angle), 360.0) + 0.0
        columns[name] = LinkColumns(np.where(angle >= 360.0, 0.0, angle), motion.omega, motion.alpha, acc_g)
    return columns


def position_records(result: AnalyzeResult) -> list[dict]:
    """One JSON-ready dict per position; infeasible positions carry no link data."""
    kin = result.kinematics
    analysis = result.scene.analysis
    with_links = analysis is None or analysis.kinematics
    columns = result.columns if with_links else {}
    lists = {name: _as_lists(c) for name, c in columns.items()}
    feasible = kin.feasible.tolist()
    records = []
    for k, angle in enumerate(result.scene.motion.angle_deg.tolist()):
        links = {name: _link_record(values, k) for name, values in lists.items()} if feasible[k] else {}
        records.append({"input_angle_deg": angle, "feasible": feasible[k], "reason": kin.reasons[k], "links": links})
    return records


def _as_lists(c: LinkColumns) -> dict[str, list]:
    values = {"angle_deg": c.angle_deg.tolist(), "omega_rad_s": c.omega.tolist(), "alpha_rad_s2": c.alpha.tolist()}
    if c.acc_g is not None:
        values["acc_G_m_s2"] = c.acc_g.tolist()
    return values


def _link_record(values: dict[str, list], k: int) -> dict:
    return {key: column[k] for key, column in values.items()}


def write_json(path: Path, data: object) -> None:
    """Write ``data`` to ``path`` whole or not at all (a temporary file beside it, then a rename)."""
    folder = path.resolve().parent
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as stream:
            json.dump(data, stream, indent=1, allow_nan=False)
            stream.write("\n")
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


def report(result: AnalyzeResult) -> str:
    """The text printed on stdout."""
    scene, kin = result.scene, result.kinematics
    parts = [f"scene {scene.path.name}: {len(kin.feasible)} positions, {int(kin.feasible.sum())} feasible"]
    parts += [describe_loop(scene, name) for name in (loop.name for loop in scene.machine.loops)]
    analysis = scene.analysis
    if analysis is None or analysis.kinematics:
        parts.append(_motion_table(result))
    bad = [(a, r) for a, r, ok in zip(scene.motion.angle_deg.tolist(), kin.reasons, kin.feasible) if not ok]
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


def _motion_table(result: AnalyzeResult) -> str:
    columns = result.columns
    kin = result.kinematics
    rows = []
    for k in np.flatnonzero(kin.feasible):
        angle = float(result.scene.motion.angle_deg[k])
        for name, c in columns.items():
            acc = ("", "") if c.acc_g is None else (float(c.acc_g[k, 0]), float(c.acc_g[k, 1]))
            rows.append((angle, name, float(c.angle_deg[k]), float(c.omega[k]), float(c.alpha[k]), *acc))
    headers = ("input [deg]", "link", "angle [deg]", "omega [rad/s]", "alpha [rad/s^2]", "a_Gx [m/s^2]", "a_Gy [m/s^2]")
    return format_table(headers, rows)
