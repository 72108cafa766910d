"""Chaining open pieces end to end into closed rings, in any order and direction.

Two ends join when each is the other's nearest end and they are within the gap tolerance; the
joint vertex is their midpoint. An end with no partner leaves its chain open; three or more ends
within the tolerance of one another are a branch. Either leaves that chain out, a problem naming
the curves, the position, the gap and a tolerance that would close it; the other chains still
close. Everything is in drawing units.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from linkstress.errors import SketchError
from linkstress.importers.flatten import Pieces
from linkstress.importers.neighbours import components, count_pairs_within, nearest, pairs_within, within_of
from linkstress.importers.primitives import Origin, describe
from linkstress.importers.problems import BRANCH, OPEN_CHAIN, SketchProblem


class Report:
    """Formats positions, lengths and curves for messages, in the drawing's unit."""

    def __init__(self, origins: list[Origin], unit: str, size: float) -> None:
        self.origins, self.unit, self.size = origins, unit, size

    def at(self, p) -> str:
        return f"({p[0]:.6g}, {p[1]:.6g}) {self.unit}"

    def length(self, d: float) -> str:
        return f"{d:.3g} {self.unit}"

    def curve(self, k: int) -> str:
        return describe(self.origins[k])


@dataclass(frozen=True)
class Rings:
    """Closed rings, vertices ``xy[start[r]:start[r + 1]]`` (first not repeated), with for each ring
    the pieces it is made of, the largest gap closed and where (NaN if none), the number of gaps
    above rounding, and its circle (cx, cy, r) when all its pieces are arcs of one circle."""

    xy: NDArray[np.float64]
    start: NDArray[np.intp]
    pieces: tuple[tuple[int, ...], ...]
    gap: NDArray[np.float64]
    gap_at: NDArray[np.float64]
    gaps: NDArray[np.intp]
    circle: tuple[tuple[float, float, float] | None, ...]

    def __len__(self) -> int:
        return len(self.pieces)

    @staticmethod
    def concatenate(first: "Rings", second: "Rings") -> "Rings":
        return Rings(
            np.concatenate([first.xy, second.xy]),
            np.concatenate([first.start[:-1], second.start + len(first.xy)]),
            first.pieces + second.pieces,
            np.concatenate([first.gap, second.gap]),
            np.concatenate([first.gap_at, second.gap_at]),
            np.concatenate([first.gaps, second.gaps]),
            first.circle + second.circle,
        )


MAX_CLOSE_PAIRS = 1_000_000
"""Pairs of points within the gap tolerance of each other that a drawing may hold. Each is a repeat
to drop, and a cluster of n points makes n^2 / 2 of them: 30,000 POINTs on one spot took 2.2 GB."""


def close_pairs(points: NDArray[np.float64], tolerance: float, what: str) -> NDArray[np.intp]:
    """(M, 2) index pairs i < j of ``points`` (N, D) within ``tolerance`` of each other, sorted; refused,
    naming ``what`` the points are, beyond MAX_CLOSE_PAIRS (counted before any is listed)."""
    count = count_pairs_within(points, tolerance)
    if count > MAX_CLOSE_PAIRS:
        raise SketchError(
            f"{count:,} pairs of {what} lie within the gap tolerance ({tolerance:.3g} drawing units) of each "
            f"other, more than {MAX_CLOSE_PAIRS:,}: the drawing repeats them on one spot or holds detail "
            "finer than the tolerance; clean the drawing, or give a smaller --tolerance"
        )
    return pairs_within(points, tolerance)


def circle_of(circles: NDArray[np.float64], tolerance: float) -> tuple[float, float, float] | None:
    """(cx, cy, r) when every row is the same circle within ``tolerance``, else None."""
    if not np.isfinite(circles).all() or np.ptp(circles, axis=0).max() > tolerance:
        return None
    cx, cy, r = circles.mean(axis=0)
    return float(cx), float(cy), float(r)


def closed_rings(pieces: Pieces, idx: NDArray[np.intp], tolerance: float) -> Rings:
    """The closed pieces ``idx`` as rings of their own."""
    counts = np.diff(pieces.start)[idx]
    first = pieces.start[idx]
    take = np.repeat(first, counts) + (np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts))
    n = len(idx)
    return Rings(
        pieces.xy[take], np.concatenate([[0], np.cumsum(counts)]).astype(np.intp),
        tuple((int(k),) for k in idx), np.zeros(n), np.full((n, 2), np.nan), np.zeros(n, np.intp),
        tuple(circle_of(pieces.circle[[k]], tolerance) for k in idx),
    )


@dataclass(frozen=True)
class Ends:
    """The two ends of each open piece ``idx[e // 2]`` (even e: first vertex, odd: last), with each
    end's nearest other end, the distance to it, and the distance to the second nearest."""

    idx: NDArray[np.intp]
    xy: NDArray[np.float64]
    nearest: NDArray[np.intp]
    gap: NDArray[np.float64]
    second: NDArray[np.float64]

    @classmethod
    def of(cls, pieces: Pieces, idx: NDArray[np.intp]) -> "Ends":
        xy = np.empty((2 * len(idx), 2))
        xy[0::2] = pieces.xy[pieces.start[idx]]
        xy[1::2] = pieces.xy[pieces.start[idx + 1] - 1]
        m = len(xy)
        if m == 0:
            return cls(idx, xy, np.zeros(0, np.intp), np.zeros(0), np.zeros(0))
        k = min(3, m)
        dist, near = nearest(xy, k)
        others_first = np.argsort(near == np.arange(m)[:, None], axis=1, kind="stable")
        near = np.take_along_axis(near, others_first, 1)
        dist = np.take_along_axis(dist, others_first, 1)
        second = dist[:, 1] if k == 3 else np.full(m, np.inf)
        return cls(idx, xy, near[:, 0], dist[:, 0], second)

    def branched(self, tolerance: float) -> NDArray[np.bool_]:
        """Ends that have two or more other ends within ``tolerance``."""
        return self.second <= tolerance


def chain(pieces: Pieces, ends: Ends, tolerance: float, rounding: float, report: Report,
          layer: str | None) -> tuple[Rings, list[SketchProblem], list[NDArray[np.intp]]]:
    """Rings of the open pieces in ``ends`` (one layer's); gaps up to ``tolerance`` close, those above
    ``rounding`` count. A chain that stays open or branches is left out: a problem each (a branch
    reported once), and the pieces of each such chain."""
    good, problems, left_out = _open_chains(pieces, ends, tolerance, report, layer)
    if not good.all():
        ends = Ends.of(pieces, ends.idx[good])
    if len(ends.idx) == 0:
        return closed_rings(pieces, ends.idx, tolerance), problems, left_out
    partner = ends.nearest.tolist()
    # Walk each cycle: enter a piece at one end, leave by the other, go on at that end's partner,
    # until back at the first entry.
    entries: list[int] = []
    ring_sizes: list[int] = []
    seen = bytearray(len(ends.idx))
    for p in range(len(ends.idx)):
        if seen[p]:
            continue
        entry, size = 2 * p, 0
        while True:
            seen[entry // 2] = 1
            entries.append(entry)
            size += 1
            entry = partner[entry ^ 1]
            if entry == 2 * p:
                break
        ring_sizes.append(size)
    rings = _assemble(pieces, ends.idx, np.array(entries), np.array(ring_sizes), tolerance, rounding)
    return rings, problems, left_out


def advised_tolerance(gap: float, size: float) -> float | None:
    """A gap tolerance (fraction of the drawing ``size``) that closes ``gap``: a quarter above it,
    rounded up to two significant digits; None when that is not below 0.5, the largest allowed."""
    wanted = 1.25 * gap / size
    if not 0 < wanted < 0.5:
        return None
    step = 10.0 ** (math.floor(math.log10(wanted)) - 1)
    advised = math.ceil(wanted / step) * step
    return advised if advised < 0.5 else None


def _open_chains(pieces: Pieces, ends: Ends, tolerance: float, report: Report,
                 layer: str | None) -> tuple[NDArray[np.bool_], list[SketchProblem], list[NDArray[np.intp]]]:
    """Which pieces of ``ends`` close into rings, and a problem per chain that does not.

    Two ends pair when each is the other's nearest, within ``tolerance``, and neither has a third
    end within it (a branch). Pieces linked by pairs form chains; a chain with an unpaired (loose)
    end is open (or branched) and is left out whole, so the rest of the layer still chains. Each is
    named by a branched end if it has one, else by the loose end nearest another curve's loose end.
    """
    n = len(ends.idx)
    if n == 0:
        return np.ones(0, bool), [], []
    rows = np.arange(2 * n)
    branch = ends.branched(tolerance)
    paired = (ends.nearest[ends.nearest] == rows) & (ends.gap <= tolerance) & ~branch & ~branch[ends.nearest]
    count, label = components(n, np.column_stack([rows[paired] // 2, ends.nearest[paired] // 2]))
    loose = rows[~paired]
    if not len(loose):
        return np.ones(n, bool), [], []
    open_chain = np.zeros(count, bool)
    open_chain[label[loose // 2]] = True
    by_chain = np.argsort(label, kind="stable")
    chain_start = np.searchsorted(label[by_chain], np.arange(count + 1))
    # Each loose end's nearest loose end on another curve (never its own curve's other end).
    k = min(len(loose), 3)
    dist, near = nearest(ends.xy[loose], k)
    dist, near = dist.reshape(-1, k), loose[near.reshape(-1, k)]
    foreign = (near // 2) != (loose // 2)[:, None]
    first = np.argmax(foreign, axis=1)
    found = foreign.any(axis=1)
    other = np.where(found, near[np.arange(len(loose)), first], -1)
    gap = np.where(found, dist[np.arange(len(loose)), first], np.inf)
    chain_of = label[loose // 2]
    order = np.lexsort((gap, ~branch[loose], chain_of))
    named = order[np.r_[True, np.diff(chain_of[order]) != 0]]
    lo = np.minimum.reduceat(pieces.xy, pieces.start[:-1])[ends.idx]
    hi = np.maximum.reduceat(pieces.xy, pieces.start[:-1])[ends.idx]
    chain_lo, chain_hi = np.full((count, 2), np.inf), np.full((count, 2), -np.inf)
    np.minimum.at(chain_lo, label, lo)
    np.maximum.at(chain_hi, label, hi)
    extent = np.hypot(*(chain_hi - chain_lo).T)
    near_of = within_of(ends.xy, tolerance) if branch.any() else None
    problems: list[SketchProblem] = []
    left_out: list[NDArray[np.intp]] = []
    branches_seen: dict[tuple[int, ...], int] = {}
    for p in named.tolist():
        e, c = int(loose[p]), int(chain_of[p])
        members = ends.idx[by_chain[chain_start[c]:chain_start[c + 1]]]
        left_out.append(members)
        if branch[e]:
            _branch(ends, near_of, e, tolerance, report, layer, members, branches_seen, problems)
        else:
            problems.append(_open_end(ends, e, int(other[p]), float(gap[p]), float(extent[c]), tolerance, report,
                                      layer, members))
    return ~open_chain[label], problems, left_out


def _branch(ends: Ends, near_of: Callable[[NDArray[np.float64]], list[int]], i: int, tolerance: float,
            report: Report, layer: str | None, members: NDArray[np.intp], seen: dict[tuple[int, ...], int],
            problems: list[SketchProblem]) -> None:
    """Three or more ends meet near end ``i`` (``near_of``: the ends within ``tolerance`` of a point), the
    chain ``members`` one of those meeting there: a problem, or the chain added to the one already made
    for that spot (``seen``: its index)."""
    meeting = tuple(near_of(ends.xy[i]))
    if meeting in seen:
        k = seen[meeting]
        problems[k] = replace(problems[k], entities=problems[k].entities + _names(report, members))
        return
    seen[meeting] = len(problems)
    names = ", ".join(report.curve(ends.idx[e // 2]) for e in meeting[:4])
    if len(meeting) > 4:
        names += f" and {len(meeting) - 4} more"
    problems.append(SketchProblem(
        layer, _point(ends.xy[i]), report.unit, _names(report, members),
        f"{len(meeting)} curve ends meet at {report.at(ends.xy[i])} ({names})",
        "a closed outline passes each corner once: remove the duplicate or overlapping curve there (or "
        "lower the gap tolerance if these are separate corners)", BRANCH,
    ))


GAP_OF_EXTENT = 0.1
"""A distance between loose ends up to this fraction of its chain's extent looks like a gap to close:
the message then advises a tolerance that closes it. Farther apart (a stray line's two ends, letters
of an engraving) raising the tolerance would join curves that are not one outline."""


def _open_end(ends: Ends, i: int, j: int, gap: float, extent: float, tolerance: float, report: Report,
              layer: str | None, members: NDArray[np.intp]) -> SketchProblem:
    """An open chain (pieces ``members``, bounding-box diagonal ``extent``) named by its loose end
    ``i``, ``gap`` from ``j``, the nearest loose end of another curve (-1 and inf if none); a lone
    curve nearer its own other end is one that does not close."""
    curve = report.curve(ends.idx[i // 2])
    own = float(np.hypot(*(ends.xy[i] - ends.xy[i ^ 1])))
    if j < 0 or (len(members) == 1 and own <= gap):
        d = own
        problem = (
            f"open curve: {curve} from {report.at(ends.xy[i])} to {report.at(ends.xy[i ^ 1])} does not "
            f"close (its ends are {report.length(own)} apart) and no other curve end is within the gap "
            f"tolerance {report.length(tolerance)}"
        )
    else:
        d = gap
        problem = (
            f"open outline: the end of {curve} at {report.at(ends.xy[i])} is {report.length(d)} from the "
            f"nearest curve end ({report.curve(ends.idx[j // 2])} at {report.at(ends.xy[j])}), more than "
            f"the gap tolerance {report.length(tolerance)}"
        )
    advised = advised_tolerance(d, report.size) if d <= GAP_OF_EXTENT * extent else None
    if advised is None:
        fix = ("delete the curve(s) if they belong to no outline (or leave their layer out with --exclude-layers), "
               "or close the outline in CAD")
    else:
        fix = f"close the gap in CAD, or raise the gap tolerance to --tolerance {advised:.2g}"
    return SketchProblem(layer, _point(ends.xy[i]), report.unit, _names(report, members), problem, fix, OPEN_CHAIN)


def _names(report: Report, pieces: NDArray[np.intp]) -> tuple[str, ...]:
    return tuple(report.curve(int(k)) for k in pieces)


def _point(p) -> tuple[float, float]:
    return float(p[0]), float(p[1])


def _assemble(pieces: Pieces, idx: NDArray[np.intp], entries: NDArray[np.intp], ring_sizes: NDArray[np.intp],
              tolerance: float, rounding: float) -> Rings:
    """Ring vertices: each piece in its walking direction without its last vertex; each joint at the
    midpoint of the arriving and the leaving end."""
    piece = idx[entries // 2]
    forward = entries % 2 == 0
    s, e = pieces.start[piece], pieces.start[piece + 1]
    taken = e - s - 1
    first = np.where(forward, s, e - 1)
    last = np.where(forward, e - 1, s)
    out_first = np.cumsum(taken) - taken
    offset = np.arange(int(taken.sum())) - np.repeat(out_first, taken)
    xy = pieces.xy[np.repeat(first, taken) + np.repeat(np.where(forward, 1, -1), taken) * offset]
    ring_first = np.cumsum(ring_sizes) - ring_sizes
    previous = np.arange(len(piece)) - 1
    previous[ring_first] = ring_first + ring_sizes - 1
    arriving = pieces.xy[last[previous]]
    gaps = np.hypot(*(xy[out_first] - arriving).T)
    xy[out_first] = (xy[out_first] + arriving) / 2
    ring = np.repeat(np.arange(len(ring_sizes)), ring_sizes)
    largest = np.zeros(len(ring_sizes))
    np.maximum.at(largest, ring, gaps)
    at_largest = np.full((len(ring_sizes), 2), np.nan)
    is_largest = (gaps == largest[ring]) & (gaps > 0)
    at_largest[ring[is_largest]] = xy[out_first[is_largest]]
    bounds = np.concatenate([out_first[ring_first], [len(xy)]]).astype(np.intp)
    members = np.split(piece, ring_first[1:])
    return Rings(
        xy, bounds, tuple(tuple(m.tolist()) for m in members), largest, at_largest,
        np.bincount(ring, weights=gaps > rounding, minlength=len(ring_sizes)).astype(np.intp),
        tuple(circle_of(pieces.circle[m], tolerance) for m in members),
    )
