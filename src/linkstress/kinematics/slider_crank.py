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
from linkstress.kinematics.blocks import angle_of, dot_into, empty_arrays, set_columns, solve_in_blocks
from linkstress.kinematics.errors import LinkageError
from linkstress.kinematics.fourbar import BRANCHES, CHANGE_POINT_REACH, TOGGLE_TOLERANCE
from linkstress.kinematics.results import FloatArray, JointMotion, LinkMotion, LoopMotion, fixed_link

FEASIBLE, TOGGLE, TOO_FAR, CHANGE_POINT = range(4)
REASONS = (
    "",
    "toggle: connecting rod perpendicular to the slider line",
    "unreachable: crank pin A is farther from the slider line than the connecting rod's length",
    "change point: crank and connecting rod aligned across the slider line, or too nearly for the joint forces "
    "to keep their digits (1 - |sin| of the rod's angle to the line under 1e-7), where the open and crossed "
    "branches meet",
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
    sweep = _Sweep.empty(n)
    solve_in_blocks(lambda rows: _solve_rows(linkage, theta2, w2, al2, sweep, rows), n)
    o2 = np.broadcast_to(np.asarray(linkage.o2), (n, 2))
    zero = np.broadcast_to(0.0, (n,))
    zero2 = np.broadcast_to(0.0, (n, 2))
    line = np.broadcast_to(linkage.slider_angle, (n,))
    pos_a, vel_a, acc_a, pos_b, vel_b, acc_b = (
        sweep.pos_a, sweep.vel_a, sweep.acc_a, sweep.pos_b, sweep.vel_b, sweep.acc_b
    )

    frames = {**DEFAULT_FRAMES, **(frame_joints or {})}
    links = {
        "crank": LinkMotion(frames["crank"], theta2, w2, al2, o2, zero2, zero2),
        "coupler": LinkMotion(frames["coupler"], sweep.theta3, sweep.omega3, sweep.alpha3, pos_a, vel_a, acc_a),
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
            sweep.status == FEASIBLE, linkage.branch,
        )
    return LoopMotion(
        "slider-crank", theta2, sweep.theta3, line, w2, sweep.omega3, zero, al2, sweep.alpha3, zero,
        joints, links, sweep.status, REASONS, sweep.x, sweep.x_dot, sweep.x_ddot, crossings,
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


def factor_reaches(linkage: SliderCrank) -> tuple[float, float]:
    """How small 1 - sin(psi) and 1 + sin(psi) may get before a position is reported as a branch
    point: ``fourbar.CHANGE_POINT_REACH`` for the factor that touches zero at a change point (1 -
    sin(psi) where |e - b| = a, 1 + sin(psi) where |e + b| = a: a double zero, whose rounding costs
    the accelerations their digits as at a four-bar's; measured, the joint forces of a slider-crank
    with a = b are 2e-6 off at 4.5e-8 and 1.7e-3 at 4.5e-10), TOGGLE_TOLERANCE otherwise."""
    a, b, e = linkage.crank, linkage.rod, linkage.offset
    tol = CHANGE_POINT_TOLERANCE * (a + b + abs(e))
    minus = CHANGE_POINT_REACH if abs(abs(e - b) - a) <= tol else TOGGLE_TOLERANCE
    plus = CHANGE_POINT_REACH if abs(abs(e + b) - a) <= tol else TOGGLE_TOLERANCE
    return minus, plus


@dataclass(frozen=True)
class _Sweep:
    """The arrays a sweep fills a block of rows at a time, as ``LoopMotion`` holds them."""

    theta3: FloatArray
    omega3: FloatArray
    alpha3: FloatArray
    x: FloatArray
    x_dot: FloatArray
    x_ddot: FloatArray
    status: np.ndarray
    pos_a: FloatArray
    vel_a: FloatArray
    acc_a: FloatArray
    pos_b: FloatArray
    vel_b: FloatArray
    acc_b: FloatArray

    @classmethod
    def empty(cls, n: int) -> _Sweep:
        vectors, pairs = empty_arrays(n, 6, 6)
        return cls(*vectors, np.zeros(n, np.int8), *pairs)


def _solve_rows(linkage: SliderCrank, theta2, w2, al2, out: _Sweep, rows: slice) -> None:
    """Rows ``rows`` of ``out`` for crank angles ``theta2`` [rad], speeds ``w2`` [rad/s] and
    accelerations ``al2`` [rad/s^2] (P,), in a few reused temporaries of the block's length."""
    a, b, e = linkage.crank, linkage.rod, linkage.offset
    ux, uy = linkage.direction
    nx, ny = -uy, ux
    w, al = w2[rows], al2[rows]
    rax, ray, along, sin_psi, cos_psi, r3x, r3y, tmp, tmp2 = np.empty((9, rows.stop - rows.start))
    # positions (Norton eqs. 4.16-4.17 in the line's frame)
    np.cos(theta2[rows], out=rax)
    rax *= a
    np.sin(theta2[rows], out=ray)
    ray *= a
    a_along = dot_into(rax, ux, ray, uy, along, tmp)  # a cos(phi)
    a_across = dot_into(rax, nx, ray, ny, sin_psi, tmp)  # a sin(phi)
    np.subtract(e, a_across, out=sin_psi)
    sin_psi /= b
    one_minus = np.subtract(1.0, sin_psi, out=tmp)
    one_plus = np.add(sin_psi, 1.0, out=tmp2)
    reach_minus, reach_plus = factor_reaches(linkage)
    all_feasible = one_minus.min() > reach_minus and one_plus.min() > reach_plus
    bad = None if all_feasible else (one_minus <= reach_minus) | (one_plus <= reach_plus)
    if not all_feasible:
        near_minus, near_plus = one_minus[bad] <= reach_minus, one_plus[bad] <= reach_plus
        at_change_point = (near_minus & (reach_minus == CHANGE_POINT_REACH)) | (
            near_plus & (reach_plus == CHANGE_POINT_REACH))
        far = (one_minus[bad] < -TOGGLE_TOLERANCE) | (one_plus[bad] < -TOGGLE_TOLERANCE)
        out.status[rows][bad] = np.where(far, TOO_FAR, np.where(at_change_point, CHANGE_POINT, TOGGLE))
    np.multiply(one_minus, one_plus, out=cos_psi)
    if not all_feasible:  # elsewhere both factors exceed their reach
        np.maximum(cos_psi, 0.0, out=cos_psi)
    np.sqrt(cos_psi, out=cos_psi)
    cos_psi *= linkage.sigma

    dot_into(cos_psi, ux, sin_psi, nx, r3x, tmp2)  # B - A
    r3x *= b
    dot_into(cos_psi, uy, sin_psi, ny, r3y, tmp2)
    r3y *= b
    angle_of(r3y, r3x, out.theta3[rows], tmp2)
    x = np.multiply(cos_psi, b, out=out.x[rows])
    x += a_along
    pos_a, pos_b = out.pos_a[rows], out.pos_b[rows]
    for k, (ra, r3) in enumerate(((rax, r3x), (ray, r3y))):
        np.add(ra, linkage.o2[k], out=pos_a[:, k])
        np.add(pos_a[:, k], r3, out=pos_b[:, k])

    # velocities (eq. 6.20) and accelerations (eq. 7.16)
    b_cos = np.multiply(cos_psi, b, out=r3x)
    if not all_feasible:
        b_cos[bad] = 1.0
    b_sin = np.multiply(sin_psi, b, out=sin_psi)
    vax = np.multiply(w, ray, out=r3y)
    np.negative(vax, out=vax)
    vay = np.multiply(w, rax, out=along)
    omega3, alpha3 = out.omega3[rows], out.alpha3[rows]
    dot_into(vax, nx, vay, ny, omega3, tmp)
    np.negative(omega3, out=omega3)
    omega3 /= b_cos
    x_dot = dot_into(vax, ux, vay, uy, out.x_dot[rows], tmp)
    x_dot -= np.multiply(omega3, b_sin, out=tmp)
    set_columns(out.vel_a[rows], vax, vay)

    w2sq = np.multiply(w, w, out=tmp2)
    aax = np.multiply(al, ray, out=vax)
    np.negative(aax, out=aax)
    aax -= np.multiply(w2sq, rax, out=tmp)
    aay = np.multiply(al, rax, out=vay)
    aay -= np.multiply(w2sq, ray, out=tmp)
    set_columns(out.acc_a[rows], aax, aay)
    w3sq = np.multiply(omega3, omega3, out=tmp2)
    np.multiply(w3sq, b_sin, out=alpha3)
    alpha3 -= dot_into(aax, nx, aay, ny, rax, tmp)
    alpha3 /= b_cos
    x_ddot = dot_into(aax, ux, aay, uy, out.x_ddot[rows], tmp)
    x_ddot -= np.multiply(alpha3, b_sin, out=tmp)
    np.multiply(w3sq, b, out=tmp)
    x_ddot -= np.multiply(tmp, cos_psi, out=tmp)
    if not all_feasible:
        for rate in (omega3, alpha3, x_dot, x_ddot):
            rate[bad] = 0.0
    vel_b, acc_b = out.vel_b[rows], out.acc_b[rows]
    for k, direction in enumerate((ux, uy)):
        np.multiply(x_dot, direction, out=vel_b[:, k])
        np.multiply(x_ddot, direction, out=acc_b[:, k])
