"""A [mechanisms.NAME] table of ``type = "linkage"``: any one-DOF planar linkage of pins and sliders.

```toml
[mechanisms.leg]
type = "linkage"
ground = "frame"
input = {link = "crank", pivot = 0, to = 1}      # or input = {slider = 0}
pins = [["frame:0", "crank:0"], ["crank:1", "rod:0"], ["rod:1", "rocker:1"], ["frame:1", "rocker:0"]]
sliders = [{point = "crank:1", on = "rocker", line = [0, 2], block = "collar"}]
branch = "as-drawn"
```

The links' joints are given in place, the mechanism drawn assembled: that pose is the assembly the
sweep follows. A linkage is its scene's only mechanism. Every check of the joint graph
(``kinematics.linkage.graph``) runs here, before any solve, each naming its key.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.graph import BRANCHES, Input, LinkageGraph, Slider, parse_joint
from linkstress.errors import SceneError
from linkstress.kinematics.errors import LinkageError
from linkstress.scene.keys import Table

LINKAGE_KEYS = ("type", "ground", "input", "pins", "sliders", "branch")
INPUT_KEYS = ("link", "pivot", "to", "slider")
SLIDER_KEYS = ("point", "on", "line", "block")


def read_linkage(entry: Table, name: str, drawn: Mapping[str, NDArray[np.float64]]) -> LinkageGraph:
    """The checked joint graph of ``[mechanisms.NAME]`` over the links' drawn joints ``drawn``."""
    entry.allow(LINKAGE_KEYS)
    entry.require("ground", "the fixed link's name, e.g. ground = \"frame\"")
    entry.require("input", "the input: input = {link = \"crank\", pivot = 0, to = 1} or input = {slider = 0}")
    entry.require("pins", "the pins, each a list of the joints it joins: pins = [[\"frame:0\", \"crank:0\"], ...]")
    ground = entry.string("ground")
    pins = _pins(entry)
    sliders = _sliders(entry)
    branch = entry.string("branch", "as-drawn", BRANCHES)
    try:
        return LinkageGraph(name, dict(drawn), ground, pins, sliders, _input(entry), branch)
    except LinkageError as error:  # its message names the key already
        raise SceneError(f"{entry.source}: {error}") from None


def _pins(entry: Table):
    raw = entry.data["pins"]
    if not isinstance(raw, list) or not raw:
        raise entry.error("pins", "must be a list of pins, each a list of joints: [[\"frame:0\", \"crank:0\"], ...]")
    pins = []
    for k, pin in enumerate(raw):
        where = entry.key_path(f"pins[{k}]")
        if not isinstance(pin, list) or len(pin) < 2:
            raise entry.error(f"pins[{k}]", f"must list the two or more joints it joins, e.g. [\"crank:1\", \"rod:0\"], got {pin!r}")
        pins.append(tuple(_joint(entry, f"pins[{k}]", text, where) for text in pin))
    return tuple(pins)


def _joint(entry: Table, key: str, text: object, where: str):
    try:
        return parse_joint(text, where)
    except LinkageError:
        raise entry.error(key, f"must name joints as \"LINK:i\" (i the joint's 0-based index), got {text!r}") from None


def _sliders(entry: Table) -> tuple[Slider, ...]:
    if not entry.has("sliders"):
        return ()
    raw = entry.data["sliders"]
    if not isinstance(raw, list):
        raise entry.error("sliders", "must be a list of tables {point = \"LINK:i\", on = \"LINK\", line = [i, j]}")
    sliders = []
    for k, item in enumerate(raw):
        spec = Table(item, entry.key_path(f"sliders[{k}]"), entry.source)
        spec.allow(SLIDER_KEYS)
        spec.require("point", "the joint that slides: point = \"LINK:i\"")
        spec.require("on", "the link whose line it slides on: on = \"LINK\" (the ground or a moving link)")
        spec.require("line", "two joints of that link through which the line runs: line = [i, j]")
        point = _joint(spec, "point", spec.data["point"], spec.key_path("point"))
        line = spec.data["line"]
        if not (isinstance(line, list) and len(line) == 2 and all(type(v) is int and v >= 0 for v in line)):
            raise spec.error("line", f"must be [i, j]: two joint indices (0-based) of link {spec.data['on']!r}, got {line!r}")
        sliders.append(Slider(point, spec.string("on"), (line[0], line[1]), spec.string("block")))
    return tuple(sliders)


def _input(entry: Table) -> Input:
    value = entry.data["input"]
    if not isinstance(value, dict):
        raise entry.error("input", f"must be {{link = \"crank\", pivot = 0, to = 1}} or {{slider = k}}, got {value!r}")
    spec = entry.table("input")
    spec.allow(INPUT_KEYS)
    if spec.has("slider"):
        for key in ("link", "pivot", "to"):
            if spec.has(key):
                raise spec.error(key, "not with slider: a slider's stroke is the input, or a crank's angle")
        return Input(slider=spec.integer("slider", minimum=0))
    spec.require("link", "the input link's name (it turns about its pivot on the ground), or slider = k")
    return Input(spec.string("link"), spec.integer("pivot", 0, minimum=0), spec.integer("to", 1, minimum=0))
