"""Peak stress at pin holes, estimated: Kt x the net-section stress of the pin force.

Beam theory does not hold within a section depth of a pin; there the engine reports nominal
section stresses and, separately, this estimate, labelled as such wherever it is shown.

What the pin force sees is measured from the link's outline, per direction of the force (member
frame), on a grid of ``DIRECTIONS`` directions computed once per link and read per position by the
force's angle (linear between the two neighbouring directions; a position is outside the tables
when either neighbour it draws on is):

- the end distance e from the hole's centre to the outline along the force (the material the pin
  bears against), and the distances to the outline at +-90 degrees from it, each at most
  ``SIDE_REACH`` d (beside a small hole farther material does not change the peak);
- the end shape, from rays ``SHAPE_RAYS_DEG`` off the force: round (every ray e long: an end
  concentric with the hole), square (a straight end, square to the force within
  ``SQUARE_TILTS_DEG``, between straight sides), open (no edge within ``OPEN_REACH`` d in the
  half-plane ahead of the pin, none within SIDE_REACH d beside it) or other;
- the width H across the force through the hole's centre: the sum of the two side distances, and
  for a round end its diameter 2 e;
- the shank behind the hole, from the chord across the force e behind the centre: its width w (for
  a round end, at most 2 e) and the force's tilt to its axis (at most ``MAX_TILT_DEG``).

The nominal stress is the net-section stress P / ((H - d) t) of the pin force P over the two
ligaments beside the hole. Kt comes from linkstress's own plane-stress FEA of pin-loaded lugs
(``python -m linkstress.validation.fea.pin_hole_kt`` reproduces the tables): square ends over d/H and
e/H, round ends (e = H / 2) over d/H and w/H, each value from a three-level refinement study, the
peak von Mises over P / ((H - d) t); linear in log d/H and in e/H or w/H between table points;
below the smallest table hole Kt (d/H) / (1 - d/H) (the peak over the bearing stress P / (d t))
stays that row's. The open plate takes the larger of the pulled and the pushed lug at d/H = 0.1
(1.55 P / (d t)). Whatever the tables do not cover (d/H above 0.7, a square end's e/H outside
0.5-1.5, a round end's shank outside 0.5-1 H, a force more than 10 degrees off the shank's axis, a
square end's hole off the middle of its width, an end neither round nor square) is flagged per position, with the reason, and kept out of safety
factors. That includes a pin pushing along the shank of a lug (e/H above 1.5 with edges near): the
FEA of pushed lugs puts the peak at the bearing contact, 17 % above the pulled lug's at d/H = 0.3.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from shapely.geometry import Polygon

from linkstress.geometry.boundary import Boundary
from linkstress.loads import LinkLoadCase, hole_at
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.sections import cut_extent

RATIOS = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7)
"""d/H of the table rows."""
END_DISTANCES = (0.5, 0.75, 1.0, 1.5)
"""e/H of the square-end columns."""
SHANKS = (0.5, 0.75, 1.0)
"""w/H of the round-end columns."""
SQUARE_KT = (
    (13.160, 13.300, 13.330, 13.335),
    (5.576, 5.762, 5.809, 5.813),
    (3.866, 3.415, 3.351, 3.350),
    (3.272, 2.750, 2.686, 2.679),
    (3.006, 2.384, 2.321, 2.314),
    (2.945, 2.179, 2.111, 2.107),
    (3.053, 2.058, 1.989, 1.985),
)
ROUND_KT = (
    (12.794, 12.993, 13.182),
    (5.960, 5.597, 5.616),
    (4.755, 4.360, 3.959),
    (4.346, 3.901, 3.408),
    (4.337, 3.787, 3.197),
    (4.660, 3.933, 3.161),
    (5.934, 4.390, 3.308),
)
OPEN_KT = 13.963
"""Kt (rows RATIOS, columns END_DISTANCES or SHANKS; and of the open plate at d/H = 0.1) from
``linkstress.validation.fea.pin_hole_kt``."""

DIRECTIONS = 72
"""Force directions per hole on which the outline is measured (every 5 degrees)."""
SHAPE_RAYS_DEG = (20, 40, 60)
"""Angles off the force (both sides) of the rays that tell a round end from a square one; multiples
of the direction step."""
SQUARE_TILTS_DEG = (-10, -5, 0, 5, 10)
"""Tilts of a square end to the force tried in the fit: within 10 degrees of square the end is read
as square (e and H still measured along and across the force)."""
SHAPE_TOLERANCE = 0.1
"""Largest relative misfit of a ray for the outline ahead to count as that shape."""
VERTEX_SLACK = 1e-9
"""Fraction of an edge's length by which a ray may miss its ends and still meet it."""
RIM_REACH = 0.55
"""Edges within this many hole diameters of the hole's centre at both ends are its own rim (a
polygon of 16 sides reaches 0.507 d from the centre of its area-equivalent circle)."""
EDGE_SLACK = 0.01
"""Relative slack at the tables' edges: an end drawn on an edge measures within rounding of it."""
SIDE_REACH = 0.5 / RATIOS[0]
"""Material farther than this many hole diameters beside a hole does not change its peak: the width
H is at most d / RATIOS[0] = 10 d, where Kt x nominal is already the bearing asymptote (the earlier
table's d/H = 0.05 and 0.1 gave 1.496 and 1.481 P / (d t), within 1 %)."""
OPEN_REACH = 3.0
"""Hole diameters from the centre within which no edge may lie ahead of an open-plate pin: pulled
square lugs of d/H = 0.1 with their end 3, 4, 5 and 10 d ahead give Kt 13.05, 13.08, 13.16, 13.33,
all below the open plate's 13.963."""
SIMPLIFY = 0.002
"""The outline is measured with its vertices merged within this many diameters of the smallest pin
hole (a 0.2 % error in e and H, well inside the tables' 1 % edge slack)."""
MAX_TILT_DEG = 10.0
"""Largest angle between the pin force and the axis of the shank behind the hole: the FEA of lugs
pulled off their axis gives 0.94 (round end d/H 0.5), 0.98 (boss d/H 0.32), 0.96 (square d/H 0.3)
of the peak at 10 degrees, 0.82, 0.84 and 0.80 at 30 degrees."""
CENTRING_TOLERANCE = 0.1
"""Largest offset of the hole from the middle of the width across the force, over H."""
SOURCE = (
    "estimate: Kt x P / ((H - d) t), H the link's width across the pin force through the hole centre "
    "(at most 10 d; a round end's diameter), for a close-fitting pin; Kt from linkstress plane-stress FEA "
    "of pin-loaded lugs with square ends (over d/H, end distance e/H), round ends concentric with the hole "
    "(over d/H, shank width w/H) and holes far from the edges (docs/numbers.md, pin holes), read per "
    "position by the direction of the pin force; a pin that carries a couple (a driving torque, a keyed "
    "shaft) is outside the tables"
)
SQUARE, ROUND, OTHER, OPEN = 0, 1, 2, 3
SHAPE_NAMES = ("square", "round", "other", "open")


@dataclass(frozen=True)
class HoleOutline:
    """What a pin force sees at one hole, per force direction k (angle 2 pi k / DIRECTIONS [rad],
    member frame): ``width`` H, ``end_distance`` e and ``shank`` w (K,) [m], ``shape`` (K,) codes
    SQUARE / ROUND / OTHER / OPEN, ``kt`` (K,) from the tables (clamped to their edges where outside),
    ``outside`` (K,) and ``reason`` (K,) object array: why Kt is outside the tables, None inside;
    ``tilt`` (K,) [deg]: the force's angle to the axis of the shank behind the hole (inf where there
    is no shank), which the tables' accuracy depends on (``linkstress.model_choice``)."""

    width: NDArray[np.float64]
    end_distance: NDArray[np.float64]
    shank: NDArray[np.float64]
    shape: NDArray[np.int64]
    kt: NDArray[np.float64]
    outside: NDArray[np.bool_]
    reason: NDArray[np.object_]
    tilt: NDArray[np.float64]


@dataclass(frozen=True)
class PinHoleEstimate:
    """At joint ``joint`` (a pin hole of diameter ``diameter`` [m] in a section ``depth`` [m] deep
    across the member axis), per position (P,): the width ``width`` [m] across the pin force, the end
    distance ``end_distance`` [m] along it, the end ``shape`` (names), the net-section stress
    ``nominal`` [Pa] of the pin force, ``kts`` and ``estimate`` = Kt x nominal [Pa], and ``outside``:
    True where the geometry the force sees is outside the Kt tables (``reasons`` says why; Kt there is
    the nearest table edge's, not to be trusted, and kept out of safety factors). ``kt`` is the Kt of
    the largest estimate inside the tables, None where no position is inside. ``tilt`` (P,) [deg]:
    the force's angle to the shank's axis, the larger of the two directions it is read from (inf
    where either has no shank; what the tables' accuracy depends on, ``linkstress.model_choice``)."""

    joint: int
    diameter: float
    depth: float
    kt: float | None
    width: NDArray[np.float64]
    end_distance: NDArray[np.float64]
    shape_code: NDArray[np.int8]
    nominal: NDArray[np.float64]
    kts: NDArray[np.float64]
    estimate: NDArray[np.float64]
    outside: NDArray[np.bool_]
    reason_code: NDArray[np.int8]
    reason_texts: tuple[str | None, ...]
    source: str = SOURCE
    tilt: NDArray[np.float64] | None = None

    @property
    def shape(self) -> tuple[str, ...]:
        """The end shape's name at every position (small sweeps; ``shapes_in`` for a block)."""
        return tuple(self.shapes_in(slice(None)))

    @property
    def reasons(self) -> tuple[str | None, ...]:
        """Why Kt is outside the tables at every position, None inside (``reasons_in`` for a block)."""
        return tuple(self.reasons_in(slice(None)))

    def shapes_in(self, positions) -> list[str]:
        """The end shape's name at ``positions`` (a slice, mask or indices): codes per position keep a
        long sweep's memory at a byte each."""
        return np.array(SHAPE_NAMES, dtype=object)[self.shape_code[positions]].tolist()

    def reasons_in(self, positions) -> list[str | None]:
        """Why Kt is outside the tables at ``positions``, None where inside."""
        return np.array(self.reason_texts, dtype=object)[self.reason_code[positions]].tolist()

    def at(self, positions: slice) -> "PinHoleEstimate":
        """The estimate at the consecutive ``positions`` only: every per-position field sliced."""
        return replace(
            self, width=self.width[positions], end_distance=self.end_distance[positions],
            shape_code=self.shape_code[positions], nominal=self.nominal[positions], kts=self.kts[positions],
            estimate=self.estimate[positions], outside=self.outside[positions],
            reason_code=self.reason_code[positions],
            tilt=None if self.tilt is None else self.tilt[positions],
        )

    def largest(self, positions) -> float | None:
        """The largest estimate [Pa] inside the tables over ``positions`` (a mask or indices), None if none."""
        values = self.estimate[positions][~self.outside[positions]]
        return float(values.max()) if values.size else None


def ray_hits(starts: NDArray[np.float64], ends: NDArray[np.float64], origins: NDArray[np.float64],
             directions: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Distance [m] from each origin (A, 2) along its unit direction (A, 2) to the first of the
    edges ``starts`` -> ``ends`` (E, 2) [m] it meets (inf if none), and how many it crosses (odd: the
    origin is inside the rings the edges form)."""
    edge = ends - starts
    # Every 2D cross product below is a (A, 2) x (2, E) product: the (A, E) tables come from BLAS.
    normal = np.stack([edge[:, 1], -edge[:, 0]])
    denominator = directions @ normal
    reach = (starts[:, 0] * edge[:, 1] - starts[:, 1] * edge[:, 0]) - origins @ normal
    twist = starts @ np.stack([directions[:, 1], -directions[:, 0]])
    along = twist.T - (origins[:, 0] * directions[:, 1] - origins[:, 1] * directions[:, 0])[:, None]
    parallel = denominator == 0
    denominator[parallel] = 1.0
    distance = reach / denominator
    along /= denominator
    ahead = ~parallel & (distance > 0)
    # A ray through a vertex meets both its edges within rounding: the nearest hit takes either,
    # the crossing count (half-open edges) exactly one.
    meets = ahead & (along >= -VERTEX_SLACK) & (along <= 1 + VERTEX_SLACK)
    crossings = (ahead & (along >= 0) & (along < 1)).sum(axis=1)
    return np.where(meets, distance, np.inf).min(axis=1), crossings


def hole_outline(boundary: Boundary, centre: NDArray[np.float64], diameter: float) -> HoleOutline:
    """Measure the outline ``boundary`` [m] around the pin hole of ``diameter`` [m] at ``centre`` (2,)
    [m] for every force direction of the grid (same frame as the boundary)."""
    angles = 2 * np.pi * np.arange(DIRECTIONS) / DIRECTIONS
    units = np.column_stack([np.cos(angles), np.sin(angles)])
    # The hole's own rim is the material the pin presses, not the outline: leave its edges out.
    rim = RIM_REACH * diameter
    own = (np.hypot(*(boundary.starts - centre).T) < rim) & (np.hypot(*(boundary.ends - centre).T) < rim)
    starts, ends = boundary.starts[~own], boundary.ends[~own]
    reach, _ = ray_hits(starts, ends, np.broadcast_to(centre, units.shape), units)
    quarter = DIRECTIONS // 4
    # Beside a small hole only material within SIDE_REACH diameters counts (the bearing regime).
    side_cap = SIDE_REACH * diameter
    end = reach
    left, right = np.minimum(turned(reach, [quarter, -quarter]), side_cap)
    shape, misfit = _end_shape(reach, left, right, side_cap)
    # The open plate: no edge within OPEN_REACH d ahead of the pin (+-90 degrees), none within
    # SIDE_REACH d beside it.
    ahead = turned(reach, np.arange(-quarter, quarter + 1)).min(axis=0)
    is_open = (ahead >= OPEN_REACH * diameter) & (np.minimum(left, right) >= side_cap)
    shape = np.where(is_open, OPEN, shape)
    # A round end concentric with the hole is as wide as its diameter 2 e across any force that meets
    # it; a shank met obliquely measures wider than the end but is no wider than it.
    is_round = shape == ROUND
    width = np.where(is_round, 2 * end, left + right)
    chord, tilt = _shank(starts, ends, centre, units, end)
    shank = np.where(is_round, np.minimum(chord, 2 * end), 0.0)
    d_over_h, e_over_h, w_over_h = diameter / width, end / width, shank / width
    offset = np.abs(left - right) / (2 * width)
    reason = np.array([
        _reason(*values) for values in zip(shape.tolist(), d_over_h.tolist(), e_over_h.tolist(),
                                            w_over_h.tolist(), offset.tolist(), misfit.tolist(), tilt.tolist())
    ], dtype=object)
    return HoleOutline(width, end, shank, shape, table_kt(shape, d_over_h, e_over_h, w_over_h),
                       np.not_equal(reason, None), reason, tilt)


def turned(values: NDArray[np.float64], steps) -> NDArray[np.float64]:
    """(S, K): per step count s of ``steps``, ``values`` (K,) of the direction s grid steps
    counter-clockwise from each direction."""
    k = np.arange(len(values))
    return values[(k[None, :] + np.asarray(steps)[:, None]) % len(values)]


def _end_shape(reach: NDArray[np.float64], left: NDArray[np.float64], right: NDArray[np.float64],
               side_cap: float) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Per direction: the end shape code and the misfit of the better of the two shapes, from the
    distances ``reach`` (K,) [m] to the outline along each direction and ``left`` / ``right`` at +-90
    degrees from it (at most ``side_cap`` [m]; rays and shapes are cut off at lines that far to
    either side). The square end may be tilted by up to SQUARE_TILTS_DEG to the force."""
    steps = np.array([int(round(d * DIRECTIONS / 360)) for d in SHAPE_RAYS_DEG])
    offsets = np.concatenate([steps, -steps])
    phi = 2 * np.pi * offsets / DIRECTIONS  # (R,)
    beside = (side_cap / np.abs(np.sin(phi)))[:, None]  # (R, 1)
    measured = np.minimum(turned(reach, offsets), beside)  # (R, K)
    round_misfit = np.abs(measured / np.minimum(reach, beside) - 1).max(axis=0)
    tilt = np.radians(np.asarray(SQUARE_TILTS_DEG))[:, None, None]  # (T, 1, 1)
    # A straight end at right angles to a normal tilted by ``tilt`` from the force, with straight
    # sides along that normal through the points the +-90 degree rays meet.
    off = phi[None, :, None] - tilt
    end = reach * np.cos(tilt) / np.cos(off)
    side = np.where(off > 0, left * np.cos(tilt), right * np.cos(tilt)) / np.abs(np.sin(off))
    square = np.minimum(np.where(np.abs(off) < np.pi / 2, np.minimum(end, side), side), beside)
    square_misfit = np.abs(measured / square - 1).max(axis=1).min(axis=0)
    is_round = round_misfit <= np.minimum(square_misfit, SHAPE_TOLERANCE)
    is_square = ~is_round & (square_misfit <= SHAPE_TOLERANCE)
    shape = np.select([is_round, is_square], [ROUND, SQUARE], OTHER)
    return shape, np.minimum(round_misfit, square_misfit)


def _shank(starts: NDArray[np.float64], ends: NDArray[np.float64], centre: NDArray[np.float64],
           units: NDArray[np.float64], end: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per direction: the shank's width [m] e behind the hole's centre (0 where that point is outside
    the material) and the force's tilt [deg] to the shank's axis (inf there: no shank). The chord across the force
    there crosses the shank obliquely: its middle, on the shank's axis, lies e tan(tilt) off the force's
    line, and it is width / cos(tilt) long."""
    behind = centre - end[:, None] * units
    across = np.column_stack([-units[:, 1], units[:, 0]])
    up, crossings = ray_hits(starts, ends, behind, across)
    down, _ = ray_hits(starts, ends, behind, -across)
    inside = crossings % 2 == 1
    # Outside the material the rays may meet nothing (inf): no shank, no tilt to measure.
    up, down = np.where(inside, up, 0.0), np.where(inside, down, 0.0)
    tilt = np.arctan2(np.abs(up - down) / 2, end)
    return np.where(inside, (up + down) * np.cos(tilt), 0.0), np.where(inside, np.degrees(tilt), np.inf)


def table_kt(shape: NDArray[np.int64], d_over_h: NDArray[np.float64], e_over_h: NDArray[np.float64],
             w_over_h: NDArray[np.float64]) -> NDArray[np.float64]:
    """Kt of each geometry (shape codes, d/H, e/H, w/H) from its table, clamped to the table's edges
    (the square table for OTHER; the open plate's Kt x (d/H) / (1 - d/H) kept at its d/H = 0.1 value)."""
    bearing = OPEN_KT * (RATIOS[0] / (1 - RATIOS[0])) * (1 - d_over_h) / d_over_h
    return np.select(
        [shape == ROUND, shape == OPEN],
        [_interpolate(ROUND_KT, SHANKS, d_over_h, w_over_h), bearing],
        _interpolate(SQUARE_KT, END_DISTANCES, d_over_h, e_over_h),
    )


def _reason(shape: int, d_over_h: float, e_over_h: float, w_over_h: float, offset: float, misfit: float,
            tilt: float) -> str | None:
    """Why one direction's geometry is outside the tables, None if it is inside."""
    if shape == OTHER:
        return (f"the end ahead of the hole is neither square to the force (within {SQUARE_TILTS_DEG[-1]} degrees) "
                f"nor round about the hole: its edge lies up to {misfit:.0%} nearer or farther from the hole's "
                "centre than either shape would put it")
    if shape == OPEN:
        return None
    low, high = 1 - EDGE_SLACK, 1 + EDGE_SLACK
    if d_over_h > RATIOS[-1] * high:
        return f"d/H = {d_over_h:.2f} above the table's {RATIOS[-1]}"
    if shape == SQUARE and e_over_h < END_DISTANCES[0] * low:
        return f"end distance e/H = {e_over_h:.2f} below the table's {END_DISTANCES[0]}"
    if shape == SQUARE and e_over_h > END_DISTANCES[-1] * high:
        return (f"end distance e/H = {e_over_h:.2f} above the table's {END_DISTANCES[-1]} (a pin pushing "
                "along the shank: its peak is at the bearing contact, not in the table)")
    if not np.isfinite(tilt):
        return "no shank behind the hole (the point e behind its centre, against the force, is outside the link)"
    if tilt > MAX_TILT_DEG:
        return (f"pin force {tilt:.0f} degrees off the axis of the shank behind the hole (the tables are "
                f"for forces within {MAX_TILT_DEG:.0f} degrees of it)")
    if shape == ROUND and not SHANKS[0] * low <= w_over_h <= SHANKS[-1] * high:
        return f"round end on a shank w/H = {w_over_h:.2f} outside the table's {SHANKS[0]}-{SHANKS[-1]}"
    if shape == SQUARE and offset > CENTRING_TOLERANCE:
        return f"hole {offset:.2f} H off the middle of the width across the force"
    return None


def _interpolate(table, columns, d_over_h: NDArray[np.float64], column: NDArray[np.float64]) -> NDArray[np.float64]:
    """Kt linear in log d/H and in the column's ratio, clamped to the table's edges; below its
    smallest hole the bearing asymptote Kt (d/H) / (1 - d/H) = that row's value."""
    values = np.asarray(table, float)
    ratios = np.asarray(RATIOS)
    at_column = np.array([np.interp(column, columns, row) for row in values])  # (rows, K)
    small = np.minimum(d_over_h, ratios[-1])
    log_r = np.log(np.maximum(small, ratios[0]))
    index = np.clip(np.searchsorted(np.log(ratios), log_r) - 1, 0, len(ratios) - 2)
    fraction = (log_r - np.log(ratios[index])) / (np.log(ratios[index + 1]) - np.log(ratios[index]))
    k = np.arange(len(column))
    log_kt = (1 - fraction) * np.log(at_column[index, k]) + fraction * np.log(at_column[index + 1, k])
    bearing = (small / (1 - small)) / (ratios[0] / (1 - ratios[0]))
    return np.exp(log_kt) / np.where(small < ratios[0], bearing, 1.0)


def link_outlines(link: LinkProfile, frame_joints: tuple[int, int]) -> dict[int, HoleOutline]:
    """Per joint that is the centre of a pin hole: its ``HoleOutline`` in member frame ``frame_joints``,
    computed once per link and frame."""
    cache = link.__dict__.setdefault("_pin_hole_outlines", {})
    key = tuple(j % len(link.joints) for j in frame_joints)
    if key not in cache:
        joints = link.frame(*frame_joints).to_local(link.joints)
        diameters = {j: 2 * float(np.sqrt(link.holes[1][hole] / np.pi))
                     for j, hole in enumerate(link.joint_holes) if hole is not None}
        boundary = _simplified_boundary(link.local_outline(*frame_joints), SIMPLIFY * min(diameters.values(), default=0.0))
        cache[key] = {j: hole_outline(boundary, joints[j], d) for j, d in diameters.items()}
    return cache[key]


def _simplified_boundary(outline: Polygon, tolerance: float) -> Boundary:
    """The edges of ``outline`` with its arcs' fine chords merged within ``tolerance`` [m]: the rays
    cost in proportion to the edges."""
    simple = outline.simplify(tolerance, preserve_topology=True) if tolerance > 0 else outline
    return Boundary.from_rings([np.asarray(r.coords)[:-1] for r in (simple.exterior, *simple.interiors)])


def pin_hole_estimates(
    link: LinkProfile, loads: LinkLoadCase, depths: dict[int, float] | None = None,
) -> tuple[PinHoleEstimate, ...]:
    """The estimate at every joint of ``link`` that is the centre of a pin hole, per position, of the
    force its pin bears: the pin force plus any point force given in that hole (a pin's load given as
    a force). ``depths`` [m]: per joint, the section depth through it across the member it sits on
    (``section_stress.member_depths``); by default the cut across the load frame's axis."""
    outlines = link_outlines(link, loads.frame_joints)
    if not outlines:
        return ()
    joints = link.frame(*loads.frame_joints).to_local(link.joints)
    depths = dict(depths or {})
    missing = [j for j in outlines if j not in depths]
    if missing:
        # The section through each pin's centre across the member axis spans the lug's depth there.
        bottom, top = cut_extent(link.boundary(*loads.frame_joints), joints[missing, 0])
        depths.update({j: float(top[k] - bottom[k]) for k, j in enumerate(missing)})
    areas = link.holes[1]
    borne = _borne_forces(link, loads)
    estimates = []
    for j, outline in outlines.items():
        diameter = 2 * float(np.sqrt(areas[link.joint_holes[j]] / np.pi))
        depth = depths[j]
        force = loads.pin_forces[:, j] + borne.get(link.joint_holes[j], 0.0)
        estimates.append(_estimate(j, diameter, depth, outline, force, loads.joint_couples[:, j], link.thickness))
    return tuple(estimates)


COUPLE_SHARE = 0.05
"""A couple C carried through a pin of radius r with force F matters above C = COUPLE_SHARE F r: its
shear on the rim, C / (2 pi r^2 t), is then more than about 1 % of the bearing pressure 2 F / (pi r t),
and it adds to the peak (at the seed crank's driven pivot the FEA peak is 13 times the bearing
estimate)."""
COUPLE_REASON = (
    "a couple is carried through this pin (a driving torque or keyed shaft): the Kt tables hold the pin's "
    "bearing alone; linkstress validate gives the FEA peak"
)


def _estimate(joint: int, diameter: float, depth: float, outline: HoleOutline, force: NDArray[np.float64],
              couple: NDArray[np.float64], thickness: float) -> PinHoleEstimate:
    """The estimate at one hole for pin forces ``force`` (P, 2) [N], member frame, and the couple
    ``couple`` (P,) [N m] carried through the pin (a driving torque, a keyed shaft): the tables hold
    bearing alone, so a position whose couple matters is outside them."""
    grid = np.mod(np.arctan2(force[:, 1], force[:, 0]) * DIRECTIONS / (2 * np.pi), DIRECTIONS)
    below = np.floor(grid).astype(int) % DIRECTIONS
    above = (below + 1) % DIRECTIONS
    share = grid - np.floor(grid)
    width = (1 - share) * outline.width[below] + share * outline.width[above]
    end = (1 - share) * outline.end_distance[below] + share * outline.end_distance[above]
    kts = (1 - share) * outline.kt[below] + share * outline.kt[above]
    nearest = np.where(share < 0.5, below, above)
    outside = (outline.outside[below] & (share < 1)) | (outline.outside[above] & (share > 0))
    # A position's reason is that of the direction it reads it from (a code into ``texts``).
    texts = (*outline.reason.tolist(), COUPLE_REASON, None)
    magnitude = np.hypot(force[:, 0], force[:, 1])
    carried = np.abs(couple) > COUPLE_SHARE * magnitude * diameter / 2
    codes = np.where(carried, DIRECTIONS, np.where(outline.outside[below], below, above)).astype(np.int8)
    outside = outside | carried
    codes[~outside] = DIRECTIONS + 1
    nominal = magnitude / ((width - diameter) * thickness)
    estimate = kts * nominal
    inside = np.flatnonzero(~outside)
    kt = float(kts[inside[np.argmax(estimate[inside])]]) if inside.size else None
    shape = outline.shape[nearest].astype(np.int8)
    source = SOURCE
    if outside.any():
        source += (f"; OUTSIDE the Kt tables at {int(outside.sum())} of {len(outside)} positions "
                   "(kt_outside_table, kt_outside_reason): no estimate there and none in the safety factors")
    tilt = np.maximum(outline.tilt[below], outline.tilt[above])
    return PinHoleEstimate(joint, diameter, depth, kt, width, end, shape, nominal, kts, estimate,
                           outside.astype(bool), codes, texts, source, tilt)


def _borne_forces(link: LinkProfile, loads: LinkLoadCase) -> dict[int, NDArray[np.float64]]:
    """Per hole (its index in the outline), the sum (P, 2) [N, member frame] of the point forces
    given inside it."""
    borne: dict[int, NDArray[np.float64]] = {}
    if not loads.point_forces:
        return borne
    outline = link.local_outline(*loads.frame_joints)
    for point in loads.point_forces:
        hole = hole_at(outline, point.at)
        if hole is not None:
            borne[hole] = borne.get(hole, 0.0) + np.asarray(point.force, float)
    return borne
