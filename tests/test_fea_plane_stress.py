"""Plane-stress constants, the factorised solve and the recovered stress field."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import box
from skfem import ElementTriP2, FacetBasis
from skfem.models.elasticity import lame_parameters, linear_stress, plane_stress

from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.mesh import MeshSettings, mesh_region
from linkstress.validation.fea.plane_stress import (
    factorise,
    minimal_support,
    plane_stress_matrix,
    plane_stress_model,
    quadrature_weights,
    vector_loads,
)
from linkstress.stress_state import von_mises
from linkstress.validation.fea.recovery import interpolation_matrix, stress_recovery

E, NU, T = 200e9, 0.3, 0.01
L, H = 1.0, 0.1


def stress_of_strain(lam_mu, strain_voigt):
    """sigma (Voigt) from skfem's linear_stress for a constant strain (e_xx, e_yy, gamma_xy)."""
    exx, eyy, gxy = strain_voigt
    eps = np.array([[exx, gxy / 2], [gxy / 2, eyy]])[:, :, None]
    s = linear_stress(*lam_mu)(eps)[:, :, 0]
    return np.array([s[0, 0], s[1, 1], s[0, 1]])


def test_plane_stress_matrix_is_the_textbook_one():
    # Timoshenko & Goodier eq. 55: E / (1 - nu^2) [[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]]
    d = plane_stress_matrix(200e9, 0.25)
    k = 200e9 / (1 - 0.0625)
    np.testing.assert_allclose(d, k * np.array([[1, 0.25, 0], [0.25, 1, 0], [0, 0, 0.375]]), rtol=1e-15)


def test_skfem_plane_stress_pair_fed_straight_to_linear_stress_gives_that_matrix():
    columns = np.column_stack([stress_of_strain(plane_stress(E, NU), e) for e in np.eye(3)])
    np.testing.assert_allclose(columns, plane_stress_matrix(E, NU), rtol=1e-14)


def test_passing_skfems_plane_stress_pair_through_lame_parameters_would_be_wrong():
    # The trap of scikit-fem 12: lame_parameters(*plane_stress(E, nu)) treats (lambda*, mu) as (E, nu).
    wrong = np.column_stack([stress_of_strain(lame_parameters(*plane_stress(E, NU)), e) for e in np.eye(3)])
    plane_strain = np.column_stack([stress_of_strain(lame_parameters(E, NU), e) for e in np.eye(3)])
    assert np.abs(wrong - plane_stress_matrix(E, NU)).max() > 0.1 * E
    # Plane strain's D11 = E (1 - nu) / ((1 + nu)(1 - 2 nu)) is (1 - nu)^2 / (1 - 2 nu) = 1.225 times
    # plane stress's E / (1 - nu^2) for nu = 0.3: the stiffness this module must not use.
    assert plane_strain[0, 0] / plane_stress_matrix(E, NU)[0, 0] == pytest.approx(
        (1 - NU) ** 2 / (1 - 2 * NU), rel=1e-12
    )


@pytest.fixture(scope="module")
def stretched_bar():
    """A 1 m x 0.1 m bar, 10 mm thick, pulled by sigma = 1 MPa on both ends, minimal support."""
    plane = mesh_region(box(0, -H / 2, L, H / 2), MeshSettings(0.025, stations=(0.5,)))
    model = plane_stress_model(plane, E, NU, T)
    mesh = plane.mesh
    middle = mesh.p[:, mesh.facets[:, plane.outline]].mean(axis=1)
    loads = 0
    for end, sign in ((L, 1.0), (0.0, -1.0)):
        basis = FacetBasis(mesh, ElementTriP2(), facets=plane.outline[np.isclose(middle[0], end)], intorder=4)
        weights, points = quadrature_weights(basis)
        traction = np.zeros((1, 2, points.shape[1]))
        traction[0, 0] = sign * 1e6
        loads = loads + vector_loads(model, weights, traction)
    fixed, support = minimal_support(model)
    u, reactions = factorise(model, fixed).solve(loads)
    return model, loads, fixed, u, reactions


def displacement_at(model, u, points):
    matrix = interpolation_matrix(model, np.asarray(points, float))
    return np.column_stack([matrix @ u[model.components[c], 0] for c in range(2)])


def test_uniaxial_bar_stretches_by_sigma_over_e_and_contracts_by_nu_sigma_over_e(stretched_bar):
    # Plane stress: e_xx = sigma / E = 5e-6, e_yy = -nu sigma / E = -1.5e-6 (plane strain would give
    # e_xx = (1 - nu^2) sigma / E). Differences taken at equal y (or x) cancel the support's rotation.
    model, _, _, u, _ = stretched_bar
    d = displacement_at(model, u, [[0.0, 0.01], [L, 0.01], [0.3, -H / 2], [0.3, H / 2]])
    assert (d[1, 0] - d[0, 0]) / L == pytest.approx(1e6 / E, rel=1e-9)
    assert (d[3, 1] - d[2, 1]) / H == pytest.approx(-NU * 1e6 / E, rel=1e-9)


def test_recovered_stress_of_a_uniform_state_is_uniform_to_rounding(stretched_bar):
    model, _, _, u, _ = stretched_bar
    s = stress_recovery(model).nodal_stress(u)[0]
    np.testing.assert_allclose(s[:, 0], 1e6, rtol=1e-9)
    np.testing.assert_allclose(s[:, 1:], 0.0, atol=1e-6)
    assert von_mises(s).max() == pytest.approx(1e6, rel=1e-9)


def test_reactions_of_self_equilibrated_tractions_vanish(stretched_bar):
    _, loads, _, _, reactions = stretched_bar
    assert np.abs(reactions).max() < 1e-9 * np.abs(loads).sum()


def test_one_factorisation_solves_many_load_cases_as_each_alone(stretched_bar):
    model, loads, fixed, _, _ = stretched_bar
    rng = np.random.default_rng(3)
    many = np.column_stack([loads[:, 0], rng.normal(size=model.n_dofs), -2.5 * loads[:, 0]])
    solver = factorise(model, fixed)
    together, _ = solver.solve(many)
    for p in range(3):
        alone, _ = solver.solve(many[:, p])
        np.testing.assert_allclose(together[:, p], alone[:, 0], rtol=1e-12, atol=1e-20)


def test_von_mises_of_pure_shear_is_root_three_tau():
    assert von_mises(np.array([0.0, 0.0, 2.0])) == pytest.approx(2 * np.sqrt(3), rel=1e-15)
    assert von_mises(np.array([3.0, 3.0, 0.0])) == pytest.approx(3.0, rel=1e-15)


def test_a_point_off_the_plate_is_an_error_that_names_it(stretched_bar):
    model = stretched_bar[0]
    with pytest.raises(FEAError, match=r"\(0\.5, 0\.2\) m is outside"):
        interpolation_matrix(model, np.array([[0.5, 0.2]]))


def test_fixing_a_dof_twice_is_an_error(stretched_bar):
    model = stretched_bar[0]
    with pytest.raises(FEAError, match="fixed twice"):
        factorise(model, np.array([0, 0, 1]))


def test_a_support_that_leaves_rigid_modes_free_is_a_solver_error(stretched_bar):
    # One fixed dof: the bar can still slide in y and turn; the unbalanced load cannot be carried.
    model, loads, _, _, _ = stretched_bar
    with pytest.raises(FEAError, match="the solver failed .* supports leave a rigid mode free"):
        factorise(model, np.array([0])).solve(np.ones(model.n_dofs))
