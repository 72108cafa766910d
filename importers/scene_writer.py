"""The scene file (TOML text) of a mechanism drawn assembled, written directly: no user text is ever
evaluated, and names (layers) are TOML strings with every character that needs it escaped.

The scene runs as written: steel, a default plate thickness, the drawn crank angle at a default
speed, no loads. Comments say what to edit. Lengths in metres, angles in degrees.
"""

from __future__ import annotations

import math
import re

from linkstress.errors import InputError
from linkstress.importers.assembly import Assembly
from linkstress.importers.linkage_assembly import LinkageAssembly
from linkstress.kinematics.machine import Loop, Role

THICKNESS_M = 0.005
"""The plate thickness written for every link [m], a placeholder the user edits."""
SPEED_RAD_S = 1.0
"""The crank speed written [rad/s], a placeholder the user edits."""
MATERIAL = ("steel", {"density": ("7850.0", "kg/m^3"), "youngs_modulus": ("200e9", "Pa"), "poisson_ratio": ("0.3", "-")})
"""The material written for every link: name, and per key its value (TOML text) and unit, to edit."""
_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")
_ESCAPES = {"\\": "\\\\", '"': '\\"', "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}


def scene_text(assembly: Assembly, sketch: str, sketch_name: str, units: str | None,
               hole_layers: tuple[str, ...] = ()) -> str:
    """The scene of ``assembly``: ``sketch`` is the sketch's path relative to the scene's folder,
    ``sketch_name`` its file name for the header, ``units`` the unit given for a sketch that does not
    say its own (``--units``; None: not given), ``hole_layers`` the layers read as holes (each sketch
    link reads them so too)."""
    lines = header_lines(sketch_name, units) + link_lines(assembly, sketch, hole_layers)
    for loop in assembly.loops:
        lines += _mechanism(loop, assembly)
    lines += _motion(assembly)
    return "\n".join(lines) + "\n"


def header_lines(sketch_name: str, units: str | None) -> list[str]:
    """A written scene's first lines: what wrote it, its title, the unit given (``units``, or None)
    and the material every link is given."""
    lines = [
        f"# Written by `linkstress import {_comment(sketch_name)} --scene`: the mechanism as drawn assembled.",
        "# Edit the material, each link's thickness and the motion; add [loads] (every key: docs/scenes.md).",
        "",
        f"title = {toml_string(sketch_name + ' as drawn')}",
    ]
    if units is not None:
        lines.append(f"units = {toml_string(units)}  # --units: for a sketch that does not say its unit")
    name, values = MATERIAL
    lines += ["", f"[materials.{name}]  # edit: the links' material"]
    lines += [f"{key} = {value}  # {unit}" for key, (value, unit) in values.items()]
    return lines


def toml_string(text: str) -> str:
    """``text`` as a TOML basic string: quotes, backslashes and control characters escaped.

    A lone surrogate (a broken name) has no TOML form and is refused."""
    out = []
    for ch in text:
        code = ord(ch)
        if ch in _ESCAPES:
            out.append(_ESCAPES[ch])
        elif 0xD800 <= code <= 0xDFFF:
            raise InputError(f"--scene: the name {text.encode('utf-8', 'backslashreplace').decode()!r} holds a broken "
                             "character (a lone surrogate); rename the layer")
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04X}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def toml_key(text: str) -> str:
    """``text`` as a TOML key: bare when it may be, else quoted."""
    return text if _BARE_KEY.fullmatch(text) else toml_string(text)


def _comment(text: str) -> str:
    """``text`` fit for a comment: one line, no control characters."""
    return "".join(ch if ch.isprintable() else "?" for ch in text)


def number(value: float) -> str:
    """A float as TOML: Python's shortest round-tripping form is valid TOML."""
    return repr(float(value))


def link_lines(assembly: Assembly | LinkageAssembly, sketch: str, hole_layers: tuple[str, ...]) -> list[str]:
    """A ``[links.NAME]`` table per drawn link, read from ``sketch``, and the bare joints of a ground not drawn."""
    lines = []
    material = MATERIAL[0]
    for name, link in assembly.links.items():
        lines += [
            "",
            f"[links.{toml_key(name)}]",
            f"sketch = {toml_string(sketch)}",
            f"layer = {toml_string(name)}",
            *([f"hole_layers = [{', '.join(toml_string(layer) for layer in hole_layers)}]"] if hole_layers else []),
            f"thickness = {number(THICKNESS_M)}  # m, a default: edit to the plate's",
            f"material = {toml_string(material)}",
        ]
    if assembly.ground_joints is not None:
        points = ", ".join(f"[{number(x)}, {number(y)}]" for x, y in assembly.ground_joints)
        lines += [
            "",
            f"[links.{toml_key(assembly.ground)}]  # {assembly.ground_rule} (m)",
            f"joints = [{points}]",
        ]
    return lines


def _mechanism(loop: Loop, assembly: Assembly) -> list[str]:
    lines = ["", f"[mechanisms.{toml_key(loop.name)}]", f"type = {toml_string(loop.kind)}"]
    if loop.driven_by is not None:
        lines.append(f"driven_by = {toml_string(loop.driven_by.loop + '.' + loop.driven_by.role)}")
    for name, role in loop.roles.items():
        line = f"{name} = {_role(role, assembly, name)}"
        if name == "crank" and loop.driven_by is None:
            line += f"  # {assembly.crank_rule}"
        if name == "ground" and loop.driven_by is None:
            line += f"  # {assembly.ground_rule}"
        lines.append(line)
    lines.append(f"branch = {toml_string(loop.branch)}  # as drawn")
    if loop.kind == "slider-crank":
        lines += [
            f"slider_angle_deg = {number(math.degrees(loop.slider_angle))}  # the slider block's longer side, as drawn",
            f"offset_m = {number(loop.offset)}  # the slider line (through its pin) from the crank's pivot, + to its left",
        ]
    return lines


def _role(role: Role, assembly: Assembly, name: str) -> str:
    """A bare name where the role's axis is the link's joints 0 -> 1 and it has two (bare ground: its
    pivots; a slider: its joint 0, and it has one), else the name with its joints."""
    ground = name == "ground" and assembly.ground_joints is not None
    count = len(assembly.ground_joints) if ground else len(assembly.links[role.link].joints)
    if name == "slider":
        if role.joints == (0, 0) and count == 1:
            return toml_string(role.link)
        return f"{{link = {toml_string(role.link)}, joints = [{role.joints[0]}]}}"
    if role.joints == (0, 1) and count == 2:
        return toml_string(role.link)
    return f"{{link = {toml_string(role.link)}, joints = [{role.joints[0]}, {role.joints[1]}]}}"


def _motion(assembly: Assembly) -> list[str]:
    angle = assembly.input_angle_deg
    start, stop = assembly.sweep_deg
    if stop - start == 360.0:
        sweep, why = f"{{start = {number(start)}, stop = {number(stop)}, num = 361}}", "one turn from the drawn angle"
    else:
        # Rounded inward, so that every position of the sweep assembles.
        inside = math.ceil(start * 1e6) / 1e6, math.floor(stop * 1e6) / 1e6
        sweep = f"{{start = {number(inside[0])}, stop = {number(inside[1])}, num = 201}}"
        why = "the crank rocks, from toggle to toggle"
    return [
        "",
        "[motion]",
        f"input_angle_deg = {number(angle)}  # the crank as drawn, degrees from +x",
        f"# input_angle_deg = {sweep}  # a sweep: {why}",
        f"input_speed_rad_s = {number(SPEED_RAD_S)}  # a default: edit",
    ]
