"""Sliders of a mechanism drawn assembled: pins in slots, blocks, and the lines they slide on.

A drawing has no mark for a sliding joint, so the shapes say it:

- A pin in a slot: a pin (the joint of one link, or of several pinned there) lying in a slot of
  another link (a hole that is not round and is at least ``SLOT_ELONGATION`` times as long as
  wide, by its smallest enclosing rectangle), on the slot's axis within the gap tolerance, slides
  on that link along the slot's axis. A link with one joint pinned there (a collar, a die block)
  is the slider's block; else the slider has no block (the pin runs in the slot).
- A block: a link with one joint, not in a slot, slides along the longer side of its outline's
  smallest enclosing rectangle (``slider_assembly.slider_direction``) on its guide: the link not
  pinned at its joint whose outline (holes filled) covers the largest part of the block's area,
  at least ``COVERED`` of it (a cylinder's barrel that the rod lies in), else the ground (a ram
  on its guide, a piston in its bore). A link with one joint that is itself such a guide (a barrel
  drawn with its pin hole only) is no block.

The line a slider's point runs on is written through two joints of its guide (``linkage.graph``'s
``line = [i, j]``): two joints that lie, with the slider's pin, on one line within the gap
tolerance, at most ``LINE_ANGLE_DEG`` off the slot's axis or the block's longer side. A slot's
ends are no joints (a POINT in a slot is a drawing problem), so a guide with no two joints on the
line is refused naming the POINTs to add. Everything here is in metres, sketch frame.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from itertools import combinations

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Point, Polygon

from linkstress.errors import SketchError
from linkstress.importers.pins import Joint
from linkstress.importers.sketch import ImportedLink
from linkstress.importers.slider_assembly import slider_direction

SLOT_ELONGATION = 1.5
"""A hole that is not round is a slot when its smallest enclosing rectangle is at least this much
longer than wide: a lightening window about as long as wide is not taken for a guide."""
COVERED = 0.25
"""A block lies in a guide (a barrel) when the guide's outline covers at least this part of it."""
LINE_ANGLE_DEG = 5.0
"""Two joints of the guide make the slider's line only within this angle of the slot's axis or the
block's longer side: a tapered rod's enclosing rectangle leans a degree or two off its axis."""


@dataclass(frozen=True)
class Slide:
    """A slider found on the drawing, before its line is named by joints. ``pin`` indexes the
    sketch's pins (``pins.shared_joints``); ``point``: the link and joint index that slides;
    ``on``: the guide (None: the ground); ``block``: the one-joint link riding on the line, or None;
    ``direction`` (2,) unit: the slot's axis or the block's longer side; ``length`` [m]: the slot's
    or the block's length along it; ``travel`` (low, high) [m]: how far the pin may move along
    ``direction`` from where it is drawn with its block (or the pin itself) still in its guide: in
    the slot, or its end inside the guide's outline (a rod's piston end in its barrel), or, on the
    ground, a block's length each way; ``how``: what the drawing shows, for the reader."""

    pin: int
    point: tuple[str, int]
    on: str | None
    block: str | None
    direction: NDArray[np.float64]
    length: float
    travel: tuple[float, float]
    how: str


@dataclass(frozen=True)
class _Slot:
    link: str
    hole: Polygon
    centre: NDArray[np.float64]
    direction: NDArray[np.float64]
    length: float
    width: float


def find_slides(links: dict[str, ImportedLink], joints: list[Joint], ground: str | None,
                tolerance: float) -> list[Slide]:
    """The sliders the drawing shows (``links`` by name, its pins ``joints``, the drawn ``ground`` or
    None), in the order of their pins; ``tolerance`` [m] the gap tolerance."""
    slots = [slot for link in links.values() for slot in _slots(link)]
    singles = {name for name, link in links.items() if len(link.joints) == 1 and name != ground}
    found: list[Slide] = []
    taken: set[str] = set()
    for k, joint in enumerate(joints):
        at = {name for name, _ in joint.ends}
        holding = [s for s in slots if s.link not in at and _on_axis(s, joint.at, tolerance)]
        if len(holding) > 1:
            raise SketchError(
                f"the pin at ({joint.at[0]:.6g}, {joint.at[1]:.6g}) m lies in slots of links "
                f"{', '.join(repr(s.link) for s in holding)} at once; a pin runs in one slot: check the drawing"
            )
        if holding:
            found.append(_in_slot(k, joint, holding[0], links, singles))
            taken |= {found[-1].block} - {None}
    guides = _guides(links, joints, singles - taken, ground)
    blocks = sorted(singles - taken - set(guides.values()), key=lambda name: _pin_of(name, joints))
    for block in blocks:
        k = _pin_of(block, joints)
        others = [end for end in joints[k].ends if end[0] != block]
        if not others:
            continue  # pinned to nothing: the graph's check names it as not connected
        guide = guides.get(block)
        u = slider_direction(links[block], np.array([1.0, 0.0]))
        at = joints[k].at
        ends = _span(links[block].outline, u, at)
        length = ends[1] - ends[0]
        if guide is None:
            how, travel = f"block {block!r} on the ground", (-length, length)
        else:
            how, travel = f"block {block!r} in the outline of {guide!r}", _inside(ends, _span(links[guide].outline, u, at))
        found.append(Slide(k, others[0], guide, block, u, length, travel, how))
    return sorted(found, key=lambda s: s.pin)


def _slots(link: ImportedLink) -> list[_Slot]:
    found = []
    for ring, diameter in zip(link.outline.interiors, link.hole_diameters_m):
        if diameter is not None:
            continue
        hole = Polygon(ring)
        corners = np.asarray(hole.minimum_rotated_rectangle.exterior.coords)[:3]
        sides = np.diff(corners, axis=0)
        lengths = np.hypot(*sides.T)
        if lengths.max() < SLOT_ELONGATION * lengths.min():
            continue
        u = sides[int(np.argmax(lengths))] / lengths.max()
        centre = np.asarray(hole.minimum_rotated_rectangle.centroid.coords[0])
        found.append(_Slot(link.name, hole, centre, u, float(lengths.max()), float(lengths.min())))
    return found


def _on_axis(slot: _Slot, at: NDArray[np.float64], tolerance: float) -> bool:
    """Whether the pin ``at`` lies in ``slot`` on its axis (within ``tolerance``)."""
    r = at - slot.centre
    return slot.hole.contains(Point(at)) and abs(float(r[0] * slot.direction[1] - r[1] * slot.direction[0])) <= tolerance


def _in_slot(k: int, joint: Joint, slot: _Slot, links: dict[str, ImportedLink], singles: set[str]) -> Slide:
    blocks = [name for name, _ in joint.ends if name in singles]
    if len(blocks) > 1:
        raise SketchError(
            f"links {', '.join(repr(b) for b in blocks)} each have one joint, the pin at ({joint.at[0]:.6g}, "
            f"{joint.at[1]:.6g}) m in the slot of {slot.link!r}: one block rides in a slot; check the drawing"
        )
    block = blocks[0] if blocks else None
    points = [end for end in joint.ends if end[0] != block]
    if not points:
        raise SketchError(
            f"block {block!r} in the slot of {slot.link!r} is pinned to no other link at ({joint.at[0]:.6g}, "
            f"{joint.at[1]:.6g}) m: a block in a slot carries a pin of another link (a crank's pin in a collar)"
        )
    how = f"the pin of {points[0][0]!r} in the slot of {slot.link!r}" + (f", in block {block!r}" if block else "")
    room = _span(slot.hole, slot.direction, joint.at)
    if block is None:
        travel = (room[0] + slot.width / 2, room[1] - slot.width / 2)  # the pin's round end in the slot's
    else:
        travel = _inside(_span(links[block].outline, slot.direction, joint.at), room)
    return Slide(k, points[0], slot.link, block, slot.direction, slot.length, travel, how)


def _pin_of(block: str, joints: list[Joint]) -> int:
    return next(k for k, joint in enumerate(joints) if any(name == block for name, _ in joint.ends))


def _guides(links: dict[str, ImportedLink], joints: list[Joint], singles: set[str], ground: str | None) -> dict[str, str]:
    """Each one-joint link's guide other than the ground: the link not pinned at its joint whose
    outline covers the most of it, at least ``COVERED``."""
    guides = {}
    shells = {name: Polygon(link.outline.exterior) for name, link in links.items()}
    for block in sorted(singles):
        pinned = {name for name, _ in joints[_pin_of(block, joints)].ends}
        area = links[block].outline.area
        shares = {
            name: shapely.intersection(shells[name], links[block].outline).area / area
            for name in links if name not in pinned and name != ground
        }
        best = max(shares, key=lambda name: (shares[name], name), default=None)
        if best is not None and shares[best] >= COVERED:
            guides[block] = best
    return guides


def _span(outline: Polygon, u: NDArray[np.float64], at: NDArray[np.float64]) -> tuple[float, float]:
    """(low, high) [m]: where ``outline`` reaches along ``u``, from ``at``."""
    along = (np.asarray(outline.exterior.coords) - at) @ u
    return float(along.min()), float(along.max())


def _inside(block: tuple[float, float], guide: tuple[float, float]) -> tuple[float, float]:
    """How far a block reaching ``block`` (low, high) [m] may move with the ends of it that lie in
    ``guide`` (low, high) staying there: a block inside moves until either end leaves, a rod with
    its back end inside until that end reaches either end of the guide; (0, 0) when no end is in."""
    inside = [end for end in block if guide[0] <= end <= guide[1]]
    if not inside:
        return 0.0, 0.0
    return guide[0] - min(inside), guide[1] - max(inside)


def line_joints(slide: Slide, guide: str, drawn: NDArray[np.float64], pinned: set[int],
                at: NDArray[np.float64], tolerance: float) -> tuple[int, int]:
    """The two joints (i, j) of ``guide`` (``drawn`` (n, 2) [m]) whose line carries ``slide``'s pin
    ``at``: on one line with it within ``tolerance`` [m], within ``LINE_ANGLE_DEG`` of its direction.
    ``i`` is a joint the guide is pinned at (``pinned``) when one is on the line, else the first; ``j``
    the farthest from it. A SketchError naming the guide when none are."""
    limit = math.sin(math.radians(LINE_ANGLE_DEG))
    fits = []
    for i, j in combinations(range(len(drawn)), 2):
        d = drawn[j] - drawn[i]
        length = math.hypot(*d)
        if length <= tolerance:
            continue
        v = d / length
        off = at - drawn[i]
        if abs(float(off[0] * v[1] - off[1] * v[0])) <= tolerance and abs(float(v[0] * slide.direction[1] - v[1] * slide.direction[0])) <= limit:
            fits.append((i, j))
    if not fits:
        angle = math.degrees(math.atan2(slide.direction[1], slide.direction[0]))
        raise SketchError(
            f"{slide.how} slides along the line through ({at[0]:.6g}, {at[1]:.6g}) m at {angle:.6g} deg, but no two "
            f"joints of {guide!r} lie on that line ({len(drawn)} joint(s), gap tolerance {tolerance:.3g} m): a slider's "
            f"line runs through two joints of its guide; put POINTs on the line in {guide!r}'s material (a link "
            "with POINTs takes its joints from its POINTs alone: put one at each of its pin holes too)"
        )
    on_line = sorted({k for pair in fits for k in pair}, key=lambda k: (k not in pinned, k))
    i = on_line[0]
    j = max((k for k in on_line if k != i), key=lambda k: (math.hypot(*(drawn[k] - drawn[i])), -k))
    return i, j


ACTUATOR_WORDS = ("cylinder", "actuator", "barrel", "rod")
"""A slider whose block or guide is on a layer with one of these words in its name is an actuator
(a hydraulic cylinder's rod in its barrel): the mechanism's input when no layer names a crank."""


def is_actuator(slide: Slide, layers: dict[str, str | None]) -> bool:
    """Whether ``slide``'s block or guide is on a layer (``layers`` by link name) named as an actuator."""
    names = [layers.get(name) or name for name in (slide.block, slide.on) if name is not None]
    return any(word in ACTUATOR_WORDS for name in names for word in re.findall(r"[a-z]+", name.casefold()))
