"""The scene file (TOML text) of a linkage drawn assembled: one ``type = "linkage"`` mechanism.

Written as ``scene_writer`` writes loops (the same header, links and material, names escaped), with
the linkage's pins, sliders and input (docs/scenes.md), the drawn input as the motion and, in a
comment, a sweep over the range where the linkage assembles. Lengths in metres, angles in degrees.
"""

from __future__ import annotations

from linkstress.importers.linkage_assembly import NAME, SWEEP_STEP_DEG, LinkageAssembly
from linkstress.importers.scene_writer import SPEED_RAD_S, header_lines, link_lines, number, toml_key, toml_string

SPEED_M_S = 0.1
"""The actuator's stroke speed written [m/s], a placeholder the user edits."""


def linkage_text(assembly: LinkageAssembly, sketch: str, sketch_name: str, units: str | None,
                 hole_layers: tuple[str, ...] = ()) -> str:
    """The scene of ``assembly``; the arguments as ``scene_writer.scene_text`` takes them."""
    lines = header_lines(sketch_name, units) + link_lines(assembly, sketch, hole_layers)
    lines += _mechanism(assembly) + _motion(assembly)
    return "\n".join(lines) + "\n"


def _joint(joint) -> str:
    return toml_string(str(joint))


def _mechanism(assembly: LinkageAssembly) -> list[str]:
    graph = assembly.graph
    lines = [
        "",
        f"[mechanisms.{toml_key(NAME)}]",
        'type = "linkage"',
        f"ground = {toml_string(graph.ground)}  # {assembly.ground_rule}",
        f"input = {_input(assembly)}  # {assembly.input_rule}",
        "pins = [",
    ]
    for pin in graph.pins:
        at = graph.drawn(pin[0])
        lines.append(f"    [{', '.join(_joint(j) for j in pin)}],  # at ({at[0]:.6g}, {at[1]:.6g}) m")
    lines.append("]")
    if graph.sliders:
        lines.append("sliders = [")
        for slider, slide in zip(graph.sliders, assembly.slides):
            block = f", block = {toml_string(slider.block)}" if slider.block is not None else ""
            lines.append(f"    {{point = {_joint(slider.point)}, on = {toml_string(slider.on)}, "
                         f"line = [{slider.line[0]}, {slider.line[1]}]{block}}},  # {_comment(slide.how)}")
        lines.append("]")
    lines.append('branch = "as-drawn"  # the assembly drawn, followed along the sweep')
    return lines


def _input(assembly: LinkageAssembly) -> str:
    given = assembly.graph.input
    if given.is_stroke:
        return f"{{slider = {given.slider}}}"
    return f"{{link = {toml_string(given.link)}, pivot = {given.pivot}, to = {given.to}}}"


def _comment(text: str) -> str:
    """``text`` fit for a comment: one line, no control characters."""
    return "".join(ch if ch.isprintable() else "?" for ch in text)


def _motion(assembly: LinkageAssembly) -> list[str]:
    start, stop = assembly.sweep
    graph = assembly.graph
    if graph.input.is_stroke:
        slider = graph.sliders[graph.input.slider]
        return [
            "",
            "[motion]",
            f"input_stroke_m = {number(assembly.input_value)}  # as drawn: {slider.point} from joint {slider.line[0]} of "
            f"{_comment(slider.on)} along its line",
            f"# input_stroke_m = {{start = {number(start)}, stop = {number(stop)}, num = 101}}  # a sweep: where the "
            "block stays in its guide (a block on the ground: its length each way) and the linkage assembles; edit "
            "to the actuator's stroke",
            f"input_speed_m_s = {number(SPEED_M_S)}  # a default: edit",
        ]
    if assembly.turns:
        sweep, why = f"{{start = {number(start)}, stop = {number(stop)}, num = 361}}", "one turn from the drawn angle"
    else:
        sweep = f"{{start = {number(start)}, stop = {number(stop)}, num = 201}}"
        why = f"the input rocks: where the linkage assembles, to the {SWEEP_STEP_DEG:g} deg step it was solved at"
    return [
        "",
        "[motion]",
        f"input_angle_deg = {number(assembly.input_value)}  # the input "
        f"{_comment(f'{graph.input.link}:{graph.input.pivot} -> {graph.input.to}')} as drawn, degrees from +x",
        f"# input_angle_deg = {sweep}  # a sweep: {why}",
        f"input_speed_rad_s = {number(SPEED_RAD_S)}  # a default: edit",
    ]
