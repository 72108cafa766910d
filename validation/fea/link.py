"""Plane-stress FEA of one link under its load case, for every position of a sweep at once.

    result = solve_link(link, loads, MeshSettings(size=..., hole_size=..., stations=..., order=2))

One mesh (member frame of ``loads.frame_joints``), one stiffness factorisation and one stress
projection serve all P positions; only the load vectors change. Rigid modes are removed by a
minimal, statically determinate support (3 dofs). The loads are the kinetics' loads in dynamic
equilibrium, so the support reactions must vanish: they are reported, with their size relative to
the gross applied load, as a check of the kinetics.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Polygon

from linkstress.loads import LinkLoadCase
from linkstress.geometry.profile import LinkProfile
from linkstress.stress_state import von_mises
from linkstress.validation.fea.cache import DiskCache
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.loads import check_load_case, link_loads, point_force_hole
from linkstress.validation.fea.mesh import MeshSettings, PlaneMesh, cached_mesh_region
from linkstress.validation.fea.plane_stress import (
    PlaneStressModel,
    factorise,
    minimal_support,
    plane_stress_model,
)
from linkstress.validation.fea.recovery import (
    CutIntegrator,
    cut_integrator,
    interpolation_matrix,
    stress_recovery,
)
from linkstress.validation.fea.vtu import write_sweep


@dataclass(frozen=True)
class SectionResultants:
    """N [N], V [N], M [N m], each (P, S), at ``stations`` (S,) [m], member frame.

    The resultants of the traction of the part x' > x on the part x' < x (outward normal +x):
    N = int sigma_xx dA, V = int tau_xy dA, M = int (y - y_na) sigma_xx dA, with ``neutral_axis``
    (S,) [m] the beam section's y_na. The beam engine uses the same convention.
    """

    stations: NDArray[np.float64]
    neutral_axis: NDArray[np.float64]
    normal: NDArray[np.float64]
    shear: NDArray[np.float64]
    moment: NDArray[np.float64]


@dataclass(frozen=True)
class CutResultants:
    """N [N], V [N], M [N m], each (P, S), over the cut ``segments`` (S, 2, 2) [m], member frame.

    The resultants of the traction on the cut face whose outward normal is ``tangent`` t (S, 2)
    (the member axis across which the cut is taken; n = t rotated +90 degrees runs along the cut):
    N = int t.sigma.t dA, V = int n.sigma.t dA, M = int (r - r_ref).n (t.sigma.t) dA about
    ``reference`` r_ref (S, 2) [m] (the beam section's centroid). A station x is the cut with t =
    +x, and gives ``SectionResultants``' values.
    """

    segments: NDArray[np.float64]
    tangent: NDArray[np.float64]
    reference: NDArray[np.float64]
    normal: NDArray[np.float64]
    shear: NDArray[np.float64]
    moment: NDArray[np.float64]


@dataclass(frozen=True)
class LinkFEAResult:
    """The FEA of one link over P positions; member frame of ``frame_joints``, SI units.

    ``displacement`` (dofs, P) [m]; ``nodal_stress`` (P, nodes, 3) [Pa]: the recovered sigma_xx,
    sigma_yy, tau_xy at the nodes (P2 or P1 elements: ``plane.order``); ``reactions`` (P, 3): support
    force x, y [N] and moment about the frame origin [N m]; ``reaction_ratio`` (P,): the larger of |force| and |moment| / length of
    the reactions over the gross applied load (sum of |nodal force|) -- ~0 for loads in equilibrium.
    """

    link: LinkProfile
    frame_joints: tuple[int, int]
    plane: PlaneMesh
    model: PlaneStressModel
    displacement: NDArray[np.float64]
    nodal_stress: NDArray[np.float64]
    reactions: NDArray[np.float64]
    reaction_ratio: NDArray[np.float64]
    applied_load: NDArray[np.float64]
    mesh_seconds: float
    solve_seconds: float

    def __getstate__(self) -> dict:
        # What the cached properties hold (von Mises, the cut integrator) is remade where it is
        # needed: a result sent from a worker need not carry it too.
        return {name: self.__dict__[name] for name in self.__dataclass_fields__}

    @property
    def dofs(self) -> int:
        return self.model.n_dofs

    @property
    def n_elements(self) -> int:
        return self.plane.n_elements

    @property
    def n_positions(self) -> int:
        return self.displacement.shape[1]

    @property
    def nodes(self) -> NDArray[np.float64]:
        """Positions (nodes, 2) [m] of the nodes (vertices, then P2 mid-edge nodes), member frame."""
        return self.model.scalar.doflocs.T

    @cached_property
    def nodal_von_mises(self) -> NDArray[np.float64]:
        """Von Mises (P, nodes) [Pa] of the recovered stress."""
        return von_mises(self.nodal_stress)

    @property
    def von_mises_peak(self) -> NDArray[np.float64]:
        """Largest recovered von Mises (P,) [Pa] anywhere in the link."""
        return self.nodal_von_mises.max(axis=1)

    @property
    def von_mises_peak_at(self) -> NDArray[np.float64]:
        """Where (P, 2) [m, member frame] the peak von Mises of each position is."""
        return self.nodes[self.nodal_von_mises.argmax(axis=1)]

    def stress_at(self, points: ArrayLike) -> NDArray[np.float64]:
        """Recovered sigma_xx, sigma_yy, tau_xy (P, Q, 3) [Pa] at ``points`` (Q, 2) [m, member frame]."""
        try:
            matrix = interpolation_matrix(self.model, np.asarray(points, float))
        except FEAError as error:
            raise FEAError(f"link {self.link.name!r}: {error}") from None
        p, n, _ = self.nodal_stress.shape
        flat = self.nodal_stress.transpose(1, 0, 2).reshape(n, 3 * p)
        return (matrix @ flat).reshape(-1, p, 3).transpose(1, 0, 2)

    def section_resultants(self, stations: ArrayLike) -> SectionResultants:
        """N, V, M (P, S) over the FEA cuts at ``stations`` [m]; each must be one of the meshed stations."""
        x = np.atleast_1d(np.asarray(stations, float))
        index = self._cut_indices(x)
        y_na = self.link.sections(x, *self.frame_joints).neutral_axis
        tangent = np.broadcast_to([1.0, 0.0], (len(x), 2))
        n, v, m = self._cuts.resultants(self.displacement, index, tangent, np.column_stack([x, y_na]))
        return SectionResultants(x, y_na, n, v, m)

    def cut_resultants(self, segments: ArrayLike, tangent: ArrayLike, reference: ArrayLike) -> CutResultants:
        """N, V, M (P, S) over the cut ``segments`` (S, 2, 2) [m, member frame], each one of the
        meshed ``MeshSettings.cuts`` (either end first), taken across ``tangent`` (S, 2) (normal to
        its segment; normalised here) about ``reference`` (S, 2) [m]; see ``CutResultants``."""
        ends = np.asarray(segments, float).reshape(-1, 2, 2)
        t = np.asarray(tangent, float).reshape(-1, 2)
        r_ref = np.asarray(reference, float).reshape(-1, 2)
        if not len(t) == len(r_ref) == len(ends):
            raise FEAError(
                f"link {self.link.name!r}: {len(ends)} cut segments need as many tangents and reference points, "
                f"got {len(t)} and {len(r_ref)}"
            )
        index = self._segment_indices(ends)
        t = t / np.hypot(*t.T)[:, None]
        along = ends[:, 1] - ends[:, 0]
        slant = np.abs((t * along).sum(axis=1)) / np.hypot(*along.T)
        if (slant > 1e-6).any():
            k = int(np.argmax(slant))
            raise FEAError(
                f"link {self.link.name!r}: the tangent {t[k].tolist()} of cut {ends[k].tolist()} m is not normal to it "
                f"(cosine {slant[k]:.3g}); a cut is taken normal to the member axis"
            )
        n, v, m = self._cuts.resultants(self.displacement, len(self.plane.stations) + index, t, r_ref)
        return CutResultants(ends, t, r_ref, n, v, m)

    def write_vtu(self, folder: str | Path) -> list[Path]:
        """One VTU per position (displacement, stresses, von Mises) and a PVD listing them; the paths."""
        return write_sweep(Path(folder), self.link.name, self.model, self.displacement, self.nodal_stress)

    @cached_property
    def _cuts(self) -> CutIntegrator:
        return cut_integrator(self.model, self.plane.cuts)

    def _cut_indices(self, x: NDArray[np.float64]) -> NDArray[np.intp]:
        meshed = self.plane.stations
        if len(meshed) == 0:
            gap = np.full(len(x), np.inf)
            index = np.zeros(len(x), dtype=np.intp)
        else:
            gap_all = np.abs(x[:, None] - meshed[None, :])
            index, gap = gap_all.argmin(axis=1), gap_all.min(axis=1)
        far = gap > 1e-12 * max(1.0, float(np.abs(meshed).max(initial=0.0)))
        if far.any():
            raise FEAError(
                f"link {self.link.name!r}: station x = {x[far][0]:.6g} m was not meshed as a cut; "
                f"put it in MeshSettings.stations (meshed: {meshed.tolist()})"
            )
        return index

    def _segment_indices(self, ends: NDArray[np.float64]) -> NDArray[np.intp]:
        """Index into ``plane.segments`` of each cut segment (S, 2, 2) [m], matched either end first."""
        meshed = self.plane.segments
        scale = 1e-12 * max(1.0, float(np.abs(meshed).max(initial=0.0)))
        gap = np.minimum(
            np.abs(ends[:, None] - meshed[None]).max(axis=(2, 3)),
            np.abs(ends[:, None, ::-1] - meshed[None]).max(axis=(2, 3)),
        )  # (S, C): largest coordinate difference, as given or reversed
        if len(meshed) == 0 or (gap.min(axis=1, initial=np.inf) > scale).any():
            k = 0 if len(meshed) == 0 else int(np.argmax(gap.min(axis=1) > scale))
            raise FEAError(
                f"link {self.link.name!r}: the cut {ends[k].tolist()} m was not meshed; put it in MeshSettings.cuts "
                f"(meshed: {meshed.tolist()})"
            )
        return gap.argmin(axis=1)


def same_mesh(parts: Sequence[LinkFEAResult]) -> None:
    """Raise FEAError unless every one of ``parts`` (one link, blocks of positions) has the same mesh."""
    first = parts[0].plane.mesh
    for part in parts[1:]:
        mesh = part.plane.mesh
        if not (np.array_equal(mesh.p, first.p) and np.array_equal(mesh.t, first.t)):
            raise FEAError(
                f"link {parts[0].link.name!r}: its blocks of positions were meshed differently ({first.t.shape[1]} and "
                f"{mesh.t.shape[1]} elements): gmsh gave another mesh for the same settings; solve it in one block"
            )


def join_results(parts: Sequence[LinkFEAResult]) -> LinkFEAResult:
    """One result over the positions of ``parts`` in their order, each the same link on the same mesh
    solved at a block of positions: what one solve of them all gives (``SOLVE_COLUMNS``); the mesh
    and solve times add up. FEAError when the blocks' meshes differ."""
    same_mesh(parts)
    return replace(
        parts[0],
        displacement=np.concatenate([p.displacement for p in parts], axis=1),
        nodal_stress=np.concatenate([p.nodal_stress for p in parts]),
        reactions=np.concatenate([p.reactions for p in parts]),
        reaction_ratio=np.concatenate([p.reaction_ratio for p in parts]),
        applied_load=np.concatenate([p.applied_load for p in parts]),
        mesh_seconds=sum(p.mesh_seconds for p in parts),
        solve_seconds=sum(p.solve_seconds for p in parts),
    )


def join_cut_resultants(parts: Sequence[CutResultants]) -> CutResultants:
    """The resultants over the same cuts at the positions of ``parts``, in their order."""
    return replace(
        parts[0],
        normal=np.concatenate([p.normal for p in parts]),
        shear=np.concatenate([p.shear for p in parts]),
        moment=np.concatenate([p.moment for p in parts]),
    )


def link_region(link: LinkProfile, loads: LinkLoadCase, mesh: MeshSettings) -> tuple[Polygon, MeshSettings, NDArray[np.float64]]:
    """What ``link`` is meshed from in the member frame of ``loads.frame_joints``: its outline, the
    mesh settings and the points (Q, 2) [m] refined to ``station_size`` (its point forces in material).

    Raises FEAError (an InputError) naming the link for a link without E and nu, or a load case that
    does not fit it.
    """
    material = link.material
    if material is None or material.youngs_modulus is None or material.poisson_ratio is None:
        raise FEAError(
            f"link {link.name!r}: the FEA needs a material with density, youngs_modulus and poisson_ratio"
        )
    check_load_case(link, loads)
    # A force in a hole bears on the hole, which is refined already; one in material needs its patch.
    refine = [
        np.asarray(p.at, float) for p in loads.point_forces
        if point_force_hole(link, loads.frame_joints, p.at) is None
    ]
    return link.local_outline(*loads.frame_joints), mesh, np.asarray(refine, float).reshape(-1, 2)


def link_model(link: LinkProfile, loads: LinkLoadCase, mesh: MeshSettings, cache: DiskCache | None = None) -> PlaneStressModel:
    """Mesh ``link`` in the member frame of ``loads.frame_joints`` (refined at its point forces in
    material; the mesh from and into ``cache`` when given) and make its plane-stress model.

    Raises FEAError (an InputError) naming the link for: a link without E and nu, a load case that
    does not fit it, a part too thin for the sizes, a gmsh failure.
    """
    region, settings, refine = link_region(link, loads, mesh)
    plane = cached_mesh_region(region, settings, refine, f"link {link.name!r}", cache)
    material = link.material
    return plane_stress_model(plane, material.youngs_modulus, material.poisson_ratio, link.thickness)


def solve_link(link: LinkProfile, loads: LinkLoadCase, mesh: MeshSettings, cache: DiskCache | None = None) -> LinkFEAResult:
    """Mesh ``link`` in the member frame of ``loads.frame_joints`` (the mesh from and into ``cache``
    when given) and solve every position of ``loads``.

    Raises FEAError (an InputError) naming the link for: a link without E and nu, a loaded joint
    without a hole, a part too thin for the sizes, a gmsh or solver failure.
    """
    start = time.perf_counter()
    model = link_model(link, loads, mesh, cache)
    meshed = time.perf_counter()
    forces = link_loads(model, link, loads, patch_radius=mesh.station_size)
    fixed, _ = minimal_support(model)
    try:
        displacement, support = factorise(model, fixed).solve(forces)
    except FEAError as error:
        raise FEAError(f"link {link.name!r}: {error}") from None
    nodal_stress = stress_recovery(model).nodal_stress(displacement)
    reactions = support_reactions(model, fixed, support)
    applied = applied_load(model, forces)
    return LinkFEAResult(
        link=link,
        frame_joints=tuple(loads.frame_joints),
        plane=model.plane,
        model=model,
        displacement=displacement,
        nodal_stress=nodal_stress,
        reactions=reactions,
        reaction_ratio=reaction_ratio(reactions, applied, region_length(model)),
        applied_load=applied,
        mesh_seconds=meshed - start,
        solve_seconds=time.perf_counter() - meshed,
    )


def applied_load(model: PlaneStressModel, forces: NDArray[np.float64]) -> NDArray[np.float64]:
    """(P,) [N]: the gross load of nodal ``forces`` (dofs, P), the sum of |nodal force|."""
    return np.hypot(forces[model.components[0]], forces[model.components[1]]).sum(axis=0)


def region_length(model: PlaneStressModel) -> float:
    """[m]: the meshed region's larger extent, the arm that makes a support moment a force."""
    return float(np.ptp(model.scalar.doflocs, axis=1).max())


def reaction_ratio(reactions: NDArray[np.float64], applied: NDArray[np.float64], length: float) -> NDArray[np.float64]:
    """(P,) [-]: the larger of the support force and moment / ``length`` [m] of ``reactions`` (P, 3),
    over the gross ``applied`` load (P,) [N]: ~0 for loads in equilibrium."""
    size = np.maximum(np.hypot(reactions[:, 0], reactions[:, 1]), np.abs(reactions[:, 2]) / length)
    return np.divide(size, applied, out=np.zeros_like(size), where=applied > 0)


def support_reactions(
    model: PlaneStressModel, fixed: NDArray[np.intp], support: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Support reactions (P, 3): force x, y [N] and moment about the origin [N m], from the fixed dofs."""
    position = np.empty((model.n_dofs, 2))
    for c in range(2):
        position[model.components[c]] = model.scalar.doflocs.T
    component = np.empty(model.n_dofs, dtype=np.intp)
    component[model.components[0]], component[model.components[1]] = 0, 1
    fx = np.where(component[fixed, None] == 0, support, 0.0).sum(axis=0)
    fy = np.where(component[fixed, None] == 1, support, 0.0).sum(axis=0)
    arm = position[fixed]
    moment = np.where(component[fixed, None] == 1, arm[:, :1] * support, -arm[:, 1:] * support).sum(axis=0)
    return np.column_stack([fx, fy, moment])
