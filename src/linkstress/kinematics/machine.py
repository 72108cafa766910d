"""A machine: loops (four-bar, slider-crank) chained by a power graph, as the scene defines it.

Each loop names, for each role, a link and the two of its joints that form the role's axis:
crank O2 -> A, coupler A -> B, output O4 -> B, ground O2 -> O4 (a slider-crank's ground gives O2
and, unless ``slider_angle`` is set, the slider line's direction), slider (B, B). Link joints are
as drawn [m]; a ground's joints are where the ground frame puts them.

One loop, the main loop, takes the machine's input motion at its crank. Every other loop is
``driven_by`` the crank or the output of another loop:

- rigid (``Drive.rigid``): its crank is the same link as the driver's role link (a bell crank or a
  crankshaft with several throws). The crank must start at that link's pivot, its angle is the
  driver's axis angle plus the angle between the two axes as drawn, and ``phase`` is 0.
- coupled: its crank is another link, turned by a coupling (belt, gears, a shaft with a key):
  its angle is the driver's axis angle plus ``phase``. Forces engines put an unknown torque between
  the two links.

Messages name scene keys (``mechanisms.NAME.ROLE``) because the scene is where a user fixes them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.fourbar import BRANCHES, FourBar
from linkstress.kinematics.linkage_class import feasible_input_ranges, slider_feasible_input_ranges
from linkstress.kinematics.slider_crank import SliderCrank

KINDS = ("four-bar", "slider-crank")
ROLE_ORDER = ("crank", "coupler", "output", "slider", "ground")
AXIS_NAMES = {"crank": "O2 -> A", "coupler": "A -> B", "output": "O4 -> B", "ground": "O2 -> O4"}
PIVOT_TOLERANCE = 1e-9
"""A rigid driven crank's O2 and its driver's pivot may differ by this fraction of the machine's size."""


@dataclass(frozen=True)
class Role:
    """Link ``link`` in a loop role, with ``joints`` (i, j): the role's axis from joint i to j
    (a slider's is (k, k): its joint B)."""

    link: str
    joints: tuple[int, int] = (0, 1)


@dataclass(frozen=True)
class Drive:
    """A driven loop's source: the ``role`` ("crank" or "output") of loop ``loop``; ``phase`` [rad]
    added to that axis angle for a coupled crank; ``rigid`` when the crank is that same link."""

    loop: str
    role: str
    phase: float = 0.0
    rigid: bool = False


@dataclass(frozen=True)
class Loop:
    """One loop of a machine. ``offset`` [m] and ``slider_angle`` [rad] (None: the ground's axis
    angle) apply to slider-cranks only."""

    name: str
    kind: str
    crank: Role
    coupler: Role
    ground: Role
    output: Role | None = None
    slider: Role | None = None
    branch: str = "open"
    offset: float = 0.0
    slider_angle: float | None = None
    driven_by: Drive | None = None

    @property
    def roles(self) -> dict[str, Role]:
        """Present roles in ``ROLE_ORDER``."""
        return {r: getattr(self, r) for r in ROLE_ORDER if getattr(self, r) is not None}


@dataclass(frozen=True)
class Machine:
    """Loops over links with drawn joints ``links[name]`` (n, 2) [m].

    On construction the loops are checked and put in solving order (``loops[0]`` is the main loop);
    ``drive.rigid`` is set from the link names. ``link_frames[name]`` is the axis (i, j) each link's
    motion is reported in: its first role in solving order.
    """

    links: Mapping[str, NDArray[np.float64]]
    loops: tuple[Loop, ...]
    link_frames: Mapping[str, tuple[int, int]] = field(init=False)

    def __post_init__(self) -> None:
        links = {}
        for name, joints in self.links.items():
            array = np.array(joints, float).reshape(-1, 2)
            array.setflags(write=False)
            links[name] = array
        object.__setattr__(self, "links", MappingProxyType(links))
        by_name = {}
        for loop in self.loops:
            if loop.name in by_name:
                raise LinkageError(f"mechanisms.{loop.name}: defined twice")
            by_name[loop.name] = loop
            self._check_roles(loop)
        ordered = tuple(_with_rigidity(loop, by_name) for loop in _solving_order(by_name))
        object.__setattr__(self, "loops", ordered)
        self._check_link_sharing()
        for loop in ordered[1:]:
            self._check_drive(loop)
        for loop in ordered:
            self._check_assembly(loop)
        frames: dict[str, tuple[int, int]] = {}
        for loop in ordered:
            for role in loop.roles.values():
                frames.setdefault(role.link, role.joints)
        object.__setattr__(self, "link_frames", MappingProxyType(frames))

    @property
    def main(self) -> Loop:
        return self.loops[0]

    def loop(self, name: str) -> Loop:
        for loop in self.loops:
            if loop.name == name:
                return loop
        raise KeyError(name)

    def used_joints(self, name: str) -> set[int]:
        """The joints of link ``name`` the loops use: the axis joints of every role it plays."""
        return {k for loop in self.loops for role in loop.roles.values() if role.link == name for k in role.joints}

    def axis(self, role: Role) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The drawn joints (2,), (2,) [m] at the two ends of ``role``'s axis."""
        joints = self.links[role.link]
        return joints[role.joints[0]], joints[role.joints[1]]

    def axis_length(self, role: Role) -> float:
        p, q = self.axis(role)
        return float(math.hypot(*(q - p)))

    def axis_angle(self, role: Role) -> float:
        """Angle [rad] of ``role``'s axis as drawn."""
        p, q = self.axis(role)
        return math.atan2(q[1] - p[1], q[0] - p[0])

    def geometry(self, loop: Loop) -> FourBar | SliderCrank:
        """The loop's closed-form linkage: lengths from the drawn joints, pivots from the ground."""
        o2, o4 = self.axis(loop.ground)
        if loop.kind == "four-bar":
            return FourBar(
                tuple(o2), tuple(o4), self.axis_length(loop.crank), self.axis_length(loop.coupler),
                self.axis_length(loop.output), loop.branch,
            )
        angle = self.axis_angle(loop.ground) if loop.slider_angle is None else loop.slider_angle
        return SliderCrank(
            tuple(o2), self.axis_length(loop.crank), self.axis_length(loop.coupler),
            loop.offset, angle, loop.branch,
        )

    def drive_offset(self, loop: Loop) -> float:
        """Angle [rad] added to the driver's axis angle to get ``loop``'s crank angle."""
        drive = loop.driven_by
        if drive is None:
            return 0.0
        if not drive.rigid:
            return drive.phase
        source = getattr(self.loop(drive.loop), drive.role)
        return self.axis_angle(loop.crank) - self.axis_angle(source)

    # -- checks ---------------------------------------------------------------------------------

    def _check_roles(self, loop: Loop) -> None:
        where = f"mechanisms.{loop.name}"
        if loop.kind not in KINDS:
            raise LinkageError(f"{where}.type: must be 'four-bar' or 'slider-crank', got {loop.kind!r}")
        if loop.branch not in BRANCHES:
            raise LinkageError(f"{where}.branch: must be 'open' or 'crossed', got {loop.branch!r}")
        if loop.kind == "four-bar" and loop.output is None:
            raise LinkageError(f"{where}.output: a four-bar needs an output link (O4 -> B)")
        if loop.kind == "four-bar" and loop.slider is not None:
            raise LinkageError(f"{where}.slider: a four-bar has no slider; use type = \"slider-crank\"")
        if loop.kind == "slider-crank" and loop.output is not None:
            raise LinkageError(f"{where}.output: a slider-crank has no output link; name its slider with slider = ...")
        seen: dict[str, str] = {}
        for role_name, role in loop.roles.items():
            self._check_role(f"{where}.{role_name}", role_name, role)
            if role.link in seen:
                raise LinkageError(
                    f"{where}: link {role.link!r} is both {seen[role.link]} and {role_name}; each role needs its own link"
                )
            seen[role.link] = role_name

    def _check_role(self, where: str, role_name: str, role: Role) -> None:
        if role.link not in self.links:
            raise LinkageError(
                f"{where}: no link named {role.link!r}; links are: {', '.join(sorted(self.links))}"
            )
        joints = self.links[role.link]
        needed = 1 if role_name == "slider" else 2
        if len(joints) < needed:
            raise LinkageError(
                f"{where}: link {role.link!r} has {len(joints)} joint(s); a {role_name} needs two "
                f"({AXIS_NAMES[role_name]}): give links.{role.link} at least two joints"
            )
        for k in role.joints:
            if not 0 <= k < len(joints):
                raise LinkageError(
                    f"{where}.joints: link {role.link!r} has joints 0..{len(joints) - 1}, no joint {k}"
                )
        i, j = role.joints
        if role_name == "slider":
            if i != j:
                raise LinkageError(f"{where}.joints: a slider has one joint B; give joints = [k]")
            return
        if np.array_equal(joints[i], joints[j]):
            raise LinkageError(
                f"{where}: joints {i} and {j} of link {role.link!r} coincide at "
                f"({joints[i][0]:.6g}, {joints[i][1]:.6g}) m; the {role_name} axis needs two distinct joints"
            )

    def _check_link_sharing(self) -> None:
        grounds: dict[str, str] = {}
        moving: dict[str, str] = {}
        for loop in self.loops:
            for role_name, role in loop.roles.items():
                label = f"the {role_name} of mechanisms.{loop.name}"
                if role_name == "ground":
                    grounds.setdefault(role.link, label)
                    continue
                rigid_crank = role_name == "crank" and loop.driven_by is not None and loop.driven_by.rigid
                if role.link in moving and not rigid_crank:
                    raise LinkageError(
                        f"mechanisms.{loop.name}.{role_name}: link {role.link!r} is already {moving[role.link]}; "
                        "a moving link belongs to one loop (a driven crank may be its driver's crank or output)"
                    )
                moving.setdefault(role.link, label)
        both = sorted(grounds.keys() & moving.keys())
        if both:
            name = both[0]
            raise LinkageError(
                f"link {name!r} is {grounds[name]} and {moving[name]}; the ground cannot move: use two links"
            )

    def _check_drive(self, loop: Loop) -> None:
        drive = loop.driven_by
        where = f"mechanisms.{loop.name}"
        if not drive.rigid:
            return
        if drive.phase != 0.0:
            raise LinkageError(
                f"{where}.phase_deg: the crank is link {loop.crank.link!r}, the same link as "
                f"{drive.loop}.{drive.role}, so its angle follows from the drawing; remove phase_deg "
                "or make the crank a separate link"
            )
        driver = self.loop(drive.loop)
        source = getattr(driver, drive.role)
        if loop.crank.joints[0] != source.joints[0]:
            raise LinkageError(
                f"{where}.crank.joints: link {loop.crank.link!r} turns about its joint {source.joints[0]} "
                f"(its pivot in mechanisms.{driver.name}); the crank must start there: "
                f"joints = [{source.joints[0]}, ...]"
            )
        pivot = self.axis(driver.ground)[0 if drive.role == "crank" else 1]
        o2 = self.axis(loop.ground)[0]
        size = max(float(np.ptp(np.vstack(list(self.links.values())), axis=0).max()), 1e-300)
        if math.hypot(*(o2 - pivot)) > PIVOT_TOLERANCE * size:
            raise LinkageError(
                f"{where}.ground: O2 at ({o2[0]:.6g}, {o2[1]:.6g}) m must be the pivot of link "
                f"{loop.crank.link!r} at ({pivot[0]:.6g}, {pivot[1]:.6g}) m, since the crank is that link"
            )

    def _check_assembly(self, loop: Loop) -> None:
        linkage = self.geometry(loop)
        if isinstance(linkage, FourBar):
            if not feasible_input_ranges(linkage):
                a, b, c, d = linkage.lengths
                raise LinkageError(
                    f"mechanisms.{loop.name}: these lengths can never assemble (crank {a:.6g} m, coupler "
                    f"{b:.6g} m, output {c:.6g} m, ground {d:.6g} m): each link must be shorter than the "
                    "sum of the other three"
                )
        elif not slider_feasible_input_ranges(linkage):
            raise LinkageError(
                f"mechanisms.{loop.name}: these lengths can never assemble (crank {linkage.crank:.6g} m, "
                f"rod {linkage.rod:.6g} m, offset {linkage.offset:.6g} m): the rod must be longer "
                "than |offset| - crank"
            )


def _solving_order(loops: dict[str, Loop]) -> list[Loop]:
    """Loops with each driver before the loops it drives; exactly one loop is undriven."""
    for loop in loops.values():
        drive = loop.driven_by
        if drive is None:
            continue
        where = f"mechanisms.{loop.name}.driven_by"
        if drive.loop not in loops:
            raise LinkageError(
                f"{where}: no mechanism named {drive.loop!r}; mechanisms are: {', '.join(sorted(loops))}"
            )
        if drive.role not in ("crank", "output"):
            raise LinkageError(f"{where}: a loop is driven by another's crank or output, got {drive.role!r}")
        if drive.loop == loop.name:
            raise LinkageError(f"{where}: a loop cannot drive itself")
        if drive.role == "output" and loops[drive.loop].kind == "slider-crank":
            raise LinkageError(
                f"{where}: mechanisms.{drive.loop} is a slider-crank: its slider translates and cannot turn "
                "a crank; drive this loop by a crank instead"
            )
    roots = [name for name, loop in loops.items() if loop.driven_by is None]
    if len(roots) > 1:
        raise LinkageError(
            f"mechanisms: {', '.join(roots)} all lack driven_by; only the main loop takes the motion's "
            f"input: give the others driven_by = \"{roots[0]}.crank\" (or .output)"
        )
    for name in loops:
        chain = [name]
        while loops[chain[-1]].driven_by is not None:
            chain.append(loops[chain[-1]].driven_by.loop)
            if chain[-1] in chain[:-1]:
                cycle = " -> ".join(chain[chain.index(chain[-1]):])
                raise LinkageError(
                    f"mechanisms.{name}.driven_by: the drives form a cycle ({cycle}); "
                    "exactly one loop must take the motion's input, without driven_by"
                )
    ordered: list[Loop] = []
    pending = [loops[roots[0]]]
    while pending:
        loop = pending.pop(0)
        ordered.append(loop)
        pending += [other for other in loops.values()
                    if other.driven_by is not None and other.driven_by.loop == loop.name]
    return ordered


def _with_rigidity(loop: Loop, loops: dict[str, Loop]) -> Loop:
    drive = loop.driven_by
    if drive is None:
        return loop
    source = getattr(loops[drive.loop], drive.role)
    rigid = source.link == loop.crank.link
    if rigid == drive.rigid:
        return loop
    return replace(loop, driven_by=replace(drive, rigid=rigid))
