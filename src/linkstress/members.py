"""A link's members: the arms between its joints, their axes, and the sections cut across them.

A member (i, j) is the arm of material from joint i to joint j. A link's members are, unless its
scene names them, the edges of the tree that joins all its joints along the material
(``member_tree``): a bar has one, a bell crank two. Everything here is in the load frame: the
member frame of the link's frame joints (``LinkLoadCase.frame_joints``).

Axis. A member's axis is the straight line through its joints, or, where the material between them
curves (a banana or arc bar), the material's centreline: the midpoints of the cuts normal to it,
found by moving points from the midline of straight cuts onto the midpoints of their normal cuts a
few times. Beyond a joint that ends the tree (a leaf), the axis runs on
straight along its end tangent to the outline (the free end); at a joint shared with another member
it stops. Stations are arc lengths s [m] along the axis, s = 0 at joint i.

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
where it acts), and at a junction when its axis point lies closer than the depth to another
member's axis: there the values are nominal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import split

from linkstress.boundary import oriented_rings, segment_moments
from linkstress.errors import GeometryError
from linkstress.profile import LinkProfile
from linkstress.region_moments import region_moments
from linkstress.sections import SectionTable, _table_from_chords, edge_crossings

OUTSIDE_PENALTY = 100.0
"""Weight per metre of a joint-to-joint line that leaves the material, against 1 per metre inside:
the tree joins joints along the material (the two arms of an L, not its hypotenuse)."""
CURVED_WANDER = 0.1
"""A member is curved when its centreline strays more than this many section depths from the line
through its joints (as ``linkstress.curvature`` judges a link)."""
REGULAR_WIDTH = 2.0
"""A first-midline cut wider than this many times the median runs along a lug or another arm."""
CENTRELINE_POINTS = 121
"""Points of a curved member's centreline between its joints."""
MARCH_STEP = 0.1
"""Steps of the centreline's tracing, in section depths."""
POLISH_PASSES = 20
"""Moves of the traced centreline's points onto the midpoints of the cuts square to it (the chord
between their neighbours), which straighten the kink of the tracing's first steps."""
ARRIVAL_COS = math.cos(math.radians(45.0))
"""Within half a width of its end joint, a tracing heading within 45 degrees of it has arrived (its
last steps would run through the joint's lug)."""
START_RAYS = 72
"""Directions tried for where a bar leaves its joint."""
CURVATURE_REACH = 1.0
"""Half the span, in section depths, of the three centreline points whose circle gives the axis's
curvature at a station (exact on a circular arc; averages the outline's flattening elsewhere)."""
SPLIT_REACH = 1e-9
"""Fraction of the link's size by which a section's segment is run past the outline to split it."""
STATION_BLOCK = 2_000_000
"""Most (station, edge) pairs cut at once."""


def member_tree(link: LinkProfile, root: tuple[int, int] = (0, 1)) -> tuple[tuple[int, int], ...]:
    """The members of ``link``: the minimum spanning tree of its joints, each pair weighted by the
    length of the straight line between them plus ``OUTSIDE_PENALTY`` times its length outside the
    material, oriented away from joint ``root[0]`` (the member of ``root``, if in the tree, keeps its
    direction). Joints in holes count as in material."""
    joints = link.joints
    n = len(joints)
    if n < 2:
        return ()
    first, second = np.triu_indices(n, 1)
    lines = shapely.linestrings(np.stack([joints[first], joints[second]], axis=1))
    inside = shapely.length(shapely.intersection(lines, Polygon(link.outline.exterior)))
    length = shapely.length(lines)
    weight = np.zeros((n, n))
    weight[first, second] = weight[second, first] = length + OUTSIDE_PENALTY * (length - inside)
    start = root[0] % n
    joined, edges = [start], []
    best = weight[start].copy()
    parent = np.full(n, start)
    best[start] = np.inf
    for _ in range(n - 1):
        k = int(np.argmin(np.where(np.isin(np.arange(n), joined), np.inf, best)))
        edges.append((int(parent[k]), k))
        joined.append(k)
        closer = weight[k] < best
        parent[closer], best[closer] = k, weight[k][closer]
        best[joined] = np.inf
    # the member of the root pair first: it is the one along the load frame
    return tuple(sorted(edges, key=lambda edge: edge != (start, root[1] % n)))


def check_members(link: LinkProfile, members: ArrayLike) -> tuple[tuple[int, int], ...]:
    """``members`` given by a scene as joint pairs, checked: each names two distinct joints of the link
    and together they join every joint without a loop (a tree); else a GeometryError that says so."""
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
    if len(pairs) != n - 1:
        raise GeometryError(
            f"link {link.name!r}: members {pairs} do not join all {n} joints; give {n - 1} pairs that join them all"
        )
    return tuple(pairs)


@dataclass(frozen=True)
class Edges:
    """A link's outline edges in the load frame: ``starts``, ``ends`` (E, 2) [m], ``outer`` (E,) for the
    edges of the outer boundary (the rest bound holes); the outline itself and its holes' centres
    (H, 2) [m]; ``moments`` (4,): A, int x dA, int y dA, int (x^2 + y^2) dA of the whole outline."""

    starts: NDArray[np.float64]
    ends: NDArray[np.float64]
    outer: NDArray[np.bool_]
    outline: Polygon
    hole_centres: NDArray[np.float64]
    moments: NDArray[np.float64]

    @classmethod
    def of(cls, link: LinkProfile, frame_joints: tuple[int, int]) -> "Edges":
        frame = link.frame(*frame_joints)
        rings = [frame.to_local(r) for r in link._rings]
        starts = np.concatenate(rings)
        ends = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
        outer = np.repeat(np.arange(len(rings)) == 0, [len(r) for r in rings])
        centres = frame.to_local(link.holes[0]).reshape(-1, 2)
        moments = segment_moments(starts, ends).sum(axis=1)
        return cls(starts, ends, outer, link.local_outline(*frame_joints), centres, moments)

    @property
    def size(self) -> float:
        """The outline's bounding-box diagonal [m]."""
        x0, y0, x1, y1 = self.outline.bounds
        return float(np.hypot(x1 - x0, y1 - y0))


@dataclass(frozen=True)
class CutLines:
    """Where the lines through ``origin`` (S, 2) along the normals of ``tangent`` (S, 2) meet the outline:
    per crossing its ``station``, offset ``v`` [m] along the normal and whether it is on the outer
    boundary; sorted by station, then v."""

    station: NDArray[np.intp]
    v: NDArray[np.float64]
    outer: NDArray[np.bool_]


def cut_lines(
    edges: Edges, origin: NDArray[np.float64], tangent: NDArray[np.float64], left_limit: bool = False,
) -> CutLines:
    """The crossings of every edge with every station's cut line. An edge crosses when its ends' signed
    distances d from the line (along the tangent) satisfy min(d) <= 0 < max(d) (the section just
    ahead of the line), or min(d) < 0 <= max(d) with ``left_limit`` (just behind it); either rule
    makes each closed ring cross each line an even number of times. Where the first meets nothing
    (a line on the outline's far end) the second is taken."""
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    found = []
    block = max(1, STATION_BLOCK // max(len(edges.starts), 1))
    for first in range(0, len(origin), block):
        rows = slice(first, first + block)
        a = edges.starts[None, :, :] - origin[rows, None, :]
        b = edges.ends[None, :, :] - origin[rows, None, :]
        t, n = tangent[rows, None, :], normal[rows, None, :]
        da, db = (a * t).sum(axis=2), (b * t).sum(axis=2)
        low, high = np.minimum(da, db), np.maximum(da, db)
        station, edge = np.nonzero((low < 0) & (high >= 0) if left_limit else (low <= 0) & (high > 0))
        fa, fb = da[station, edge], db[station, edge]
        va, vb = (a[station, edge] * n[station, 0]).sum(axis=1), (b[station, edge] * n[station, 0]).sum(axis=1)
        v = va + (vb - va) * (fa / (fa - fb))
        found.append((station + first, v, edges.outer[edge]))
    station, v, outer = (
        (np.concatenate(parts) for parts in zip(*found)) if found else (np.zeros(0, int), np.zeros(0), np.zeros(0, bool))
    )
    if not left_limit:
        missed = np.setdiff1d(np.arange(len(origin)), station)
        if len(missed):
            behind = cut_lines(edges, origin[missed], tangent[missed], left_limit=True)
            station = np.concatenate([station, missed[behind.station]])
            v, outer = np.concatenate([v, behind.v]), np.concatenate([outer, behind.outer])
    order = np.lexsort((v, station))
    return CutLines(station[order], v[order], outer[order])


def through_axis(lines: CutLines, count: int) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """Per station, the interval [bottom, top] (S,) [m] of the outline's filled shape on the cut line
    that holds the axis point (v = 0), or the nearest one; and how many intervals the line meets."""
    if count == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, int)
    outer = lines.outer
    station = lines.station[outer][::2]
    lo, hi = lines.v[outer][::2], lines.v[outer][1::2]
    intervals = np.bincount(station, minlength=count)
    if (intervals == 0).any():
        k = int(np.flatnonzero(intervals == 0)[0])
        raise GeometryError(f"the cut at station {k} meets no material of the link")
    gap = np.maximum(np.maximum(lo, -hi), 0.0)
    order = np.lexsort((gap, station))
    first = order[np.r_[True, station[order][1:] != station[order][:-1]]]
    return lo[first], hi[first], intervals


def section_chords(lines: CutLines, bottom: NDArray[np.float64], top: NDArray[np.float64]):
    """The material chords of each station's section: the crossings within [bottom, top] (the outer
    boundary's two and the holes' pairs), paired. Returns station (C,), a (C,), b (C,)."""
    keep = (lines.v >= bottom[lines.station]) & (lines.v <= top[lines.station])
    station, v = lines.station[keep], lines.v[keep]
    return station[::2], v[::2], v[1::2]


def half_plane_moments(edges: Edges, origin: NDArray[np.float64], tangent: NDArray[np.float64]) -> NDArray[np.float64]:
    """(4, S): A, int x dA, int y dA, int (x^2 + y^2) dA [per unit thickness, load frame, about its origin]
    of the outline's part (x - c).t <= 0 behind each station's cut line, exactly: Green's theorem in
    the cut's frame on every edge clipped to that side (the cut line, along which x' is constant, adds
    nothing), moved to the load frame."""
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    out = np.zeros((4, len(origin)))
    block = max(1, STATION_BLOCK // max(len(edges.starts), 1))
    for first in range(0, len(origin), block):
        rows = slice(first, first + block)
        t, n = tangent[rows, None, :], normal[rows, None, :]
        a = edges.starts[None, :, :] - origin[rows, None, :]
        b = edges.ends[None, :, :] - origin[rows, None, :]
        a = np.stack([(a * t).sum(axis=2), (a * n).sum(axis=2)], axis=2)
        b = np.stack([(b * t).sum(axis=2), (b * n).sum(axis=2)], axis=2)
        behind_a, behind_b = a[..., 0] <= 0, b[..., 0] <= 0
        step = a[..., 0] - b[..., 0]
        u = np.divide(a[..., 0], step, out=np.zeros_like(step), where=step != 0)[..., None]
        crossing = a + u * (b - a)
        start = np.where(behind_a[..., None], a, crossing)
        end = np.where(behind_b[..., None], b, crossing)
        local = segment_moments(start.reshape(-1, 2), end.reshape(-1, 2)).reshape(4, *start.shape[:2]).sum(axis=2)
        out[:, rows] = _to_load_frame(local, origin[rows], tangent[rows])
    return out


def _to_load_frame(local: NDArray[np.float64], origin: NDArray[np.float64], tangent: NDArray[np.float64]) -> NDArray[np.float64]:
    """Moments (4, S) about each cut's frame (origin c, axes t and n) moved to the load frame's origin."""
    area, sx, sy, polar = local
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    first = sx[:, None] * tangent + sy[:, None] * normal  # int r' dA in load-frame axes
    return np.stack([
        area,
        area * origin[:, 0] + first[:, 0],
        area * origin[:, 1] + first[:, 1],
        polar + 2 * (origin * first).sum(axis=1) + area * (origin * origin).sum(axis=1),
    ])


def piece_moments(piece: Polygon) -> NDArray[np.float64]:
    """(4,): A, int x dA, int y dA, int (x^2 + y^2) dA [per unit thickness] of a polygon with holes."""
    rings = oriented_rings(piece)
    starts = np.concatenate(rings)
    ends = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
    return segment_moments(starts, ends).sum(axis=1)


@dataclass(frozen=True)
class MemberCuts:
    """The sections of one member at stations s (S,) [m], load frame.

    ``origin`` (S, 2) [m]: the axis point; ``tangent`` (S, 2): the unit vector along the axis, and
    ``normal`` the one across it (tangent turned +90 degrees); ``curvature`` (S,) [1/m]: signed, > 0
    when the axis turns toward +normal; ``table``: the sections (x = s, chords in v [m] along the
    normal from ``origin``); ``near_hole`` and ``junction`` (S,): stations whose values are nominal;
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
        table = self.table
        present = np.arange(table.lower.shape[1])[None, :] < table.n_chords[:, None]
        kappa = self.curvature[:, None]
        reach = np.where(present, np.maximum(kappa * table.lower, kappa * table.upper), 0.0)
        return reach.max(axis=1) >= 1 - TIGHT

    @property
    def nominal(self) -> NDArray[np.bool_]:
        """(S,): stations near a hole, at a junction or ``tight``, where beam values are nominal."""
        return self.near_hole | self.junction | self.tight

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
        # the circles keep a section depth clear of the joints, where the centreline runs through a lug
        margin = min(h + self.depth, self.length / 2)
        centre = np.clip(s, margin, self.length - margin)
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
    near_hole = (_segment_distance(edges.hole_centres, ends).T < depth[:, None] * (1 - NEAR_SLACK)).any(axis=1)
    junction = np.zeros(len(s), dtype=bool)
    for path in member.others:
        pieces = np.stack([path[:-1], path[1:]], axis=1)
        junction |= (_segment_distance(origin, pieces) < depth[:, None] * (1 - NEAR_SLACK)).any(axis=1)
    return MemberCuts(
        member.joints, origin, tangent, curvature, table, near_hole, junction, left, edges.moments, right_pieces,
    )


def vertical_lines(link: LinkProfile, pair: tuple[int, int], x: NDArray[np.float64]) -> CutLines:
    """``cut_lines`` of the cuts square to the line through joints ``pair`` at distances ``x`` [m] from
    its first joint (v measured from that line), by the sorted sweep of vertical cuts in that member
    frame (``linkstress.sections``): the cost grows with the crossings, not edges x stations. A cut
    at the outline's far end takes the section just behind it."""
    boundary = link.boundary(*pair)
    x = np.clip(x, boundary.x_min, boundary.x_max)
    order = np.argsort(x, kind="stable")
    at_end = x[order] == boundary.x_max
    outer = len(link._rings[0])
    found = []
    for rows, left_limit in ((order[~at_end], False), (order[at_end], True)):
        if len(rows):
            cut = edge_crossings(boundary.starts, boundary.ends, x[rows], left_limit=left_limit, sort=False)
            found.append((rows[cut.station], cut.y, cut.edge < outer))
    station, v, on_outer = (np.concatenate(parts) for parts in zip(*found))
    sort = np.lexsort((v, station))
    return CutLines(station[sort], v[sort], on_outer[sort])


def _straight_cuts(member: Member, s: NDArray[np.float64], tangent: NDArray[np.float64]) -> tuple[CutLines, NDArray[np.float64]]:
    """``cut_lines`` and ``half_plane_moments`` of a straight member's stations, by sorted sweeps of
    vertical cuts in its member frame (``vertical_lines``, ``linkstress.region_moments``)."""
    boundary = member.link.boundary(*member.joints)
    moments = region_moments(boundary, np.clip(s, boundary.x_min, boundary.x_max))
    local = np.array([moments.area, moments.first_x, moments.first_y, moments.polar])
    joint = np.broadcast_to(member.path[0], (len(s), 2))
    return vertical_lines(member.link, member.joints, s), _to_load_frame(local, joint, tangent)


TIGHT = 0.1
"""A curved section whose material comes within this fraction of its radius of the centre of
curvature is no beam: its values are nominal (straight-beam), as near holes."""
NEAR_SLACK = 1e-9
"""A station exactly one depth from a pin (the midpoint of a bar as long as two depths) is not near it."""


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


def _segment_distance(points: NDArray[np.float64], segments: NDArray[np.float64]) -> NDArray[np.float64]:
    """(N, M): distance [m] from each point (N, 2) to each segment (M, 2, 2)."""
    a, b = segments[None, :, 0, :], segments[None, :, 1, :]
    p = points[:, None, :]
    d = b - a
    length2 = (d * d).sum(axis=2)
    along = ((p - a) * d).sum(axis=2)
    u = np.clip(np.divide(along, length2, out=np.zeros(along.shape), where=length2 > 0), 0, 1)
    gap = p - (a + u[..., None] * d)
    return np.hypot(gap[..., 0], gap[..., 1])


def link_members(
    link: LinkProfile, frame_joints: tuple[int, int], members: ArrayLike | None = None,
) -> tuple[Member, ...]:
    """The members of ``link`` in the load frame of ``frame_joints``: the scene's ``members`` (checked
    by ``check_members``), else ``member_tree``."""
    pairs = check_members(link, members) if members is not None else member_tree(link, frame_joints)
    edges = Edges.of(link, frame_joints)
    joints = link.frame(*frame_joints).to_local(link.joints)
    degree = np.bincount(np.array(pairs, dtype=int).ravel(), minlength=len(joints))
    built = [_member(link, pair, frame_joints, edges, joints, degree) for pair in pairs]
    return tuple(
        Member(m.link, m.joints, m.frame_joints, m.edges, m.path, m.arc, m.extent, m.curved, m.wander, m.depth,
               tuple(o.path for o in built if o is not m))
        for m in built
    )


def frame_member(link: LinkProfile, frame_joints: tuple[int, int], members: ArrayLike | None = None) -> Member:
    """The member of ``link`` along its ``frame_joints`` (``link_members``), or, where that pair is not
    a member, the pair taken as a member alone (both its ends free)."""
    for member in link_members(link, frame_joints, members):
        if member.joints == tuple(frame_joints):
            return member
    joints = link.frame(*frame_joints).to_local(link.joints)
    degree = np.zeros(len(joints), dtype=int)
    degree[list(frame_joints)] = 1
    return _member(link, tuple(frame_joints), frame_joints, Edges.of(link, frame_joints), joints, degree)


def _member(link, pair, frame_joints, edges: Edges, joints, degree) -> Member:
    i, j = pair
    a, b = joints[i], joints[j]
    path, depth, wander = centreline(edges, a, b, vertical_lines(link, pair, _first_midline(a, b)))
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


def _march(edges: Edges, a, b, start: tuple[NDArray[np.float64], float] | None = None) -> NDArray[np.float64] | None:
    """The centreline (K, 2) [m] from ``a`` to ``b`` traced in steps of ``MARCH_STEP`` of the bar's
    width, starting along ``start`` (a direction and the bar's width [m]; by default along the bar,
    ``_bar_start``): each step looks a step ahead along the last chord,
    moves to the midpoint of the cut square to it there, and takes the chord to that point as the
    next direction; None if it does not arrive at ``b`` (``ARRIVAL_COS``) before it has run half the
    outline's perimeter."""
    direction, width = start or _bar_start(edges, a, b)
    tangent = np.asarray(direction, float) / np.hypot(*direction)
    step = MARCH_STEP * width
    point, points = np.asarray(a, float), [np.asarray(a, float)]
    for _ in range(int(edges.outline.exterior.length / 2 / step) + 1):
        gap = b - point
        distance = np.hypot(*gap)
        # arrived: a step away, or within the lug (half a width) heading into it
        if distance <= 1.5 * step or (distance <= width / 2 and gap @ tangent >= distance * ARRIVAL_COS):
            return np.vstack([*points, b])
        ahead = point + step * tangent
        lines = cut_lines(edges, ahead[None, :], tangent[None, :])
        if not len(lines.station):
            return None  # stepped off the material
        bottom, top, _ = through_axis(lines, 1)
        middle = ahead + (bottom[0] + top[0]) / 2 * np.array([-tangent[1], tangent[0]])
        chord = middle - point
        tangent = chord / np.hypot(*chord)
        point = middle
        points.append(point)
    return None


def _bar_start(edges: Edges, a, b) -> tuple[NDArray[np.float64], float]:
    """The direction (2,) in which the bar leaves joint ``a`` toward ``b``, and its width [m] there: of
    ``START_RAYS`` rays from a, the one along which the material runs farthest, weighted by (1 + cos)
    / 2 of its angle to b (so a bar running on past a joint goes toward b); the width is that of the
    cut square to it, a third of that run along."""
    angles = 2 * np.pi * np.arange(START_RAYS) / START_RAYS
    rays = np.column_stack([np.cos(angles), np.sin(angles)])
    # a cut square to the ray's normal lies along the ray: its top is how far the material runs
    lines = cut_lines(edges, np.broadcast_to(a, rays.shape).copy(), np.column_stack([rays[:, 1], -rays[:, 0]]))
    _, run, _ = through_axis(lines, START_RAYS)
    toward = (b - a) / np.hypot(*(b - a))
    k = int(np.argmax(run * (1 + rays @ toward) / 2))
    across = a + rays[k] * run[k] / 3
    bottom, top, _ = through_axis(cut_lines(edges, across[None, :], rays[k][None, :]), 1)
    return rays[k], float(top[0] - bottom[0])


def _widths(edges: Edges, path: NDArray[np.float64]) -> NDArray[np.float64]:
    """(K - 2,) [m]: the widths of the cuts square to ``path`` at its inner points."""
    chord = path[2:] - path[:-2]
    bottom, top, _ = through_axis(cut_lines(edges, path[1:-1], chord / np.hypot(*chord.T)[:, None]), len(path) - 2)
    return top - bottom


def _first_midline(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distances [m] from ``a`` toward ``b`` of the centreline's points between them."""
    return float(np.hypot(*(b - a))) * np.arange(1, CENTRELINE_POINTS + 1) / (CENTRELINE_POINTS + 1)


def centreline(
    edges: Edges, a: NDArray[np.float64], b: NDArray[np.float64], square: CutLines,
) -> tuple[NDArray[np.float64], float, float]:
    """The material centreline (K, 2) [m] from joint point ``a`` to ``b``, its usual section depth [m]
    clear of the joints, and how far it strays from a straight line, in those depths.

    Cuts square to the line a-b at ``_first_midline`` (``square``, v measured from that line) give a
    first midline. Its points whose cut is more than
    ``REGULAR_WIDTH`` times the usual (median) width cut along a lug or another arm and are left out;
    the rest, more than their width from each joint (a lug's rounded end says nothing of the bar's
    axis), measure its bow: the spread of a least-squares cubic through them about their
    least-squares line (refitted without the few points a notch or a hole moves off the first fit),
    in their median width. A
    member is curved when that bow exceeds ``CURVED_WANDER``, or when the line a-b leaves the material by more than half the
    usual width (a U, a hook: their straight cuts run along the legs, and say little); else it keeps
    the line a-b. A curved one's centreline is traced from a along the bar (``_march``; from b if
    that does not arrive)."""
    span = b - a
    length = float(np.hypot(*span))
    along = span / length
    count = CENTRELINE_POINTS
    points = a + np.outer(_first_midline(a, b), along)
    bottom, top, _ = through_axis(square, count)
    width = top - bottom
    points = points + ((bottom + top) / 2)[:, None] * np.array([-along[1], along[0]])
    far = (np.hypot(*(points - a).T) > width) & (np.hypot(*(points - b).T) > width)
    usual = np.median(width[far]) if far.any() else np.median(width)
    regular = width <= REGULAR_WIDTH * usual
    clear = regular & far
    # the line a-b itself leaves the material by more than half a usual width (a U, a hook, a banana)
    astray = bool((np.maximum(np.maximum(bottom, -top), 0.0) > usual / 2).any())
    depth, wander = float(width.min()), 0.0
    if clear.sum() >= 4:
        local = (points[clear] - a) @ np.column_stack([along, [-along[1], along[0]]])
        x, y = local.T
        depth = float(np.median(width[clear]))
        # the bow of a cubic through the midline; the few points a notch or a hole moves off it (more
        # than CURVED_WANDER depths) are left out of a second fit
        fit = np.polyval(np.polyfit(x, y, 3), x)
        kept = np.abs(y - fit) <= CURVED_WANDER * depth
        if kept.sum() >= max(4, 0.8 * len(x)):
            x, y = x[kept], y[kept]
        bow = np.polyval(np.polyfit(x, y, 3), x) - np.polyval(np.polyfit(x, y, 1), x)
        wander = float(np.ptp(bow)) / depth
    if wander <= CURVED_WANDER and not astray:
        return np.array([a, b]), depth, wander
    # from either joint, toward the first midline's points clear of the joints, else along the bar
    tries = [(a, b, None), (b, a, None)]
    if clear.sum() >= 3:
        tries = [(a, b, (points[clear][0] - a, usual)), (b, a, (points[clear][-1] - b, usual)), *tries]
    for start, end, heading in tries:
        path = _march(edges, start, end, heading)
        if path is not None:
            path = path if start is a else path[::-1]
            break
    else:
        return np.array([a, b]), depth, wander
    usual = float(np.median(_widths(edges, path)))
    # how far the traced centreline strays from the line a-b, in depths
    wander = float(np.abs((path - a) @ np.array([-along[1], along[0]])).max()) / usual
    # a section depth from each joint: the points there cut through a lug
    inner = np.flatnonzero((np.hypot(*(path - a).T) > usual) & (np.hypot(*(path - b).T) > usual))
    inner = inner[(inner > 0) & (inner < len(path) - 1)]
    for _ in range(POLISH_PASSES):
        chord = path[inner + 1] - path[inner - 1]
        tangent = chord / np.hypot(*chord.T)[:, None]
        bottom, top, _ = through_axis(cut_lines(edges, path[inner], tangent), len(inner))
        path[inner] += ((bottom + top) / 2)[:, None] * np.column_stack([-tangent[:, 1], tangent[:, 0]])
    points = path[1:-1]
    width = _widths(edges, path)
    far = (np.hypot(*(points - a).T) > width) & (np.hypot(*(points - b).T) > width)
    depth = float(width[far].min()) if far.any() else depth
    return np.vstack([a, points, b]), depth, wander
