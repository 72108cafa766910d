"""The [mechanisms.NAME] tables: loops, their roles, branch and how they are driven.

A role is a link name (its joints 0 -> 1; a slider's joint 0) or ``{link = "NAME", joints = [i, j]}``
(a slider: ``joints = [k]``; ``[k, j]`` with j != k is refused by the machine). A link with three or
more joints must be named with its joints: a sketch's joints are numbered by x then y, so "0 -> 1"
of a bell crank is whichever two pins happen to come first. ``branch`` is "open" (default) or "crossed". Slider-cranks take
``offset_m`` (the slider line's signed distance from O2, positive to the left of its direction) and
``slider_angle_deg`` (its direction from the ground frame's +x; default: the ground link's axis).
A loop other than the main one has ``driven_by = "LOOP.crank"`` or ``"LOOP.output"`` and, when its
crank is a different link from the driver's, an optional ``phase_deg``. A ``type = "linkage"``
mechanism (``scene.linkage``) is the scene's only one (``read_machine``).
"""

from __future__ import annotations

import math

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import SceneError
from linkstress.kinematics.fourbar import BRANCHES
from linkstress.kinematics.linkage.graph import LinkageGraph
from linkstress.kinematics.machine import KINDS, Drive, Loop, Machine, Role
from linkstress.messages import capped
from linkstress.scene.keys import Table, shown_value
from linkstress.scene.linkage import read_linkage

ROLES = {
    "four-bar": ("crank", "coupler", "output", "ground"),
    "slider-crank": ("crank", "coupler", "ground", "slider"),
}
REQUIRED = {"four-bar": ("crank", "coupler", "output", "ground"), "slider-crank": ("crank", "coupler", "ground")}
SLIDER_ONLY = ("slider", "offset_m", "slider_angle_deg")
MECHANISM_KEYS = (
    "type", "crank", "coupler", "output", "ground", "slider", "branch", "offset_m", "slider_angle_deg",
    "driven_by", "phase_deg",
)
ROLE_KEYS = ("link", "joints")
"""The keys of a role given as an inline table: ``crank = {link = "NAME", joints = [i, j]}``."""


def read_machine(table: Table, drawn: Mapping[str, NDArray[np.float64]]) -> Machine | LinkageGraph:
    """The scene's machine: a ``type = "linkage"`` mechanism (then the scene's only one,
    ``scene.linkage``), else the loops of every [mechanisms.NAME] chained into a ``Machine``."""
    names = list(table.data)
    linkages = [
        name for name in names if isinstance(table.data[name], dict) and table.data[name].get("type") == "linkage"
    ]
    if linkages:
        if len(names) > 1:
            other = next(name for name in names if name != linkages[0])
            raise table.error(
                other, f"a scene with a type = \"linkage\" mechanism ({linkages[0]!r}) has no other mechanism: a linkage "
                "holds every loop of the machine; write this one's links and pins into it"
            )
        return read_linkage(table.table(linkages[0]), linkages[0], drawn)
    return Machine(dict(drawn), tuple(read_mechanisms(table, drawn)))


def read_mechanisms(table: Table, drawn: Mapping[str, NDArray[np.float64]]) -> list[Loop]:
    """Every [mechanisms.NAME] as a kinematic ``Loop`` (the machine checks links and the drive graph).

    ``drawn``: each link's joints (n, 2) [m] as drawn, to refuse a bare name for a link with three
    or more joints."""
    loops = [_read_loop(table.table(name), name, drawn) for name in table.data]
    if not loops:
        raise table.error(None, "no mechanisms; add a [mechanisms.main] table with type = \"four-bar\"")
    return loops


def _read_loop(entry: Table, name: str, drawn: Mapping[str, NDArray[np.float64]]) -> Loop:
    entry.allow(MECHANISM_KEYS)
    entry.require("type", "type = \"four-bar\", type = \"slider-crank\" or type = \"linkage\"")
    kind = entry.string("type", choices=KINDS + ("linkage",))
    if kind == "four-bar":
        for key in SLIDER_ONLY:
            if entry.has(key):
                raise entry.error(key, "only for type = \"slider-crank\"")
    elif entry.has("output"):
        raise entry.error("output", "a slider-crank has no output link; name its slider with slider = \"NAME\"")
    roles = {}
    for role in ROLES[kind]:
        if role in REQUIRED[kind]:
            entry.require(role, f"the {role}'s link name, e.g. {role} = \"{role}\"")
        if entry.has(role):
            roles[role] = _read_role(entry, role, drawn)
    phase = entry.number("phase_deg", 0.0, unit="deg")
    drive = None
    if entry.has("driven_by"):
        text = entry.string("driven_by")
        source, _, role = text.rpartition(".")
        if not source or role not in ("crank", "output"):
            raise entry.error("driven_by", f"must be \"LOOP.crank\" or \"LOOP.output\", got {text!r}")
        drive = Drive(source, role, math.radians(phase))
    elif entry.has("phase_deg"):
        raise entry.error("phase_deg", "only for a loop with driven_by; the main loop's crank follows [motion]")
    slider_angle = entry.number("slider_angle_deg", unit="deg")
    return Loop(
        name=name,
        kind=kind,
        branch=entry.string("branch", "open", BRANCHES),
        offset=entry.number("offset_m", 0.0, unit="m"),
        slider_angle=None if slider_angle is None else math.radians(slider_angle),
        driven_by=drive,
        **roles,
    )


def _read_role(entry: Table, role: str, drawn: Mapping[str, NDArray[np.float64]]) -> Role:
    value = entry.data[role]
    if isinstance(value, str) and value:
        if len(drawn.get(value, ())) >= 3:
            raise _ambiguous(entry, role, value, drawn[value])
        return Role(value, (0, 0) if role == "slider" else (0, 1))
    if not isinstance(value, dict):
        raise entry.error(role, f"must be a link name or {{link = \"NAME\", joints = [i, j]}}, got {value!r}")
    spec = entry.table(role)
    spec.allow(ROLE_KEYS)
    spec.require("link", "the link's name, e.g. link = \"crank\"")
    link = spec.string("link")
    counts, shape = ((1, 2), "[k] (or [k, k])") if role == "slider" else ((2,), "[i, j]")
    joints = (0, 0) if role == "slider" else (0, 1)
    if spec.has("joints"):
        raw = spec.data["joints"]
        if not (isinstance(raw, list) and len(raw) in counts and all(type(k) is int and k >= 0 for k in raw)):
            raise spec.error("joints", f"must be {shape}: joint indices (0-based) of link {link!r}, got {shown_value(raw)}")
        joints = (raw[0], raw[-1])
    return Role(link, joints)


def _ambiguous(entry: Table, role: str, link: str, points: NDArray[np.float64]) -> SceneError:
    """The error for a bare name of a link with three or more joints: which two does the role use?"""
    listed = capped(f"{k} at ({x:.6g}, {y:.6g}) m" for k, (x, y) in enumerate(points))
    shape = "[k]" if role == "slider" else "[i, j]"
    return entry.error(
        role,
        f"link {link!r} has {len(points)} joints ({listed}; numbered as given: a sketch's by x, then y), "
        f"so its name alone does not say which this {role} uses; give them: "
        f"{role} = {{link = \"{link}\", joints = {shape}}}",
    )
