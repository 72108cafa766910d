"""The loads on one link over a sweep of positions: what the beam engine and the FEA both apply.

Everything is in the link's member frame (origin at its frame joint i, +x toward joint j), which
moves with the link: vectors are the inertial quantities expressed in the member axes at that
instant. P positions, J joints (the link profile's joints, in its order).

The d'Alembert load per unit volume at a point r of the link is rho (g - a(r)) with
a(r) = a_O + alpha k x r - omega^2 r: the rigid-body acceleration of that material point.

A point force acts where it is given: in the link's material, or in one of its holes, where it is
the load of a pin in that hole (``hole_at``). Anywhere else is off the link (``distance_outside``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Polygon

from linkstress.geometry.profile import LinkProfile

OUTLINE_TOLERANCE = 1e-3
"""A point within this fraction of the outline's size (its bounding-box diagonal) outside the
outline is on it: a flattened arc runs up to a sagitta inside the drawn curve."""


@dataclass(frozen=True)
class PointForce:
    """A force applied at a fixed point of the link: ``at`` (2,) [m] and ``force`` (P, 2) [N], member frame.

    In material it acts at ``at``; in a hole it is the load of a pin in that hole."""

    at: NDArray[np.float64]
    force: NDArray[np.float64]


@dataclass(frozen=True)
class SlidingContact:
    """A slider block's push on the link it slides along (its guide), at a point that moves along
    the guide: ``at`` (P, 2) [m], ``force`` (P, 2) [N] and ``couple`` (P,) [N m], member frame.

    ``anchor`` is the guide's joint the slider's line starts at. The section forces take the
    contact as its equivalent there (``equivalent``: the same force and the couple that moves it),
    which keeps them linear in fixed load coefficients, and then correct the cuts between the anchor
    and the contact, where the force really enters (``linkstress.dynamics.section_stress``)."""

    at: NDArray[np.float64]
    force: NDArray[np.float64]
    couple: NDArray[np.float64]
    anchor: int
    length: float = 0.0
    """[m]: the block's length along the line, over which it bears (0: no block drawn)."""

    def record(self) -> dict[str, object]:
        """The contact as plain data (for cache keys)."""
        return {"at": np.asarray(self.at, float), "force": np.asarray(self.force, float),
                "couple": np.asarray(self.couple, float), "anchor": int(self.anchor), "length": float(self.length)}

    def equivalent(self, joints: NDArray[np.float64]) -> NDArray[np.float64]:
        """(P, 3): F_x, F_y [N] and the couple [N m] at the anchor (``joints`` (J, 2) [m], member
        frame) equivalent to the contact."""
        arm = self.at - np.asarray(joints, float)[self.anchor]
        return np.column_stack([self.force, self.couple + _cross(arm, self.force)])


@dataclass(frozen=True)
class LinkLoadCase:
    """Loads on a link over P positions, member frame of joints ``frame_joints``.

    pin_forces (P, J, 2) [N]: force on this link from its neighbour (or the ground) at each joint.
    joint_couples (P, J) [N m]: couples applied to the link at each joint, counter-clockwise positive
    (a driving torque acts at its pivot joint; an external couple at the joint the scene names).
    point_forces: forces at points of the link other than joints.
    contacts: the pushes of slider blocks that slide along the link (``SlidingContact``).
    omega (P,) [rad/s], alpha (P,) [rad/s^2]: the link's angular velocity and acceleration.
    origin_acceleration (P, 2) [m/s^2]: acceleration of the frame origin (joint i).
    gravity (P, 2) [m/s^2]: gravity in member axes (zero when the scene has none).
    """

    frame_joints: tuple[int, int]
    pin_forces: NDArray[np.float64]
    joint_couples: NDArray[np.float64]
    omega: NDArray[np.float64]
    alpha: NDArray[np.float64]
    origin_acceleration: NDArray[np.float64]
    gravity: NDArray[np.float64]
    point_forces: tuple[PointForce, ...] = field(default_factory=tuple)
    contacts: tuple[SlidingContact, ...] = field(default_factory=tuple)

    @property
    def n_positions(self) -> int:
        return len(self.omega)

    def at(self, positions: NDArray[np.intp]) -> "LinkLoadCase":
        """The same loads at a subset of the positions (indices into this sweep)."""
        k = np.asarray(positions, dtype=np.intp)
        return LinkLoadCase(
            self.frame_joints, self.pin_forces[k], self.joint_couples[k], self.omega[k], self.alpha[k],
            self.origin_acceleration[k], self.gravity[k],
            tuple(PointForce(pf.at, pf.force[k]) for pf in self.point_forces),
            tuple(SlidingContact(c.at[k], c.force[k], c.couple[k], c.anchor, c.length) for c in self.contacts),
        )

    def body_force_density(self, points: NDArray[np.float64], density: float) -> NDArray[np.float64]:
        """d'Alembert load per unit volume [N/m^3] at ``points`` (Q, 2) [m]: shape (P, Q, 2), member frame."""
        r = points[None, :, :]
        w2 = (self.omega**2)[:, None, None]
        al = self.alpha[:, None, None]
        a = self.origin_acceleration[:, None, :] + al * np.stack([-r[..., 1], r[..., 0]], axis=-1) - w2 * r
        return density * (self.gravity[:, None, :] - a)

    def residual(self, link: LinkProfile) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Net force (P, 2) [N] and net moment about the frame origin (P,) [N m] of all loads on
        ``link``, d'Alembert load included: zero for loads in dynamic equilibrium."""
        frame = link.frame(*self.frame_joints)
        return self.residual_of(
            link.mass, link.mass_moment_of_inertia, frame.to_local(link.center_of_mass), frame.to_local(link.joints),
        )

    def residual_of(
        self, mass: float, inertia: float, center_of_mass: NDArray[np.float64], joints: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``residual`` for a link given by its mass [kg], inertia about G [kg m^2], and its centre of
        mass (2,) and joints (J, 2) [m] in the member frame."""
        r_g = np.asarray(center_of_mass, float)
        free = self.gravity - self.origin_acceleration
        force = self.pin_forces.sum(axis=1) + mass * (
            free - self.alpha[:, None] * np.array([-r_g[1], r_g[0]]) + (self.omega**2)[:, None] * r_g
        )
        moment = (
            _cross(np.asarray(joints, float)[None, :, :], self.pin_forces).sum(axis=1)
            + self.joint_couples.sum(axis=1)
            + mass * _cross(r_g, free)
            - self.alpha * (inertia + mass * r_g @ r_g)
        )
        for pf in self.point_forces:
            force = force + pf.force
            moment = moment + _cross(pf.at, pf.force)
        for c in self.contacts:
            force = force + c.force
            moment = moment + _cross(c.at, c.force) + c.couple
        return force, moment


def _cross(r: NDArray[np.float64], f: NDArray[np.float64]) -> NDArray[np.float64]:
    """z-component of r x f over the last axis."""
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def hole_at(outline: Polygon, point: ArrayLike) -> int | None:
    """The index of the hole of ``outline`` (shapely interior order) whose area covers ``point``
    (2,) [m, the outline's frame], edge included; None for a point in material or off the link."""
    where = shapely.Point(np.asarray(point, float))
    for k, ring in enumerate(outline.interiors):
        if Polygon(ring).covers(where):
            return k
    return None


def contact_hole(outline: Polygon, contact: SlidingContact) -> int | None:
    """The hole of ``outline`` (shapely interior order, the contact's member frame) that holds the
    contact's point at every position (a slot the block runs in), None where some position has it
    in material or off the link."""
    points = shapely.points(np.asarray(contact.at, float).reshape(-1, 2))
    for k, ring in enumerate(outline.interiors):
        if shapely.covers(Polygon(ring), points).all():
            return k
    return None


def contacts_in_slots(outline: Polygon, loads: LinkLoadCase) -> bool:
    """Whether every sliding contact of ``loads`` stays inside a closed slot of ``outline`` (their
    member frame) at all its positions: where the FEA can bear its block (``contact_hole``)."""
    return all(contact_hole(outline, c) is not None for c in loads.contacts)


def distance_outside(outline: Polygon, point: ArrayLike) -> float:
    """How far [m] ``point`` (2,) [m, the outline's frame] lies outside the outer boundary of
    ``outline``, 0 inside it (in material or in a hole) or within OUTLINE_TOLERANCE of it."""
    gap = Polygon(outline.exterior).distance(shapely.Point(np.asarray(point, float)))
    x0, y0, x1, y1 = outline.bounds
    return gap if gap > OUTLINE_TOLERANCE * float(np.hypot(x1 - x0, y1 - y0)) else 0.0
