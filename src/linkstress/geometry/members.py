"""A link's members: the arms between its joints, their axes, and the sections cut across them.

A member (i, j) is the arm of material from joint i to joint j. A link's members are, unless its
scene names them, the edges of the tree that joins all its joints along the material
(``member_tree``): a bar has one, a bell crank two. Everything here is in the load frame: the
member frame of the link's frame joints (``LinkLoadCase.frame_joints``).

Axis. A member's axis is the straight line through its joints, or, where the material between them
curves (a banana, an arc, a U), the material's centreline (``linkstress.geometry.centreline``). Beyond a
joint that ends the tree (a leaf), the axis runs on straight to the outline (the free end); at a
joint shared with another member it stops. Stations are arc lengths s [m] along the axis, s = 0 at
joint i.

Sections. The cut at s is the line through the axis point c(s) along the normal n(s) (the tangent
t(s) turned +90 degrees). It meets the outline's filled shape (holes filled) in intervals; the
section is the interval through c (the material chord through the member axis, to the outline),
less the holes it crosses, with v [m] measured along n from c. The cut separates the link into two
pieces; the left one holds joint i. Where the cut line meets no other material, the left piece is
the half-plane (x - c).t <= 0 of the link, whose area moments come exactly from Green's theorem
in the cut's own frame (the cut adds nothing: dx = 0 along it); elsewhere (the cut line crosses
another arm) the outline is split along the section's segment.

Flags. A station is near a hole when a hole's centre lies closer to its cut segment than the
section's depth (St-Venant: a pin's load spreads into a beam-like stress state about one depth from
where it acts), at a junction when its axis point lies closer than the depth to another member's
axis, at a bend when it lies within its depth (along the axis) of a stretch of the centreline that
turns faster than the curved-beam range allows (``linkstress.geometry.bends``: a radius under a section
depth, a dog-leg's corner), and tight when a curved section nearly reaches its centre of curvature:
there the values are nominal.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import split

from linkstress.geometry.bends import near_bends, sharp_arcs
from linkstress.geometry.centreline import centreline, first_midline
from linkstress.geometry.curved_beam import centre_reach
from linkstress.errors import GeometryError
from linkstress.geometry.member_cuts import (
    CutLines, Edges, cut_lines, half_plane_moments, piece_moments, section_chords, segment_distance, through_axis,
    to_load_frame, vertical_lines,
)
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.region_moments import region_moments
from linkstress.geometry.sections import SectionTable, _table_from_chords

OUTSIDE_PENALTY = 100.0
"""Weight per metre of a joint-to-joint line that leaves the material, against 1 per metre inside:
the tree joins joints along the material (the two arms of an L, not its hypotenuse)."""


CURVATURE_REACH = 1.0
"""Half the span, in section depths, of the three centreline points whose circle gives the axis's
curvature at a station (exact on a circular arc; averages the outline's flattening elsewhere)."""


SPLIT_REACH = 1e-9
"""Fraction of the link's size by which a section's segment is run past the outline to split it."""


TIGHT = 0.1
"""A curved section whose material comes within this fraction of its radius of the centre of
curvature is no beam: its values are nominal (straight-beam), as near holes."""


NEAR_SLACK = 1e-9
"""A station exactly one depth from a pin (the midpoint of a bar as long as two depths) is not near it."""


def member_tree(
    link: LinkProfile, root: tuple[int, int] = (0, 1), joints: Sequence[int] | None = None,
) -> tuple[tuple[int, int], ...]:
    """The members of ``link``: the minimum spanning tree of its ``joints`` (default: all of them),
    each pair weighted by the length of the straight line between them plus ``OUTSIDE_PENALTY`` times
    its length outside the material, oriented away from joint ``root[0]`` (the member of ``root``, if
    in the tree, keeps its direction). Joints in holes count as in material."""
    n = len(link.joints)
    start = root[0] % n if n else 0
    # sorted by hand: np.unique imports numpy.ma, 10 ms of every analyze's start
    chosen = np.arange(n) if joints is None else np.array(sorted({int(k) % n for k in (*joints, start)}), dtype=int)
    m = len(chosen)
    if m < 2:
        return ()
    if m == 2:
        return ((start, int(chosen[chosen != start][0])),)
    points = link.joints[chosen]
    first, second = np.triu_indices(m, 1)
    lines = shapely.linestrings(np.stack([points[first], points[second]], axis=1))
    inside = shapely.length(shapely.intersection(lines, Polygon(link.outline.exterior)))
    length = shapely.length(lines)
    weight = np.zeros((m, m))
    weight[first, second] = weight[second, first] = length + OUTSIDE_PENALTY * (length - inside)
    home = int(np.flatnonzero(chosen == start)[0])
    joined, edges = [home], []
    best = weight[home].copy()
    parent = np.full(m, home)
    best[home] = np.inf
    for _ in range(m - 1):
        k = int(np.argmin(np.where(np.isin(np.arange(m), joined), np.inf, best)))
        edges.append((int(chosen[parent[k]]), int(chosen[k])))
        joined.append(k)
        closer = weight[k] < best
        parent[closer], best[closer] = k, weight[k][closer]
        best[joined] = np.inf
    # the member of the root pair first: it is the one along the load frame
    return tuple(sorted(edges, key=lambda edge: edge != (start, root[1] % n)))


def check_members(
    link: LinkProfile, members: ArrayLike, joints: Sequence[int] | None = None,
) -> tuple[tuple[int, int], ...]:
    """``members`` given by a scene as joint pairs, checked: each names two distinct joints of the link
    and together they join every one of ``joints`` (default: all the link's joints) and the joints
    they name, without a loop (a tree); else a GeometryError that says so."""
    n = len(link.joints)
    pairs = [tuple(int(v) for v in pair) for pair in np.asarray(members, dtype=int).reshape(-1, 2)]
    for i, j in pairs:
        if not (0 <= i < n and 0 <= j < n) or i == j:
            raise GeometryError(
                f"link {link.name!r}: member {[i, j]} must join two different joints among 0..{n - 1}"
            )
    group = list(range(n))

    def find(k: int) -> int:
        while group[k] != k:
            k = group[k]
        return k

    for i, j in pairs:
        a, b = find(i), find(j)
        if a == b:
            raise GeometryError(f"link {link.name!r}: members {pairs} close a loop at member {[i, j]}; give a tree")
        group[a] = b
    if joints is None:
        if len(pairs) != n - 1:
            raise GeometryError(
                f"link {link.name!r}: members {pairs} do not join all {n} joints; give {n - 1} pairs that join them all"
            )
        return tuple(pairs)
    needed = sorted({int(k) % n for k in joints} | {k for pair in pairs for k in pair})
    if len({find(k) for k in needed}) != 1:
        raise GeometryError(
            f"link {link.name!r}: members {pairs} do not join the joints {needed} that its mechanisms, loads and "
            f"members use; give {len(needed) - 1} pairs that join them all"
        )
    return tuple(pairs)


@dataclass(frozen=True)
class MemberCuts:
    """The sections of one member at stations s (S,) [m], load frame.

    ``origin`` (S, 2) [m]: the axis point; ``tangent`` (S, 2): the unit vector along the axis, and
    ``normal`` the one across it (tangent turned +90 degrees); ``curvature`` (S,) [1/m]: signed, > 0
    when the axis turns toward +normal; ``table``: the sections (x = s, chords in v [m] along the
    normal from ``origin``); ``near_hole``, ``junction`` and ``bend`` (S,): stations whose values are
    nominal (near a hole's centre, another member's axis, or a bend sharper than the curved-beam range);
    ``left_moments`` (4, S): A, int x dA, int y dA, int (x^2 + y^2) dA [per unit thickness, about the
    load frame's origin] of the left piece (the one that holds joint i); ``right_pieces``: the right
    piece's filled outline at the stations whose cut line crosses other material (elsewhere the
    pieces are the half-planes of the cut line)."""

    joints: tuple[int, int]
    origin: NDArray[np.float64]
    tangent: NDArray[np.float64]
    curvature: NDArray[np.float64]
    table: SectionTable
    near_hole: NDArray[np.bool_]
    junction: NDArray[np.bool_]
    bend: NDArray[np.bool_]
    left_moments: NDArray[np.float64]
    total_moments: NDArray[np.float64]
    right_pieces: dict[int, Polygon]

    @property
    def s(self) -> NDArray[np.float64]:
        return self.table.x

    @property
    def normal(self) -> NDArray[np.float64]:
        return np.column_stack([-self.tangent[:, 1], self.tangent[:, 0]])

    @property
    def tight(self) -> NDArray[np.bool_]:
        """(S,): sections that reach within ``TIGHT`` of their radius of their centre of curvature
        (the inside of a hook), where no beam theory holds."""
        return centre_reach(self.table, self.curvature) >= 1 - TIGHT

    @property
    def nominal(self) -> NDArray[np.bool_]:
        """(S,): stations near a hole, at a junction, at a sharp bend or ``tight``, where beam values
        are nominal."""
        return self.near_hole | self.junction | self.bend | self.tight

    @property
    def ends(self) -> NDArray[np.float64]:
        """(S, 2, 2) [m]: each section segment's ends, at v = bottom and v = top."""
        return np.stack([self.points(self.table.bottom), self.points(self.table.top)], axis=1)

    @property
    def cut_points(self) -> NDArray[np.float64]:
        """(S, 2) [m]: each section's centroid, the point its moment is taken about."""
        return self.points(self.table.neutral_axis)

    def points(self, v: ArrayLike) -> NDArray[np.float64]:
        """Points (..., S, 2) [m, load frame] at offsets ``v`` (..., S) [m] along each station's normal."""
        return self.origin + np.asarray(v, float)[..., None] * self.normal

    def on_left(self, points: ArrayLike) -> NDArray[np.bool_]:
        """(S, K): whether each of ``points`` (K, 2) [m, load frame] lies on the left piece of each cut;
        a point on the cut line counts as left, as a joint at a station always has."""
        p = np.asarray(points, float).reshape(-1, 2)
        along = np.einsum("skd,sd->sk", p[None, :, :] - self.origin[:, None, :], self.tangent)
        left = along <= 0
        for k, piece in self.right_pieces.items():
            left[k] = ~shapely.covers(piece, shapely.points(p)) | (along[k] == 0)
        return left


@dataclass(frozen=True)
class Member:
    """One arm of ``link`` from joint ``joints[0]`` (i) to ``joints[1]`` (j), load frame of
    ``frame_joints``: its axis ``path`` (K, 2) [m] through the joints, at arc lengths ``arc`` (K,) [m]
    (0 at joint i, ``length`` at joint j; straight on past the ends), and the stations' ``extent``
    (s_lo, s_hi) [m]. ``curved``: sectioned normal to its centreline, which strays ``wander`` section
    depths from the line through its joints; ``depth`` [m]: its smallest section depth between the
    joints; ``others``: the other members' axes (K, 2), for the junction flags."""

    link: LinkProfile
    joints: tuple[int, int]
    frame_joints: tuple[int, int]
    edges: Edges
    path: NDArray[np.float64]
    arc: NDArray[np.float64]
    extent: tuple[float, float]
    curved: bool
    wander: float
    depth: float
    others: tuple[NDArray[np.float64], ...] = ()

    @property
    def length(self) -> float:
        return float(self.arc[-1])

    def stations(self, count: int) -> NDArray[np.float64]:
        """``count`` stations [m]: the centres of equal cells over the member's extent (never on an end,
        where a rounded end's section shrinks to a point)."""
        lo, hi = self.extent
        return lo + (hi - lo) * (np.arange(count) + 0.5) / count

    def point_at(self, s: ArrayLike) -> NDArray[np.float64]:
        """Axis points (S, 2) [m] at arc lengths ``s`` [m], straight on past the path's ends."""
        s = np.asarray(s, float).ravel()
        k = np.clip(np.searchsorted(self.arc, s, side="right") - 1, 0, len(self.arc) - 2)
        step = self.path[k + 1] - self.path[k]
        return self.path[k] + ((s - self.arc[k]) / (self.arc[k + 1] - self.arc[k]))[:, None] * step

    def axis_at(self, s: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Axis points (S, 2) [m], unit tangents (S, 2) and signed curvatures (S,) [1/m] at arc
        lengths ``s`` [m]. A curved axis takes its tangent and curvature from the circle through its
        points at s - h, s and s + h, h = CURVATURE_REACH depths (within h of a joint, that circle's
        nearest inside; past the joints the axis is straight)."""
        s = np.asarray(s, float).ravel()
        origin = self.point_at(s)
        if not self.curved:
            d = self.path[-1] - self.path[0]
            return origin, np.broadcast_to(d / np.hypot(*d), origin.shape).copy(), np.zeros(len(s))
        h = min(CURVATURE_REACH * self.depth, self.length / 3)
        # the circles keep clear of the joints' lugs (a section depth, or a boss's radius), through
        # which the centreline runs straight to the pin
        first, last = (min(h + max(self.depth, lug), self.length / 2) for lug in self.lugs)
        centre = np.clip(s, first, self.length - last)
        # the path's own vertices (on the centreline) nearest to s - h, s, s + h: a chord's interpolated
        # points lie inside the arc by its sagitta
        a, b, c = (self.path[self._vertex(x)] for x in (centre - h, centre, centre + h))
        ab, ac = b - a, c - a
        cross = ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]
        size = np.hypot(*ab.T) * np.hypot(*(c - b).T) * np.hypot(*ac.T)
        bend = np.divide(2 * cross, size, out=np.zeros(len(s)), where=size > 0)
        curvature = np.where((s >= 0) & (s <= self.length), bend, 0.0)
        around = self.point_at(np.minimum(s + h / 2, self.length)) - self.point_at(np.maximum(s - h / 2, 0.0))
        tangent = around / np.hypot(*around.T)[:, None]
        before, after = s < 0, s > self.length
        tangent[before] = self._end_tangent(0)
        tangent[after] = self._end_tangent(-1)
        return origin, tangent, curvature

    def _vertex(self, s: NDArray[np.float64]) -> NDArray[np.intp]:
        """The index of the path vertex nearest to each arc length ``s``."""
        k = np.clip(np.searchsorted(self.arc, s), 1, len(self.arc) - 1)
        return np.where(s - self.arc[k - 1] < self.arc[k] - s, k - 1, k)

    def _end_tangent(self, end: int) -> NDArray[np.float64]:
        d = self.path[1] - self.path[0] if end == 0 else self.path[-1] - self.path[-2]
        return d / np.hypot(*d)

    @cached_property
    def lugs(self) -> tuple[float, float]:
        """The radii [m] of the lugs round joints i and j: how far each joint is from the outline's
        outer boundary (a boss's radius; half a bar's width at a joint on its midline)."""
        ring = self.edges.outline.exterior
        return tuple(float(ring.distance(Point(p))) for p in (self.path[0], self.path[-1]))

    @cached_property
    def sharp(self) -> NDArray[np.float64]:
        """Arc lengths [m] where a curved member's centreline turns faster than the curved-beam range
        allows (``linkstress.geometry.bends``), clear of the joints' lugs; none on a straight member."""
        if not self.curved:
            return np.zeros(0)
        clear = (max(self.lugs[0], self.depth / 2), self.length - max(self.lugs[1], self.depth / 2))
        return sharp_arcs(self.path, self.arc, self.depth, clear)

    @cached_property
    def end_depths(self) -> tuple[float, float]:
        """The section depths [m] through joints i and j (``depths``)."""
        first, last = self.depths([0.0, self.length])
        return float(first), float(last)

    def depths(self, stations: ArrayLike) -> NDArray[np.float64]:
        """The section depths [m] (outline to outline, across any hole) at ``stations`` (arc lengths
        [m]), without the rest of their sections."""
        s = np.clip(np.asarray(stations, float).ravel(), *self.extent)
        origin, tangent, _ = self.axis_at(s)
        lines = cut_lines(self.edges, origin, tangent) if self.curved else vertical_lines(self.link, self.joints, s)
        bottom, top, _ = through_axis(lines, len(s))
        return top - bottom

    def cuts(self, stations: ArrayLike) -> MemberCuts:
        """The sections at ``stations`` (arc lengths [m]), load frame."""
        s = np.asarray(stations, float).ravel()
        lo, hi = self.extent
        slack = 1e-9 * (hi - lo)
        bad = ~np.isfinite(s) | (s < lo - slack) | (s > hi + slack)
        if bad.any():
            raise GeometryError(
                f"link {self.link.name!r}, member {list(self.joints)}: station s = {float(s[bad][0])!r} m is "
                f"outside the member's extent [{lo:.6g}, {hi:.6g}] m"
            )
        origin, tangent, curvature = self.axis_at(np.clip(s, lo, hi))
        return _member_cuts(self, s, origin, tangent, curvature)


def _member_cuts(member: Member, s, origin, tangent, curvature) -> MemberCuts:
    edges, link = member.edges, member.link
    if member.curved:
        lines = cut_lines(edges, origin, tangent)
        left = half_plane_moments(edges, origin, tangent)
    else:
        lines, left = _straight_cuts(member, s, tangent)
    try:
        bottom, top, intervals = through_axis(lines, len(s))
    except GeometryError as error:
        raise GeometryError(f"link {link.name!r}, member {list(member.joints)}: {error}") from None
    station, a, b = section_chords(lines, bottom, top)
    table = _table_from_chords(s, link.thickness, station, a, b)
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    right_pieces = {}
    for k in np.flatnonzero(intervals > 1):
        piece = _right_piece(member, origin[k], tangent[k], normal[k], table, k)
        right_pieces[int(k)] = Polygon(piece.exterior)
        left[:, k] = edges.moments - piece_moments(piece)
    depth = table.top - table.bottom
    ends = np.stack([origin + bottom[:, None] * normal, origin + top[:, None] * normal], axis=1)
    near_hole = (segment_distance(edges.hole_centres, ends).T < depth[:, None] * (1 - NEAR_SLACK)).any(axis=1)
    junction = np.zeros(len(s), dtype=bool)
    for path in member.others:
        pieces = np.stack([path[:-1], path[1:]], axis=1)
        junction |= (segment_distance(origin, pieces) < depth[:, None] * (1 - NEAR_SLACK)).any(axis=1)
    bend = near_bends(s, depth, member.sharp)
    return MemberCuts(
        member.joints, origin, tangent, curvature, table, near_hole, junction, bend, left, edges.moments, right_pieces,
    )


def _straight_cuts(member: Member, s: NDArray[np.float64], tangent: NDArray[np.float64]) -> tuple[CutLines, NDArray[np.float64]]:
    """``cut_lines`` and ``half_plane_moments`` of a straight member's stations, by sorted sweeps of
    vertical cuts in its member frame (``vertical_lines``, ``linkstress.geometry.region_moments``)."""
    boundary = member.link.boundary(*member.joints)
    moments = region_moments(boundary, np.clip(s, boundary.x_min, boundary.x_max))
    local = np.array([moments.area, moments.first_x, moments.first_y, moments.polar])
    joint = np.broadcast_to(member.path[0], (len(s), 2))
    return vertical_lines(member.link, member.joints, s), to_load_frame(local, joint, tangent)


def _right_piece(member: Member, origin, tangent, normal, table: SectionTable, k: int) -> Polygon:
    """The piece of the outline beyond the section at station ``k`` (toward joint j): the outline split
    along the section's segment, the part just ahead of the section's widest chord."""
    reach = SPLIT_REACH * member.edges.size
    ends = [origin + (table.bottom[k] - reach) * normal, origin + (table.top[k] + reach) * normal]
    pieces = [g for g in split(member.edges.outline, LineString(ends)).geoms if isinstance(g, Polygon)]
    chords = table.chords(k)
    widest = chords[np.argmax(chords[:, 1] - chords[:, 0])]
    probe = Point(origin + widest.mean() * normal + 1e-6 * (widest[1] - widest[0]) * tangent)
    ahead = [p for p in pieces if p.covers(probe)]
    if len(pieces) < 2 or len(ahead) != 1:
        raise GeometryError(
            f"link {member.link.name!r}, member {list(member.joints)}: the section at s = {table.x[k]:.6g} m does "
            "not split the outline in two; name the link's members (links.NAME.members) or redraw the junction"
        )
    return ahead[0]


def link_members(
    link: LinkProfile, frame_joints: tuple[int, int], members: ArrayLike | None = None,
    used_joints: Sequence[int] | None = None,
) -> tuple[Member, ...]:
    """The members of ``link`` in the load frame of ``frame_joints``: the scene's ``members`` (checked
    by ``check_members``), else ``member_tree`` over ``used_joints`` (those a scene's mechanisms,
    loads and members use; default: every joint) and the frame joints. A joint left out (the centre
    of a lightening hole) ends no member: its hole is a plain hole. Made once per link, frame and
    member pairs (the profile is immutable; like its ``boundary``, they are kept with it)."""
    joints = None if used_joints is None else (*used_joints, *frame_joints)
    pairs = check_members(link, members, joints) if members is not None else member_tree(link, frame_joints, joints)
    n = len(link.joints)
    key = (frame_joints[0] % n, frame_joints[1] % n, pairs)
    cache = link.__dict__.setdefault("_members", {})
    if key not in cache:
        cache[key] = _link_members(link, frame_joints, pairs)
    return cache[key]


def _link_members(link: LinkProfile, frame_joints: tuple[int, int], pairs) -> tuple[Member, ...]:
    edges = Edges.of(link, frame_joints)
    joints = link.frame(*frame_joints).to_local(link.joints)
    degree = np.bincount(np.array(pairs, dtype=int).ravel(), minlength=len(joints))
    built = [_member(link, pair, frame_joints, edges, joints, degree) for pair in pairs]
    return tuple(
        Member(m.link, m.joints, m.frame_joints, m.edges, m.path, m.arc, m.extent, m.curved, m.wander, m.depth,
               tuple(o.path for o in built if o is not m))
        for m in built
    )


def frame_member(
    link: LinkProfile, frame_joints: tuple[int, int], members: ArrayLike | None = None,
    used_joints: Sequence[int] | None = None,
) -> Member:
    """The member of ``link`` along its ``frame_joints`` (``link_members``), or, where that pair is not
    a member, the pair taken as a member alone (both its ends free)."""
    for member in link_members(link, frame_joints, members, used_joints):
        if member.joints == tuple(frame_joints):
            return member
    joints = link.frame(*frame_joints).to_local(link.joints)
    degree = np.zeros(len(joints), dtype=int)
    degree[list(frame_joints)] = 1
    return _member(link, tuple(frame_joints), frame_joints, Edges.of(link, frame_joints), joints, degree)


def _member(link, pair, frame_joints, edges: Edges, joints, degree) -> Member:
    i, j = pair
    a, b = joints[i], joints[j]
    if not np.hypot(*(b - a)) > 1e-9 * np.ptp(joints, axis=0).max():
        raise GeometryError(
            f"link {link.name!r}: joints {i} and {j} are at the same point ({a[0]:.6g}, {a[1]:.6g}) m of the load "
            "frame, so no arm joins them; merge them in the sketch, or name the link's members"
        )
    path, depth, wander = centreline(edges, a, b, vertical_lines(link, pair, first_midline(a, b)))
    curved = len(path) > 2
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T))])
    length = float(arc[-1])
    if len(joints) == 2 and not curved:
        lo, hi = link.x_extent(i, j)
    else:
        start = (path[1] - path[0]) / np.hypot(*(path[1] - path[0]))
        end = (path[-1] - path[-2]) / np.hypot(*(path[-1] - path[-2]))
        lo = -_reach(edges, a, -start) if degree[i] == 1 else 0.0
        hi = length + _reach(edges, b, end) if degree[j] == 1 else length
    return Member(link, (i, j), frame_joints, edges, path, arc, (lo, hi), curved, wander, depth)


def _reach(edges: Edges, point, direction) -> float:
    """How far [m] the outline's filled shape runs from ``point`` along ``direction`` (the interval of
    the line through them that holds the point)."""
    lines = cut_lines(edges, np.asarray(point, float)[None, :], np.array([[direction[1], -direction[0]]]))
    bottom, top, _ = through_axis(lines, 1)
    return float(top[0])
