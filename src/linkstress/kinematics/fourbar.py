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
from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.results import JointMotion, LinkMotion, LoopMotion, fixed_link, stack_xy

TOGGLE_TOLERANCE = 1e-12
"""A position is a toggle when 1 - |cos(mu)| is below this. The computed rates carry a relative
error of about 1e-16 / (1 - |cos(mu)|), so every reported position keeps at least 4 digits."""

CHANGE_POINT_ANGLE = 1e-4
"""A toggle with the crank within this angle [rad] of the ground line is a change point."""

FEASIBLE, TOGGLE, TOO_FAR, TOO_CLOSE, CHANGE_POINT = range(5)
REASONS = (
    "",
    "toggle: coupler and output aligned",
    "unreachable: crank pin A is farther from O4 than coupler + output",
    "unreachable: crank pin A is closer to O4 than |coupler - output|",
    "change point: all four links aligned, where the open and crossed branches meet",
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
    a, b, c, _ = linkage.lengths
    sigma = linkage.sigma
    dx, dy = linkage.o4[0] - linkage.o2[0], linkage.o4[1] - linkage.o2[1]

    cos2, sin2 = np.cos(theta2), np.sin(theta2)
    rax, ray = a * cos2, a * sin2
    ddx, ddy = dx - rax, dy - ray  # D = O4 - A
    s2 = ddx * ddx + ddy * ddy
    one_minus_cos = (s2 - (b - c) ** 2) / (2 * b * c)
    one_plus_cos = ((b + c) ** 2 - s2) / (2 * b * c)
    status = _status(one_minus_cos, one_plus_cos, cos2, sin2, linkage.ground_angle)
    all_feasible = not status.any()

    sin_mu = np.sqrt(np.maximum(one_minus_cos * one_plus_cos, 0.0))
    along = b * b - c * c + s2
    across = (sigma * 2 * b * c) * sin_mu
    # Feasible positions have s^2 >= 2 b c TOGGLE_TOLERANCE; only filler positions get a stand-in.
    half_inv_s2 = 0.5 / (s2 if all_feasible else np.where(s2 > 1e-20 * b * c, s2, b * c))
    r3x = (along * ddx - across * ddy) * half_inv_s2  # B - A
    r3y = (along * ddy + across * ddx) * half_inv_s2
    r4x, r4y = r3x - ddx, r3y - ddy  # B - O4
    theta3 = np.arctan2(r3y, r3x)
    theta4 = np.arctan2(r4y, r4x)

    cross34 = (sigma * b * c) * sin_mu  # (B - A) x (B - O4), exactly
    if not all_feasible:
        cross34 = np.where(status == FEASIBLE, cross34, 1.0)
    vax, vay = -w2 * ray, w2 * rax
    omega3 = -(vax * r4x + vay * r4y) / cross34
    omega4 = -(vax * r3x + vay * r3y) / cross34
    w2sq, w3sq, w4sq = w2 * w2, omega3 * omega3, omega4 * omega4
    aax, aay = -al2 * ray - w2sq * rax, al2 * rax - w2sq * ray
    dot34 = r3x * r4x + r3y * r4y
    alpha3 = (w3sq * dot34 - w4sq * (c * c) - (aax * r4x + aay * r4y)) / cross34
    alpha4 = (w3sq * (b * b) - w4sq * dot34 - (aax * r3x + aay * r3y)) / cross34
    if not all_feasible:
        bad = status != FEASIBLE
        for rate in (omega3, omega4, alpha3, alpha4):
            rate[bad] = 0.0

    o2 = np.broadcast_to(np.asarray(linkage.o2), (n, 2))
    o4 = np.broadcast_to(np.asarray(linkage.o4), (n, 2))
    zero2 = np.broadcast_to(0.0, (n, 2))
    pos_a = stack_xy(rax + linkage.o2[0], ray + linkage.o2[1])
    vel_a = stack_xy(vax, vay)
    acc_a = stack_xy(aax, aay)
    pos_b = stack_xy(pos_a[:, 0] + r3x, pos_a[:, 1] + r3y)
    vel_b = stack_xy(-omega4 * r4y, omega4 * r4x)
    acc_b = stack_xy(-alpha4 * r4y - w4sq * r4x, alpha4 * r4x - w4sq * r4y)

    frames = {**DEFAULT_FRAMES, **(frame_joints or {})}
    links = {
        "crank": LinkMotion(frames["crank"], theta2, w2, al2, o2, zero2, zero2),
        "coupler": LinkMotion(frames["coupler"], theta3, omega3, alpha3, pos_a, vel_a, acc_a),
        "output": LinkMotion(frames["output"], theta4, omega4, alpha4, o4, zero2, zero2),
        "ground": fixed_link(frames["ground"], linkage.ground_angle, linkage.o2, n),
    }
    joints = {
        "O2": JointMotion(o2, zero2, zero2),
        "A": JointMotion(pos_a, vel_a, acc_a),
        "B": JointMotion(pos_b, vel_b, acc_b),
        "O4": JointMotion(o4, zero2, zero2),
    }
    crossings = ()
    points = branch_points(linkage)
    if points and n > 1:
        side = sigma * (sin2 * math.cos(linkage.ground_angle) - cos2 * math.sin(linkage.ground_angle))
        crossings = find_crossings(
            points, theta2, np.diff(theta2) if steps is None else np.asarray(steps, float),
            status == FEASIBLE, linkage.branch, side, mode_names(linkage),
        )
    return LoopMotion(
        "four-bar", theta2, theta3, theta4, w2, omega3, omega4, al2, alpha3, alpha4,
        joints, links, status, REASONS, crossings=crossings,
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


def _status(one_minus_cos, one_plus_cos, cos2, sin2, theta1: float):
    """Per-position code into ``REASONS`` from 1 -/+ cos(mu) and the crank direction."""
    status = np.zeros(one_minus_cos.shape, np.int8)
    bad = (one_minus_cos <= TOGGLE_TOLERANCE) | (one_plus_cos <= TOGGLE_TOLERANCE)
    if not bad.any():
        return status
    p, q = one_minus_cos[bad], one_plus_cos[bad]
    crank_off_ground = np.abs(sin2[bad] * math.cos(theta1) - cos2[bad] * math.sin(theta1))
    code = np.where(crank_off_ground <= CHANGE_POINT_ANGLE, CHANGE_POINT, TOGGLE)
    code = np.where(q < -TOGGLE_TOLERANCE, TOO_FAR, code)
    code = np.where(p < -TOGGLE_TOLERANCE, TOO_CLOSE, code)
    status[bad] = code
    return status


def _point(value, name: str) -> tuple[float, float]:
    p = np.asarray(value, float)
    if p.shape != (2,) or not np.isfinite(p).all():
        raise LinkageError(f"four-bar pivot {name} must be a finite (x, y) pair in metres, got {value!r}")
    return float(p[0]), float(p[1])
