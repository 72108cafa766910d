"""Internal forces N, V, M along a link from the free body on each side of every cut.

Member frame of the load case, P positions, S stations. The cut at x splits the link into the part
x' <= x (left: its joints with x_j <= x and its material left of x) and the rest. N, V, M are the
resultants of the traction that the right part exerts on the left part's face (outward normal +x):

    N = int sigma_xx dA,   V = int tau_xy dA,   M = int (y - y_na) sigma_xx dA,

so that sigma_xx = N / A + M (y - y_na) / I. From the left free body, with F_L and M_L (about the
cut's neutral-axis point c) the resultant of every load on the left part, d'Alembert load included:

    (N, V) = -F_L,   M = M_L.

The right free body gives the same values when the loads are in equilibrium; the difference, the
resultant of all loads about the cut point, is reported as the equilibrium check, relative to the
link's load: the force against the sum of the sizes of every load on the link (pin and point
forces, the d'Alembert load's resultant), the moment against that sum times the reach of the cuts
from the frame's origin plus the sum of the loads' own moments about it (couples, the force of each
pin times its lever arm, the rotary inertia's). So a balanced link reads ~1e-16 whatever its
section forces: a two-force link in pure tension has M ~ 0 along it, and a moment mismatch taken
over that largest M would be rounding over rounding.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely
from numpy.typing import NDArray

from linkstress.loads import LinkLoadCase
from linkstress.geometry.members import MemberCuts
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.region_moments import RegionMoments, region_moments
from linkstress.geometry.sections import SectionTable


@dataclass(frozen=True)
class InternalForces:
    """N [N], V [N], M [N m] at each station (P, S), and the two-sided check.

    ``mismatch`` (P,): largest difference between the left and right free bodies, relative to the
    link's load at that position (``ForceBasis.mismatch``), the force's or the moment's, whichever
    is worse.
    """

    x: NDArray[np.float64]
    normal: NDArray[np.float64]
    shear: NDArray[np.float64]
    moment: NDArray[np.float64]
    mismatch: NDArray[np.float64]


FREE_X, FREE_Y, ALPHA, OMEGA2 = -4, -3, -2, -1
"""Columns of ``load_coefficients``: (g - a_O)_x, (g - a_O)_y [m/s^2], alpha [rad/s^2], omega^2 [rad^2/s^2]."""
BODY = slice(FREE_X, None)
"""The columns the d'Alembert body load is linear in."""


def load_coefficients(loads: LinkLoadCase, joints: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Per position, the load quantities every section force is linear in (P, Q).

    Columns: for each joint (F_x, F_y, C); for each sliding contact its equivalent (F_x, F_y, C) at
    its anchor joint (``joints`` (J, 2) [m, member frame] place them; needed only with contacts);
    for each point force (F_x, F_y); then g - a_O (2), alpha, omega^2.
    """
    n_pos = len(loads.omega)
    per_joint = np.concatenate([loads.pin_forces, loads.joint_couples[..., None]], axis=2).reshape(n_pos, -1)
    contacts = [c.equivalent(joints) for c in loads.contacts]
    point = [pf.force for pf in loads.point_forces]
    return np.column_stack([
        per_joint, *contacts, *point, loads.gravity - loads.origin_acceleration, loads.alpha, loads.omega**2,
    ])


def load_basis(loads, joints, on_side, points_on_side, moments, cut, rho_t):
    """Matrices (3, Q, S) mapping ``load_coefficients`` to (F_x, F_y, M about the cut) of one side.

    ``on_side`` (S, J) and ``points_on_side`` (S, n_point_forces) select that side's joints and
    point forces; ``moments`` = (A, S_x, S_y, J_O) (S,) of that side's material, per unit thickness.
    The d'Alembert load rho t (g - a_O - alpha k x r + omega^2 r) integrates to
    F = rho t [(g - a_O) A + alpha (S_y, -S_x) + omega^2 (S_x, S_y)] and, about the origin,
    M_O = rho t [S_x (g - a_O)_y - S_y (g - a_O)_x - alpha J_O].
    """
    n_st = len(cut)
    fx, fy, mo = [], [], []
    zero = np.zeros(n_st)
    for j, (xj, yj) in enumerate(joints):
        side = on_side[:, j].astype(float)
        fx += [side, zero, zero]
        fy += [zero, side, zero]
        mo += [-yj * side, xj * side, side]
    for contact in loads.contacts:
        side = on_side[:, contact.anchor].astype(float)
        xj, yj = joints[contact.anchor]
        fx += [side, zero, zero]
        fy += [zero, side, zero]
        mo += [-yj * side, xj * side, side]
    for k, pf in enumerate(loads.point_forces):
        side = points_on_side[:, k].astype(float)
        fx += [side, zero]
        fy += [zero, side]
        mo += [-pf.at[1] * side, pf.at[0] * side]
    area, sx, sy, polar = (rho_t * np.asarray(m, float) * np.ones(n_st) for m in moments)
    fx += [area, zero, sy, sx]
    fy += [zero, area, -sx, sy]
    mo += [-sy, sx, -polar, zero]
    fx, fy, mo = (np.array(b) for b in (fx, fy, mo))
    m_cut = mo - cut[:, 0] * fy + cut[:, 1] * fx
    return np.stack([fx, fy, m_cut])


EVERY_CUT_PAIRS = 25_000
"""(Position, cut) pairs up to which the equilibrium check takes every cut instead of the corners of
their hull (about as long as finding the hull, 80 us)."""


@dataclass(frozen=True)
class ForceBasis:
    """N, V, M per unit load coefficient: ``normal``, ``shear``, ``moment`` (Q, S), so that
    ``load_coefficients(loads) @ normal`` is N (P, S); ``whole`` (3, Q): the resultant (F_x, F_y,
    M about the origin) of every load on the link; ``cut`` (S, 2): the cut points (x, y_na)."""

    normal: NDArray[np.float64]
    shear: NDArray[np.float64]
    moment: NDArray[np.float64]
    whole: NDArray[np.float64]
    cut: NDArray[np.float64]

    @cached_property
    def corners(self) -> NDArray[np.float64]:
        """(H, 2): the corners of the cut points' convex hull."""
        return shapely.get_coordinates(shapely.convex_hull(shapely.multipoints(self.cut)))

    def mismatch(self, coefficients: NDArray[np.float64]) -> NDArray[np.float64]:
        """The two-sided check (P,) of the section forces made from ``coefficients`` (P, Q),
        relative to the link's load (``load_scales``).

        The right free body carries every load not on the left, so its cut differs from the left's
        by the resultant of all loads, taken about the cut point. That moment is affine in the
        cut point, so its largest size over the cuts is at a corner of their convex hull (on few
        positions every cut is checked: finding the hull would cost more).
        """
        total = coefficients @ self.whole.T
        d_force = np.maximum(np.abs(total[:, 0]), np.abs(total[:, 1]))
        few = len(coefficients) * len(self.cut) <= EVERY_CUT_PAIRS
        x, y = (self.cut if few else self.corners).T
        d_moment = _largest(total @ np.stack([y, -x, np.ones_like(x)]))
        force_scale, moment_scale = self.load_scales(coefficients)
        return np.maximum(_ratio(d_force, force_scale), _ratio(d_moment, moment_scale))

    def load_scales(self, coefficients: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The link's load at each position of ``coefficients`` (P, Q): the gross force (P,) [N],
        the sum of every load term's resultant size (each pin force's and point force's components,
        the d'Alembert load's terms), and the gross moment (P,) [N m], that force times the cuts'
        largest distance from the frame's origin plus the sum of the terms' own moments about it
        (couples, pin forces times their lever arms, the rotary inertia's)."""
        size = np.abs(coefficients) @ np.hypot(self.whole[0], self.whole[1])
        own = np.abs(coefficients) @ np.abs(self.whole[2])
        reach = float(np.hypot(*self.cut.T).max(initial=0.0))
        return size, size * reach + own


def force_basis(
    link: LinkProfile, loads: LinkLoadCase, sections: SectionTable, moments: RegionMoments | None = None,
) -> ForceBasis:
    """The ``ForceBasis`` at the stations of ``sections`` (member frame of ``loads.frame_joints``),
    from the free body left of each cut: (N, V) = -F_L, M = M_L."""
    i, j = loads.frame_joints
    x = sections.x
    joints = link.frame(i, j).to_local(link.joints)
    if moments is None:
        moments = region_moments(link.boundary(i, j), x, sections.crossings)
    cut = np.column_stack([x, sections.neutral_axis])
    point_x = np.array([pf.at[0] for pf in loads.point_forces]).reshape(-1)
    # One more column past the stations: the whole link, its moment about the origin.
    beyond = np.append(x, np.inf)[:, None]
    sides = np.column_stack([moments.area, moments.first_x, moments.first_y, moments.polar])
    basis = load_basis(
        loads, joints, joints[None, :, 0] <= beyond, point_x[None, :] <= beyond,
        np.vstack([sides, moments.total]).T, np.vstack([cut, np.zeros(2)]), link.density * link.thickness,
    )
    left = basis[:, :, :-1]
    return ForceBasis(-left[0], -left[1], left[2], basis[:, :, -1], cut)


def member_force_basis(link: LinkProfile, loads: LinkLoadCase, cuts: MemberCuts) -> ForceBasis:
    """The ``ForceBasis`` at the sections of one member (``linkstress.geometry.members``), load frame, from the
    free body of each cut's left piece (the one that holds the member's joint i): with F_L and M_L
    (about the section's centroid) the resultant of every load on that piece, d'Alembert load
    included, N = -F_L . t, V = -F_L . n and M = M_L (t along the member axis, n across it). On a
    straight member along the load frame's x these are the (N, V) = -F_L of ``force_basis``."""
    joints = link.frame(*loads.frame_joints).to_local(link.joints)
    points = np.array([pf.at for pf in loads.point_forces], float).reshape(-1, 2)
    cut = cuts.cut_points
    on_side = np.vstack([cuts.on_left(joints), np.ones(len(joints), bool)])
    points_on_side = np.vstack([cuts.on_left(points), np.ones(len(points), bool)])
    whole = cuts.total_moments[:, None]
    basis = load_basis(
        loads, joints, on_side, points_on_side, np.hstack([cuts.left_moments, whole]),
        np.vstack([cut, np.zeros(2)]), link.density * link.thickness,
    )
    left = basis[:, :, :-1]
    t, n = cuts.tangent.T, cuts.normal.T
    normal = -(left[0] * t[0] + left[1] * t[1])
    shear = -(left[0] * n[0] + left[1] * n[1])
    return ForceBasis(normal, shear, left[2], basis[:, :, -1], cut)


def contact_terms(loads: LinkLoadCase, joints: NDArray[np.float64], on_left, cut: NDArray[np.float64],
                  tangent: NDArray[np.float64], normal: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
    """(dN, dV, dM) (P, S) [N, N, N m]: what the sliding contacts add to the section forces made from
    their equivalents at their anchors (``load_coefficients``). A cut with the anchor and the contact
    on one side has it right; a cut between them has the force on the wrong side, so the left
    piece's resultant changes by delta (F, C + (a - c) x F), delta = [a on the left] - [anchor on
    the left]. ``on_left(points (K, 2))`` gives (S, K); ``cut`` (S, 2) the cut points, ``tangent``
    and ``normal`` (S, 2) the section's axes (member frame)."""
    count = len(loads.omega)
    terms = [np.zeros((count, len(cut))) for _ in range(3)]
    for contact in loads.contacts:
        delta = on_left(contact.at).T.astype(float) - on_left(joints[contact.anchor : contact.anchor + 1])[:, 0]
        f = contact.force[:, None, :]
        terms[0] -= delta * (f[..., 0] * tangent[:, 0] + f[..., 1] * tangent[:, 1])
        terms[1] -= delta * (f[..., 0] * normal[:, 0] + f[..., 1] * normal[:, 1])
        arm = contact.at[:, None, :] - cut[None, :, :]
        terms[2] += delta * (contact.couple[:, None] + arm[..., 0] * f[..., 1] - arm[..., 1] * f[..., 0])
    return tuple(terms)


def internal_forces(
    link: LinkProfile,
    loads: LinkLoadCase,
    sections: SectionTable,
    moments: RegionMoments | None = None,
) -> InternalForces:
    """N, V, M at the stations of ``sections`` (member frame of ``loads.frame_joints``)."""
    basis = force_basis(link, loads, sections, moments)
    joints = link.frame(*loads.frame_joints).to_local(link.joints)
    coefficients = load_coefficients(loads, joints)
    normal, shear, moment = (coefficients @ b for b in (basis.normal, basis.shear, basis.moment))
    if loads.contacts:
        x = sections.x
        along = np.column_stack([np.ones_like(x), np.zeros_like(x)])
        d_n, d_v, d_m = contact_terms(loads, joints, lambda p: p[None, :, 0] <= x[:, None], basis.cut, along, along[:, ::-1])
        normal, shear, moment = normal + d_n, shear + d_v, moment + d_m
    return InternalForces(sections.x, normal, shear, moment, basis.mismatch(coefficients))


def _largest(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """max |values| over the stations, (P,), by two reductions instead of a temporary |values|."""
    return np.maximum(values.max(axis=1), -values.min(axis=1))


def _ratio(diff, scale):
    return np.where(scale > 0, diff / np.where(scale > 0, scale, 1.0), diff)
