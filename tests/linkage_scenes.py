"""Scene texts for the linkage tests: links with bare joints and explicit mass data, written as TOML."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from linkstress.scene import load_scene


def link_table(name: str, joints, mass: float | None = None, com=(0.0, 0.0), inertia: float = 0.0) -> str:
    rows = ", ".join(f"[{float(x)!r}, {float(y)!r}]" for x, y in np.asarray(joints, float))
    text = f"[links.{name}]\njoints = [{rows}]\n"
    if mass is not None:
        text += f"mass = {mass!r}\ninertia = {inertia!r}\ncenter_of_mass = [{float(com[0])!r}, {float(com[1])!r}]\n"
    return text


def pins_text(pins) -> str:
    return "[" + ", ".join("[" + ", ".join(f'"{j}"' for j in pin) + "]" for pin in pins) + "]"


def sliders_text(sliders) -> str:
    items = []
    for s in sliders:
        block = f', block = "{s["block"]}"' if s.get("block") else ""
        items.append(f'{{point = "{s["point"]}", on = "{s["on"]}", line = [{s["line"][0]}, {s["line"][1]}]{block}}}')
    return "[" + ", ".join(items) + "]"


def linkage_scene(tmp_path: Path, links: str, pins, motion: str, *, sliders=(), ground="ground",
                  input_="{link = \"crank\", pivot = 0, to = 1}", extra: str = "", name: str = "linkage.toml"):
    """A ``type = "linkage"`` scene read from ``tmp_path / name``."""
    text = (
        links
        + f"\n[mechanisms.main]\ntype = \"linkage\"\nground = \"{ground}\"\ninput = {input_}\npins = {pins_text(pins)}\n"
        + (f"sliders = {sliders_text(sliders)}\n" if sliders else "")
        + f"\n[motion]\n{motion}\n{extra}"
    )
    path = tmp_path / name
    path.write_text(text)
    return load_scene(path)
