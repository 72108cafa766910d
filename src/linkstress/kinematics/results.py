"""What a kinematic sweep returns: the motion of every link, joint and loop over P positions.

All arrays are in the ground frame, SI units: positions [m], velocities [m/s], accelerations
[m/s^2], angles [rad] counter-clockwise from the ground frame's +x (any 2 pi representative),
angular velocities [rad/s] and accelerations [rad/s^2] counter-clockwise positive.

At a position that is not feasible (a toggle, an input angle the loop cannot reach) the arrays hold
finite filler values and nothing downstream may read them: ``feasible`` says where they hold.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from linkstress.kinematics.linkage.sweep import LinkageMotion

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class LinkMotion:
    """Rigid-body motion of one link over P positions.

    The link's member frame has its origin at joint ``frame_joints[0]`` and +x toward joint
    ``frame_joints[1]`` (the axis its loop uses: crank O2->A, coupler A->B, output O4->B, ground
    O2->O4). A slider's frame is ``(k, k)``: origin at its joint B, +x along the slider line.

    angle (P,) [rad] of that +x axis; omega (P,) [rad/s]; alpha (P,) [rad/s^2];
    origin, origin_velocity, origin_acceleration (P, 2) [m, m/s, m/s^2] of the frame origin.
    """

    frame_joints: tuple[int, int]
    angle: FloatArray
    omega: FloatArray
    alpha: FloatArray
    origin: FloatArray
    origin_velocity: FloatArray
    origin_acceleration: FloatArray

    def point(self, local: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position, velocity and acceleration of material points of the link, ground frame.

        ``local`` (2,) or (Q, 2) [m] in the member frame. Returns three arrays of shape (P, 2) or
        (P, Q, 2): r = O + R r', v = v_O + omega k x (R r'), a = a_O + alpha k x (R r') - omega^2 R r'
        (rigid-body kinematics, Norton, Design of Machinery, eqs. 6.5 and 7.4).
        """
        r_local = np.asarray(local, float)
        if r_local.shape[-1:] != (2,) or r_local.ndim not in (1, 2):
            raise ValueError(f"local points must have shape (2,) or (Q, 2), got {r_local.shape}")
        many = r_local.ndim == 2
        c, s = np.cos(self.angle), np.sin(self.angle)
        if many:
            c, s = c[:, None], s[:, None]
        x, y = r_local[..., 0], r_local[..., 1]
        rx, ry = c * x - s * y, s * x + c * y
        w = self.omega[:, None] if many else self.omega
        al = self.alpha[:, None] if many else self.alpha
        origin, vel, acc = self.origin, self.origin_velocity, self.origin_acceleration
        if many:
            origin, vel, acc = origin[:, None, :], vel[:, None, :], acc[:, None, :]
        position = origin + np.stack([rx, ry], axis=-1)
        velocity = vel + np.stack([-w * ry, w * rx], axis=-1)
        w2 = w * w
        acceleration = acc + np.stack([-al * ry - w2 * rx, al * rx - w2 * ry], axis=-1)
        return position, velocity, acceleration


@dataclass(frozen=True)
class JointMotion:
    """Position, velocity and acceleration (P, 2) [m, m/s, m/s^2] of one joint, ground frame."""

    position: FloatArray
    velocity: FloatArray
    acceleration: FloatArray


@dataclass(frozen=True)
class Crossing:
    """A step from position ``position - 1`` to ``position`` that passes branch point ``kind`` at
    crank angle ``angle`` [rad] (the 2 pi representative inside the step). ``root`` is the branch
    ("open" or "crossed") the rows from ``position`` follow; at a change point with named assembly
    modes, ``modes`` names both ("parallelogram or antiparallelogram") and ``mode`` the one those
    rows are in, else both are ""."""

    position: int
    angle: float
    kind: str
    root: str
    mode: str = ""
    modes: str = ""


@dataclass(frozen=True)
class LoopMotion:
    """One loop (four-bar or slider-crank) over P positions.

    ``joints``: "O2", "A", "B", "O4" for a four-bar; "O2", "A", "B" for a slider-crank.
    theta2..theta4 (P,) [rad]: crank O2->A, coupler A->B, output O4->B (a slider-crank's theta4 is
    its slider line's angle); omega/alpha likewise. ``slider_position`` (P,) [m]: the slider's
    distance along its line from the foot of the perpendicular from O2, with its velocity and
    acceleration (None for a four-bar). ``status`` (P,) indexes ``reason_texts`` ("" = feasible).
    ``links`` maps each role ("crank", "coupler", "output", "ground", "slider") to its motion.
    ``crossings``: the steps between two feasible positions that pass one of the loop's toggles or
    change points, in row order (``kinematics.crossings``).
    """

    kind: str
    theta2: FloatArray
    theta3: FloatArray
    theta4: FloatArray
    omega2: FloatArray
    omega3: FloatArray
    omega4: FloatArray
    alpha2: FloatArray
    alpha3: FloatArray
    alpha4: FloatArray
    joints: dict[str, JointMotion]
    links: dict[str, LinkMotion]
    status: NDArray[np.int8]
    reason_texts: tuple[str, ...]
    slider_position: FloatArray | None = None
    slider_velocity: FloatArray | None = None
    slider_acceleration: FloatArray | None = None
    crossings: tuple[Crossing, ...] = ()

    @property
    def feasible(self) -> NDArray[np.bool_]:
        """(P,) True where the loop assembles with finite rates."""
        return self.status == 0

    @property
    def reasons(self) -> tuple[str, ...]:
        """Per position: "" where feasible, else why not."""
        return tuple(np.asarray(self.reason_texts, dtype=object)[self.status].tolist())

    @cached_property
    def transmission_angle(self) -> FloatArray:
        """(P,) [rad] in [0, pi/2]: Norton's transmission angle (eq. 4.32), the acute angle between
        coupler and output; for a slider-crank between the rod and the normal to the slider line."""
        d = self.theta4 - self.theta3
        if self.kind == "slider-crank":
            return np.arctan2(np.abs(np.cos(d)), np.abs(np.sin(d)))
        return np.arctan2(np.abs(np.sin(d)), np.abs(np.cos(d)))


@dataclass(frozen=True)
class MachineMotion:
    """A machine of chained loops over P positions, driven at its main crank.

    input_angle (P,) [rad], input_speed (P,) [rad/s], input_acceleration (P,) [rad/s^2] of the main
    crank; ``time`` (P,) [s] when the motion is a function of time, else None. ``feasible`` (P,) is
    False where any loop is infeasible, ``reasons`` says why ("" where feasible). ``links`` holds every
    link by scene name (grounds with zero motion); ``loops`` every loop by mechanism name.
    ``crossings``: (row, message) for every step into that row that passes a loop's toggle or
    change point between feasible positions (the row stays feasible; ``warnings`` per position).
    ``linkage``: for a ``type = "linkage"`` mechanism (no loops), every joint's motion and the
    groups it was solved in (``linkage.sweep.LinkageMotion``); None for loops.
    """

    input_angle: FloatArray
    input_speed: FloatArray
    input_acceleration: FloatArray
    time: FloatArray | None
    feasible: NDArray[np.bool_]
    reasons: tuple[str, ...]
    links: dict[str, LinkMotion]
    loops: dict[str, LoopMotion]
    crossings: tuple[tuple[int, str], ...] = ()
    linkage: LinkageMotion | None = None

    @cached_property
    def warnings(self) -> tuple[tuple[str, ...], ...]:
        """Per position: the messages of the crossings into that row (empty almost everywhere)."""
        per_row: list[tuple[str, ...]] = [()] * self.input_angle.shape[0]
        for row, message in self.crossings:
            per_row[row] += (message,)
        return tuple(per_row)


def fixed_link(frame_joints: tuple[int, int], angle: float, origin: ArrayLike, n: int) -> LinkMotion:
    """A link that does not move (a ground): constant ``angle`` [rad] and ``origin`` [m] over ``n`` positions."""
    zero = np.broadcast_to(0.0, (n,))
    zero2 = np.broadcast_to(0.0, (n, 2))
    return LinkMotion(
        frame_joints,
        np.broadcast_to(float(angle), (n,)),
        zero,
        zero,
        np.broadcast_to(np.asarray(origin, float), (n, 2)),
        zero2,
        zero2,
    )
