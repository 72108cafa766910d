"""The joint graph of a one-DOF planar linkage: links, pins, sliders, the ground and the input.

A link is its joints as drawn (n, 2) [m], every link in place: the drawing is one assembled pose.
``"LINK:i"`` names joint i of a link. A pin joins two or more joints of different links at one
point. A slider holds a link's joint (its ``point``) on the line through joints ``line`` = (i, j)
of link ``on``; its optional ``block`` is a link pinned to the point at the block's joint 0 that
slides on that line and turns with ``on``. The input turns link ``link`` about its joint ``pivot``
(pinned to the ground; the input angle is the direction ``pivot`` -> ``to``), or drives the stroke
of slider ``slider`` along its line.

Checks, each naming the scene key (``mechanisms.NAME.KEY``) that holds the culprit:

- every name and joint index exists; no joint is named twice (a block's joint 0 is named by its
  slider); a pin joins joints of different links; a slider's line has two distinct joints;
- Gruebler-Kutzbach: F = 3 (n - 1) - 2 j1 - j2 = 1, with n the links (blocks included), a pin of k
  links k - 1 full joints, a slider with a block a pin and a full sliding joint, one without a
  half joint (Uicker, Pennock & Shigley, Theory of Machines and Mechanisms, sec. 1.10);
- every link is connected to the ground;
- the joints as given close every pin and slider within ``CLOSURE_TOLERANCE`` of the drawing's size.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.errors import LinkageError

CLOSURE_TOLERANCE = 1e-4
"""Joints a pin joins (or a slider's point and its line) may be this fraction of the drawing's size
apart: the gap tolerance with which ``import`` finds pins on a drawing."""
BRANCHES = ("as-drawn",)


@dataclass(frozen=True, order=True)
class Joint:
    """Joint ``index`` (0-based, in the link's joint order) of link ``link``: "LINK:i"."""

    link: str
    index: int

    def __str__(self) -> str:
        return f"{self.link}:{self.index}"


@dataclass(frozen=True)
class Slider:
    """``point`` held on the line through joints ``line`` (i, j) of link ``on``; ``block`` (or None:
    massless) pinned to the point at its joint 0, sliding on that line and turning with ``on``."""

    point: Joint
    on: str
    line: tuple[int, int]
    block: str | None = None


@dataclass(frozen=True)
class Input:
    """A crank (``link`` turning about its joint ``pivot``; the angle is the direction ``pivot`` ->
    ``to``) or a slider's stroke (``slider``: the index of the slider whose stroke is driven)."""

    link: str | None = None
    pivot: int = 0
    to: int = 1
    slider: int | None = None

    @property
    def is_stroke(self) -> bool:
        return self.slider is not None


@dataclass(frozen=True)
class LinkageGraph:
    """A checked linkage. ``links[name]`` (n, 2) [m] as drawn; ``pins`` as given, ``all_pins`` with
    each block's pin merged in (the block's joint 0 joins its slider's point). ``frames[name]`` is
    the link's member frame: (0, 1), or (0, 0) for a one-joint link (origin at its joint, +x along
    its slider's line, or the ground frame's +x for a one-joint ground); ``drawn_angles[name]`` that
    frame's angle [rad] as drawn; ``local[name]`` (n, 2) [m] its joints in that frame."""

    name: str
    links: Mapping[str, NDArray[np.float64]]
    ground: str
    pins: tuple[tuple[Joint, ...], ...]
    sliders: tuple[Slider, ...]
    input: Input
    branch: str = "as-drawn"
    all_pins: tuple[tuple[Joint, ...], ...] = field(init=False)
    frames: Mapping[str, tuple[int, int]] = field(init=False)
    drawn_angles: Mapping[str, float] = field(init=False)
    local: Mapping[str, NDArray[np.float64]] = field(init=False)

    def __post_init__(self) -> None:
        links = {}
        for name, joints in self.links.items():
            array = np.array(joints, float).reshape(-1, 2)
            array.setflags(write=False)
            links[name] = array
        object.__setattr__(self, "links", MappingProxyType(links))
        self._check_names()
        object.__setattr__(self, "all_pins", self._merged_pins())
        self._check_joints_once()
        self._check_connected()
        frames, angles, local = self._frames()
        object.__setattr__(self, "frames", MappingProxyType(frames))
        object.__setattr__(self, "drawn_angles", MappingProxyType(angles))
        object.__setattr__(self, "local", MappingProxyType(local))
        self._check_closure()
        self._check_mobility()

    # -- what other stages read ---------------------------------------------------------------

    @property
    def key(self) -> str:
        return f"mechanisms.{self.name}"

    @cached_property
    def groups(self):
        """The input and the groups in solving order (``groups.decompose``)."""
        from linkstress.kinematics.linkage.groups import decompose

        return decompose(self)

    @property
    def link_frames(self) -> Mapping[str, tuple[int, int]]:
        """``frames``, under the name a loop machine gives them."""
        return self.frames

    @property
    def loops(self) -> tuple:
        """A linkage has no four-bar or slider-crank loops: code that walks a machine's loops skips it."""
        return ()

    def used_joints(self, name: str) -> set[int]:
        """The joints of link ``name`` the linkage uses: its pins, its slider points, the lines it
        guides and the input's pivot and direction."""
        used = {j.index for pin in self.all_pins for j in pin if j.link == name}
        used |= {s.point.index for s in self.sliders if s.point.link == name}
        used |= {k for s in self.sliders if s.on == name for k in s.line}
        if self.input.link == name:
            used |= {self.input.pivot, self.input.to}
        return used

    @property
    def blocks(self) -> dict[str, int]:
        """Block link name -> the index of its slider."""
        return {s.block: k for k, s in enumerate(self.sliders) if s.block is not None}

    @property
    def moving(self) -> tuple[str, ...]:
        """Every link but the ground, in the scene's order."""
        return tuple(name for name in self.links if name != self.ground)

    @property
    def size(self) -> float:
        """The drawing's size [m]: the largest extent of all joints (at least 1e-300)."""
        points = np.vstack(list(self.links.values()))
        return max(float(np.ptp(points, axis=0).max()), 1e-300)

    def drawn(self, joint: Joint) -> NDArray[np.float64]:
        """Where ``joint`` is drawn (2,) [m]."""
        return self.links[joint.link][joint.index]

    def line_direction(self, slider: Slider) -> NDArray[np.float64]:
        """Unit direction (2,) of the slider's line as drawn, from its joint i toward j."""
        i, j = slider.line
        d = self.links[slider.on][j] - self.links[slider.on][i]
        return d / math.hypot(*d)

    def drawn_stroke(self, slider: Slider) -> float:
        """The slider's stroke as drawn [m]: its point's distance along the line from joint i, + toward j."""
        origin = self.links[slider.on][slider.line[0]]
        return float(self.line_direction(slider) @ (self.drawn(slider.point) - origin))

    def pin_label(self, pin: tuple[Joint, ...]) -> str:
        """"pin crank:1-rod:0": the joints a pin joins, as the report lists them."""
        return "pin " + "-".join(str(j) for j in pin)

    def gruebler(self) -> tuple[int, int, int, int]:
        """(F, n, j1, j2): degrees of freedom by Gruebler-Kutzbach, links, full and half joints."""
        n = len(self.links)
        j1 = sum(len(pin) - 1 for pin in self.all_pins) + sum(1 for s in self.sliders if s.block is not None)
        j2 = sum(1 for s in self.sliders if s.block is None)
        return 3 * (n - 1) - 2 * j1 - j2, n, j1, j2

    # -- checks -------------------------------------------------------------------------------

    def _check_names(self) -> None:
        key = self.key
        if self.ground not in self.links:
            raise LinkageError(f"{key}.ground: no link named {self.ground!r}; links are: {', '.join(self.links)}")
        if len(self.links[self.ground]) == 0:
            raise LinkageError(f"{key}.ground: link {self.ground!r} has no joints; the ground's joints are its pivots")
        for k, pin in enumerate(self.pins):
            where = f"{key}.pins[{k}]"
            if len(pin) < 2:
                raise LinkageError(f"{where}: a pin joins two or more joints, e.g. [\"crank:1\", \"rod:0\"]")
            for joint in pin:
                self._check_joint(where, joint)
            seen: dict[str, Joint] = {}
            for joint in pin:
                if joint.link in seen:
                    raise LinkageError(
                        f"{where}: joints {seen[joint.link]} and {joint} are of one link; a pin joins joints of "
                        "different links"
                    )
                seen[joint.link] = joint
        blocks: dict[str, int] = {}
        for k, slider in enumerate(self.sliders):
            where = f"{key}.sliders[{k}]"
            self._check_joint(f"{where}.point", slider.point)
            if slider.on not in self.links:
                raise LinkageError(f"{where}.on: no link named {slider.on!r}; links are: {', '.join(self.links)}")
            if slider.on == slider.point.link:
                raise LinkageError(f"{where}: the point {slider.point} is on link {slider.on!r} itself; a slider's "
                                   "point is a joint of another link")
            joints = self.links[slider.on]
            i, j = slider.line
            for index in (i, j):
                if not 0 <= index < len(joints):
                    raise LinkageError(f"{where}.line: link {slider.on!r} has joints 0..{len(joints) - 1}, no joint {index}")
            if i == j or np.array_equal(joints[i], joints[j]):
                raise LinkageError(f"{where}.line: joints {i} and {j} of link {slider.on!r} do not make a line; "
                                   "give two joints drawn apart")
            if slider.block is None:
                continue
            if slider.block not in self.links:
                raise LinkageError(f"{where}.block: no link named {slider.block!r}; links are: {', '.join(self.links)}")
            if slider.block in (self.ground, slider.on, slider.point.link):
                raise LinkageError(f"{where}.block: link {slider.block!r} is the ground, the guide or the point's "
                                   "link; a block is a link of its own")
            if slider.block in blocks:
                raise LinkageError(f"{where}.block: link {slider.block!r} is already the block of sliders[{blocks[slider.block]}]")
            blocks[slider.block] = k
        self._check_input()

    def _check_input(self) -> None:
        where = f"{self.key}.input"
        if self.input.is_stroke:
            if not 0 <= self.input.slider < len(self.sliders):
                raise LinkageError(f"{where}.slider: the mechanism has sliders 0..{len(self.sliders) - 1}, "
                                   f"no slider {self.input.slider}")
            return
        link = self.input.link
        if link not in self.links:
            raise LinkageError(f"{where}.link: no link named {link!r}; links are: {', '.join(self.links)}")
        if link == self.ground:
            raise LinkageError(f"{where}.link: the ground does not turn; the input is a link pivoted on it")
        for key, index in (("pivot", self.input.pivot), ("to", self.input.to)):
            if not 0 <= index < len(self.links[link]):
                raise LinkageError(f"{where}.{key}: link {link!r} has joints 0..{len(self.links[link]) - 1}, no joint {index}")
        if self.input.pivot == self.input.to or np.array_equal(self.links[link][self.input.pivot], self.links[link][self.input.to]):
            raise LinkageError(f"{where}: joints {self.input.pivot} and {self.input.to} of link {link!r} give no "
                               "direction; the input angle is the direction pivot -> to")

    def _check_joint(self, where: str, joint: Joint) -> None:
        if joint.link not in self.links:
            raise LinkageError(f"{where}: no link named {joint.link!r} (in {str(joint)!r}); links are: {', '.join(self.links)}")
        count = len(self.links[joint.link])
        if not 0 <= joint.index < count:
            raise LinkageError(f"{where}: link {joint.link!r} has joints 0..{count - 1}, no joint {joint.index} (in {str(joint)!r})")

    def _merged_pins(self) -> tuple[tuple[Joint, ...], ...]:
        """The pins with each block's joint 0 joined to its slider's point."""
        pins = [list(pin) for pin in self.pins]
        for k, slider in enumerate(self.sliders):
            if slider.block is None:
                continue
            block_joint = Joint(slider.block, 0)
            for pin in pins:
                if block_joint in pin:
                    raise LinkageError(
                        f"{self.key}.pins: joint {block_joint} is the block of sliders[{k}], pinned to its point "
                        f"{slider.point} already; leave it out of pins"
                    )
            holder = next((pin for pin in pins if slider.point in pin), None)
            if holder is None:
                pins.append([slider.point, block_joint])
            else:
                holder.append(block_joint)
        return tuple(tuple(pin) for pin in pins)

    def _check_joints_once(self) -> None:
        seen: dict[Joint, int] = {}
        for k, pin in enumerate(self.pins):
            for joint in pin:
                if joint in seen:
                    raise LinkageError(
                        f"{self.key}.pins[{k}]: joint {joint} is named twice (also in pins[{seen[joint]}]); "
                        "a joint is in one pin: list every joint at that point in one pin"
                    )
                seen[joint] = k

    def _check_connected(self) -> None:
        neighbours: dict[str, set[str]] = {name: set() for name in self.links}
        for pin in self.all_pins:
            for a in pin:
                neighbours[a.link] |= {b.link for b in pin if b.link != a.link}
        for s in self.sliders:
            neighbours[s.point.link].add(s.on)
            neighbours[s.on].add(s.point.link)
        reached, todo = {self.ground}, [self.ground]
        while todo:
            for other in neighbours[todo.pop()] - reached:
                reached.add(other)
                todo.append(other)
        apart = [name for name in self.links if name not in reached]
        if apart:
            raise LinkageError(
                f"{self.key}: link(s) {', '.join(apart)} are not connected to the ground {self.ground!r} through "
                "pins or sliders; pin them to the mechanism or remove them"
            )

    def _frames(self):
        frames, angles, local = {}, {}, {}
        line_of = {s.block: s for s in self.sliders if s.block is not None}
        for name, joints in self.links.items():
            if len(joints) >= 2:
                frames[name] = (0, 1)
                d = joints[1] - joints[0]
                if not np.any(d):
                    raise LinkageError(
                        f"links.{name}.joints: joints 0 and 1 coincide at ({joints[0][0]:.6g}, {joints[0][1]:.6g}) m; "
                        "a link's member frame runs from its joint 0 to its joint 1: draw them apart"
                    )
                angle = math.atan2(d[1], d[0])
            else:
                frames[name] = (0, 0)
                angle = 0.0
                if name in line_of:
                    u = self.line_direction(line_of[name])
                    angle = math.atan2(u[1], u[0])
            angles[name] = angle
            c, s = math.cos(angle), math.sin(angle)
            p = joints - joints[0]
            array = np.column_stack([c * p[:, 0] + s * p[:, 1], -s * p[:, 0] + c * p[:, 1]])
            array.setflags(write=False)
            local[name] = array
        return frames, angles, local

    def _check_closure(self) -> None:
        tolerance = CLOSURE_TOLERANCE * self.size
        for pin in self.all_pins:
            first = self.drawn(pin[0])
            for joint in pin[1:]:
                gap = float(math.hypot(*(self.drawn(joint) - first)))
                if gap > tolerance:
                    raise LinkageError(
                        f"{self.key}.pins: {self.pin_label(pin)} does not close as drawn: {pin[0]} at "
                        f"({first[0]:.6g}, {first[1]:.6g}) m and {joint} at ({self.drawn(joint)[0]:.6g}, "
                        f"{self.drawn(joint)[1]:.6g}) m are {gap:.3g} m apart (tolerance {tolerance:.3g} m); draw the "
                        "links assembled, the joints a pin joins at one point"
                    )
        for k, slider in enumerate(self.sliders):
            u = self.line_direction(slider)
            offset = self.drawn(slider.point) - self.links[slider.on][slider.line[0]]
            gap = abs(float(offset[0] * u[1] - offset[1] * u[0]))
            if gap > tolerance:
                raise LinkageError(
                    f"{self.key}.sliders[{k}]: the point {slider.point} is drawn {gap:.3g} m off the line through "
                    f"joints {slider.line[0]} and {slider.line[1]} of {slider.on!r} (tolerance {tolerance:.3g} m); "
                    "draw the point on its line"
                )

    def _check_mobility(self) -> None:
        from linkstress.kinematics.linkage.groups import mobility_problem

        dof, n, j1, j2 = self.gruebler()
        count = f"Gruebler: F = 3 (n - 1) - 2 j1 - j2 = 3 ({n} - 1) - 2 x {j1} - {j2} = {dof}"
        if dof == 1:
            problem = mobility_problem(self)
            if problem:
                raise LinkageError(f"{self.key}: {count}, yet {problem}")
            return
        detail = mobility_problem(self) or (
            "some links float" if dof > 1 else "some loop is locked (a structure)"
        )
        raise LinkageError(
            f"{self.key}: {count} degrees of freedom; one input needs exactly 1: {detail}"
        )


def parse_joint(text: object, where: str) -> Joint:
    """A joint named "LINK:i" (i a whole number >= 0)."""
    if isinstance(text, str):
        link, sep, index = text.rpartition(":")
        if sep and link and index.isdigit():
            return Joint(link, int(index))
    raise LinkageError(f"{where}: must name a joint as \"LINK:i\" (i its 0-based index), got {text!r}")
