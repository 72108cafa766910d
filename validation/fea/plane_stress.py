"""Plane-stress linear elasticity on quadratic (P2, default) or linear (P1) triangles with scikit-fem,
and its factorised solve.

Constitutive law (plane stress, e.g. Timoshenko & Goodier, Theory of Elasticity, 3rd ed., eq. 55):

    [sigma_xx, sigma_yy, tau_xy] = E / (1 - nu^2) [[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]] [e_xx, e_yy, gamma_xy]

which is sigma = 2 mu e + lambda* tr(e) I with mu = E / (2 (1 + nu)) and lambda* = E nu / (1 - nu^2).
scikit-fem 12's ``plane_stress(E, nu)`` returns exactly (lambda*, mu), to be fed straight to
``linear_elasticity``; passing them through ``lame_parameters`` as well would give the plane-strain
(3D) lambda of the wrong moduli. The stiffness is scaled by the plate thickness t, so loads are
forces [N] and stresses are in-plane [Pa].

The stiffness is assembled as its 2 x 2 blocks (x and y displacements), each a scalar form in the
derivatives of the basis functions with D's entries: the same matrix as scikit-fem's vector
``linear_elasticity`` form to rounding (``tests/test_fea_fast_solve.py``), in less than half its time
(three scalar forms over the 6 x 6 pairs of an element's P2 functions, instead of one vector form
over 12 x 12 pairs, each a tensor product). The stress projections of the recovery are made the
same way from two scalar matrices.

One stiffness factorisation serves any number of load cases: solve takes all the right-hand sides
(dofs, P) at once, and hands them to the factors SOLVE_COLUMNS at a time. The factors are a sparse
Cholesky (CHOLMOD, from scikit-sparse: ``pip install "linkstress[fast]"``) when it is installed, else
SuperLU, which always is; ``LINKSTRESS_SOLVER`` (``cholmod`` or ``superlu``) chooses one.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.linalg import splu
from skfem import Basis, BilinearForm, Element, ElementTriP1, ElementTriP2, ElementVector, asm

from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.mesh import PlaneMesh

SOLVE_COLUMNS = 8
"""Right-hand sides per call of a factorisation's solve (``solve_columns``). SuperLU solves several
at once with blocked BLAS kernels, whose rounding depends on how many there are (and, for many,
on how the work is split over BLAS's threads): a position's displacement then changed in its last
bits with the positions solved beside it (2.5e-16 to 1.6e-15 relative, six_bar's links). In chunks
of this many, a position's result is the same bit for bit whether a sweep is solved whole or in
blocks of a multiple of it (``validate`` splits a link's positions so), on any number of threads.
Measured no slower than one call: 0.29 s against 0.31 s for 108 positions of 23,000 dofs (one
column at a time: 0.76 s). CHOLMOD's simplicial solve is column by column, so chunks change none of
its bits either (tested for both)."""
SOLVER_VARIABLE = "LINKSTRESS_SOLVER"
"""Environment variable naming the sparse solver of the SPD systems: ``cholmod`` or ``superlu``;
unset or empty: CHOLMOD when scikit-sparse is installed, else SuperLU."""
SOLVERS = ("cholmod", "superlu")

INTORDER = 4
"""Quadrature degree on cells: exact for the P2 stiffness and for P2 x linear loads on straight cells."""
ELEMENTS = {1: ElementTriP1, 2: ElementTriP2}
"""The scalar Lagrange element of each mesh order (the displacement is its vector version)."""


def scalar_element(order: int) -> Element:
    """The scalar Lagrange triangle of ``order`` (1 or 2) that fields and test functions use."""
    return ELEMENTS[order]()
SOLVE_TOLERANCE = 1e-8
"""Largest residual |K u - f| of the free dofs, relative to |f| + |K u|, of a successful solve."""
REFINEMENT_STEPS = 2
"""Steps of iterative refinement a column above SOLVE_TOLERANCE gets before the solve is refused."""


def plane_stress_matrix(youngs_modulus: float, poisson_ratio: float) -> NDArray[np.float64]:
    """The plane-stress elasticity matrix D [Pa] in Voigt order (xx, yy, xy with engineering shear strain)."""
    e, nu = youngs_modulus, poisson_ratio
    return e / (1 - nu * nu) * np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, (1 - nu) / 2]])


@dataclass(frozen=True)
class PlaneStressModel:
    """A plate on a mesh: vector ``basis`` for displacements [m], scalar ``scalar`` for fields, both
    Lagrange of the mesh's order (P2 on a quadratic mesh, P1 on a linear one).

    ``components[c, i]`` is the displacement dof of component c (0 = x, 1 = y) at scalar dof i, so a
    nodal field computed on ``scalar`` scatters into the displacement vector. ``stiffness`` [N/m]
    includes the thickness [m]; it is assembled when first asked for (a model rebuilt from cached
    unit-load solutions never needs it).
    """

    plane: PlaneMesh
    youngs_modulus: float
    poisson_ratio: float
    thickness: float
    basis: Basis
    scalar: Basis
    components: NDArray[np.intp]

    @cached_property
    def stiffness(self) -> sp.csr_matrix:
        """K (dofs, dofs) [N/m]: thickness x the plane-stress stiffness, from its scalar blocks."""
        d = plane_stress_matrix(self.youngs_modulus, self.poisson_ratio)
        # K_cd[i, j] = int B_i^c . D B_j^d, with B of phi e_x = (d_x phi, 0, d_y phi) and of phi e_y =
        # (0, d_y phi, d_x phi); i is the test function v (row), j the trial function u (column).
        xx = BilinearForm(lambda u, v, w: d[0, 0] * u.grad[0] * v.grad[0] + d[2, 2] * u.grad[1] * v.grad[1])
        yy = BilinearForm(lambda u, v, w: d[1, 1] * u.grad[1] * v.grad[1] + d[2, 2] * u.grad[0] * v.grad[0])
        xy = BilinearForm(lambda u, v, w: d[0, 1] * u.grad[1] * v.grad[0] + d[2, 2] * u.grad[0] * v.grad[1])
        blocks = {(0, 0): asm(xx, self.scalar), (1, 1): asm(yy, self.scalar), (0, 1): asm(xy, self.scalar)}
        blocks[(1, 0)] = blocks[(0, 1)].T
        return self.thickness * self.vector_matrix(blocks, self.components, self.components)

    def vector_matrix(self, blocks: dict, rows: NDArray[np.intp] | None, cols: NDArray[np.intp] | None) -> sp.csr_matrix:
        """The matrix whose block (c, d) is ``blocks[(c, d)]`` (scalar dofs), rows (cols) scattered
        to the vector dofs ``rows[c]`` (``cols[d]``), or kept scalar where None."""
        shape = (self.n_dofs if rows is not None else self.scalar.N, self.n_dofs if cols is not None else self.scalar.N)
        parts = [sp.coo_matrix(b) for b in blocks.values()]
        row = np.concatenate([p.row if rows is None else rows[c][p.row] for (c, _), p in zip(blocks, parts)])
        col = np.concatenate([p.col if cols is None else cols[d][p.col] for (_, d), p in zip(blocks, parts)])
        return sp.csr_matrix((np.concatenate([p.data for p in parts]), (row, col)), shape=shape)

    @property
    def n_dofs(self) -> int:
        return int(self.basis.N)

    @property
    def order(self) -> int:
        return self.plane.order

    def stress_projections(self) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
        """B_c (scalar dofs, dofs) [N/m] with (B_c u)_i = int sigma_c(u) psi_i dA for c = xx, yy, xy
        (psi_i the scalar basis), from two scalar matrices C_a[i, j] = int psi_i d_a phi_j dA."""
        d = plane_stress_matrix(self.youngs_modulus, self.poisson_ratio)
        cx, cy = (asm(form, self.scalar) for form in _VALUE_GRADIENT_PRODUCTS)
        # sigma(phi e_x) = (D11 d_x phi, D12 d_x phi, D33 d_y phi); sigma(phi e_y) = (D12 d_y phi, D22 d_y phi, D33 d_x phi).
        per_component = (
            {(0, 0): d[0, 0] * cx, (0, 1): d[0, 1] * cy},
            {(0, 0): d[1, 0] * cx, (0, 1): d[1, 1] * cy},
            {(0, 0): d[2, 2] * cy, (0, 1): d[2, 2] * cx},
        )
        return tuple(self.vector_matrix(blocks, None, self.components) for blocks in per_component)


_VALUE_GRADIENT_PRODUCTS = (
    BilinearForm(lambda u, v, w: u.grad[0] * v),
    BilinearForm(lambda u, v, w: u.grad[1] * v),
)
"""int psi_i d_a phi_j dA for a = x, y: entry [i, j] of C_x and C_y."""


def plane_stress_model(
    plane: PlaneMesh, youngs_modulus: float, poisson_ratio: float, thickness: float
) -> PlaneStressModel:
    """The plane-stress model of ``plane`` for E [Pa], nu [-] and thickness t [m]: its bases (the
    stiffness is assembled when first used)."""
    basis = Basis(plane.mesh, ElementVector(scalar_element(plane.order)), intorder=INTORDER)
    scalar = basis.with_element(scalar_element(plane.order))
    components = np.empty((2, scalar.N), dtype=np.intp)
    components[:, scalar.nodal_dofs[0]] = basis.nodal_dofs
    if scalar.facet_dofs.size:  # the mid-edge nodes of P2
        components[:, scalar.facet_dofs[0]] = basis.facet_dofs
    return PlaneStressModel(plane, float(youngs_modulus), float(poisson_ratio), float(thickness), basis, scalar, components)


def quadrature_weights(basis: Basis) -> tuple[sp.csr_matrix, NDArray[np.float64]]:
    """W (scalar dofs, Nq) with W[i, q] = phi_i(q) dA_q, and the points (2, Nq) [m] of basis' quadrature.

    ``basis`` is a scalar cell or facet basis; a field f sampled at the points integrates
    against every test function at once: W @ f = int phi_i f.
    """
    n_el, n_qp = basis.dx.shape
    rows = np.repeat(basis.element_dofs, n_qp, axis=1)
    cols = np.tile(np.arange(n_el * n_qp).reshape(n_el, n_qp), (basis.Nbfun, 1))
    values = np.concatenate([np.asarray(basis.basis[k][0]) * basis.dx for k in range(basis.Nbfun)])
    weights = sp.csr_matrix((values.ravel(), (rows.ravel(), cols.ravel())), shape=(basis.N, n_el * n_qp))
    points = np.asarray(basis.global_coordinates()).reshape(2, -1)
    return weights, points


def vector_loads(
    model: PlaneStressModel, weights: sp.csr_matrix, density: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Nodal forces (dofs, P) [N] of a load ``density`` (P, 2, Nq) per unit area [Pa = N/m^2] or volume.

    ``weights`` from :func:`quadrature_weights` (facet basis: traction [Pa] times t; cell basis:
    body force [N/m^3] times t). The thickness is applied here.
    """
    loads = np.zeros((model.n_dofs, density.shape[0]))
    for c in range(2):
        loads[model.components[c]] = model.thickness * (weights @ density[:, c, :].T)
    return loads


@dataclass(frozen=True)
class FactorisedStiffness:
    """The stiffness with dofs ``fixed`` prescribed, factorised once; solves many load cases."""

    stiffness: sp.csr_matrix
    fixed: NDArray[np.intp]
    free: NDArray[np.intp]
    lu: SPDFactors

    def solve(
        self, loads: NDArray[np.float64], prescribed: NDArray[np.float64] | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Displacements (dofs, P) [m] and reactions (fixed, P) [N] for nodal ``loads`` (dofs, P) [N].

        ``prescribed`` (fixed, P) [m]: displacements of the fixed dofs (zero when None).
        """
        loads = np.asarray(loads, float).reshape(self.stiffness.shape[0], -1)
        u = np.zeros_like(loads)
        if prescribed is not None:
            u[self.fixed] = np.asarray(prescribed, float).reshape(len(self.fixed), -1)
        rhs = loads[self.free] - self.stiffness[self.free][:, self.fixed] @ u[self.fixed]
        u[self.free] = solve_columns(self.lu, rhs)
        internal = self.stiffness @ u
        residual = np.linalg.norm(internal[self.free] - loads[self.free], axis=0)
        scale = np.linalg.norm(loads[self.free], axis=0) + np.linalg.norm(internal[self.free], axis=0)
        for _ in range(REFINEMENT_STEPS):
            # A simplicial LDL^T leaves some ill-conditioned columns just above the tolerance: a step of
            # iterative refinement on those columns alone brings them down to rounding.
            above = np.flatnonzero(residual > SOLVE_TOLERANCE * scale)
            if not len(above):
                break
            u[np.ix_(self.free, above)] += solve_columns(self.lu, (loads[:, above] - internal[:, above])[self.free])
            internal[:, above] = self.stiffness @ u[:, above]
            residual[above] = np.linalg.norm(internal[self.free][:, above] - loads[self.free][:, above], axis=0)
            scale[above] = np.linalg.norm(loads[self.free][:, above], axis=0) + np.linalg.norm(internal[self.free][:, above], axis=0)
        if not np.isfinite(u).all() or (residual > SOLVE_TOLERANCE * scale).any():
            worst = float(
                np.max(np.divide(residual, scale, out=np.full_like(residual, np.inf), where=scale > 0))
            )
            raise FEAError(
                f"the solver failed (relative residual {worst:.2g}): the stiffness is singular, "
                "the supports leave a rigid mode free or the mesh has a loose part"
            )
        return u, internal[self.fixed] - loads[self.fixed]


def factorise(model: PlaneStressModel, fixed: NDArray[np.intp]) -> FactorisedStiffness:
    """Factorise the stiffness with the dofs ``fixed`` removed (prescribed at solve time): SPD once
    they remove the rigid modes (``minimal_support``), so a Cholesky factorisation applies."""
    fixed = np.asarray(fixed, dtype=np.intp)
    if len(np.unique(fixed)) != len(fixed):
        raise FEAError(f"a dof is fixed twice in {fixed.tolist()}")
    free = np.setdiff1d(np.arange(model.n_dofs), fixed)
    try:
        lu = factorise_spd(model.stiffness[free][:, free])
    except NotPositiveDefinite as error:
        raise FEAError(
            f"the stiffness could not be factorised ({error}): the supports leave a rigid mode free"
        ) from error
    return FactorisedStiffness(model.stiffness, fixed, free, lu)


def solve_columns(factors: SPDFactors, rhs: NDArray[np.float64]) -> NDArray[np.float64]:
    """``factors.solve`` of the right-hand sides ``rhs`` (n, P), SOLVE_COLUMNS at a time."""
    rhs = np.asarray(rhs, float)
    if rhs.ndim == 1 or rhs.shape[1] <= SOLVE_COLUMNS:
        return factors.solve(rhs)
    return np.concatenate([factors.solve(rhs[:, k:k + SOLVE_COLUMNS]) for k in range(0, rhs.shape[1], SOLVE_COLUMNS)], axis=1)


class NotPositiveDefinite(FEAError):
    """The matrix given as SPD could not be factorised as one (singular, or a rigid mode left free)."""


@dataclass(frozen=True)
class SPDFactors:
    """The factors of a symmetric positive definite matrix by ``solver`` (``SOLVERS``); ``solve``
    maps right-hand sides (n,) or (n, P) to solutions of the same shape."""

    solver: str
    solve: Callable[[NDArray[np.float64]], NDArray[np.float64]]


def spd_solver() -> str:
    """The solver ``factorise_spd`` uses: ``LINKSTRESS_SOLVER`` if set, else CHOLMOD when
    scikit-sparse is installed, else SuperLU. FEAError for an unknown name, or CHOLMOD asked for and
    not installed."""
    asked = os.environ.get(SOLVER_VARIABLE, "").strip().lower()
    if asked and asked not in SOLVERS:
        raise FEAError(f"{SOLVER_VARIABLE}: {asked!r} is not a solver; use one of {', '.join(SOLVERS)}, or unset it")
    available = _cholmod() is not None
    if asked == "cholmod" and not available:
        raise FEAError(
            f"{SOLVER_VARIABLE}=cholmod: scikit-sparse is not installed; pip install \"linkstress[fast]\" (it needs "
            "SuiteSparse: apt-get install libsuitesparse-dev), or unset it for SuperLU"
        )
    return asked or ("cholmod" if available else "superlu")


def factorise_spd(matrix: sp.spmatrix, solver: str | None = None) -> SPDFactors:
    """Factors of a symmetric positive definite matrix by ``solver`` (default ``spd_solver()``).

    CHOLMOD: simplicial LDL^T with AMD ordering (on the links' peak meshes 0.6 to 0.8 of SuperLU's
    time to factorise and to solve; supernodal is slower with Debian's reference BLAS). It reads the lower
    triangle, SuperLU the whole matrix: the stiffness is symmetric to rounding. SuperLU: minimum
    degree ordering on A^T + A, symmetric mode and no pivoting (the diagonal of an SPD matrix is a
    safe pivot): about four times less fill and time than SuperLU's defaults. NotPositiveDefinite
    when the matrix is not (numerically) SPD.
    """
    solver = solver or spd_solver()
    if solver == "cholmod":
        cholmod = _cholmod()
        try:
            factor = cholmod.cholesky(sp.csc_matrix(matrix), ordering_method="amd", mode="simplicial")
        except cholmod.CholmodNotPositiveDefiniteError as error:
            raise NotPositiveDefinite(f"CHOLMOD: {error}") from None
        return SPDFactors("cholmod", factor.solve_A)
    try:
        lu = splu(
            matrix.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
        )
    except RuntimeError as error:
        raise NotPositiveDefinite(f"SuperLU: {error}") from None
    return SPDFactors("superlu", lu.solve)


@lru_cache(maxsize=1)
def _cholmod():
    """scikit-sparse's CHOLMOD module, or None when it is not installed."""
    try:
        from sksparse import cholmod
    except ImportError:
        return None
    return cholmod


def minimal_support(model: PlaneStressModel) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """Three dofs that remove the rigid modes, and the two support points (2, 2) [m].

    Both displacements at the vertex of least x (then least y) and the y displacement at the vertex
    of greatest x (then greatest y): statically determinate, so for loads in equilibrium the
    reactions vanish and the stresses do not depend on this choice.
    """
    p = model.plane.mesh.p[:, : model.plane.mesh.nvertices]
    first = int(np.lexsort((p[1], p[0]))[0])
    second = int(np.lexsort((-p[1], -p[0]))[0])
    if np.isclose(p[0, first], p[0, second]):
        raise FEAError("the region has no extent in x: cannot place a minimal support")
    dofs = np.array(
        [
            model.basis.nodal_dofs[0, first],
            model.basis.nodal_dofs[1, first],
            model.basis.nodal_dofs[1, second],
        ]
    )
    return dofs, p[:, [first, second]].T
