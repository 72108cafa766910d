"""Names a designer recognises for the places of a link: its pins, arms, junctions and bends.

A joint is named by Norton's letter in the first loop whose role uses it (crank O2 -> A, coupler
A -> B, output O4 -> B, ground O2 -> O4, a slider's pin B), prefixed by the loop's name where two
joints of one link would get the same letter ("second.A"), and by the links its pin joins ("A
(crank-coupler)", which tells the A of one loop from the A of another); a joint no loop uses is
"joint 2". A point of a link (member frame of its frame joints, the frame of its section
stresses and FEA peaks) is named, in this order, as:

- the pin hole at a joint ("pin hole A (crank-coupler)") or a hole no joint uses ("hole at (x, y) m
  of the drawing, no joint", its centre; "slot at ..." for one 1.5 times as long as wide), within
  ``HOLE_REACH - 1`` hole radii of its edge: ``HOLE_REACH`` radii of a round hole's centre (where
  validate looks for a hole's peak), and along a slot's whole rim (a slot's radius is half its width);
- on a member's section: "junction of arms O4-B and O4-C" (the station is within a section depth of
  another arm's axis), "inner fillet of arm O4-C" (an FEA value; a beam value is at the "inner edge of
  the bend") or "outer edge of the bend of arm O4-C" (the axis there turns tighter than
  ``BEND_DEPTHS`` section depths, on the concave or convex side), or "arm
  O4-C at 40 % of its length" (from its first joint), "beside pin hole O4" when the section is within
  a section depth of a pin (nominal), and "past O4, toward the free end" beyond an end joint;
- otherwise the nearest joint ("near joint 2").
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon

from linkstress.geometry.members import MemberCuts
from linkstress.geometry.profile import LinkProfile
from linkstress.report.cells import without_noise
from linkstress.scene import Scene

NORTON = {"crank": ("O2", "A"), "coupler": ("A", "B"), "output": ("O4", "B"), "ground": ("O2", "O4"), "slider": ("B", "B")}
"""Norton's letters of a role's axis joints (i, j)."""
HOLE_REACH = 2.0
"""A point within this many hole radii of a hole's centre is at that hole (its rim and a radius of
material around it: where a pin's stress raiser lies)."""
SLOT_ASPECT = 1.5
"""A hole this many times as long as it is wide is named a slot."""
BEND_DEPTHS = 10.0
"""An axis whose radius of curvature is under this many section depths bends: the curved-beam range."""
SECTION_SLACK = 0.05
"""Fraction of a section's depth by which a point may lie off its chord and still be on that section."""


@dataclass(frozen=True)
class JointName:
    """A joint's ``label`` ("A", "main.O4", "joint 2") and the ``links`` its pin joins (role order)."""

    label: str
    links: tuple[str, ...] = ()

    def words(self) -> str:
        """"A (crank-coupler)", or the bare label when no loop names its links."""
        return f"{self.label} ({'-'.join(self.links)})" if len(self.links) > 1 else self.label


def joint_names(scene: Scene) -> dict[str, tuple[JointName, ...]]:
    """Per link of ``scene``, the name of each of its joints (``JointName``)."""
    if scene.linkage is not None:
        return _linkage_joint_names(scene)
    pins = [(loop.name, letter, r.link, joint) for loop in scene.machine.loops for r, joint, letter in _lettered(loop)]
    joined: dict[tuple[str, str], list[str]] = {}
    for loop, letter, link, _ in pins:
        links = joined.setdefault((loop, letter), [])
        if link not in links:
            links.append(link)
    labels: dict[tuple[str, int], tuple[str, str]] = {}
    links_at: dict[tuple[str, int], list[str]] = {}
    for loop, letter, link, joint in pins:
        labels.setdefault((link, joint), (loop, letter))
        # every loop letter that names the joint counts: a rocker's pivot is O4 of one loop, O2 of the next
        here = links_at.setdefault((link, joint), [])
        here += [name for name in joined[(loop, letter)] if name not in here]
    names = {}
    for name, link in scene.links.items():
        found = [labels.get((name, j)) for j in range(len(link.joints))]
        letters = [f[1] for f in found if f is not None]
        names[name] = tuple(
            JointName(
                f"joint {j}" if f is None else f"{f[0]}.{f[1]}" if letters.count(f[1]) > 1 else f[1],
                tuple(links_at.get((name, j), ())),
            )
            for j, f in enumerate(found)
        )
    return names


def _lettered(loop):
    """(role, joint index, Norton letter) of each pin of ``loop``'s roles."""
    for role, r in loop.roles.items():
        letters = NORTON[role]
        if loop.kind == "slider-crank" and role == "ground":
            letters = letters[:1]  # its second joint marks the slider line's direction, not a pin
        for joint, letter in zip(r.joints, letters):
            yield r, joint, letter


@dataclass(frozen=True)
class MemberPlace:
    """One member of a link for naming: its ``joints`` (i, j), axis ``length`` [m] between them, and
    its section ``cuts`` (load frame)."""

    joints: tuple[int, int]
    length: float
    cuts: MemberCuts


@dataclass(frozen=True)
class LinkPlaces:
    """What names the places of one link: its ``joints`` (``JointName`` per joint), the pin holes'
    and other holes' centres (H, 2) [m, load frame] and sizes (H, 2) [m]
    (``LinkProfile.hole_sizes``) with the joint each is at (``hole_joints``, None for a hole no
    joint uses), its ``members``, the joint ``points`` (n, 2) [m, load frame], and ``to_drawing``
    taking load-frame points to the drawing's frame [m]."""

    joints: tuple[JointName, ...]
    hole_centres: NDArray[np.float64]
    hole_sizes: NDArray[np.float64]
    hole_joints: tuple[int | None, ...]
    hole_rings: tuple[NDArray[np.float64], ...]
    """Each hole's boundary (K, 2) [m, load frame]."""
    members: tuple[MemberPlace, ...]
    points: NDArray[np.float64]
    drawing_origin: NDArray[np.float64]
    drawing_rotation: NDArray[np.float64]

    def joint(self, j: int) -> str:
        return self.joints[j].label

    def pin_hole(self, j: int) -> str:
        """"pin hole A (crank-coupler)"."""
        return f"pin hole {self.joints[j].words()}"

    def arm(self, m: int) -> str:
        i, j = self.members[m].joints
        return f"arm {self.joint(i)}-{self.joint(j)}"

    def name(self, point: NDArray[np.float64], beam: bool = True) -> str:
        """The name of ``point`` (2,) [m, load frame] (see the module's docstring) where a ``beam``
        value is (on a section within a section depth of a pin: "beside pin hole X (nominal)"; on a
        bend's concave side "inner edge of the bend"), or else an FEA value ("inner fillet")."""
        p = np.asarray(point, float)
        hole = self._hole_at(p)
        if hole is not None:
            return hole
        found = self._section_at(p)
        if found is None:
            j = int(np.argmin(np.hypot(*(self.points - p).T)))
            return f"near joint {self.joint(j)}"
        m, k = found
        return self._on_member(p, m, k, beam)

    def _hole_at(self, p: NDArray[np.float64]) -> str | None:
        if not len(self.hole_rings):
            return None
        # Within (HOLE_REACH - 1) radii of a hole's edge: HOLE_REACH radii of a round hole's centre; a
        # slot's radius is half its width, so its rim is named from end to end.
        point = shapely.Point(p)
        radii = self.hole_sizes[:, 1] / 2
        reach = np.array([Polygon(ring).distance(point) for ring in self.hole_rings]) / radii
        h = int(np.argmin(reach))
        if reach[h] > HOLE_REACH - 1:
            return None
        joint = self.hole_joints[h]
        if joint is not None:
            return self.pin_hole(joint)
        centre = self.to_drawing(self.hole_centres[h])
        x, y = without_noise(centre, float(np.abs(centre).max()))
        length, width = self.hole_sizes[h]
        kind = "slot" if length >= SLOT_ASPECT * width else "hole"
        return f"{kind} at ({x:.4g}, {y:.4g}) m of the drawing, no joint"

    def to_drawing(self, p: NDArray[np.float64]) -> NDArray[np.float64]:
        """A load-frame point (2,) [m] in the drawing's frame [m]."""
        return self.drawing_origin + self.drawing_rotation @ p

    def _section_at(self, p: NDArray[np.float64]) -> tuple[int, int] | None:
        """(member, station) whose section holds ``p``: on each member, the cut line nearest to it among
        those whose chord (outline to outline) reaches it, within a station's spacing; of those, the
        member whose axis is nearest (a cut across one arm may run on through another); None when none."""
        best, found = np.inf, None
        for m, member in enumerate(self.members):
            cuts = member.cuts
            offset = p - cuts.origin
            along = np.abs(np.einsum("sd,sd->s", offset, cuts.tangent))
            across = np.einsum("sd,sd->s", offset, cuts.normal)
            bottom, top = cuts.table.bottom, cuts.table.top
            slack = SECTION_SLACK * (top - bottom)
            on_chord = (across >= bottom - slack) & (across <= top + slack)
            if not on_chord.any():
                continue
            # stations are the centres of equal cells (``Member.stations``); numpy's median would load numpy.ma
            spacing = float(np.ptp(cuts.s)) / (len(cuts.s) - 1) if len(cuts.s) > 1 else float(top[0] - bottom[0])
            k = int(np.flatnonzero(on_chord)[np.argmin(along[on_chord])])
            if along[k] <= spacing and abs(across[k]) < best:
                best, found = abs(across[k]), (m, k)
        return found

    def _on_member(self, p: NDArray[np.float64], m: int, k: int, beam: bool) -> str:
        member = self.members[m]
        cuts = member.cuts
        i, j = member.joints
        depth = float(cuts.table.top[k] - cuts.table.bottom[k])
        if cuts.junction[k]:
            other = self._nearest_other_arm(p, m)
            return f"junction of arms {self.joint(i)}-{self.joint(j)} and {other}" if other else f"junction at {self.arm(m)}"
        # the point's own arc length: its station's, plus its offset along the axis there
        s = float(cuts.s[k] + np.dot(p - cuts.origin[k], cuts.tangent[k]))
        if s < 0 or s > member.length:
            end = i if s < 0 else j
            return f"{self.arm(m)} past {self.joint(end)}, toward its free end"
        if beam and cuts.near_hole[k]:
            pin = self._nearest_pin(cuts.origin[k])
            if pin is not None:
                return f"{self.arm(m)} beside pin hole {self.joint(pin)} (nominal)"
        share = f"{self.arm(m)} at {100 * s / member.length:.0f} % of its length"
        curvature = float(cuts.curvature[k])
        if abs(curvature) * depth * BEND_DEPTHS > 1:
            side = float(np.dot(p - cuts.origin[k], cuts.normal[k])) * curvature
            inner = "inner edge of the bend of" if beam else "inner fillet of"
            return f"{inner} {share}" if side > 0 else f"outer edge of the bend of {share}"
        return share

    def _nearest_other_arm(self, p: NDArray[np.float64], m: int) -> str:
        best, name = np.inf, ""
        for n, other in enumerate(self.members):
            if n == m:
                continue
            gap = float(np.hypot(*(other.cuts.origin - p).T).min())
            if gap < best:
                i, j = other.joints
                best, name = gap, f"{self.joint(i)}-{self.joint(j)}"
        return name

    def _nearest_pin(self, point: NDArray[np.float64]) -> int | None:
        pins = [j for j in self.hole_joints if j is not None]
        if not pins:
            return None
        gaps = [float(np.hypot(*(self.points[j] - point))) for j in pins]
        return pins[int(np.argmin(gaps))]


def link_places(scene: Scene, name: str, members: Sequence[tuple[tuple[int, int], float, MemberCuts]],
                names: Mapping[str, tuple[JointName, ...]] | None = None) -> LinkPlaces:
    """The places of link ``name`` of ``scene`` (a profiled link), whose ``members`` are given as
    (joints, length [m], cuts in the load frame); ``names`` the scene's ``joint_names`` if known."""
    link = scene.links[name]
    return profile_places(link.profile, link.frame_joints, (names or joint_names(scene))[name], members)


def profile_places(profile: LinkProfile, frame_joints: tuple[int, int], joints: Sequence[JointName],
                   members: Sequence[tuple[tuple[int, int], float, MemberCuts]]) -> LinkPlaces:
    """The places of the link ``profile`` in the load frame of ``frame_joints``, its joints named
    ``joints``, its ``members`` given as (joints, length [m], cuts in that frame)."""
    frame = profile.frame(*frame_joints)
    centres, areas = profile.holes
    joints_at = {hole: j for j, hole in enumerate(profile.joint_holes) if hole is not None}
    rings = tuple(np.asarray(ring.coords) for ring in profile.local_outline(*frame_joints).interiors)
    return LinkPlaces(
        tuple(joints),
        frame.to_local(centres).reshape(-1, 2),
        profile.hole_sizes,
        tuple(joints_at.get(h) for h in range(len(areas))),
        rings,
        tuple(MemberPlace(tuple(pair), float(length), cuts) for pair, length, cuts in members),
        frame.to_local(profile.joints).reshape(-1, 2),
        np.asarray(frame.origin, float),
        frame.rotation,
    )


def _linkage_joint_names(scene: Scene) -> dict[str, tuple[JointName, ...]]:
    """A linkage's joints by their scene names ("crank:1"), each with the links its pin joins."""
    joined = {(j.link, j.index): tuple(dict.fromkeys(k.link for k in pin)) for pin in scene.linkage.all_pins for j in pin}
    return {
        name: tuple(JointName(f"{name}:{j}", joined.get((name, j), ())) for j in range(len(link.joints)))
        for name, link in scene.links.items()
    }


def _linkage_force_names(scene: Scene) -> dict[str, dict[str, str]]:
    """A linkage's force keys (``dynamics.linkage_forces``) by the links they act between: "pin
    crank:1-rod:0" is "crank on rod at crank:1"; "pin A:i-B:j-C:k on B:j" is "A, C on B at A:i";
    "slider crank:1 on lever" is "lever on its block at crank:1, across the line"."""
    graph = scene.linkage
    names = {}
    for pin in graph.all_pins:
        label = graph.pin_label(pin)
        if len(pin) == 2:
            names[label] = f"{pin[0].link} on {pin[1].link} at {pin[0]}"
            continue
        for j in pin[1:]:
            others = ", ".join(dict.fromkeys(k.link for k in pin if k.link != j.link))
            names[f"{label} on {j}"] = f"{others} on {j.link} at {pin[0]}"
    for s in graph.sliders:
        names[f"slider {s.point} on {s.on}"] = f"{s.on} on its block at {s.point}, across the line"
    return {graph.name: names}


def force_names(scene: Scene) -> dict[str, dict[str, str]]:
    """Per mechanism (loop), each joint force's name by the links it acts between and where: "F32"
    (the force of link 3 on link 2) is "coupler on crank at A" (Norton's numbering per loop: 1
    ground, 2 crank, 3 coupler, 4 output or slider); a linkage's by its pins and sliders."""
    if scene.linkage is not None:
        return _linkage_force_names(scene)
    names = joint_names(scene)
    out = {}
    for loop in scene.machine.loops:
        crank, coupler, ground = loop.crank, loop.coupler, loop.ground

        def at(role, end: int) -> str:
            return names[role.link][role.joints[end]].label

        forces = {
            "F12": f"{ground.link} on {crank.link} at {at(crank, 0)}",
            "F32": f"{coupler.link} on {crank.link} at {at(crank, 1)}",
        }
        if loop.output is not None:
            forces["F43"] = f"{loop.output.link} on {coupler.link} at {at(coupler, 1)}"
            forces["F14"] = f"{ground.link} on {loop.output.link} at {at(loop.output, 0)}"
        else:
            slider = loop.slider.link if loop.slider is not None else "the slider"
            forces["F43"] = f"{slider} on {coupler.link} at {at(coupler, 1)}"
            forces["F14"] = f"{ground.link} on {slider}, along its line"
        out[loop.name] = forces
    return out
