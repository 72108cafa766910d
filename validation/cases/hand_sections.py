"""Hand section figures and converged FEA at the same cuts, for the cases' truth tables (truth.py).

A cut is a straight line across a bar of rectangular section (depth h, the link's thickness t)
through the point ``centre`` on its centre line; ``toward`` is the unit normal of the cut pointing
into the piece beyond it (the free end: a straight arm's tip, an arc's end). Everything is in the
member frame of the link's load case (``loads.frame_joints``), SI units, over P positions.

Sign conventions, as the beam engine and the FEA resultants use them (``SectionResultants``):
s = ``toward``, n = s turned +90 degrees; N [N], V [N] and M [N m] are the resultants of the
traction of the piece beyond the cut on the rest, N = int sigma_ss dA, V = int tau_sn dA,
M = int y sigma_ss dA with y [m] along n from the centre line; so sigma = N/A + M y/I, N > 0 is
tension and M > 0 puts the fibre at y = +h/2 in tension.

Hand figures: statics of the piece beyond the cut under the loads linkstress puts on the link
(pin forces, couples and point forces of joints in the piece, and the d'Alembert body load of the
piece's material, integrated exactly over its polygon): N s + V n = F and M = -(moment of the
loads about the cut's centre).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from shapely.geometry import Polygon

from linkstress.loads import LinkLoadCase
from linkstress.geometry.mass_properties import area_properties
from linkstress.geometry.profile import LinkProfile
from linkstress.stress_state import von_mises
from linkstress.validation.fea.link import LinkFEAResult, solve_link
from linkstress.validation.fea.mesh import MeshSettings

REFINEMENT_RATIO = 1.5
"""Each refinement divides every element size by this (as validate's study does)."""
CONVERGED = 0.005
"""Two consecutive meshes agree when every reported FEA figure moved less than this, relative to
its scale (a cut's fibres: the larger von Mises of the cut at that position; a peak: itself)."""
GAUSS_POINTS = 64
"""Points across a cut for the FEA's N, V, M (Gauss-Legendre over the depth)."""


@dataclass(frozen=True)
class Cut:
    """A cut across a rectangular bar: ``name``, ``centre`` (2,) [m] on the centre line, ``toward``
    (2,) unit normal into the piece beyond, ``depth`` h [m]; member frame."""

    name: str
    centre: NDArray[np.float64]
    toward: NDArray[np.float64]
    depth: float

    @property
    def across(self) -> NDArray[np.float64]:
        """n: ``toward`` turned +90 degrees, the direction of y."""
        return np.array([-self.toward[1], self.toward[0]])

    def points(self, y: NDArray[np.float64]) -> NDArray[np.float64]:
        """Points (Q, 2) [m] of the cut at heights ``y`` (Q,) [m] along n."""
        return self.centre + np.asarray(y, float)[:, None] * self.across


@dataclass(frozen=True)
class Resultants:
    """N [N], V [N], M [N m] at a cut, each (P,)."""

    normal: NDArray[np.float64]
    shear: NDArray[np.float64]
    moment: NDArray[np.float64]


def straight_cut(name: str, start: NDArray[np.float64], end: NDArray[np.float64], distance: float, depth: float) -> Cut:
    """The cut square to the arm ``start`` -> ``end`` (joints [m]) at ``distance`` [m] from
    ``start``, the piece beyond being the ``end`` side."""
    axis = (np.asarray(end, float) - start) / math.dist(start, end)
    return Cut(name, np.asarray(start, float) + distance * axis, axis, depth)


def radial_cut(name: str, centre: NDArray[np.float64], radius: float, angle_deg: float, sense: int, depth: float) -> Cut:
    """The radial cut of an arc bar (centre line of ``radius`` [m] about ``centre``) at polar
    angle ``angle_deg``; the piece beyond lies at smaller angles for ``sense`` = -1, larger for +1."""
    radial = np.array([math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
    hoop = np.array([-radial[1], radial[0]])
    return Cut(name, np.asarray(centre, float) + radius * radial, sense * hoop, depth)


def piece_beyond(outline: Polygon, cut: Cut) -> Polygon:
    """The material of ``outline`` (member frame) beyond ``cut``: one polygon, or a ValueError."""
    size = 10 * math.dist(outline.bounds[:2], outline.bounds[2:])
    c, s, n = cut.centre, cut.toward, cut.across
    half_plane = Polygon([c - size * n, c - size * n + size * s, c + size * n + size * s, c + size * n])
    piece = outline.intersection(half_plane)
    if not isinstance(piece, Polygon):
        raise ValueError(f"cut {cut.name}: the material beyond it is {piece.geom_type}, not one piece")
    return piece


def hand_resultants(link: LinkProfile, loads: LinkLoadCase, cut: Cut) -> Resultants:
    """N, V, M (P,) at ``cut`` by statics of the piece beyond it (module docstring)."""
    frame = link.frame(*loads.frame_joints)
    piece = piece_beyond(link.local_outline(*loads.frame_joints), cut)
    c, s, n = cut.centre, cut.toward, cut.across
    joints = frame.to_local(link.joints)
    beyond = (joints - c) @ s > 0
    force = loads.pin_forces[:, beyond].sum(axis=1)
    moment = (
        _cross(joints[beyond] - c, loads.pin_forces[:, beyond]).sum(axis=1)
        + loads.joint_couples[:, beyond].sum(axis=1)
    )
    for pf in loads.point_forces:
        if (pf.at - c) @ s > 0:
            force = force + pf.force
            moment = moment + _cross(pf.at - c, pf.force)
    body_force, body_moment = _body_load(piece, loads, link.material.density * link.thickness, c)
    force, moment = force + body_force, moment + body_moment
    return Resultants(force @ s, force @ n, -moment)


def _body_load(
    piece: Polygon, loads: LinkLoadCase, areal_density: float, about: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Resultant (P, 2) [N] and moment about ``about`` (P,) [N m] of the d'Alembert load
    rho t (g - a_O + omega^2 r + alpha (r_y, -r_x)) over ``piece``: affine in r, so the area, first
    moment and polar moment about the origin integrate it exactly."""
    props = area_properties(piece)
    area, rc = props.area, np.asarray(props.centroid)
    polar_origin = props.polar + area * rc @ rc
    free = loads.gravity - loads.origin_acceleration  # (P, 2)
    w2, al = loads.omega**2, loads.alpha
    first = area * rc
    force = area * free + w2[:, None] * first + al[:, None] * np.array([first[1], -first[0]])
    moment = (
        _cross(rc - about, free) * area
        - w2 * _cross(about, first)
        + al * (-polar_origin + about @ first)
    )
    return areal_density * force, areal_density * moment


def straight_fibres(res: Resultants, depth: float, thickness: float) -> NDArray[np.float64]:
    """Straight-beam sigma_ss (P, 2) [Pa] at y = -h/2 and +h/2: N/A + M y/I, rectangle h x t."""
    area, inertia = depth * thickness, thickness * depth**3 / 12
    y = np.array([-depth / 2, depth / 2])
    return res.normal[:, None] / area + res.moment[:, None] * y / inertia


def winkler_bach_fibres(res: Resultants, radius: float, depth: float, thickness: float) -> NDArray[np.float64]:
    """Winkler-Bach hoop stress (P, 2) [Pa] at the inner (r_i) and outer (r_o) fibre of a
    rectangle h x t whose centroid is at ``radius`` R: r_n = h / ln(r_o / r_i), e = R - r_n,
    sigma = N/A + M (r - r_n) / (A e r), M > 0 putting the outer fibre in tension (y = r - R)."""
    inner, outer = radius - depth / 2, radius + depth / 2
    r_n = depth / math.log(outer / inner)
    area, e = depth * thickness, radius - r_n
    r = np.array([inner, outer])
    return res.normal[:, None] / area + res.moment[:, None] * (r - r_n) / (area * e * r)


@dataclass(frozen=True)
class CutFEA:
    """FEA at a cut, each over P positions: sigma_ss and von Mises (P, 2) [Pa] at y = -h/2, +h/2,
    and the resultants over the cut."""

    sigma: NDArray[np.float64]
    von_mises: NDArray[np.float64]
    resultants: Resultants


def cut_fea(result: LinkFEAResult, cut: Cut, thickness: float) -> CutFEA:
    """The FEA's fibre stresses at ``cut`` (its two edge points) and N, V, M integrated across it."""
    g, w = np.polynomial.legendre.leggauss(GAUSS_POINTS)
    y = np.concatenate([[-cut.depth / 2, cut.depth / 2], g * cut.depth / 2])
    stress = result.stress_at(cut.points(y))  # (P, Q, 3)
    s, n = cut.toward, cut.across
    sxx, syy, txy = stress[..., 0], stress[..., 1], stress[..., 2]
    sigma_ss = s[0] ** 2 * sxx + s[1] ** 2 * syy + 2 * s[0] * s[1] * txy
    tau_sn = s[0] * n[0] * sxx + s[1] * n[1] * syy + (s[0] * n[1] + s[1] * n[0]) * txy
    weight = w * cut.depth / 2 * thickness
    res = Resultants(sigma_ss[:, 2:] @ weight, tau_sn[:, 2:] @ weight, (sigma_ss[:, 2:] * y[2:]) @ weight)
    return CutFEA(sigma_ss[:, :2], von_mises(stress[:, :2]), res)


@dataclass(frozen=True)
class Peak:
    """The FEA's largest von Mises (P,) [Pa] within a region and where (P, 2) [m, member frame]."""

    value: NDArray[np.float64]
    at: NDArray[np.float64]


def region_peak(result: LinkFEAResult, inside: NDArray[np.bool_]) -> Peak:
    """Largest nodal von Mises over the nodes ``inside`` (nodes,), per position."""
    vm = np.where(inside[None, :], result.nodal_von_mises, -np.inf)
    k = vm.argmax(axis=1)
    return Peak(vm[np.arange(len(k)), k], result.nodes[k])


@dataclass(frozen=True)
class Converged:
    """The finest FEA of a refinement study and what each level measured: ``dofs`` per level,
    ``change`` [-] the largest relative change of any reported figure from the level before."""

    result: LinkFEAResult
    cuts: dict[str, CutFEA]
    peaks: dict[str, Peak]
    dofs: list[int]
    change: list[float]


def converged_fea(
    link: LinkProfile, loads: LinkLoadCase, cuts: list[Cut], regions, base: MeshSettings,
    tolerance: float = CONVERGED, min_levels: int = 3, max_levels: int = 7,
) -> Converged:
    """Refine ``base`` by REFINEMENT_RATIO until two consecutive meshes agree within ``tolerance``
    on every fibre von Mises at ``cuts`` and every peak of ``regions`` (name -> function of the
    nodes (Q, 2) giving a mask), after at least ``min_levels`` meshes (a study, as validate's);
    P2 elements. Raises RuntimeError if ``max_levels`` meshes do not converge."""
    previous, dofs, changes = None, [], []
    for level in range(max_levels):
        result = solve_link(link, loads, base.refined(REFINEMENT_RATIO**level))
        at_cuts = {cut.name: cut_fea(result, cut, link.thickness) for cut in cuts}
        peaks = {name: region_peak(result, inside(result.nodes)) for name, inside in regions.items()}
        figures = _figures(at_cuts, peaks)
        dofs.append(result.dofs)
        if previous is not None:
            changes.append(float(np.max(np.abs(figures[0] - previous[0]) / figures[1])))
            if changes[-1] < tolerance and level + 1 >= min_levels:
                return Converged(result, at_cuts, peaks, dofs, [math.nan, *changes])
        previous = figures
    raise RuntimeError(f"link {link.name!r}: not converged within {max_levels} meshes (changes {changes})")


def _figures(cuts: dict[str, CutFEA], peaks: dict[str, Peak]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Every reported FEA figure (flattened) and its scale (same shape)."""
    values = [c.von_mises for c in cuts.values()] + [p.value[:, None] for p in peaks.values()]
    scales = [np.broadcast_to(c.von_mises.max(axis=1, keepdims=True), c.von_mises.shape) for c in cuts.values()]
    scales += [p.value[:, None] for p in peaks.values()]
    return np.concatenate(values, axis=1).ravel(), np.concatenate(scales, axis=1).ravel()


def base_mesh(depth: float, hole: float) -> MeshSettings:
    """validate's default sizes: a sixth of the section depth, an eighth of the pin hole's diameter at holes."""
    size = depth / 6
    return MeshSettings(size=size, hole_size=min(hole / 8, size / 2), order=2)


def _cross(r: NDArray[np.float64], f: NDArray[np.float64]) -> NDArray[np.float64]:
    """z-component of r x f over the last axis."""
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]
