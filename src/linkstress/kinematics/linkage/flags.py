"""Where a sweep's rows are flagged: positions where a group cannot close or toggles, and steps that
pass a group's change point or a gap, each naming the group's links.

- infeasible where a group cannot close, or at a toggle (its rate equations singular);
- a warning where the step into a sample row (from the previous sample, or from the drawn pose for
  the first) passes a change point of a group (a dyad's clearance dips to zero and back: its height
  h, the square root of the clearance, comes down to zero in a V within a sampling step; a Newton
  group's Jacobian changes sign), or passes inputs where a group cannot close, or where a Newton
  group solved again after positions where it could not. The rows keep the drawn assembly of
  closed-form groups; nothing switches assembly without a flag.

A closed-form group is recorded a block of path positions at a time (``PathFlags.record``), from
any thread: a block that closes everywhere costs two reductions, and the clearance's local minima
(the candidates for a V) are found while the block is in the cache.
"""

from __future__ import annotations

import threading

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.groups import Group
from linkstress.kinematics.linkage.rates import SINGULAR

FloatArray = NDArray[np.float64]

TOGGLE = 1e-12
"""A clearance below this fraction of the group's size squared, or rate equations conditioned worse
than ``rates.SINGULAR``, is a toggle."""
V_DEPTH = 0.5
"""A dyad's height whose V-shaped dip reaches within this fraction of one sampling step's change of
zero passes (or grazes) a change point."""

WHAT = {
    "change": "passes a change point of the {label} (its links come into line, or within a sampling step of it): "
              "the rows from here keep that group's drawn assembly, which a smooth motion may leave there",
    "gap": "passes inputs where the {label} cannot close: the rows from here keep its drawn assembly; sample the "
           "sweep more finely there to see where",
    "restart": "passes inputs where the mechanism cannot close; the {label} was solved again from its last closed "
               "position and may be in another assembly from here: check it",
}


class PathFlags:
    """Which groups fail where along a path of ``n`` positions. Group g (in solving order) has the
    status codes 2 g + 1 (cannot close) and 2 g + 2 (toggle) into ``texts``."""

    def __init__(self, groups: tuple[Group, ...], n: int) -> None:
        self.groups, self.n = groups, n
        self.texts = [""]
        for group in groups:
            self.texts += [f"the {group.label} cannot close", f"toggle of the {group.label}: its rates are unbounded"]
        self.fails: dict[int, NDArray[np.bool_]] = {}
        self.toggles: dict[int, NDArray[np.bool_]] = {}
        self.kept: dict[int, list[tuple[NDArray[np.intp], FloatArray]]] = {}
        self.minima: dict[int, list[NDArray[np.intp]]] = {}
        self._lock = threading.Lock()

    def expect(self, g: int) -> None:
        """Closed-form group g will be recorded block by block."""
        self.kept[g], self.minima[g] = [], []

    def record(self, g: int, rows: slice, closure, tiny: float) -> NDArray[np.bool_] | None:
        """How group g closes at path positions ``rows`` (``placing.Closure``): where it fails there
        (None: nowhere). A toggle: clearance below ``tiny`` [m^2] or conditioning below
        ``SINGULAR``."""
        count = rows.stop - rows.start
        c = clearance = closure.clearance if np.ndim(closure.clearance) else np.full(count, closure.clearance)
        # kept: the clearance at the block's ends (the minima there are found once the neighbouring
        # blocks' ends are known) and about its local minima
        ends = np.r_[0:min(4, count), max(count - 4, 0):count]
        self.kept[g].append((rows.start + ends, c[ends]))
        if count >= 3:
            mid = 1 + np.flatnonzero((c[1:-1] < c[:-2]) & (c[1:-1] <= c[2:]))
            if len(mid):
                about = np.clip(mid[:, None] + np.arange(-2, 3), 0, count - 1).ravel()
                self.kept[g].append((rows.start + about, c[about]))
                self.minima[g].append(rows.start + mid)
        if clearance.min() > tiny and closure.least > SINGULAR:  # also False where either is nan
            return None
        toggle = (np.abs(clearance) <= tiny) | ~(closure.conditioning() > SINGULAR)
        fails = toggle | ~(clearance >= 0)
        self.mark(g, rows, fails, toggle & (clearance >= 0))
        return fails

    def mark(self, g: int, rows, fails: NDArray[np.bool_], toggles: NDArray[np.bool_] | None = None) -> None:
        """Group g fails at ``rows`` where ``fails``; ``toggles``: where that is a toggle."""
        with self._lock:
            if g not in self.fails:
                self.fails[g], self.toggles[g] = np.zeros(self.n, bool), np.zeros(self.n, bool)
        self.fails[g][rows] = fails
        if toggles is not None:
            self.toggles[g][rows] = toggles

    def closed(self, upto: int | None = None) -> NDArray[np.bool_]:
        """(F,) where the groups before ``upto`` (all: None) close."""
        closed = np.ones(self.n, bool)
        for g, fails in self.fails.items():
            if upto is None or g < upto:
                closed &= ~fails
        return closed

    def status(self) -> NDArray[np.intp]:
        """(F,) each position's code into ``texts``: the first failing group's, 0 where all close."""
        status = np.zeros(self.n, np.intp)
        closed = np.ones(self.n, bool)
        for g in sorted(self.fails):
            new = closed & self.fails[g]
            status[new] = 2 * g + 1 + self.toggles[g][new]
            closed &= ~self.fails[g]
        return status

    def dyad_events(self, g: int, path) -> list[tuple[int, str]]:
        """(sample row, what) for steps passing a change point of closed-form group g, or inputs
        where it cannot close, between two samples where it closes."""
        group = self.groups[g]
        fails = self.fails.get(g)
        events = []
        if fails is not None:
            for row in np.unique(path.step_of[_inside(path) & fails]).tolist():
                events.append((row, "gap"))
        if self.n >= 5:
            c = {f: v for at, values in self.kept[g] for f, v in zip(at.tolist(), values.tolist())}
            events += [(row, "change") for row in _v_dips(c, self._minima(g, c), fails, path)]
        return [(row, kind + "|" + group.label) for row, kind in events if row >= 0]

    def _minima(self, g: int, c: dict[int, float]) -> NDArray[np.intp]:
        """The path positions f where group g's clearance c (kept at ``c``) has a local minimum,
        c[f] < c[f - 1] and c[f] <= c[f + 1]: those found inside the blocks and those at their ends."""
        ends = [f for f in c if 1 <= f <= self.n - 2 and f - 1 in c and f + 1 in c and c[f] < c[f - 1] and c[f] <= c[f + 1]]
        return np.unique(np.concatenate(self.minima[g] + [np.array(ends, np.intp)]).astype(np.intp))


def _v_dips(c: dict[int, float], mid: NDArray[np.intp], fails, path) -> list[int]:
    """The sample rows whose step holds a V-shaped dip of the height h = sqrt(clearance c) to
    zero, at the local minima ``mid`` (c: the clearance at path positions about them): the lines
    through the two points on either side meet within ``V_DEPTH`` of a step's change of zero."""
    mid = mid[(mid >= 2) & (mid <= len(path.x) - 3)]
    if not len(mid):
        return []
    window = np.stack([mid - 2, mid - 1, mid, mid + 1, mid + 2])
    h, x = np.sqrt(np.maximum([[c[f] for f in row] for row in window.tolist()], 0.0)), path.x[window]
    steps = np.sign(np.diff(x, axis=0))
    steady = (steps == steps[0]).all(axis=0) & (steps[0] != 0)
    if fails is not None:
        steady &= ~fails[window].any(axis=0)
    rows = []
    for k in np.flatnonzero(steady).tolist():
        hk, xk, f = h[:, k], x[:, k], int(mid[k])
        left = (hk[1] - hk[0]) / (xk[1] - xk[0])
        right = (hk[4] - hk[3]) / (xk[4] - xk[3])
        if left * right >= 0 or right == left:
            continue
        at = (hk[3] - hk[1] + left * xk[1] - right * xk[3]) / (left - right)
        depth = hk[1] + left * (at - xk[1])
        reach = V_DEPTH * min(abs(left), abs(right)) * abs(xk[3] - xk[1]) / 2
        if depth <= reach:
            rows.append(int(path.step_of[f + 1] if (at - xk[2]) * (xk[3] - xk[2]) > 0 else path.step_of[f]))
    return rows


def _inside(path) -> NDArray[np.bool_]:
    """(F,) the path's points between samples (not the drawn pose)."""
    inside = np.ones(len(path.x), bool)
    inside[path.rows] = False
    inside[0] = False
    return inside


def newton_events(group: Group, path, restarts, flips, fails: NDArray[np.bool_]) -> list[tuple[int, str]]:
    """(sample row, what) for a Newton group: where it solved again (``restarts``: path indices),
    where its Jacobian's sign flips between neighbours (``flips``: the path index after), and
    inputs between samples where it cannot close."""
    events = [(int(path.step_of[f]), "restart|" + group.label) for f in restarts]
    events += [(int(path.step_of[f]), "change|" + group.label) for f in flips]
    events += [(row, "gap|" + group.label) for row in np.unique(path.step_of[_inside(path) & fails]).tolist()]
    return [(row, what) for row, what in events if row >= 0]


def messages(name: str, events, feasible: NDArray[np.bool_], step_text) -> tuple[tuple[int, str], ...]:
    """(row, message) for each event into a feasible row whose previous row is feasible (or that
    is a restart), in row order: ``step_text(row)`` says which step."""
    out = []
    for row, what in sorted(set(events)):
        kind, label = what.split("|", 1)
        if not (feasible[row] and (row == 0 or feasible[row - 1] or kind == "restart")):
            continue
        out.append((row, f"mechanism {name}: {step_text(row)} " + WHAT[kind].format(label=label)))
    return tuple(out)
