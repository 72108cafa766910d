"""Stresses from displacements: recovered nodal field, values at points, von Mises and cut resultants.

The P2 displacement gives a stress that is linear in each element and jumps between elements (P1:
constant in each element). The recovered field is its L2 projection onto the continuous scalar
space of the mesh's order (the "nodal averaged" stress of commercial codes, done variationally:
M s = int phi sigma_h dA, M the scalar mass matrix), one solve per component for all load cases at
once. Peak von Mises (``linkstress.stress_state``) is taken over its nodes.

Section resultants are integrated over a cut meshed as element edges (``MeshSettings.stations`` and
``MeshSettings.cuts``), at any angle, from the raw element stresses, averaging the two sides of each edge; linear stresses on straight
edges make a three-point Gauss rule per edge exact, moments included (isoparametric edges: to the
quadrature order). The edge's points come from the mesh's topology, not from inverting the map.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from skfem import BilinearForm, asm

from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.plane_stress import (
    PlaneStressModel,
    SPDFactors,
    factorise_spd,
    plane_stress_matrix,
    solve_columns,
)

OUTSIDE_TOLERANCE = 0.05
"""How far outside an element (in its reference coordinates) a point may be and still be evaluated
on its edge: a fibre on the drawing's flattened boundary can sit a flattening tolerance outside the
mesh, whose curved edges follow the exact arcs and splines."""
CANDIDATES = 12
NEWTON_STEPS = 12
CUT_POINTS = 3
"""Gauss points per cut edge: exact for the linear P2 stresses on a straight edge (degree 5)."""


@dataclass(frozen=True)
class StressRecovery:
    """Operators from displacements to the recovered (L2-projected, continuous) stress field."""

    model: PlaneStressModel
    projections: tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]
    mass: SPDFactors

    def nodal_stress(self, displacement: NDArray[np.float64]) -> NDArray[np.float64]:
        """Recovered stress (P, scalar dofs, 3) [Pa] at the nodes for displacements (dofs, P) [m]."""
        u = np.asarray(displacement, float).reshape(self.model.n_dofs, -1)
        return np.stack([solve_columns(self.mass, b @ u) for b in self.projections], axis=-1).transpose(1, 0, 2)


def stress_recovery(model: PlaneStressModel) -> StressRecovery:
    """Assemble and factorise the projection of ``model``'s stresses onto its continuous scalar space."""
    mass = asm(BilinearForm(lambda u, v, w: u * v), model.scalar).tocsc()
    return StressRecovery(model, model.stress_projections(), factorise_spd(mass))


def interpolation_matrix(model: PlaneStressModel, points: NDArray[np.float64]) -> sp.csr_matrix:
    """Matrix (Q, scalar dofs) that evaluates a nodal field of ``model.scalar`` at ``points`` (Q, 2) [m].

    Each point is found in its (curved) element by inverting the isoparametric map; a point more
    than ``OUTSIDE_TOLERANCE`` outside every element is an error that names it.
    """
    points = np.asarray(points, float).reshape(-1, 2)
    scalar = model.scalar
    element = scalar.elem
    cells, local = _locate(element, scalar.doflocs, scalar.element_dofs, points)
    values = np.stack([element.lbasis(local, k)[0] for k in range(scalar.Nbfun)])
    rows = np.broadcast_to(np.arange(len(points)), values.shape)
    return sp.csr_matrix(
        (values.ravel(), (rows.ravel(), scalar.element_dofs[:, cells].ravel())), shape=(len(points), scalar.N)
    )


def _locate(element, nodes, element_dofs, points) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """Element (Q,) and reference coordinates (2, Q) of each point, by Newton on the isoparametric
    map of the Lagrange ``element`` (one step is exact on P1's affine map).

    Candidates are the elements with the nearest centroids; points not found among them (a small
    element's centroid can be nearer than the large element holding the point) are searched again
    among ever more candidates, up to every element.
    """
    from scipy.spatial import cKDTree  # scipy.spatial takes 0.1 s to import: only where points are located

    n_el = element_dofs.shape[1]
    tree = cKDTree(nodes[:, element_dofs[:3]].mean(axis=1).T)
    cells = np.zeros(len(points), dtype=np.intp)
    local = np.zeros((2, len(points)))
    todo = np.arange(len(points))
    for k in (CANDIDATES, 8 * CANDIDATES, 64 * CANDIDATES, n_el):
        k = min(k, n_el)
        candidates = tree.query(points[todo], k)[1].reshape(len(todo), k)
        found_cell, found_local, outside = _best_candidate(element, nodes, element_dofs, points[todo], candidates)
        found = outside <= OUTSIDE_TOLERANCE
        cells[todo[found]], local[:, todo[found]] = found_cell[found], found_local[:, found]
        todo = todo[~found]
        if len(todo) == 0 or k == n_el:
            break
    if len(todo):
        bad = points[todo[0]]
        raise FEAError(f"the point ({bad[0]:.6g}, {bad[1]:.6g}) m is outside the meshed plate")
    chosen = np.clip(local, 0.0, 1.0)
    return cells, chosen - np.maximum(chosen.sum(axis=0) - 1, 0.0) / 2


def _best_candidate(element, nodes, element_dofs, points, candidates):
    """For each point, the candidate element it is least outside of: cell, reference coords, outsideness."""
    n_points, k = candidates.shape
    cell = candidates.ravel()
    target = np.repeat(points, k, axis=0).T
    local = np.full((2, len(cell)), 1 / 3)
    with np.errstate(all="ignore"):
        for _ in range(NEWTON_STEPS):
            x = np.zeros_like(target)
            jac = np.zeros((2, 2, len(cell)))
            for a in range(element_dofs.shape[0]):
                phi, dphi = element.lbasis(local, a)
                node = nodes[:, element_dofs[a, cell]]
                x += node * phi
                jac += node[:, None, :] * dphi[None, :, :]
            det = jac[0, 0] * jac[1, 1] - jac[0, 1] * jac[1, 0]
            r = target - x
            step = np.array([jac[1, 1] * r[0] - jac[0, 1] * r[1], -jac[1, 0] * r[0] + jac[0, 0] * r[1]])
            local = local + step / det
        outside = np.max([-local[0], -local[1], local.sum(axis=0) - 1, np.zeros(len(cell))], axis=0)
    outside = np.where(np.isfinite(outside), outside, np.inf).reshape(n_points, k)
    best = np.argmin(outside, axis=1)
    pick = np.arange(n_points) * k + best
    return cell[pick], local[:, pick], outside[np.arange(n_points), best]


def strain_operators(
    element_dofs: NDArray[np.intp], grads: list[NDArray[np.float64]], n_dofs: int
) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
    """Matrices (E * Q, dofs) giving e_xx, e_yy and gamma_xy at Q points in each of E elements.

    ``element_dofs`` (Nbfun, E): the vector basis' dofs of each element; ``grads[k]`` (2, 2, E, Q):
    the gradient of its k-th vector basis function at the points.
    """
    n_el, n_qp = grads[0].shape[2:]
    rows = np.tile(np.arange(n_el * n_qp).reshape(n_el, n_qp), (len(grads), 1))
    cols = np.repeat(element_dofs, n_qp, axis=1)
    parts = {
        "xx": [g[0, 0] for g in grads],
        "yy": [g[1, 1] for g in grads],
        "xy": [g[0, 1] + g[1, 0] for g in grads],
    }
    shape = (n_el * n_qp, n_dofs)
    return tuple(
        sp.csr_matrix((np.concatenate(v).ravel(), (rows.ravel(), cols.ravel())), shape=shape)
        for v in parts.values()
    )


@dataclass(frozen=True)
class CutIntegrator:
    """Integrates the stress over cuts meshed as element edges.

    ``weights`` (cuts, Nq) [m^2]: dA = t ds of each quadrature point on its cut; ``xy`` (2, Nq) [m]
    the points; ``stress``: operators (Nq, dofs) to sigma_xx, sigma_yy, tau_xy, both sides of each
    edge averaged.
    """

    weights: sp.csr_matrix
    xy: NDArray[np.float64]
    stress: tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]

    def resultants(
        self,
        displacement: NDArray[np.float64],
        cuts: NDArray[np.intp],
        tangent: NDArray[np.float64],
        reference: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """N = int t.sigma.t dA [N], V = int n.sigma.t dA [N], M = int (r - r_ref).n (t.sigma.t) dA
        [N m], each (P, S): the resultants of the traction on the cut face of outward normal t.

        ``cuts`` (S,) picks the cuts; ``tangent`` (S, 2) is each cut's unit normal t (the member
        axis across which it is taken), n = t rotated +90 degrees runs along the cut; ``reference``
        (S, 2) [m] the moment reference points r_ref on the cuts. With t = +x (a station x): N = int
        sigma_xx dA, V = int tau_xy dA, M = int (y - y_ref) sigma_xx dA.
        """
        weights = self.weights[np.asarray(cuts, dtype=np.intp)]
        t = np.asarray(tangent, float).reshape(-1, 2)
        n = np.column_stack([-t[:, 1], t[:, 0]])
        stress = np.stack([s @ displacement for s in self.stress])  # (3, Nq, P)
        # Integrals (3, S, P) of each stress component and of its first moments x, y over each cut;
        # the rotated components are linear in them, so the rotation is per cut, not per point.
        plain = np.stack([(weights @ s) for s in stress])
        first = [np.stack([(weights @ (c[:, None] * s)) for s in stress]) for c in self.xy]
        tt = np.stack([t[:, 0] ** 2, t[:, 1] ** 2, 2 * t[:, 0] * t[:, 1]])[:, :, None]  # t.sigma.t per component
        nt = np.stack([-t[:, 0] * t[:, 1], t[:, 0] * t[:, 1], t[:, 0] ** 2 - t[:, 1] ** 2])[:, :, None]
        normal = (tt * plain).sum(axis=0)
        shear = (nt * plain).sum(axis=0)
        arm = n[:, 0, None] * (tt * first[0]).sum(axis=0) + n[:, 1, None] * (tt * first[1]).sum(axis=0)
        moment = arm - (np.asarray(reference, float).reshape(-1, 2) * n).sum(axis=1)[:, None] * normal
        return normal.T, shear.T, moment.T


def cut_integrator(model: PlaneStressModel, cuts: tuple[NDArray[np.intp], ...]) -> CutIntegrator:
    """The integrator over ``cuts`` (interior facet indices of each cut), stresses averaged over both sides."""
    d = plane_stress_matrix(model.youngs_modulus, model.poisson_ratio)
    facets = np.concatenate([np.zeros(0, dtype=np.intp), *cuts])
    owner = np.repeat(np.arange(len(cuts)), [len(c) for c in cuts])
    if len(facets) == 0:
        empty = sp.csr_matrix((0, model.n_dofs))
        return CutIntegrator(sp.csr_matrix((len(cuts), 0)), np.zeros((2, 0)), (empty, empty, empty))
    s, w = np.polynomial.legendre.leggauss(CUT_POINTS)
    s, w = (s + 1) / 2, w / 2
    sides = [_cut_side(model, facets, side, s) for side in (0, 1)]
    strains = [strain_operators(model.basis.element_dofs[:, cells], grads, model.n_dofs) for cells, grads, _, _ in sides]
    stress = tuple(
        (0.5 * sum(d[c, 0] * e[0] + d[c, 1] * e[1] + d[c, 2] * e[2] for e in strains)).tocsr()
        for c in range(3)
    )
    _, _, length, xy = sides[0]
    weights = sp.csr_matrix(
        (model.thickness * (length * w).ravel(), (np.repeat(owner, len(s)), np.arange(len(facets) * len(s)))),
        shape=(len(cuts), len(facets) * len(s)),
    )
    return CutIntegrator(weights, xy.reshape(2, -1), stress)


def _cut_side(model: PlaneStressModel, facets: NDArray[np.intp], side: int, s: NDArray[np.float64]):
    """The elements on ``side`` of each facet, the vector basis' gradients (2, 2, F, Q) at the
    points s (Q,) along it, |dx/ds| (F, Q) and the points (2, F, Q) [m].

    The points are placed from the mesh's topology: the facet is the edge between two of the
    element's vertices, so its reference points lie on the straight reference edge between them. No
    inverse isoparametric mapping is needed (skfem's FacetBasis inverts the map by Newton, which
    stalls on small elements far from the origin: its stopping test is absolute).
    """
    mesh = model.plane.mesh
    cells = mesh.f2t[side, facets]
    ends = [np.argmax(mesh.t[:, cells] == mesh.facets[k, facets], axis=0) for k in (0, 1)]
    corners = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])  # the reference triangle's vertices
    a, b = corners[:, ends[0]], corners[:, ends[1]]
    ref = a[:, :, None] * (1 - s) + b[:, :, None] * s  # (2, F, Q): both sides meet at the same points
    mapping = model.basis.mapping
    jacobian = np.broadcast_to(mapping.DF(ref, tind=cells), (2, 2, *ref.shape[1:]))
    along = np.einsum("ijfq,jf->ifq", jacobian, b - a)
    grads = [model.basis.elem.gbasis(mapping, ref, k, tind=cells)[0].grad for k in range(model.basis.Nbfun)]
    return cells, grads, np.hypot(*along), mapping.F(ref, tind=cells)
