"""Newton-Euler joint forces of planar pin-jointed assemblies, one linear system per position.

Each moving body k gives three equations (Norton, Design of Machinery, eqs. 11.1 and 11.9):

    sum F = m_k a_Gk,    sum (r_P - r_Gk) x F_P + sum C = I_Gk alpha_k

The unknowns are the pin forces (two per pin), the reaction of each slide (a force normal to its
line and a couple), the torque of each actuator and the force of each force actuator. For a four-bar this is exactly Norton's 9 x 9
system (eq. 11.9); for a slider-crank his eq. 11.14 with Coulomb friction F = -mu |N| sign(v) on the
slide. A slide's guide may be a moving body (a block in a slotted lever): it takes the opposite
force at the same point and the opposite couple, and friction follows the relative sliding
velocity. A pin joining k bodies is k - 1 ``Pin``s, each between one of them and the same other
body (``pins_of``): the pin itself, massless, passes the rest to that body. All positions are assembled at once and solved as a batch; a position where the system is
singular (a toggle, where the joint forces are unbounded) is reported, not solved.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from linkstress.threads import cores, even_blocks, in_parallel

GROUND = -1
"""Body index of the fixed frame."""

SINGULAR_RATIO = 1e-12
"""Positions whose scaled system has |det A| below this fraction of the product of its row norms
(Hadamard's bound, which |det A| reaches for orthogonal rows) are reported as singular."""


@dataclass(frozen=True)
class Body:
    """A moving rigid body over P positions: mass [kg], inertia about G [kg m^2], G's position and
    acceleration (P, 2) [m, m/s^2] and angular acceleration (P,) [rad/s^2], ground frame."""

    name: str
    mass: float
    inertia: float
    position_g: NDArray[np.float64]
    acc_g: NDArray[np.float64]
    alpha: NDArray[np.float64]


@dataclass(frozen=True)
class Pin:
    """A revolute joint at ``position`` (P, 2) [m]. Its unknown F is the force on ``body`` from
    ``other`` (GROUND for the frame); ``other`` receives -F."""

    name: str
    body: int
    other: int
    position: NDArray[np.float64]


@dataclass(frozen=True)
class Slide:
    """A prismatic joint between ``body`` and its ``guide`` (GROUND: the frame) along the unit
    ``direction`` (2,) or (P, 2).

    The guide pushes ``body`` with N n + f u at ``position`` (P, 2), n = k x u, plus a couple, and
    takes the opposite; with ``friction`` mu > 0, f = -mu |N| sign(velocity) for ``velocity`` (P,)
    [m/s], the body's sliding velocity along u relative to the guide.
    """

    name: str
    body: int
    direction: NDArray[np.float64]
    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    friction: float = 0.0
    guide: int = GROUND


@dataclass(frozen=True)
class Actuator:
    """An unknown torque T [N m] on ``body`` (counter-clockwise), reacting as -T on ``other``."""

    name: str
    body: int
    other: int = GROUND


@dataclass(frozen=True)
class ForceActuator:
    """An unknown force P [N] on ``body`` along the unit ``direction`` (2,) or (P, 2) at ``position``
    (P, 2) (a cylinder pushing a slider), reacting on ``other`` (GROUND: the frame) at the same point."""

    name: str
    body: int
    direction: NDArray[np.float64]
    position: NDArray[np.float64]
    other: int = GROUND


@dataclass(frozen=True)
class AppliedForce:
    """A known force (P, 2) [N] on ``body`` at ``point`` (P, 2) [m], ground frame."""

    body: int
    point: NDArray[np.float64]
    force: NDArray[np.float64]


@dataclass(frozen=True)
class AppliedCouple:
    """A known couple (P,) [N m], counter-clockwise, on ``body``."""

    body: int
    couple: NDArray[np.float64]


@dataclass(frozen=True)
class Assembly:
    """Bodies, joints, actuators and known loads of a machine over P positions."""

    bodies: tuple[Body, ...]
    pins: tuple[Pin, ...]
    actuators: tuple[Actuator, ...]
    slides: tuple[Slide, ...] = ()
    forces: tuple[AppliedForce, ...] = ()
    couples: tuple[AppliedCouple, ...] = ()
    gravity: NDArray[np.float64] = field(default_factory=lambda: np.zeros(2))
    force_actuators: tuple[ForceActuator, ...] = ()


@dataclass(frozen=True)
class ForceSolution:
    """Joint forces over P positions, ground frame.

    pin_forces[name] (P, 2) [N]: force on the pin's ``body`` from its ``other``. slide_forces[name]
    (P, 2) [N]: total force of the ground on the slider (normal + friction); slide_couples[name] (P,)
    [N m]. torques[name] (P,) [N m] of the actuators; actuator_forces[name] (P,) [N] of the force
    actuators. ``solved`` (P,) is False where the system is singular (and the values there are zero
    filler).
    """

    pin_forces: dict[str, NDArray[np.float64]]
    slide_forces: dict[str, NDArray[np.float64]]
    slide_couples: dict[str, NDArray[np.float64]]
    torques: dict[str, NDArray[np.float64]]
    actuator_forces: dict[str, NDArray[np.float64]]
    solved: NDArray[np.bool_]


def pins_of(name: str, bodies: list[int], position: NDArray[np.float64]) -> tuple[Pin, ...]:
    """A pin at ``position`` (P, 2) joining ``bodies`` (two or more; GROUND allowed, first if
    present): one ``Pin`` "NAME|k" per body but the first, its force on that body from the first."""
    first, *rest = sorted(bodies, key=lambda b: b != GROUND)
    return tuple(Pin(f"{name}|{k}", body, first, position) for k, body in enumerate(rest))


def _cross(r: NDArray[np.float64], f: NDArray[np.float64]) -> NDArray[np.float64]:
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def _length_scale(assembly: Assembly) -> float:
    points = [p.position for p in assembly.pins] + [b.position_g for b in assembly.bodies]
    # (2, n): each coordinate a contiguous row, so that its extremes are two fast reductions
    stacked = np.concatenate([p.reshape(-1, 2).T for p in points], axis=1)
    span = float((stacked.max(axis=1) - stacked.min(axis=1)).max()) if stacked.shape[1] else 0.0
    return span if span > 0 else 1.0


def solve_forces(assembly: Assembly, mask: NDArray[np.bool_] | None = None) -> ForceSolution:
    """Solve the Newton-Euler system at every position where ``mask`` (P,) is True (default: all)."""
    bodies, n_pos = assembly.bodies, len(assembly.bodies[0].alpha)
    mask = np.ones(n_pos, bool) if mask is None else np.asarray(mask, bool)
    n_eq = 3 * len(bodies)
    n_unknowns = (2 * len(assembly.pins) + 2 * len(assembly.slides) + len(assembly.actuators)
                  + len(assembly.force_actuators))
    if n_unknowns != n_eq:
        raise ValueError(f"assembly has {n_eq} equations and {n_unknowns} unknowns")
    scale = _length_scale(assembly)
    rhs = _right_hand_side(assembly, n_pos, scale)
    friction_sign = np.zeros((n_pos, len(assembly.slides)))
    matrix = _matrix(assembly, n_pos, scale, friction_sign)
    solved, x = _solve_systems(matrix, rhs, mask)
    if any(s.friction > 0 for s in assembly.slides):
        # Friction follows the sign of the normal force: solve without, then with that sign (Norton 11.8).
        for _ in range(3):
            normal = x[:, _slide_columns(assembly)[0::2]]
            new_sign = np.sign(normal)
            if np.array_equal(new_sign, friction_sign):
                break
            friction_sign = new_sign
            matrix = _matrix(assembly, n_pos, scale, friction_sign)
            solved, x = _solve_systems(matrix, rhs, mask)
    return _unpack(assembly, x, scale, friction_sign, solved)


THREADED_SYSTEMS = 1000
"""Positions from which the systems are factorised on every core (LAPACK lets go of the interpreter
lock): 3,600 systems of 9 x 9 took 13 ms on one core, 10 ms on two."""


def _solve_systems(matrix, rhs, mask):
    """Where ``mask`` holds and the system is regular (``_regular``): ``solved`` (P,), and the
    solutions ``x`` (P, n) there (zeros elsewhere); long sweeps in a block of positions per core."""
    solved, x = np.empty(len(matrix), bool), np.zeros_like(rhs)

    def solve(p: slice) -> None:
        solved[p] = mask[p] & _regular(matrix[p])
        x[p] = _batched_solve(matrix[p], rhs[p], solved[p])

    pieces = cores() if len(matrix) >= THREADED_SYSTEMS else 1
    in_parallel(solve, even_blocks(len(matrix), pieces))
    return solved, x


def _regular(matrix: NDArray[np.float64]) -> NDArray[np.bool_]:
    """(P,) True where the system is far from singular (one LU per position, no SVD)."""
    sign, logdet = np.linalg.slogdet(matrix)
    with np.errstate(divide="ignore"):  # an empty row has det 0: sign 0 decides
        log_rows = np.log(np.einsum("pij,pij->pi", matrix, matrix)).sum(axis=1) / 2
    return (sign != 0) & (logdet - log_rows > np.log(SINGULAR_RATIO))


def _batched_solve(matrix, rhs, solved):
    if solved.all():  # no copy of the systems
        return np.linalg.solve(matrix, rhs[..., None])[..., 0]
    x = np.zeros_like(rhs)
    if solved.any():
        x[solved] = np.linalg.solve(matrix[solved], rhs[solved][..., None])[..., 0]
    return x


def _slide_columns(assembly: Assembly) -> NDArray[np.intp]:
    start = 2 * len(assembly.pins)
    return np.arange(start, start + 2 * len(assembly.slides))


def _friction_coefficients(slide: Slide, sign_n: NDArray[np.float64]) -> NDArray[np.float64]:
    """c in f = c N: f = -mu |N| sign(v) = -mu sign(N) sign(v) N."""
    return -slide.friction * sign_n * np.sign(slide.velocity)


def _matrix(assembly: Assembly, n_pos: int, scale: float, friction_sign) -> NDArray[np.float64]:
    bodies = assembly.bodies
    a = np.zeros((n_pos, 3 * len(bodies), 3 * len(bodies)))

    def force_columns(body: int, sign: float, col_x: int, col_y: int, point, coeff_x, coeff_y):
        """Add a force sign * (coeff_x * u_x, coeff_y * u_y) acting at ``point`` on ``body``."""
        if body == GROUND:
            return
        r = point - bodies[body].position_g
        row = 3 * body
        a[:, row, col_x] += sign * coeff_x[..., 0]
        a[:, row + 1, col_x] += sign * coeff_x[..., 1]
        a[:, row + 2, col_x] += sign * _cross(r, coeff_x) / scale
        if col_y is not None:
            a[:, row, col_y] += sign * coeff_y[..., 0]
            a[:, row + 1, col_y] += sign * coeff_y[..., 1]
            a[:, row + 2, col_y] += sign * _cross(r, coeff_y) / scale

    ex = np.broadcast_to([1.0, 0.0], (n_pos, 2))
    ey = np.broadcast_to([0.0, 1.0], (n_pos, 2))
    for k, pin in enumerate(assembly.pins):
        for body, sign in ((pin.body, 1.0), (pin.other, -1.0)):
            force_columns(body, sign, 2 * k, 2 * k + 1, pin.position, ex, ey)
    col = 2 * len(assembly.pins)
    for s, slide in enumerate(assembly.slides):
        u = np.broadcast_to(np.asarray(slide.direction, float), (n_pos, 2))
        n = np.stack([-u[:, 1], u[:, 0]], axis=-1)
        along = n + _friction_coefficients(slide, friction_sign[:, s])[:, None] * u
        force_columns(slide.body, 1.0, col, None, slide.position, along, None)
        force_columns(slide.guide, -1.0, col, None, slide.position, along, None)
        a[:, 3 * slide.body + 2, col + 1] += 1.0  # the guide's couple, solved for as C / scale
        if slide.guide != GROUND:
            a[:, 3 * slide.guide + 2, col + 1] -= 1.0
        col += 2
    for actuator in assembly.actuators:
        a[:, 3 * actuator.body + 2, col] += 1.0
        if actuator.other != GROUND:
            a[:, 3 * actuator.other + 2, col] -= 1.0
        col += 1
    for actuator in assembly.force_actuators:
        u = np.broadcast_to(np.asarray(actuator.direction, float), (n_pos, 2))
        force_columns(actuator.body, 1.0, col, None, actuator.position, u, None)
        force_columns(actuator.other, -1.0, col, None, actuator.position, u, None)
        col += 1
    return a


def _right_hand_side(assembly: Assembly, n_pos: int, scale: float) -> NDArray[np.float64]:
    b = np.zeros((n_pos, 3 * len(assembly.bodies)))
    g = np.asarray(assembly.gravity, float)
    for k, body in enumerate(assembly.bodies):
        b[:, 3 * k : 3 * k + 2] = body.mass * (body.acc_g - g)
        b[:, 3 * k + 2] = body.inertia * body.alpha / scale
    for load in assembly.forces:
        r = load.point - assembly.bodies[load.body].position_g
        b[:, 3 * load.body : 3 * load.body + 2] -= load.force
        b[:, 3 * load.body + 2] -= _cross(r, load.force) / scale
    for load in assembly.couples:
        b[:, 3 * load.body + 2] -= load.couple / scale
    return b


def _unpack(assembly: Assembly, x, scale: float, friction_sign, solved) -> ForceSolution:
    pins = {pin.name: x[:, 2 * k : 2 * k + 2] for k, pin in enumerate(assembly.pins)}
    slide_forces, slide_couples = {}, {}
    col = 2 * len(assembly.pins)
    for s, slide in enumerate(assembly.slides):
        u = np.broadcast_to(np.asarray(slide.direction, float), (len(x), 2))
        n = np.stack([-u[:, 1], u[:, 0]], axis=-1)
        normal = x[:, col]
        friction = _friction_coefficients(slide, friction_sign[:, s]) * normal
        slide_forces[slide.name] = normal[:, None] * n + friction[:, None] * u
        slide_couples[slide.name] = x[:, col + 1] * scale
        col += 2
    torques = {}
    for actuator in assembly.actuators:
        torques[actuator.name] = x[:, col] * scale
        col += 1
    pushes = {}
    for actuator in assembly.force_actuators:
        pushes[actuator.name] = x[:, col]
        col += 1
    return ForceSolution(pins, slide_forces, slide_couples, torques, pushes, solved)
