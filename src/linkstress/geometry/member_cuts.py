"""Where cut lines meet a link's outline: the crossings, the section through a member's axis, and
the area moments of the part of the link behind a cut.

Everything is in a link's load frame (the member frame of its frame joints). A cut is the line
through a point c along the normal n of a unit tangent t (n = t turned +90 degrees); v [m] is the
offset along n from c. The outline's edges cross it where their ends lie on either side of it
(``cut_lines``); the outer boundary's crossings pair into the intervals of the filled shape (holes
filled), and the section of a member is the interval through its axis point less the holes it
crosses (``through_axis``, ``section_chords``). The part of the link behind the cut line
((x - c).t <= 0) has its area moments from Green's theorem in the cut's own frame, along which the
cut adds nothing (``half_plane_moments``). Straight members are cut by the sorted sweep of vertical
cuts in their member frame instead, whose cost grows with the crossings (``vertical_lines``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray
from shapely.geometry import Polygon

from linkstress.geometry.boundary import oriented_rings, segment_moments
from linkstress.errors import GeometryError
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.sections import edge_crossings

STATION_BLOCK = 2_000_000
"""Most (station, edge) pairs cut at once."""


@dataclass(frozen=True)
class Edges:
    """A link's outline edges in the load frame (the member frame of ``frame_joints``): ``starts``,
    ``ends`` (E, 2) [m], ``outer`` (E,) for the edges of the outer boundary (the rest bound holes); its
    holes' centres (H, 2) [m]; ``moments`` (4,): A, int x dA, int y dA, int (x^2 + y^2) dA of the
    whole outline; ``outline`` the polygon itself (made when a cut needs splitting it)."""

    starts: NDArray[np.float64]
    ends: NDArray[np.float64]
    outer: NDArray[np.bool_]
    hole_centres: NDArray[np.float64]
    moments: NDArray[np.float64]
    link: LinkProfile
    frame_joints: tuple[int, int]

    @cached_property
    def outline(self) -> Polygon:
        return self.link.local_outline(*self.frame_joints)

    @classmethod
    def of(cls, link: LinkProfile, frame_joints: tuple[int, int]) -> "Edges":
        frame = link.frame(*frame_joints)
        rings = [frame.to_local(r) for r in link._rings]
        starts = np.concatenate(rings)
        ends = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
        outer = np.repeat(np.arange(len(rings)) == 0, [len(r) for r in rings])
        centres = frame.to_local(link.holes[0]).reshape(-1, 2)
        moments = segment_moments(starts, ends).sum(axis=1)
        return cls(starts, ends, outer, centres, moments, link, tuple(frame_joints))

    @property
    def size(self) -> float:
        """The outline's bounding-box diagonal [m]."""
        return float(np.hypot(*np.ptp(self.starts, axis=0)))

    @property
    def perimeter(self) -> float:
        """The outer boundary's length [m]."""
        step = self.ends[self.outer] - self.starts[self.outer]
        return float(np.hypot(*step.T).sum())


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
        out[:, rows] = to_load_frame(local, origin[rows], tangent[rows])
    return out


def to_load_frame(local: NDArray[np.float64], origin: NDArray[np.float64], tangent: NDArray[np.float64]) -> NDArray[np.float64]:
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


def vertical_lines(link: LinkProfile, pair: tuple[int, int], x: NDArray[np.float64]) -> CutLines:
    """``cut_lines`` of the cuts square to the line through joints ``pair`` at distances ``x`` [m] from
    its first joint (v measured from that line), by the sorted sweep of vertical cuts in that member
    frame (``linkstress.geometry.sections``): the cost grows with the crossings, not edges x stations. A cut
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


def segment_distance(points: NDArray[np.float64], segments: NDArray[np.float64]) -> NDArray[np.float64]:
    """(N, M): distance [m] from each point (N, 2) to each segment (M, 2, 2)."""
    a, b = segments[None, :, 0, :], segments[None, :, 1, :]
    p = points[:, None, :]
    d = b - a
    length2 = (d * d).sum(axis=2)
    along = ((p - a) * d).sum(axis=2)
    u = np.clip(np.divide(along, length2, out=np.zeros(along.shape), where=length2 > 0), 0, 1)
    gap = p - (a + u[..., None] * d)
    return np.hypot(gap[..., 0], gap[..., 1])
