"""Joint forces by Newton-Euler, written from the textbook for the cases' independent truths, and
the power balance that checks them.

Every moving link is a rigid body: sum F = m a_G and sum M_G = I_G alpha (Uicker, Pennock & Shigley,
Theory of Machines and Mechanisms, ch. 13; Norton, Design of Machinery, ch. 11). Unknowns:

- a pin joining k links: k - 1 forces (x, y), each on one of its links from its reference link (the
  ground's, when the ground is in the pin, else the first); the reference takes their sum, opposite:
  the pin itself is massless;
- a slider: the guide's push N on the block along the line's left normal n = k x u (u the line's
  direction, from its joint i toward j), at the slider's point, and (with a block) a couple C on the
  block; the guide takes -N n there and -C. Without a block the point's link takes N n itself;
- the input: a torque T on the crank (reacting on the ground), or a force F along u on the input
  slider's block (reacting on its guide at the point).

One dense square system per position, solved for all positions at once (numpy's batched solve).
The power balance (input power = d/dt kinetic energy - power of the applied loads, gravity
included) needs no second solver: the constraint forces do no work on velocities the joints allow.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Body:
    """A moving link over P positions: mass [kg], inertia about G [kg m^2], G (P, 2) [m] and its
    acceleration (P, 2) [m/s^2], the angular acceleration (P,) [rad/s^2]."""

    name: str
    mass: float
    inertia: float
    com: FloatArray
    com_acceleration: FloatArray
    alpha: FloatArray


@dataclass(frozen=True)
class PinJoint:
    """A pin: the joints it joins ("LINK:i") and their links, at ``at`` (P, 2) [m]."""

    joints: tuple[str, ...]
    links: tuple[str, ...]
    at: FloatArray


@dataclass(frozen=True)
class Slide:
    """The block (or, without one, the point's link) ``carrier`` sliding on ``guide`` at ``at``
    (P, 2) along the unit ``direction`` (P, 2); ``has_block``: a couple is carried too."""

    carrier: str
    guide: str
    at: FloatArray
    direction: FloatArray
    has_block: bool


@dataclass(frozen=True)
class Load:
    """Known loads on a link: a force (P, 2) [N] at ``at`` (P, 2) [m], or a couple (P,) [N m]."""

    link: str
    force: FloatArray | None = None
    at: FloatArray | None = None
    couple: FloatArray | None = None


@dataclass(frozen=True)
class Forces:
    """Per pin the force (P, 2) [N] it puts on each joint's link; per slide N (P,) [N] and C (P,)
    [N m] (zero without a block); the input's torque [N m] or force [N] (P,)."""

    pins: tuple[dict[str, FloatArray], ...]
    normals: tuple[FloatArray, ...]
    couples: tuple[FloatArray, ...]
    drive: FloatArray
    columns: dict[str, int] = field(repr=False)


def solve(bodies: list[Body], ground: str, pins: list[PinJoint], slides: list[Slide], drive: tuple,
          loads: list[Load], gravity: FloatArray) -> Forces:
    """The joint forces at every position. ``drive``: ("torque", crank link) or ("force", slide index)."""
    rows = {b.name: 3 * k for k, b in enumerate(bodies)}
    com = {b.name: b.com for b in bodies}
    n_pos = len(bodies[0].alpha)
    columns: dict[str, int] = {}
    entries: list[tuple[str, int, FloatArray, FloatArray, FloatArray | None]] = []
    # Each entry: (link, column, force per unit unknown (P, 2), its point (P, 2), couple per unit or None).

    def column(name: str) -> int:
        columns[name] = len(columns)
        return columns[name]

    for p, pin in enumerate(pins):
        reference = pin.links.index(ground) if ground in pin.links else 0
        for k, (joint, link) in enumerate(zip(pin.joints, pin.links)):
            if k == reference:
                continue
            for axis in (0, 1):
                c = column(f"pin{p}|{joint}|{'xy'[axis]}")
                e = np.zeros((n_pos, 2))
                e[:, axis] = 1.0
                entries.append((link, c, e, pin.at, None))
                entries.append((pin.links[reference], c, -e, pin.at, None))
    for s, slide in enumerate(slides):
        normal = np.column_stack([-slide.direction[:, 1], slide.direction[:, 0]])
        c = column(f"slide{s}|N")
        entries.append((slide.carrier, c, normal, slide.at, None))
        entries.append((slide.guide, c, -normal, slide.at, None))
        if slide.has_block:
            c = column(f"slide{s}|C")
            zero = np.zeros((n_pos, 2))
            entries.append((slide.carrier, c, zero, slide.at, np.ones(n_pos)))
            entries.append((slide.guide, c, zero, slide.at, -np.ones(n_pos)))
    c = column("drive")
    if drive[0] == "torque":
        entries.append((drive[1], c, np.zeros((n_pos, 2)), np.zeros((n_pos, 2)), np.ones(n_pos)))
    else:
        slide = slides[drive[1]]
        entries.append((slide.carrier, c, slide.direction, slide.at, None))
        entries.append((slide.guide, c, -slide.direction, slide.at, None))

    size = 3 * len(bodies)
    if len(columns) != size:
        raise ValueError(f"{len(columns)} unknowns for {size} equations: the joints do not make one degree of freedom")
    matrix = np.zeros((n_pos, size, size))
    for link, c, force, at, couple in entries:
        if link == ground:
            continue
        r = rows[link]
        arm = at - com[link]
        matrix[:, r, c] += force[:, 0]
        matrix[:, r + 1, c] += force[:, 1]
        matrix[:, r + 2, c] += arm[:, 0] * force[:, 1] - arm[:, 1] * force[:, 0]
        if couple is not None:
            matrix[:, r + 2, c] += couple

    rhs = np.zeros((n_pos, size))
    for b in bodies:
        r = rows[b.name]
        rhs[:, r:r + 2] = b.mass * (b.com_acceleration - gravity)
        rhs[:, r + 2] = b.inertia * b.alpha
    for load in loads:
        r = rows[load.link]
        if load.force is not None:
            arm = load.at - com[load.link]
            rhs[:, r:r + 2] -= load.force
            rhs[:, r + 2] -= arm[:, 0] * load.force[:, 1] - arm[:, 1] * load.force[:, 0]
        if load.couple is not None:
            rhs[:, r + 2] -= load.couple
    x = np.linalg.solve(matrix, rhs[..., None])[..., 0]

    pin_forces = []
    for p, pin in enumerate(pins):
        on = {joint: np.zeros((n_pos, 2)) for joint in pin.joints}
        reference = pin.joints[pin.links.index(ground) if ground in pin.links else 0]
        for joint in pin.joints:
            if joint == reference:
                continue
            force = np.column_stack([x[:, columns[f"pin{p}|{joint}|x"]], x[:, columns[f"pin{p}|{joint}|y"]]])
            on[joint] += force
            on[reference] -= force
        pin_forces.append(on)
    normals = tuple(x[:, columns[f"slide{s}|N"]] for s in range(len(slides)))
    couples = tuple(
        x[:, columns[f"slide{s}|C"]] if slide.has_block else np.zeros(n_pos) for s, slide in enumerate(slides)
    )
    return Forces(tuple(pin_forces), normals, couples, x[:, columns["drive"]], columns)


@dataclass(frozen=True)
class Power:
    """The power balance per position [W]: the input's power, the rate of kinetic energy, the power
    of the applied loads (gravity included), and input - (kinetic - applied)."""

    input: FloatArray
    kinetic: FloatArray
    applied: FloatArray

    @property
    def mismatch(self) -> FloatArray:
        return self.input - (self.kinetic - self.applied)


def power_balance(bodies: list[Body], velocities: dict[str, FloatArray], omegas: dict[str, FloatArray],
                  loads: list[Load], load_velocities: list[FloatArray | None], gravity: FloatArray,
                  input_power: FloatArray) -> Power:
    """``velocities``: each body's G velocity (P, 2); ``omegas``: each link's (P,); per load the
    velocity (P, 2) of the point its force acts at (None for a couple alone).

    d/dt KE = sum (m v_G . a_G + I omega alpha); applied = sum (m g . v_G + F . v + C omega)."""
    kinetic = sum(
        b.mass * np.sum(velocities[b.name] * b.com_acceleration, axis=1) + b.inertia * omegas[b.name] * b.alpha
        for b in bodies
    )
    applied = sum(b.mass * velocities[b.name] @ gravity for b in bodies)
    for load, v in zip(loads, load_velocities):
        if load.force is not None:
            applied = applied + np.sum(load.force * v, axis=1)
        if load.couple is not None:
            applied = applied + load.couple * omegas[load.link]
    return Power(np.asarray(input_power, float), kinetic, applied)
