"""The pin-jointed four-bar loop, closed form over a whole sweep of crank angles.

Norton's notation (Design of Machinery, ch. 4, 6, 7): ground O2 -> O4 of length d, crank O2 -> A of
length a, coupler A -> B of length b, output O4 -> B of length c. With D = O4 - A and s = |D|, the
joint B is where the circles (A, b) and (O4, c) meet (law of cosines):

    B - A = ((b^2 - c^2 + s^2) D + sigma 2 b c sin(mu) k x D) / (2 s^2)

mu being the angle at B between the coupler and the output, cos(mu) = (b^2 + c^2 - s^2) / (2 b c).
``open`` is Norton's minus root of eq. 4.10 (the half-angle solution for theta4); it is sigma = +1,
B to the left of the directed line A -> O4, at every position and for every linkage (a
hypothesis test checks this against eq. 4.10 itself); ``crossed`` is sigma = -1. A fixed sigma is a
continuous branch: the two roots only meet where sin(mu) = 0, the toggles, which a sweep reports;
a step between two samples that passes one is a crossing (``crossings``), also reported.

Velocities and accelerations solve the loop's relative-motion equations (Norton eqs. 6.18 and 7.12
in vector form): v_A + omega3 k x (B - A) = omega4 k x (B - O4), and the same for accelerations.

A sweep is solved a block of positions at a time (``kinematics.blocks``), each block in a dozen
temporaries updated in place: the work is a few dozen arithmetic passes besides the four
transcendental ones (sin and cos of theta2, arctan2 for theta3 and theta4), so memory traffic, not
arithmetic, is what a whole-sweep temporary per step would cost.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from linkstress.kinematics.crossings import (
    CHANGE_POINT_TOLERANCE,
    KIND_CHANGE_POINT,
    KIND_TOGGLE,
    BranchPoint,
    find_crossings,
)
from linkstress.kinematics.blocks import angle_of, dot_into, empty_arrays, solve_in_blocks
from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.results import FloatArray, JointMotion, LinkMotion, LoopMotion, fixed_link

TOGGLE_TOLERANCE = 1e-12
"""A position is a toggle when 1 - |cos(mu)| is below this. The computed rates carry a relative
error of about 1e-16 / (1 - |cos(mu)|), so every reported position keeps at least 4 digits; near
a toggle the motion's own rates grow as fast, and the joint forces keep their digits: measured on a
non-Grashof four-bar, 3.8e-6 from exact kinematics at 1 - |cos(mu)| = 1.6e-10
(tests/test_kinematics_change_points.py)."""

CHANGE_POINT_REACH = 1e-7
"""A position is the change point when the factor of sin^2(mu) that touches zero there (1 + cos(mu)
where a + d = b + c, 1 - cos(mu) where |a - d| = |b - c|) is below this. There the factor is a
double zero, ~(crank angle off the point)^2, which the rounding of the crank pin's coordinates
(~1e-16) moves by its own size long before it vanishes: the accelerations, which stay finite through
the point, lose their digits, and the joint forces that grow as 1 / (angle off the point) with them.
Measured against exact kinematics (tests/test_kinematics_change_points.py), the worst joint force of
four change-point four-bars is 3e-6 off at a factor of 4.4e-7, 1.1e-3 at 4e-8, 24 % at 4.4e-9 and
off by a factor of 9,400 at 4e-12 (the seed 3.1e-6 rad = 1.8e-4 deg from its change point, as a
sweep of 1,000,000 samples puts one); at this reach (the seed 0.027 deg off) every reported row
keeps its forces within about 1e-4."""

FEASIBLE, TOGGLE, TOO_FAR, TOO_CLOSE, CHANGE_POINT = range(5)
REASONS = (
    "",
    "toggle: coupler and output aligned",
    "unreachable: crank pin A is farther from O4 than coupler + output",
    "unreachable: crank pin A is closer to O4 than |coupler - output|",
    "change point: all four links aligned, or too nearly for the joint forces to keep their digits (1 - |cos| "
    "of the coupler-output angle under 1e-7), where the open and crossed branches meet",
)

BRANCHES = ("open", "crossed")
DEFAULT_FRAMES = {"crank": (0, 1), "coupler": (0, 1), "output": (0, 1), "ground": (0, 1)}


@dataclass(frozen=True)
class FourBar:
    """A four-bar: ground pivots ``o2``, ``o4`` [m] (ground frame), link lengths [m], branch."""

    o2: tuple[float, float]
    o4: tuple[float, float]
    crank: float
    coupler: float
    output: float
    branch: str = "open"

    def __post_init__(self) -> None:
        object.__setattr__(self, "o2", _point(self.o2, "O2"))
        object.__setattr__(self, "o4", _point(self.o4, "O4"))
        for key in ("crank", "coupler", "output"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise LinkageError(f"four-bar {key} length must be a finite number > 0 m, got {value!r}")
            object.__setattr__(self, key, float(value))
        if not self.ground > 0:
            raise LinkageError(f"four-bar ground pivots O2 and O4 coincide at {self.o2}; they must differ")
        if self.branch not in BRANCHES:
            raise LinkageError(f"four-bar branch must be 'open' or 'crossed', got {self.branch!r}")

    @property
    def ground(self) -> float:
        """d = |O4 - O2| [m]."""
        return math.hypot(self.o4[0] - self.o2[0], self.o4[1] - self.o2[1])

    @property
    def ground_angle(self) -> float:
        """theta1 [rad]: angle of O2 -> O4 from the ground frame's +x."""
        return math.atan2(self.o4[1] - self.o2[1], self.o4[0] - self.o2[0])

    @property
    def lengths(self) -> tuple[float, float, float, float]:
        """(a, b, c, d) [m]: crank, coupler, output, ground."""
        return self.crank, self.coupler, self.output, self.ground

    @property
    def sigma(self) -> float:
        return 1.0 if self.branch == "open" else -1.0


def solve_fourbar(
    linkage: FourBar,
    theta2: ArrayLike,
    omega2: ArrayLike = 0.0,
    alpha2: ArrayLike = 0.0,
    frame_joints: Mapping[str, tuple[int, int]] | None = None,
    steps: ArrayLike | None = None,
) -> LoopMotion:
    """Angles, angular velocities and accelerations of every link, and joint motions, for a sweep.

    theta2 (P,) [rad]: crank angle O2 -> A, counter-clockwise from the ground frame's +x;
    omega2 [rad/s] and alpha2 [rad/s^2] scalars or (P,). ``frame_joints`` names each role's joint
    pair for the returned ``LinkMotion``s (default (0, 1) for every role). ``steps`` (P - 1,) [rad]:
    how far the crank turns from each position to the next, for the crossings of toggles and change
    points (default: the differences of theta2).
    """
    theta2 = np.atleast_1d(np.asarray(theta2, float))
    n = theta2.shape[0]
    w2 = np.broadcast_to(np.asarray(omega2, float), (n,))
    al2 = np.broadcast_to(np.asarray(alpha2, float), (n,))
    points = branch_points(linkage)
    names = mode_names(linkage)
    sweep = _Sweep.empty(n, mode_side=bool(points) and names is not None and n > 1)
    solve_in_blocks(lambda rows: _solve_rows(linkage, theta2, w2, al2, sweep, rows), n)
    o2 = np.broadcast_to(np.asarray(linkage.o2), (n, 2))
    o4 = np.broadcast_to(np.asarray(linkage.o4), (n, 2))
    zero2 = np.broadcast_to(0.0, (n, 2))

    frames = {**DEFAULT_FRAMES, **(frame_joints or {})}
    links = {
        "crank": LinkMotion(frames["crank"], theta2, w2, al2, o2, zero2, zero2),
        "coupler": LinkMotion(
            frames["coupler"], sweep.theta3, sweep.omega3, sweep.alpha3, sweep.pos_a, sweep.vel_a, sweep.acc_a
        ),
        "output": LinkMotion(frames["output"], sweep.theta4, sweep.omega4, sweep.alpha4, o4, zero2, zero2),
        "ground": fixed_link(frames["ground"], linkage.ground_angle, linkage.o2, n),
    }
    joints = {
        "O2": JointMotion(o2, zero2, zero2),
        "A": JointMotion(sweep.pos_a, sweep.vel_a, sweep.acc_a),
        "B": JointMotion(sweep.pos_b, sweep.vel_b, sweep.acc_b),
        "O4": JointMotion(o4, zero2, zero2),
    }
    crossings = ()
    if points and n > 1:
        crossings = find_crossings(
            points, theta2, np.diff(theta2) if steps is None else np.asarray(steps, float),
            sweep.status == FEASIBLE, linkage.branch, sweep.mode_side, names,
        )
    return LoopMotion(
        "four-bar", theta2, sweep.theta3, sweep.theta4, w2, sweep.omega3, sweep.omega4, al2, sweep.alpha3,
        sweep.alpha4, joints, links, sweep.status, REASONS, crossings=crossings,
    )


def branch_points(linkage: FourBar) -> tuple[BranchPoint, ...]:
    """Crank angles [rad] where |A O4| = b + c or |b - c| (law of cosines in the crank angle
    phi = theta2 - theta1). Where a + d = b + c (at phi = pi) or |a - d| = |b - c| (at phi = 0) to
    ``CHANGE_POINT_TOLERANCE`` of the perimeter, the distance only touches its limit: a change point."""
    a, b, c, d = linkage.lengths
    tol = CHANGE_POINT_TOLERANCE * (a + b + c + d)
    theta1 = linkage.ground_angle
    points = []
    for target, reach, phi_touch in ((b + c, a + d, math.pi), (abs(b - c), abs(a - d), 0.0)):
        if abs(reach - target) <= tol:
            points.append(BranchPoint(theta1 + phi_touch, KIND_CHANGE_POINT))
            continue
        cos_phi = (a * a + d * d - target * target) / (2 * a * d)
        if -1.0 < cos_phi < 1.0:
            phi = math.acos(cos_phi)
            points += [BranchPoint(theta1 + phi, KIND_TOGGLE), BranchPoint(theta1 - phi, KIND_TOGGLE)]
    return tuple(points)


def mode_names(linkage: FourBar) -> tuple[str, str] | None:
    """Names of a double change-point four-bar's two assembly modes: the first where
    sigma sin(phi) > 0, the second elsewhere (None for other linkages).

    The two roots B are mirror images across the line A -> O4, and root sigma lies on side sigma.
    With a = c, b = d the parallelogram's B (A + O4 - O2) lies on side sin(phi); with a = d, b = c
    O2 lies on side -sin(phi) and B on the far side makes a convex kite; with a = b, c = d one root
    is B = O2 itself (the output stands still), which lies on side -sin(phi)."""
    a, b, c, d = linkage.lengths
    tol = CHANGE_POINT_TOLERANCE * (a + b + c + d)
    if abs(a - c) <= tol and abs(b - d) <= tol:
        return "parallelogram", "antiparallelogram"
    if abs(a - d) <= tol and abs(b - c) <= tol:
        return "kite (convex)", "dart (concave)"
    if abs(a - b) <= tol and abs(c - d) <= tol:
        return "kite", "folded (B held at O2, output still)"
    return None


@dataclass(frozen=True)
class _Sweep:
    """The arrays a sweep fills a block of rows at a time: angles, rates and joint motions as
    ``LoopMotion`` holds them, and ``mode_side`` (P,) for ``find_crossings`` (None when the
    linkage has no named assembly modes)."""

    theta3: FloatArray
    theta4: FloatArray
    omega3: FloatArray
    omega4: FloatArray
    alpha3: FloatArray
    alpha4: FloatArray
    status: np.ndarray
    pos_a: FloatArray
    vel_a: FloatArray
    acc_a: FloatArray
    pos_b: FloatArray
    vel_b: FloatArray
    acc_b: FloatArray
    mode_side: FloatArray | None

    @classmethod
    def empty(cls, n: int, mode_side: bool) -> _Sweep:
        vectors, pairs = empty_arrays(n, 6, 6)
        return cls(*vectors, np.zeros(n, np.int8), *pairs, np.empty(n) if mode_side else None)


def _solve_rows(linkage: FourBar, theta2, w2, al2, out: _Sweep, rows: slice) -> None:
    """Rows ``rows`` of ``out`` for crank angles ``theta2`` [rad], speeds ``w2`` [rad/s] and
    accelerations ``al2`` [rad/s^2] (P,), in a dozen reused temporaries of the block's length."""
    a, b, c, _ = linkage.lengths
    sigma = linkage.sigma
    dx, dy = linkage.o4[0] - linkage.o2[0], linkage.o4[1] - linkage.o2[1]
    w, al = w2[rows], al2[rows]
    cos2, sin2, rax, ray, ddx, ddy, s2, sin_mu, r3x, r3y, tmp, tmp2 = np.empty((12, rows.stop - rows.start))
    # positions: B where the circles (A, b) and (O4, c) meet
    np.cos(theta2[rows], out=cos2)
    np.sin(theta2[rows], out=sin2)
    np.multiply(cos2, a, out=rax)
    np.multiply(sin2, a, out=ray)
    np.subtract(dx, rax, out=ddx)  # D = O4 - A
    np.subtract(dy, ray, out=ddy)
    dot_into(ddx, ddx, ddy, ddy, s2, tmp)
    one_minus_cos = np.subtract(s2, (b - c) ** 2, out=tmp)
    one_minus_cos /= 2 * b * c
    one_plus_cos = np.subtract((b + c) ** 2, s2, out=tmp2)
    one_plus_cos /= 2 * b * c
    reach_minus, reach_plus = factor_reaches(linkage)
    all_feasible = one_minus_cos.min() > reach_minus and one_plus_cos.min() > reach_plus
    bad = None if all_feasible else (one_minus_cos <= reach_minus) | (one_plus_cos <= reach_plus)
    if not all_feasible:
        out.status[rows] = _status(one_minus_cos, one_plus_cos, reach_minus, reach_plus)
    if out.mode_side is not None:
        side = out.mode_side[rows]
        np.multiply(sin2, math.cos(linkage.ground_angle), out=side)
        side -= np.multiply(cos2, math.sin(linkage.ground_angle), out=cos2)
        side *= sigma

    np.multiply(one_minus_cos, one_plus_cos, out=sin_mu)
    if not all_feasible:  # elsewhere both factors exceed their reach
        np.maximum(sin_mu, 0.0, out=sin_mu)
    np.sqrt(sin_mu, out=sin_mu)
    along = np.add(s2, b * b - c * c, out=cos2)
    across = np.multiply(sin_mu, sigma * 2 * b * c, out=sin2)
    # Feasible positions have s^2 >= 2 b c TOGGLE_TOLERANCE; only filler positions get a stand-in.
    if not all_feasible:
        s2[s2 <= 1e-20 * b * c] = b * c
    half_inv_s2 = np.divide(0.5, s2, out=s2)
    np.multiply(along, ddx, out=r3x)  # B - A
    r3x -= np.multiply(across, ddy, out=tmp)
    r3x *= half_inv_s2
    dot_into(along, ddy, across, ddx, r3y, tmp)
    r3y *= half_inv_s2
    r4x = np.subtract(r3x, ddx, out=ddx)  # B - O4
    r4y = np.subtract(r3y, ddy, out=ddy)
    theta3 = angle_of(r3y, r3x, out.theta3[rows], tmp)
    theta4 = angle_of(r4y, r4x, out.theta4[rows], tmp)
    if not all_feasible:  # filler B - A or B - O4 may be the zero vector
        theta3[bad] = np.arctan2(r3y[bad], r3x[bad])
        theta4[bad] = np.arctan2(r4y[bad], r4x[bad])

    # velocities (Norton eq. 6.18), then accelerations (eq. 7.12), dotted with B - A and B - O4
    cross34 = np.multiply(sin_mu, sigma * b * c, out=sin_mu)  # (B - A) x (B - O4), exactly
    if not all_feasible:
        cross34[bad] = 1.0
    # v_A = omega2 k x (A - O2) and a_A = alpha2 k x (A - O2) - omega2^2 (A - O2), each with its
    # x component kept negated and the sign folded into the sums (negation is exact)
    minus_vax = np.multiply(w, ray, out=cos2)
    vay = np.multiply(w, rax, out=sin2)
    omega3, omega4, alpha3, alpha4 = out.omega3[rows], out.omega4[rows], out.alpha3[rows], out.alpha4[rows]
    # omega3 = -(v_A . (B - O4)) / cross34, omega4 = -(v_A . (B - A)) / cross34
    np.multiply(minus_vax, r4x, out=omega3)
    omega3 -= np.multiply(vay, r4y, out=tmp)
    omega3 /= cross34
    np.multiply(minus_vax, r3x, out=omega4)
    omega4 -= np.multiply(vay, r3y, out=tmp)
    omega4 /= cross34
    vel_a = out.vel_a[rows]
    np.negative(minus_vax, out=vel_a[:, 0])
    vel_a[:, 1] = vay

    w2sq = np.multiply(w, w, out=tmp2)
    minus_aax = dot_into(al, ray, w2sq, rax, cos2, tmp)
    aay = np.multiply(al, rax, out=sin2)
    aay -= np.multiply(w2sq, ray, out=tmp)
    acc_a = out.acc_a[rows]
    np.negative(minus_aax, out=acc_a[:, 0])
    acc_a[:, 1] = aay
    pos_a, pos_b = out.pos_a[rows], out.pos_b[rows]
    for k, (ra, r3) in enumerate(((rax, r3x), (ray, r3y))):
        np.add(ra, linkage.o2[k], out=pos_a[:, k])
        np.add(pos_a[:, k], r3, out=pos_b[:, k])

    dot34 = dot_into(r3x, r4x, r3y, r4y, rax, tmp)
    w3sq = np.multiply(omega3, omega3, out=ray)
    w4sq = np.multiply(omega4, omega4, out=tmp2)
    # alpha3 = (w3^2 dot34 - w4^2 c^2 - a_A . (B - O4)) / cross34, alpha4 likewise
    np.multiply(w3sq, dot34, out=alpha3)
    alpha3 -= np.multiply(w4sq, c * c, out=tmp)
    np.multiply(minus_aax, r4x, out=s2)
    s2 -= np.multiply(aay, r4y, out=tmp)
    alpha3 += s2
    alpha3 /= cross34
    np.multiply(w3sq, b * b, out=alpha4)
    alpha4 -= np.multiply(w4sq, dot34, out=tmp)
    np.multiply(minus_aax, r3x, out=s2)
    s2 -= np.multiply(aay, r3y, out=tmp)
    alpha4 += s2
    alpha4 /= cross34
    if bad is not None:
        for rate in (omega3, omega4, alpha3, alpha4):
            rate[bad] = 0.0

    # v_B = omega4 k x (B - O4), a_B = alpha4 k x (B - O4) - omega4^2 (B - O4)
    vel_b, acc_b = out.vel_b[rows], out.acc_b[rows]
    np.negative(np.multiply(omega4, r4y, out=tmp), out=vel_b[:, 0])
    np.multiply(omega4, r4x, out=vel_b[:, 1])
    np.negative(dot_into(alpha4, r4y, w4sq, r4x, tmp, s2), out=acc_b[:, 0])
    np.multiply(alpha4, r4x, out=tmp)
    np.subtract(tmp, np.multiply(w4sq, r4y, out=s2), out=acc_b[:, 1])


def factor_reaches(linkage: FourBar) -> tuple[float, float]:
    """How small 1 - cos(mu) and 1 + cos(mu) may get before a position is reported as a branch
    point: CHANGE_POINT_REACH for the factor that touches zero at a change point (1 + cos(mu) where
    a + d = b + c, 1 - cos(mu) where |a - d| = |b - c|), TOGGLE_TOLERANCE otherwise."""
    a, b, c, d = linkage.lengths
    tol = CHANGE_POINT_TOLERANCE * (a + b + c + d)
    minus = CHANGE_POINT_REACH if abs(abs(a - d) - abs(b - c)) <= tol else TOGGLE_TOLERANCE
    plus = CHANGE_POINT_REACH if abs((a + d) - (b + c)) <= tol else TOGGLE_TOLERANCE
    return minus, plus


def _status(one_minus_cos, one_plus_cos, reach_minus: float, reach_plus: float):
    """Per-position code into ``REASONS`` from 1 -/+ cos(mu) and how small each may get
    (``factor_reaches``): a factor within its reach is the change point where that reach is
    CHANGE_POINT_REACH, else a toggle; one below -TOGGLE_TOLERANCE is out of reach."""
    status = np.zeros(one_minus_cos.shape, np.int8)
    near_minus, near_plus = one_minus_cos <= reach_minus, one_plus_cos <= reach_plus
    bad = near_minus | near_plus
    if not bad.any():
        return status
    p, q = one_minus_cos[bad], one_plus_cos[bad]
    at_change_point = (near_minus[bad] & (reach_minus == CHANGE_POINT_REACH)) | (
        near_plus[bad] & (reach_plus == CHANGE_POINT_REACH))
    code = np.where(at_change_point, CHANGE_POINT, TOGGLE)
    code = np.where(q < -TOGGLE_TOLERANCE, TOO_FAR, code)
    code = np.where(p < -TOGGLE_TOLERANCE, TOO_CLOSE, code)
    status[bad] = code
    return status


def _point(value, name: str) -> tuple[float, float]:
    p = np.asarray(value, float)
    if p.shape != (2,) or not np.isfinite(p).all():
        raise LinkageError(f"four-bar pivot {name} must be a finite (x, y) pair in metres, got {value!r}")
    return float(p[0]), float(p[1])
