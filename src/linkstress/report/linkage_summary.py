"""What the text and HTML reports say about a ``type = "linkage"`` mechanism: its links, joints,
Gruebler count, input and the groups it is solved in, in order."""

from __future__ import annotations

import math

from linkstress.kinematics.linkage.graph import LinkageGraph


def describe_linkage(graph: LinkageGraph) -> str:
    """The mechanism's summary, a few lines."""
    dof, n, j1, j2 = graph.gruebler()
    if graph.input.is_stroke:
        slider = graph.sliders[graph.input.slider]
        given = graph.drawn_stroke(slider)
        driven = (f"input: the stroke of slider {graph.input.slider} ({slider.point} on {slider.on!r}, from its joint "
                  f"{slider.line[0]} toward {slider.line[1]}), drawn at {given:.6g} m; unknown: the actuator's force")
    else:
        joints = graph.links[graph.input.link]
        d = joints[graph.input.to] - joints[graph.input.pivot]
        drawn = math.degrees(math.atan2(d[1], d[0])) % 360.0
        driven = (f"input: link {graph.input.link} turning about its joint {graph.input.pivot} (angle of joint "
                  f"{graph.input.pivot} -> {graph.input.to}), drawn at {drawn:.6g} deg; unknown: the driving torque")
    lines = [
        f"mechanism {graph.name}: linkage of {n} links, {len(graph.all_pins)} pins, {len(graph.sliders)} sliders, "
        f"ground {graph.ground!r}; assembly as drawn",
        f"  Gruebler: F = 3 (n - 1) - 2 j1 - j2 = 3 ({n} - 1) - 2 x {j1} - {j2} = {dof}",
        f"  {driven}",
        "  solved in order: " + "; ".join(
            group.label + (f" with block(s) {', '.join(group.riders)}" if group.riders else "") for group in graph.groups
        ),
    ]
    for k, slider in enumerate(graph.sliders):
        block = f", block {slider.block}" if slider.block else ", massless block"
        lines.append(f"  slider {k}: {slider.point} on the line through joints {slider.line[0]}, {slider.line[1]} of "
                     f"{slider.on}{block}")
    return "\n".join(lines)
