"""The slider-crank loop (offset, inclined slider line), closed form over a whole sweep.

Crank O2 -> A of length a, connecting rod A -> B of length b, slider at B on a straight line of
direction u (angle theta1) whose signed distance from O2 is the offset e, measured along
n = k x u (positive: the line passes to the left of O2 looking along u). With psi the rod's angle
from u and phi = theta2 - theta1 (Norton, Design of Machinery, eqs. 4.16-4.17, 6.20, 7.16 in the
line's frame):

    b sin(psi) = e - a sin(phi),    x = a cos(phi) + b cos(psi)

x being the slider's position along u from the foot of the perpendicular from O2. ``open`` takes
cos(psi) > 0 (the slider ahead of the crank pin along u), ``crossed`` cos(psi) < 0. The loop
toggles where the rod is perpendicular to the slider line (cos(psi) = 0).
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
from linkstress.kinematics.fourbar import BRANCHES, TOGGLE_TOLERANCE
from linkstress.kinematics.results import JointMotion, LinkMotion, LoopMotion, fixed_link, stack_xy

FEASIBLE, TOGGLE, TOO_FAR = range(3)
REASONS = (
    "",
    "toggle: connecting rod perpendicular to the slider line",
    "unreachable: crank pin A is farther from the slider line than the connecting rod's length",
)
DEFAULT_FRAMES = {"crank": (0, 1), "coupler": (0, 1), "ground": (0, 1), "slider": (0, 0)}


@dataclass(frozen=True)
class SliderCrank:
    """A slider-crank: crank pivot ``o2`` [m], crank and rod lengths [m], ``offset`` [m],
    ``slider_angle`` [rad] of the slider line's direction, branch."""

    o2: tuple[float, float]
    crank: float
    rod: float
    offset: float = 0.0
    slider_angle: float = 0.0
    branch: str = "open"

    def __post_init__(self) -> None:
        p = np.asarray(self.o2, float)
        if p.shape != (2,) or not np.isfinite(p).all():
            raise LinkageError(f"slider-crank pivot O2 must be a finite (x, y) pair in metres, got {self.o2!r}")
        object.__setattr__(self, "o2", (float(p[0]), float(p[1])))
        for key in ("crank", "rod"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise LinkageError(f"slider-crank {key} length must be a finite number > 0 m, got {value!r}")
            object.__setattr__(self, key, float(value))
        for key in ("offset", "slider_angle"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise LinkageError(f"slider-crank {key} must be a finite number, got {value!r}")
            object.__setattr__(self, key, float(value))
        if self.branch not in BRANCHES:
            raise LinkageError(f"slider-crank branch must be 'open' or 'crossed', got {self.branch!r}")

    @property
    def direction(self) -> tuple[float, float]:
        """u: unit vector along the slider line."""
        return math.cos(self.slider_angle), math.sin(self.slider_angle)

    @property
    def sigma(self) -> float:
        return 1.0 if self.branch == "open" else -1.0


def solve_slider_crank(
    linkage: SliderCrank,
    theta2: ArrayLike,
    omega2: ArrayLike = 0.0,
    alpha2: ArrayLike = 0.0,
    frame_joints: Mapping[str, tuple[int, int]] | None = None,
    steps: ArrayLike | None = None,
) -> LoopMotion:
    """Crank, rod and slider motion for a sweep of crank angles ``theta2`` (P,) [rad].

    omega2 [rad/s], alpha2 [rad/s^2]: scalars or (P,). The returned loop's theta4 is the slider
    line's angle (constant) and ``slider_position`` its x [m] with velocity and acceleration. Its
    "slider" link motion is the slider body's (frame at B along the line) and its "ground" the
    fixed frame at O2 along the line (a machine reports its grounds' own drawn axes instead).
    ``steps`` (P - 1,) [rad]: how far the crank turns from each position to the next, for the
    crossings of toggles and change points (default: the differences of theta2).
    """
    theta2 = np.atleast_1d(np.asarray(theta2, float))
    n = theta2.shape[0]
    w2 = np.broadcast_to(np.asarray(omega2, float), (n,))
    al2 = np.broadcast_to(np.asarray(alpha2, float), (n,))
    a, b, e = linkage.crank, linkage.rod, linkage.offset
    ux, uy = linkage.direction
    nx, ny = -uy, ux

    rax, ray = a * np.cos(theta2), a * np.sin(theta2)
    a_along = rax * ux + ray * uy  # a cos(phi)
    a_across = rax * nx + ray * ny  # a sin(phi)
    sin_psi = (e - a_across) / b
    one_minus, one_plus = 1.0 - sin_psi, 1.0 + sin_psi
    status = np.zeros(n, np.int8)
    bad = (one_minus <= TOGGLE_TOLERANCE) | (one_plus <= TOGGLE_TOLERANCE)
    if bad.any():
        far = (one_minus[bad] < -TOGGLE_TOLERANCE) | (one_plus[bad] < -TOGGLE_TOLERANCE)
        status[bad] = np.where(far, TOO_FAR, TOGGLE)
    all_feasible = not bad.any()
    cos_psi = linkage.sigma * np.sqrt(np.maximum(one_minus * one_plus, 0.0))
    r3x = b * (cos_psi * ux + sin_psi * nx)  # B - A
    r3y = b * (cos_psi * uy + sin_psi * ny)
    theta3 = np.arctan2(r3y, r3x)
    x = a_along + b * cos_psi

    b_cos = b * cos_psi if all_feasible else np.where(status == FEASIBLE, b * cos_psi, 1.0)
    b_sin = b * sin_psi
    vax, vay = -w2 * ray, w2 * rax
    omega3 = -(vax * nx + vay * ny) / b_cos
    x_dot = vax * ux + vay * uy - omega3 * b_sin
    w2sq, w3sq = w2 * w2, omega3 * omega3
    aax, aay = -al2 * ray - w2sq * rax, al2 * rax - w2sq * ray
    alpha3 = (w3sq * b_sin - (aax * nx + aay * ny)) / b_cos
    x_ddot = aax * ux + aay * uy - alpha3 * b_sin - w3sq * b * cos_psi
    if not all_feasible:
        for rate in (omega3, alpha3, x_dot, x_ddot):
            rate[bad] = 0.0

    o2 = np.broadcast_to(np.asarray(linkage.o2), (n, 2))
    zero = np.broadcast_to(0.0, (n,))
    zero2 = np.broadcast_to(0.0, (n, 2))
    pos_a = stack_xy(rax + linkage.o2[0], ray + linkage.o2[1])
    vel_a, acc_a = stack_xy(vax, vay), stack_xy(aax, aay)
    pos_b = stack_xy(pos_a[:, 0] + r3x, pos_a[:, 1] + r3y)
    vel_b, acc_b = stack_xy(x_dot * ux, x_dot * uy), stack_xy(x_ddot * ux, x_ddot * uy)
    line = np.broadcast_to(linkage.slider_angle, (n,))

    frames = {**DEFAULT_FRAMES, **(frame_joints or {})}
    links = {
        "crank": LinkMotion(frames["crank"], theta2, w2, al2, o2, zero2, zero2),
        "coupler": LinkMotion(frames["coupler"], theta3, omega3, alpha3, pos_a, vel_a, acc_a),
        "slider": LinkMotion(frames["slider"], line, zero, zero, pos_b, vel_b, acc_b),
        "ground": fixed_link(frames["ground"], linkage.slider_angle, linkage.o2, n),
    }
    joints = {
        "O2": JointMotion(o2, zero2, zero2),
        "A": JointMotion(pos_a, vel_a, acc_a),
        "B": JointMotion(pos_b, vel_b, acc_b),
    }
    crossings = ()
    points = branch_points(linkage)
    if points and n > 1:
        crossings = find_crossings(
            points, theta2, np.diff(theta2) if steps is None else np.asarray(steps, float),
            status == FEASIBLE, linkage.branch,
        )
    return LoopMotion(
        "slider-crank", theta2, theta3, line, w2, omega3, zero, al2, alpha3, zero,
        joints, links, status, REASONS, x, x_dot, x_ddot, crossings,
    )


def branch_points(linkage: SliderCrank) -> tuple[BranchPoint, ...]:
    """Crank angles [rad] where the rod is perpendicular to the slider line: a sin(phi) = e -+ b,
    phi = theta2 - slider_angle. Where |e -+ b| = a to ``CHANGE_POINT_TOLERANCE`` of a + b + |e|,
    sin(phi) only touches +-1: a change point."""
    a, b, e = linkage.crank, linkage.rod, linkage.offset
    tol = CHANGE_POINT_TOLERANCE * (a + b + abs(e))
    theta1 = linkage.slider_angle
    points = []
    for reach in (e - b, e + b):
        if abs(abs(reach) - a) <= tol:
            points.append(BranchPoint(theta1 + math.copysign(math.pi / 2, reach), KIND_CHANGE_POINT))
            continue
        if -a < reach < a:
            phi = math.asin(reach / a)
            points += [BranchPoint(theta1 + phi, KIND_TOGGLE), BranchPoint(theta1 + math.pi - phi, KIND_TOGGLE)]
    return tuple(points)
