"""Mechanisms drawn assembled: links in place, each on its own layer, pinned where their pins meet.

A joint shared by links is a place where their pin centres (a POINT, or a circular hole's centre:
``ImportedLink.joints``) coincide within the sketch's gap tolerance, across layers. Links are the
nodes of a graph and joints its (hyper)edges; a four-bar is a cycle of four links and four distinct
joints through the ground:

- Ground: the link on a layer named ground, frame or base (any case); else, when the drawn links
  close a loop by themselves, the link common to every loop with the most joints (then the largest
  area); else the ground is not drawn, and the joints that only one link uses are its fixed pivots.
- Main loop: the one whose crank is the link on a layer named crank, input or driver; else the
  shortest link pivoted on the ground of any loop.
- Further loops: one that shares a single link with the loops found so far, where that link is
  their crank or output and pivots on the same ground joint, is ``driven_by`` it (a rigid drive).
- Slider-crank (``slider_assembly``): a crank pivoted on the ground, a rod, and a block with one pin.
  It is the main loop when no four-bar loop closes, else a further loop when its crank is a placed
  loop's crank or output on the same pivot.

Everything here is in metres, sketch frame = ground frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import SketchError
from linkstress.messages import capped
from linkstress.importers.pins import (
    ANGLE_DIGITS,
    BARE_GROUND,
    Joint,
    others,
    pin_distance,
    pins_of,
    shared_joints,
    users,
)
from linkstress.importers.sketch import ImportedLink, Sketch
from linkstress.importers.slider_assembly import (
    SliderChain,
    driven_sliders,
    pivot_ground,
    slider_chains,
    slider_loop,
)
from linkstress.kinematics.fourbar import FourBar
from linkstress.kinematics.linkage_class import feasible_input_ranges, slider_feasible_input_ranges
from linkstress.kinematics.machine import Drive, Loop, Role
from linkstress.kinematics.slider_crank import SliderCrank
from linkstress.kinematics.solve import solve_machine
from linkstress.scene.model import Scene

GROUND_NAMES = ("ground", "frame", "base")
CRANK_NAMES = ("crank", "input", "driver")


class NotLoops(SketchError):
    """The drawing is not four-bar loops and slider-cranks chained as linkstress chains them (no loop
    closes, a link is in none, the crank named is in none): it may still be a linkage of pins and
    sliders (``linkage_assembly``)."""


@dataclass(frozen=True)
class Assembly:
    """The mechanisms of a drawing.

    ``links``: the drawn links by name (the ground too when drawn); ``ground``: the ground's name;
    ``ground_joints`` (k, 2) [m]: the fixed pivots of a ground that is not drawn, else None;
    ``loops``: the loops, main first, roles' joints indexing each link's joints; ``input_angle_deg``:
    the main crank as drawn (from its pivot to its other joint, counter-clockwise from +x, to
    ``ANGLE_DIGITS`` decimals); ``sweep_deg``: (start, stop) [deg] of the main loop's input range
    about the drawn angle, one turn from it when the crank turns fully, else toggle to toggle;
    ``ground_rule`` and ``crank_rule``: how the ground and the crank were chosen, for the reader.
    """

    links: dict[str, ImportedLink]
    ground: str
    ground_joints: NDArray[np.float64] | None
    loops: tuple[Loop, ...]
    input_angle_deg: float
    sweep_deg: tuple[float, float]
    ground_rule: str
    crank_rule: str


    def summary(self) -> list[str]:
        """One line per loop, for the terminal: its links by role, its branch and how it is driven."""
        lines = []
        for loop in self.loops:
            roles = ", ".join(f"{name} {role.link!r}" for name, role in loop.roles.items())
            drive = f"driven by {loop.driven_by.loop}'s {loop.driven_by.role}" if loop.driven_by else (
                f"crank drawn at {self.input_angle_deg:.6g} deg")
            line = f"mechanism {loop.name}: {loop.kind}, {roles}; {loop.branch} branch; {drive}"
            if loop.kind == "slider-crank":
                line += (f"; slider line at {math.degrees(loop.slider_angle):.6g} deg, offset {loop.offset:.6g} m "
                         f"(along the slider's longer side, through its pin)")
            lines.append(line)
        return lines


@dataclass(frozen=True)
class _Cycle:
    """A four-bar loop through the ground: pivoted links ``p`` at joint ``jp`` and ``q`` at ``jq``,
    coupler ``k`` pinned to ``p`` at ``kp`` and to ``q`` at ``kq`` (joints by index into the list)."""

    p: str
    jp: int
    kp: int
    k: str
    kq: int
    q: str
    jq: int

    @property
    def moving(self) -> frozenset[str]:
        return frozenset((self.p, self.k, self.q))

    def reversed(self) -> "_Cycle":
        return _Cycle(self.q, self.jq, self.kq, self.k, self.kp, self.p, self.jp)


def find_assembly(sketch: Sketch) -> Assembly:
    """The mechanisms of ``sketch``, its links drawn in place; a SketchError that names the links and
    the joints found when no four-bar loop closes, or when some link is in none."""
    links = {link.name: link for link in sketch.links}
    joints = shared_joints(sketch.links, sketch.gap_tolerance_m)
    ground, ground_rule = find_ground(sketch, joints)
    if ground is None:
        joints = with_bare_ground(joints)
        ground_rule = "the ground is not drawn: its pivots are the joints that only one link uses"
    cycles = _cycles(joints, ground if ground is not None else BARE_GROUND)
    if not cycles:
        chains = slider_chains(joints, ground if ground is not None else BARE_GROUND, links)
        if not chains:
            raise NotLoops(f"no mechanism found: {what_joins(sketch, joints)}")
        return _slider_assembly(sketch, links, joints, chains, ground, ground_rule)
    crank, main, crank_rule = _main_cycle(cycles, joints, links)
    chosen = _chain(main, cycles)
    ground_name = ground if ground is not None else BARE_GROUND
    covered = set().union(*(c.moving for c, _ in chosen))
    sliders = driven_sliders(_grounded(chosen), slider_chains(joints, ground_name, links), covered)
    covered |= {name for chain, _ in sliders for name in (chain.k, chain.s)}
    left = [name for name in links if name not in covered and name != ground_name]
    if left:
        raise NotLoops(
            f"link(s) {capped(repr(n) for n in left)} are in no four-bar loop or slider-crank driven from "
            f"the main one ({what_joins(sketch, joints)}); linkstress chains loops through a shared crank "
            "or output pivoted on the ground: leave their layers out with --exclude-layers, or write the scene by hand"
        )
    bare = _bare_pivots(chosen, joints) if ground is None else None
    loops = tuple(_loop(k, cycle, drive, joints, ground_name, bare) for k, (cycle, drive) in enumerate(chosen))
    loops += tuple(
        slider_loop(f"loop{len(loops) + k + 1}", chain, joints, links, pivot_ground(chain, joints, links, ground_name, bare), drive)
        for k, (chain, drive) in enumerate(sliders)
    )
    main_crank = links[crank]
    o2, a = (main_crank.joints[i] for i in loops[0].crank.joints)
    # Rounded to 1e-9 deg, so that a crank drawn at 60 deg reads 60.0, not 59.999999999999986.
    angle = round(math.degrees(math.atan2(a[1] - o2[1], a[0] - o2[0])), ANGLE_DIGITS)
    ground_joints = None if bare is None else np.array([joints[j].at for j in bare])
    sweep = _sweep(chosen[0][0], joints, loops[0].branch, angle)
    return Assembly(links, ground_name, ground_joints, loops, angle, sweep, ground_rule, crank_rule)


def find_ground(sketch: Sketch, joints: list[Joint]) -> tuple[str | None, str]:
    """The drawn ground and why, or None when the drawing has no ground."""
    named = [link.name for link in sketch.links if is_named(link, GROUND_NAMES)]
    if len(named) > 1:
        raise SketchError(
            f"layers {capped(repr(n) for n in named)} are all named as a ground; keep one "
            f"layer named {' or '.join(GROUND_NAMES)}"
        )
    if named:
        return named[0], f"the link on layer {named[0]!r}"
    cycles = {name: _cycles(joints, name) for name in (link.name for link in sketch.links)}
    loops = [c.moving | {g} for g, found in cycles.items() for c in found]
    if not loops:
        return None, ""
    common = [link for link in sketch.links if all(link.name in loop for loop in loops)]
    if not common:
        return None, ""
    pick = max(common, key=lambda link: (len(link.joints), link.outline.area))
    return pick.name, (
        f"no layer is named {', '.join(GROUND_NAMES)}: the link in every loop with the most joints "
        "(then the largest area); rename its layer ground if this is wrong"
    )


def is_named(link: ImportedLink, names: tuple[str, ...]) -> bool:
    return any(text is not None and text.casefold() in names for text in (link.layer, link.name))


def with_bare_ground(joints: list[Joint]) -> list[Joint]:
    """The joints with the missing ground pinned at every joint that only one link uses."""
    return [Joint(j.at, j.ends + ((BARE_GROUND, -1),)) if len(j.ends) == 1 else j for j in joints]


def _cycles(joints: list[Joint], ground: str) -> list[_Cycle]:
    """Every four-bar loop through ``ground``: four distinct links, four distinct joints, each found once."""
    at = pins_of(joints)
    found: dict[tuple, _Cycle] = {}
    for jp in at.get(ground, []):
        for p in others(joints[jp], ground):
            for kp in at[p]:
                if kp == jp:
                    continue
                for k in others(joints[kp], ground, p):
                    for kq in at[k]:
                        if kq in (kp, jp):
                            continue
                        for q in others(joints[kq], ground, p, k):
                            for jq in at[q]:
                                if jq not in (jp, kp, kq) and ground in users(joints[jq]):
                                    cycle = _Cycle(p, jp, kp, k, kq, q, jq)
                                    key = min(_key(cycle), _key(cycle.reversed()))
                                    found.setdefault(key, cycle)
    return [found[key] for key in sorted(found)]


def _key(cycle: _Cycle) -> tuple:
    return (cycle.p, cycle.jp, cycle.kp, cycle.k, cycle.kq, cycle.q, cycle.jq)


def _main_cycle(cycles: list[_Cycle], joints: list[Joint], links: dict[str, ImportedLink]) -> tuple[str, _Cycle, str]:
    """The crank, the main loop oriented with the crank as ``p``, and why that crank."""
    named = [name for name, link in links.items() if is_named(link, CRANK_NAMES)]
    if named:
        crank = named[0]
        for cycle in cycles:
            for oriented in (cycle, cycle.reversed()):
                if oriented.p == crank:
                    return crank, oriented, f"the link on layer {crank!r}"
        raise NotLoops(
            f"link {crank!r} (on a layer named as the crank) is not pivoted on the ground in any four-bar loop; "
            "the crank turns about a fixed pivot"
        )
    options = [
        (pin_distance(joints, c.jp, c.kp), c.p, k, c)
        for k, cycle in enumerate(cycles) for c in (cycle, cycle.reversed())
    ]
    _, crank, _, main = min(options, key=lambda o: o[:3])
    return crank, main, (
        f"no layer is named {', '.join(CRANK_NAMES)}: the shortest link pivoted on the ground; rename its layer "
        "crank to choose another"
    )


def _chain(main: _Cycle, cycles: list[_Cycle]) -> list[tuple[_Cycle, Drive | None]]:
    """The main loop, then each loop driven rigidly by a placed loop's crank or output."""
    chosen: list[tuple[_Cycle, Drive | None]] = [(main, None)]
    grounded = {(main.p, main.jp): ("main", "crank"), (main.q, main.jq): ("main", "output")}
    covered = set(main.moving)
    growing = True
    while growing:
        growing = False
        for cycle in cycles:
            for oriented in (cycle, cycle.reversed()):
                if (oriented.p, oriented.jp) not in grounded or len(oriented.moving & covered) != 1:
                    continue
                loop, role = grounded[(oriented.p, oriented.jp)]
                name = f"loop{len(chosen) + 1}"
                chosen.append((oriented, Drive(loop, role)))
                grounded[(oriented.q, oriented.jq)] = (name, "output")
                covered |= oriented.moving
                growing = True
                break
    return chosen


def _grounded(chosen: list[tuple[_Cycle, Drive | None]]) -> dict[tuple[str, int], Drive]:
    """The placed loops' cranks and outputs, by link and ground pivot: what a further loop's crank
    can turn with."""
    grounded: dict[tuple[str, int], Drive] = {}
    for k, (cycle, _) in enumerate(chosen):
        name = "main" if k == 0 else f"loop{k + 1}"
        grounded.setdefault((cycle.p, cycle.jp), Drive(name, "crank"))
        grounded.setdefault((cycle.q, cycle.jq), Drive(name, "output"))
    return grounded


def _bare_pivots(chosen: list[tuple[_Cycle, Drive | None]], joints: list[Joint]) -> list[int]:
    """The undrawn ground's pivots (indices into ``joints``) in the order the loops use them."""
    return list(dict.fromkeys(j for cycle, _ in chosen for j in (cycle.jp, cycle.jq)))


def _loop(k: int, cycle: _Cycle, drive: Drive | None, joints: list[Joint], ground: str,
          bare: list[int] | None) -> Loop:
    """The cycle as a four-bar: crank p (O2 -> A), coupler k (A -> B), output q (O4 -> B), ground O2 -> O4,
    on the branch the drawing shows."""
    o2, a, b, o4 = (joints[j] for j in (cycle.jp, cycle.kp, cycle.kq, cycle.jq))
    name = "main" if k == 0 else f"loop{k + 1}"
    if bare is None:
        ground_joints = (o2.index(ground), o4.index(ground))
    else:
        ground_joints = (bare.index(cycle.jp), bare.index(cycle.jq))
    return Loop(
        name=name,
        kind="four-bar",
        crank=Role(cycle.p, (o2.index(cycle.p), a.index(cycle.p))),
        coupler=Role(cycle.k, (a.index(cycle.k), b.index(cycle.k))),
        output=Role(cycle.q, (o4.index(cycle.q), b.index(cycle.q))),
        ground=Role(ground, ground_joints),
        branch=_branch(name, a.at, b.at, o4.at, cycle),
        driven_by=drive,
    )


def _sweep(main: _Cycle, joints: list[Joint], branch: str, angle_deg: float) -> tuple[float, float]:
    """The main loop's input range [deg] that holds the drawn angle (linkage_class.feasible_input_ranges)."""
    o2, a, b, o4 = (joints[j].at for j in (main.jp, main.kp, main.kq, main.jq))
    lengths = (float(np.hypot(*(q - p))) for p, q in ((o2, a), (a, b), (o4, b)))
    return _range_holding(feasible_input_ranges(FourBar(tuple(o2), tuple(o4), *lengths, branch)), angle_deg)


def _range_holding(ranges: tuple[tuple[float, float], ...], angle_deg: float) -> tuple[float, float]:
    """Of the input ``ranges`` [rad], the one that holds ``angle_deg``, in degrees about it: one turn
    from it when the crank turns fully."""
    angle = math.radians(angle_deg)
    for start, stop in ranges:
        if stop - start >= 2 * math.pi - 1e-12:
            return angle_deg, angle_deg + 360.0
        turns = math.floor((angle - start) / (2 * math.pi))
        if start + 2 * math.pi * turns <= angle <= stop + 2 * math.pi * turns:
            return tuple(math.degrees(x + 2 * math.pi * turns) for x in (start, stop))
    return angle_deg, angle_deg


def _branch(name: str, a: NDArray[np.float64], b: NDArray[np.float64], o4: NDArray[np.float64], cycle: _Cycle) -> str:
    """The drawn branch in kinematics.fourbar's terms: ``open`` has B to the left of the directed line
    A -> O4 (sigma = +1), ``crossed`` to the right. B on that line is a toggle, which has no branch."""
    d, r = o4 - a, b - a
    cross = float(d[0] * r[1] - d[1] * r[0])
    if abs(cross) <= 1e-9 * float(np.hypot(*d)) * float(np.hypot(*r)):
        raise SketchError(
            f"mechanism {name}: the drawing is at a toggle (coupler {cycle.k!r} and output {cycle.q!r} in line at "
            f"B ({b[0]:.6g}, {b[1]:.6g}) m), where neither branch is drawn; draw the mechanism at another crank angle"
        )
    return "open" if cross > 0 else "crossed"


def _slider_assembly(sketch: Sketch, links: dict[str, ImportedLink], joints: list[Joint], chains: list[SliderChain],
                     ground: str | None, ground_rule: str) -> Assembly:
    """The drawing as one slider-crank (``chains`` from ``_slider_chains``): the crank named as one,
    else the shortest."""
    named = [c for c in chains if is_named(links[c.p], CRANK_NAMES)]
    if named:
        chain, crank_rule = named[0], f"the link on layer {named[0].p!r}"
    else:
        chain = min(chains, key=lambda c: (pin_distance(joints, c.jp, c.kp), c.p, c.k, c.s))
        crank_rule = (f"no layer is named {', '.join(CRANK_NAMES)}: the shortest link pivoted on the ground; rename "
                      "its layer crank to choose another")
    ground_name = ground if ground is not None else BARE_GROUND
    left = [name for name in links if name not in (chain.p, chain.k, chain.s, ground_name)]
    if left:
        raise NotLoops(
            f"link(s) {capped(repr(n) for n in left)} are not in the slider-crank {chain.p!r}, {chain.k!r}, {chain.s!r} "
            f"({what_joins(sketch, joints)}): leave their layers out with --exclude-layers, or write the scene by hand"
        )
    o2, a = joints[chain.jp], joints[chain.kp]
    if ground is None:
        # The undrawn ground has one pivot: its axis is given a second point, along the slider line.
        loop = slider_loop("main", chain, joints, links, Role(BARE_GROUND, (0, 1)))
        travel = pin_distance(joints, chain.jp, chain.kp) + pin_distance(joints, chain.kp, chain.kb)
        u = np.array([math.cos(loop.slider_angle), math.sin(loop.slider_angle)])
        ground_joints = np.array([o2.at, o2.at + travel * u])
        ground_rule = "the ground is not drawn: the crank's pivot, then a point along the slider line's direction"
    else:
        loop = slider_loop("main", chain, joints, links, pivot_ground(chain, joints, links, ground, None))
        ground_joints = None
    angle = round(math.degrees(math.atan2(*(a.at - o2.at)[::-1])), ANGLE_DIGITS)
    linkage = SliderCrank(tuple(o2.at), pin_distance(joints, chain.jp, chain.kp), pin_distance(joints, chain.kp, chain.kb),
                          loop.offset, loop.slider_angle, loop.branch)
    sweep = _range_holding(slider_feasible_input_ranges(linkage), angle)
    return Assembly(links, ground_name, ground_joints, (loop,), angle, sweep, ground_rule, crank_rule)


def what_joins(sketch: Sketch, joints: list[Joint]) -> str:
    """Which links share which joints, for a refusal."""
    shared = [j for j in joints if len({n for n, _ in j.ends if n != BARE_GROUND}) > 1]
    few = [f"{link.name!r} ({len(link.joints)})" for link in sketch.links if len(link.joints) < 2]
    hint = (
        f"; links with fewer than two joints: {capped(few)} (joints are POINTs, else the centres of round holes: "
        "a bore with a keyway or a flat gives none; a slider block has one)" if few else ""
    )
    names = capped(repr(link.name) for link in sketch.links)
    if not shared:
        return (
            f"no two of the links ({names}) share a joint: pin centres (POINTs or circular holes) of links "
            f"drawn in place must coincide within the gap tolerance {sketch.gap_tolerance_m:.3g} m{hint}"
        )
    pairs = capped((
        f"links {', '.join(repr(n) for n in dict.fromkeys(users(j)) if n != BARE_GROUND)} share the joint at "
        f"({j.at[0]:.6g}, {j.at[1]:.6g}) m" for j in shared
    ), separator="; ")
    return (
        f"{pairs}; no closed loop of four links and four joints through a ground (a layer named "
        f"{', '.join(GROUND_NAMES)}, or fixed pivots that one link alone uses), nor a slider-crank (a crank "
        f"pivoted on the ground, a rod, and a slider block with one pin){hint}"
    )


def check_pose(scene: Scene, tolerance: float, solved: str = "the loop solved at the drawn crank angle") -> None:
    """Refuse a scene whose kinematics at its (single) input does not put every drawn joint of every
    link back where it is drawn, within ``tolerance`` [m]: a wrong branch, or a drawing whose links
    do not close (lengths that fit no pose of the loop). ``solved`` names what was solved, for the
    message."""
    motion = solve_machine(scene.machine, scene.motion)
    if not motion.feasible[0]:
        raise SketchError(f"the mechanism as drawn does not assemble at the drawn input: {motion.reasons[0]}")
    for name, link in scene.links.items():
        moved, _, _ = motion.links[name].point(link.to_member(link.joints))
        miss = np.hypot(*(moved[0] - link.joints).T)
        k = int(np.argmax(miss))
        if miss[k] > tolerance:
            x, y = link.joints[k]
            sx, sy = moved[0, k]
            raise SketchError(
                f"link {name!r}, joint {k} drawn at ({x:.6g}, {y:.6g}) m: {solved} "
                f"puts it at ({sx:.6g}, {sy:.6g}) m, {miss[k]:.3g} m away (more than the gap tolerance "
                f"{tolerance:.3g} m); the links' pins do not meet in one pose of the mechanism: check the drawing"
            )
