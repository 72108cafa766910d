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


def scene_of_graph(tmp_path: Path, graph, motion: str, *, masses: dict | None = None, extra: str = "",
                   name: str = "graph.toml"):
    """The scene of a ``LinkageGraph`` (its drawn joints, pins, sliders and input) with mass data:
    ``masses[link] = (mass, inertia, centre of mass in the member frame)``, by default 0.1 kg per
    0.1 m of the link's extent, its inertia that of a rod, its centre at the joints' mean."""
    links = ""
    for link, joints in graph.links.items():
        if link == graph.ground:
            links += link_table(link, joints)
            continue
        local = graph.local[link]
        size = max(float(np.ptp(local, axis=0).max()), 0.02)
        mass, inertia, com = (masses or {}).get(link, (size, size**3 / 12, local.mean(axis=0)))
        links += link_table(link, joints, mass, com, inertia)
    pins = [[str(j) for j in pin] for pin in graph.pins]
    sliders = [{"point": str(s.point), "on": s.on, "line": s.line, "block": s.block} for s in graph.sliders]
    if graph.input.is_stroke:
        input_ = f"{{slider = {graph.input.slider}}}"
    else:
        input_ = f'{{link = "{graph.input.link}", pivot = {graph.input.pivot}, to = {graph.input.to}}}'
    return linkage_scene(tmp_path, links, pins, motion, sliders=sliders, ground=graph.ground, input_=input_,
                         extra=extra, name=name)
