"""A one-DOF linkage of pins and sliders drawn assembled: the ``type = "linkage"`` mechanism of a drawing.

What the drawing holds, read as ``kinematics.linkage.graph`` takes it:

- Pins: where pin centres of links on different layers coincide within the gap tolerance
  (``pins.shared_joints``), two or more links each; ternary and quaternary links are links with
  three or four joints.
- Ground: as for loops (``assembly.find_ground``): the layer named ground, frame or base, else the
  link common to every four-bar loop with the most joints; else it is not drawn, and a joint that
  one link alone uses, at the centre of a pin hole of that link, is a fixed pivot (a POINT in
  material, such as a foot or a coupler point, is not).
- Sliders (``slides``): a pin in a slot of another link, a block in a guide's outline or on the
  ground; each line runs through two joints of its guide (two points written on the line for a
  ground not drawn).
- Input (``linkage_input``): the crank named, an actuator named, else the shortest grounded link.

The graph's checks run here, before the scene is written: Gruebler's count gives one degree of
freedom (else the count and the links that float or lock), every link is connected to the ground,
and the groups solve in order. Everything in metres, sketch frame = ground frame.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from shapely.geometry import Point

from linkstress.errors import SketchError
from linkstress.importers.assembly import find_ground
from linkstress.importers.linkage_input import choose_input
from linkstress.importers.pins import ANGLE_DIGITS, BARE_GROUND, Joint, shared_joints
from linkstress.importers.sketch import ImportedLink, Sketch
from linkstress.importers.slides import Slide, find_slides, line_joints
from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.linkage.graph import Input, LinkageGraph, Slider
from linkstress.kinematics.linkage.graph import Joint as GraphJoint
from linkstress.kinematics.motion import angle_motion, stroke_motion
from linkstress.kinematics.solve import solve_machine

NAME = "main"
"""The written linkage's mechanism name."""
SWEEP_STEP_DEG = 0.5
"""The step [deg] to which the range where a crank's linkage assembles is found, each way from the
drawn angle."""
STROKE_SAMPLES = 200
"""The steps each way from the drawn stroke, over the slider's length, to which the range where it
assembles is found."""
SWEEP_FINE = 10
"""Fine steps in a coarse one: the range is first solved at ten times those steps (5 deg)."""
STROKE_DIGITS = 12
"""Decimals of the drawn stroke written [m]."""


@dataclass(frozen=True)
class LinkageAssembly:
    """A drawing's one linkage.

    ``links``: the drawn links by name; ``ground``: the ground's name; ``ground_joints`` (k, 2) [m]:
    the pivots (then points of slider lines) of a ground that is not drawn, else None; ``graph``:
    the checked joint graph (its pins, sliders and input as the scene writes them); ``slides``: what
    the drawing shows of each slider, in ``graph.sliders`` order; ``input_value``: the drawn input
    (degrees, to ``ANGLE_DIGITS`` decimals, or a stroke [m]); ``sweep``: (start, stop) of the input
    about it where the linkage assembles, ``turns``: whether that is a full turn of a crank;
    ``ground_rule`` and ``input_rule``: how they were chosen, for the reader.
    """

    links: dict[str, ImportedLink]
    ground: str
    ground_joints: NDArray[np.float64] | None
    graph: LinkageGraph
    slides: tuple[Slide, ...]
    input_value: float
    sweep: tuple[float, float]
    turns: bool
    ground_rule: str
    input_rule: str

    def summary(self) -> list[str]:
        """Lines for the terminal: the linkage, its input, how it is solved and its sliders."""
        graph = self.graph
        if graph.input.is_stroke:
            drive = f"input the stroke of slider {graph.input.slider}, drawn at {self.input_value:.6g} m"
        else:
            drive = (f"input {graph.input.link!r} turning about its joint {graph.input.pivot}, drawn at "
                     f"{self.input_value:.6g} deg")
        lines = [
            f"mechanism {NAME}: linkage of {len(graph.links)} links and {len(graph.pins)} pins, ground {self.ground!r}; {drive}",
            f"  solved as: {', '.join(group.label for group in graph.groups)}",
        ]
        for k, (slide, slider) in enumerate(zip(self.slides, graph.sliders)):
            lines.append(f"  slider {k}: {slider.point} on {slider.on!r} (line through its joints {slider.line[0]} "
                         f"and {slider.line[1]}): {slide.how}")
        return lines


def find_linkage(sketch: Sketch) -> LinkageAssembly:
    """The one-DOF linkage drawn in ``sketch``; a SketchError naming what does not make one."""
    links = {link.name: link for link in sketch.links}
    tolerance = sketch.gap_tolerance_m
    joints = shared_joints(sketch.links, tolerance)
    ground, ground_rule = find_ground(sketch, joints)
    slides = find_slides(links, joints, ground, tolerance)
    if ground is None:
        ground_rule = ("the ground is not drawn: its pivots are the pin holes that one link alone has (then points "
                       "of slider lines on it)")
    name = ground if ground is not None else BARE_GROUND
    pivots = [] if ground is not None else _bare_pivots(links, joints, slides)
    drawn = {link: item.joints for link, item in links.items()}
    if ground is None:
        drawn[name] = np.array([joints[k].at for k in pivots] + _ground_lines(slides, joints)).reshape(-1, 2)
    pins = _pins(joints, slides, pivots, name)
    sliders = _sliders(slides, joints, pins, drawn, name, len(pivots) if ground is None else None, tolerance)
    used = _used(pins, sliders)
    chosen, input_rule = choose_input(links, drawn, name, pins, slides, used)
    graph = _graph(drawn, name, pins, sliders, chosen)
    if chosen.is_stroke:
        value = round(graph.drawn_stroke(graph.sliders[chosen.slider]), STROKE_DIGITS)
    else:
        d = drawn[chosen.link][chosen.to] - drawn[chosen.link][chosen.pivot]
        value = round(math.degrees(math.atan2(d[1], d[0])), ANGLE_DIGITS)
    try:
        sweep, turns = _sweep(graph, value, _strokes(graph, slides[chosen.slider], chosen.slider) if chosen.is_stroke else None)
    except LinkageError as error:  # a group drawn at a toggle, found as it is solved
        raise SketchError(_without_key(str(error))) from None
    ground_joints = drawn[name] if ground is None else None
    return LinkageAssembly(links, name, ground_joints, graph, tuple(slides), value, sweep, turns, ground_rule, input_rule)


def _bare_pivots(links: dict[str, ImportedLink], joints: list[Joint], slides: list[Slide]) -> list[int]:
    """The pins (indices into ``joints``) that the ground not drawn holds: a joint one link alone has,
    in a pin hole of it, that slides in no slot."""
    sliding = {s.pin for s in slides}
    return [
        k for k, joint in enumerate(joints)
        if len(joint.ends) == 1 and k not in sliding and _in_hole(links[joint.ends[0][0]], joint.at)
    ]


def _in_hole(link: ImportedLink, at: NDArray[np.float64]) -> bool:
    return not link.outline.covers(Point(at))


def _ground_lines(slides: list[Slide], joints: list[Joint]) -> list[NDArray[np.float64]]:
    """Two points [m] on the line of each slider on a ground not drawn: its pin, and its length along."""
    points = []
    for slide in slides:
        if slide.on is None:
            at = joints[slide.pin].at
            points += [at, at + slide.length * slide.direction]
    return points


def _pins(joints: list[Joint], slides: list[Slide], pivots: list[int], ground: str) -> list[tuple[tuple[str, int], ...]]:
    """The scene's pins: each shared joint's links (a block's end left out: its slider pins it), the
    ground's pivot added where the ground is not drawn."""
    blocks = {s.pin: s.block for s in slides if s.block is not None}
    pins = []
    for k, joint in enumerate(joints):
        ends = [end for end in joint.ends if end[0] != blocks.get(k)]
        if k in pivots:
            ends.append((ground, pivots.index(k)))
        seen: dict[str, int] = {}
        for link, index in ends:
            if link in seen:
                raise SketchError(
                    f"link {link!r} has joints {seen[link]} and {index} at ({joint.at[0]:.6g}, {joint.at[1]:.6g}) m, closer "
                    "than the gap tolerance: one pin hole drawn twice? Delete one"
                )
            seen[link] = index
        if len(ends) >= 2:
            pins.append(tuple(ends))
    return pins


def _sliders(slides: list[Slide], joints: list[Joint], pins: list[tuple[tuple[str, int], ...]],
             drawn: dict[str, NDArray[np.float64]], ground: str, pivots: int | None, tolerance: float) -> list[Slider]:
    """The graph's sliders: each slide's line named by two joints of its guide. ``pivots``: the
    number of pivots of a ground not drawn (its slider lines' points follow them, two a slider, in
    the order of ``slides``), None for a drawn ground."""
    sliders = []
    on_ground = 0
    for slide in slides:
        guide = slide.on if slide.on is not None else ground
        if slide.on is None and pivots is not None:
            line = (pivots + 2 * on_ground, pivots + 2 * on_ground + 1)
            on_ground += 1
        else:
            pinned = {index for pin in pins for link, index in pin if link == guide}
            line = line_joints(slide, guide, drawn[guide], pinned, joints[slide.pin].at, tolerance)
        sliders.append(Slider(GraphJoint(*slide.point), guide, line, slide.block))
    return sliders


def _used(pins: list[tuple[tuple[str, int], ...]], sliders: list[Slider]) -> dict[str, set[int]]:
    used: dict[str, set[int]] = {}
    for pin in pins:
        for link, index in pin:
            used.setdefault(link, set()).add(index)
    for slider in sliders:
        used.setdefault(slider.point.link, set()).add(slider.point.index)
        used.setdefault(slider.on, set()).update(slider.line)
    return used


def _graph(drawn: dict[str, NDArray[np.float64]], ground: str, pins: list[tuple[tuple[str, int], ...]],
           sliders: list[Slider], chosen: Input) -> LinkageGraph:
    """The checked joint graph, its groups found; a SketchError with the graph's reason, its scene
    keys left out (the scene is not written yet)."""
    try:
        graph = LinkageGraph(NAME, drawn, ground, tuple(tuple(GraphJoint(*end) for end in pin) for pin in pins),
                             tuple(sliders), chosen)
        graph.groups  # noqa: B018 - the decomposition's own refusals, before the scene is written
    except LinkageError as error:
        raise SketchError(_without_key(str(error))) from None
    return graph


def _without_key(message: str) -> str:
    """A graph message without its leading scene key (``mechanisms.main...: ``)."""
    return re.sub(rf"^mechanisms\.{NAME}[^:\s]*: ", "", message)


def _strokes(graph: LinkageGraph, slide: Slide, k: int) -> tuple[float, float]:
    """The strokes' change (low, high) [m] from the drawn one over the input slider's ``travel``:
    the stroke runs along its line from joint i toward j, the travel along the slide's direction."""
    i, j = graph.sliders[k].line
    drawn = graph.links[graph.sliders[k].on]
    sign = 1.0 if float((drawn[j] - drawn[i]) @ slide.direction) > 0 else -1.0
    low, high = sorted(sign * x for x in slide.travel)
    return low, high


def _sweep(graph: LinkageGraph, value: float, travel: tuple[float, float] | None) -> tuple[tuple[float, float], bool]:
    """The input's range about the drawn ``value`` where the linkage assembles, each way to its last
    fine step that does (``_reach``): one turn each way for a crank (a full turn when it assembles
    all round); for a stroke, within its ``travel`` (low, high) [m] from the drawn one."""
    if travel is None:
        coarse = round(360.0 / (SWEEP_FINE * SWEEP_STEP_DEG))
        ahead, whole = _reach(graph, value, 360.0, coarse, angle_motion)
        if whole:
            return (value, value + 360.0), True
        behind, _ = _reach(graph, value, -360.0, coarse, angle_motion)
        return (behind, ahead), False
    coarse = STROKE_SAMPLES // SWEEP_FINE
    strokes = value + np.linspace(travel[0], travel[1], 2 * coarse + 1)
    if solve_machine(graph, stroke_motion(strokes)).feasible.all():
        return (float(strokes[0]), float(strokes[-1])), False
    ahead, _ = _reach(graph, value, travel[1], coarse, stroke_motion)
    behind, _ = _reach(graph, value, travel[0], coarse, stroke_motion)
    return (behind, ahead), False


def _reach(graph: LinkageGraph, value: float, span: float, coarse: int, motion) -> tuple[float, bool]:
    """How far from ``value`` toward ``value + span`` the linkage assembles: solved at ``coarse``
    steps, then at ``SWEEP_FINE`` finer ones within the coarse step where it stops assembling (the
    path through the coarse steps before it, so that it follows the drawn assembly). The last fine
    step that assembles, and whether the whole span does. A Newton group refines every step where
    it cannot close, so the steps past the end are kept few."""
    steps = value + np.linspace(0.0, span, coarse + 1)
    feasible = solve_machine(graph, motion(steps)).feasible
    if feasible.all():
        return float(steps[-1]), True
    k = int(np.argmin(feasible))
    if k == 0:
        return value, False
    fine = np.linspace(steps[k - 1], steps[k], SWEEP_FINE + 1)[1:-1]
    ok = solve_machine(graph, motion(np.concatenate([steps[:k], fine]))).feasible[k:]
    run = len(fine) if ok.all() else int(np.argmin(ok))
    return float(fine[run - 1]) if run else float(steps[k - 1]), False
