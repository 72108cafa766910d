"""Internal forces N, V, M along a link from the free body on each side of every cut.

Member frame of the load case, P positions, S stations. The cut at x splits the link into the part
x' <= x (left: its joints with x_j <= x and its material left of x) and the rest. N, V, M are the
resultants of the traction that the right part exerts on the left part's face (outward normal +x):

    N = int sigma_xx dA,   V = int tau_xy dA,   M = int (y - y_na) sigma_xx dA,

so that sigma_xx = N / A + M (y - y_na) / I. From the left free body, with F_L and M_L (about the
cut's neutral-axis point c) the resultant of every load on the left part, d'Alembert load included:

    (N, V) = -F_L,   M = M_L.

The right free body gives the same values when the loads are in equilibrium; the difference is
reported as the equilibrium check.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.loads import LinkLoadCase
from linkstress.profile import LinkProfile
from linkstress.region_moments import RegionMoments, region_moments
from linkstress.sections import SectionTable


@dataclass(frozen=True)
class InternalForces:
    """N [N], V [N], M [N m] at each station (P, S), and the two-sided check.

    ``mismatch`` (P,): largest difference between the left and right free bodies, relative to the
    largest section force (N, V) or moment (M) of that position, whichever is worse.
    """

    x: NDArray[np.float64]
    normal: NDArray[np.float64]
    shear: NDArray[np.float64]
    moment: NDArray[np.float64]
    mismatch: NDArray[np.float64]


def _cross(r, f):
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def _side_loads(loads, joints, region, cut, left, rho_t, moments):
    """Force (P, S, 2) and moment about the cut points (P, S) of the loads on one side.

    ``left`` (S, J) selects the joints on that side; ``moments`` = (A, S_x, S_y, J_O) (S,) of that
    side's material.
    """
    mask = left.astype(float)
    pin_force = np.einsum("sj,pjk->psk", mask, loads.pin_forces)
    pin_moment = np.einsum("sj,pj->ps", mask, _cross(joints[None, :, :], loads.pin_forces))
    couples = np.einsum("sj,pj->ps", mask, loads.joint_couples)
    area, first_x, first_y, polar = moments
    free = (loads.gravity - loads.origin_acceleration)[:, None, :]  # g - a_O
    alpha, w2 = loads.alpha[:, None], (loads.omega**2)[:, None]
    first = np.stack([first_x, first_y], axis=-1)[None]
    spin = np.stack([-first_y, first_x], axis=-1)[None]
    body_force = rho_t * (free * area[None, :, None] - alpha[..., None] * spin + w2[..., None] * first)
    body_moment = rho_t * (first_x * free[..., 1] - first_y * free[..., 0] - alpha * polar)
    force = pin_force + body_force
    moment = pin_moment + couples + body_moment
    for pf in loads.point_forces:
        on_side = region(pf.at[0]).astype(float)[None, :]
        force = force + on_side[..., None] * pf.force[:, None, :]
        moment = moment + on_side * _cross(pf.at, pf.force)[:, None]
    return force, moment - _cross(cut[None], force)


def internal_forces(
    link: LinkProfile,
    loads: LinkLoadCase,
    sections: SectionTable,
    moments: RegionMoments | None = None,
) -> InternalForces:
    """N, V, M at the stations of ``sections`` (member frame of ``loads.frame_joints``)."""
    i, j = loads.frame_joints
    x = sections.x
    joints = link.frame(i, j).to_local(link.joints)
    if moments is None:
        moments = region_moments(link.local_outline(i, j), x)
    rho_t = link.density * link.thickness
    cut = np.column_stack([x, sections.neutral_axis])
    on_left = joints[None, :, 0] <= x[:, None]
    left = (moments.area, moments.first_x, moments.first_y, moments.polar)
    right = tuple(total - part for total, part in zip(moments.total, left))
    f_left, m_left = _side_loads(loads, joints, lambda xa: xa <= x, cut, on_left, rho_t, left)
    f_right, m_right = _side_loads(loads, joints, lambda xa: xa > x, cut, ~on_left, rho_t, right)
    normal, shear, moment = -f_left[..., 0], -f_left[..., 1], m_left
    # Right free body: its face has outward normal -x, so (N, V) = F_R and M = -M_R.
    d_force = np.maximum(np.abs(normal - f_right[..., 0]), np.abs(shear - f_right[..., 1])).max(axis=1)
    d_moment = np.abs(moment + m_right).max(axis=1)
    force_scale = np.maximum(np.abs(normal), np.abs(shear)).max(axis=1)
    moment_scale = np.abs(moment).max(axis=1)
    mismatch = np.maximum(_ratio(d_force, force_scale), _ratio(d_moment, moment_scale))
    return InternalForces(x, normal, shear, moment, mismatch)


def _ratio(diff, scale):
    return np.where(scale > 0, diff / np.where(scale > 0, scale, 1.0), diff)
