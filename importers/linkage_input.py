"""The input of a linkage drawn assembled: which crank turns, or which actuator strokes.

- A link on a layer named crank, input or driver (``assembly.CRANK_NAMES``), pinned to the ground:
  it turns about that pin.
- Else a slider named as an actuator (``slides.is_actuator``: its block or guide on a layer whose
  name has the word cylinder, actuator, barrel or rod): its stroke is the input.
- Else the shortest link pinned to the ground (from that pin to its nearest other joint the
  linkage uses), as for four-bar loops.

A crank's angle is the direction from its pivot to that nearest used joint. Everything in metres,
sketch frame.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import SketchError
from linkstress.importers.assembly import CRANK_NAMES, is_named
from linkstress.importers.sketch import ImportedLink
from linkstress.importers.slides import Slide, is_actuator
from linkstress.kinematics.linkage.graph import Input


def choose_input(links: dict[str, ImportedLink], drawn: dict[str, NDArray[np.float64]], ground: str,
                 pins: list[tuple[tuple[str, int], ...]], slides: list[Slide],
                 used: dict[str, set[int]]) -> tuple[Input, str]:
    """The input and why it was chosen. ``drawn``: every link's joints [m] (the ground's too);
    ``pins``: the pins as joints (link, index); ``slides``: the sliders, in the scene's order;
    ``used``: per link the joints the linkage uses."""
    pivots = {end[0]: end[1] for pin in pins if any(name == ground for name, _ in pin) for end in pin if end[0] != ground}
    blocks = {s.block for s in slides if s.block is not None}
    named = [name for name, link in links.items() if name != ground and is_named(link, CRANK_NAMES)]
    if named:
        crank = named[0]
        if crank not in pivots:
            raise SketchError(
                f"link {crank!r} (on a layer named as the crank) is not pinned to the ground: the crank turns about "
                "a pin on the ground; rename its layer, or the layer of the link meant"
            )
        chosen = _crank(crank, pivots[crank], drawn, used)
        if chosen.to == chosen.pivot:
            raise SketchError(f"link {crank!r} (on a layer named as the crank) has one joint: a crank's angle runs from "
                              "its pivot to a second joint (a POINT or a pin hole)")
        return chosen, f"the link on layer {crank!r}"
    layers = {name: link.layer for name, link in links.items()}
    actuators = [k for k, slide in enumerate(slides) if is_actuator(slide, layers)]
    if actuators:
        k = actuators[0]
        return Input(slider=k), (
            f"no layer is named {', '.join(CRANK_NAMES)}: the stroke of {slides[k].how}, a layer named as an "
            "actuator (cylinder, actuator, barrel, rod)"
        )
    options = [
        (math.hypot(*(drawn[name][to.to] - drawn[name][pivot])), name, to)
        for name, pivot in pivots.items() if name not in blocks
        for to in [_crank(name, pivot, drawn, used)] if to.to != pivot
    ]
    if not options:
        raise SketchError(
            f"no link is pinned to the ground {ground!r} with a second joint to turn, and no slider is named as an "
            "actuator: name the input's layer crank (or a cylinder's barrel cylinder)"
        )
    _, _, chosen = min(options, key=lambda o: o[:2])
    return chosen, (
        f"no layer is named {', '.join(CRANK_NAMES)} or as an actuator: the shortest link pinned to the ground; "
        "rename its layer crank to choose another"
    )


def _crank(name: str, pivot: int, drawn: dict[str, NDArray[np.float64]], used: dict[str, set[int]]) -> Input:
    """``name`` turning about its joint ``pivot``, its angle toward the nearest other joint the
    linkage uses (any other joint when it uses none), or ``to = pivot`` when it has no other joint."""
    joints = drawn[name]
    others = [k for k in sorted(used.get(name, set())) if k != pivot] or [k for k in range(len(joints)) if k != pivot]
    if not others:
        return Input(name, pivot, pivot)
    to = min(others, key=lambda k: (math.hypot(*(joints[k] - joints[pivot])), k))
    return Input(name, pivot, to)
