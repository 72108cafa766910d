"""The faster first solve: the stiffness and stress projections assembled as scalar blocks equal
scikit-fem's vector forms; CHOLMOD (optional) and SuperLU (always there) solve the same systems to
rounding, each bit for bit the same in chunks; the peaks over a sweep equal those of the SuperLU
solver and vector assembly before (recorded from that code)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from shapely.geometry import Point, box
from skfem import BilinearForm, asm
from skfem.helpers import sym_grad
from skfem.models.elasticity import linear_elasticity, linear_stress, plane_stress

from linkstress.analysis import plan_for, run_analysis
from linkstress.scene import load_scene
from linkstress.validation.fea import plane_stress as plane_stress_module
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.mesh import MeshSettings, mesh_region
from linkstress.validation.fea.plane_stress import (
    SOLVE_COLUMNS,
    FactorisedStiffness,
    SPDFactors,
    SOLVER_VARIABLE,
    factorise,
    factorise_spd,
    minimal_support,
    plane_stress_model,
    solve_columns,
    spd_solver,
)

SEED = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar"
E, NU, T = 200e9, 0.3, 0.01


def cholmod_or_skip() -> str:
    pytest.importorskip("sksparse.cholmod", reason='CHOLMOD is optional: pip install "linkstress[fast]"')
    return "cholmod"


@pytest.fixture(params=["superlu", "cholmod"])
def solver(request, monkeypatch) -> str:
    """Each solver in turn, chosen as a user would (LINKSTRESS_SOLVER); CHOLMOD skipped where absent."""
    if request.param == "cholmod":
        cholmod_or_skip()
    monkeypatch.setenv(SOLVER_VARIABLE, request.param)
    return request.param


def plates():
    """Plates with holes of several sizes and places, on P1 and P2 meshes of several sizes."""
    for length, depth, holes, size, order in (
        (0.3, 0.05, [(0.05, 0.0, 0.01), (0.25, 0.0, 0.01)], 0.012, 2),
        (0.12, 0.04, [(0.06, 0.005, 0.008)], 0.006, 2),
        (0.5, 0.1, [(0.1, 0.0, 0.02), (0.3, 0.02, 0.015), (0.4, -0.02, 0.01)], 0.03, 1),
    ):
        region = box(0, -depth / 2, length, depth / 2)
        for x, y, r in holes:
            region = region.difference(Point(x, y).buffer(r, 64))
        yield mesh_region(region, MeshSettings(size, order=order))


@pytest.mark.parametrize("plane", list(plates()), ids=["p2-two-holes", "p2-one-hole", "p1-three-holes"])
def test_scalar_block_stiffness_is_scikit_fems_vector_elasticity_to_rounding(plane):
    """Reference: scikit-fem's ``linear_elasticity`` with ``plane_stress(E, nu)`` (the plane-stress
    Lame pair lambda* = E nu / (1 - nu^2), mu = E / (2 (1 + nu)); Timoshenko & Goodier eq. 55)."""
    model = plane_stress_model(plane, E, NU, T)
    reference = T * asm(linear_elasticity(*plane_stress(E, NU)), model.basis)
    difference = abs(model.stiffness - reference).max() / abs(reference).max()
    assert difference < 1e-14
    # Symmetric to rounding: CHOLMOD reads one triangle, SuperLU both.
    assert abs(model.stiffness - model.stiffness.T).max() <= 1e-15 * abs(reference).max()


@pytest.mark.parametrize("plane", list(plates()), ids=["p2-two-holes", "p2-one-hole", "p1-three-holes"])
def test_stress_projections_are_scikit_fems_vector_forms_to_rounding(plane):
    """Reference: int sigma_c(u) v dA with sigma = C(sym_grad u) (scikit-fem's ``linear_stress``)."""
    model = plane_stress_model(plane, E, NU, T)
    stress = linear_stress(*plane_stress(E, NU))
    for (i, j), projection in zip(((0, 0), (1, 1), (0, 1)), model.stress_projections()):
        form = BilinearForm(lambda u, v, w: stress(sym_grad(u))[i, j] * v)
        reference = asm(form, model.basis, model.scalar)
        assert abs(projection - reference).max() / abs(reference).max() < 1e-14


def spd_system(n: int, seed: int) -> sp.csc_matrix:
    """A sparse SPD matrix (a random graph Laplacian plus a diagonal shift) of size n."""
    rng = np.random.default_rng(seed)
    rows, cols = rng.integers(0, n, 6 * n), rng.integers(0, n, 6 * n)
    weights = sp.csr_matrix((rng.random(6 * n), (rows, cols)), shape=(n, n))
    weights = weights + weights.T
    laplacian = sp.diags(np.asarray(weights.sum(axis=1)).ravel()) - weights
    return sp.csc_matrix(laplacian + 0.1 * sp.eye(n))


@pytest.mark.parametrize("n, columns", [(60, 29), (500, 64), (2000, 19)])
def test_either_solver_gives_the_same_bits_in_chunks_as_whole(solver, n, columns):
    """A block of positions solved alone, in a multiple of SOLVE_COLUMNS, equals the same positions
    solved with the whole sweep, to the last bit (validate joins blocks on that)."""
    factors = factorise_spd(spd_system(n, n))
    assert factors.solver == solver
    rhs = np.random.default_rng(columns).standard_normal((n, columns))
    whole = solve_columns(factors, rhs)
    step = 2 * SOLVE_COLUMNS
    blocks = np.concatenate([solve_columns(factors, rhs[:, k:k + step]) for k in range(0, columns, step)], axis=1)
    assert np.array_equal(whole, blocks)
    assert np.allclose(spd_system(n, n) @ whole, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())


@pytest.mark.parametrize("n", [50, 400])
def test_cholmod_and_superlu_solve_the_same_system_to_rounding(n):
    cholmod_or_skip()
    matrix = spd_system(n, 3 * n)
    rhs = np.random.default_rng(n).standard_normal((n, 5))
    fast, fallback = (solve_columns(factorise_spd(matrix, s), rhs) for s in ("cholmod", "superlu"))
    assert np.abs(fast - fallback).max() <= 1e-10 * np.abs(fallback).max()


def test_a_plate_with_a_rigid_mode_left_free_is_refused_by_either_solver(solver):
    plane = next(iter(plates()))
    model = plane_stress_model(plane, E, NU, T)
    fixed, _ = minimal_support(model)
    loads = np.random.default_rng(0).standard_normal((model.n_dofs, 3))
    with pytest.raises(FEAError, match="rigid mode"):
        factorise(model, fixed[:2]).solve(loads)  # the rotation is free: K is singular


def test_the_solver_is_chosen_by_variable_with_superlu_the_fallback(monkeypatch):
    monkeypatch.setenv(SOLVER_VARIABLE, "superlu")
    assert spd_solver() == "superlu"
    monkeypatch.setenv(SOLVER_VARIABLE, "umfpack")
    with pytest.raises(FEAError, match="LINKSTRESS_SOLVER: 'umfpack' is not a solver; use one of cholmod, superlu"):
        spd_solver()
    monkeypatch.setattr(plane_stress_module, "_cholmod", lambda: None)  # as without scikit-sparse
    monkeypatch.delenv(SOLVER_VARIABLE)
    assert spd_solver() == "superlu"
    assert factorise_spd(spd_system(30, 2)).solver == "superlu"
    monkeypatch.setenv(SOLVER_VARIABLE, "cholmod")
    with pytest.raises(FEAError, match=re.escape('scikit-sparse is not installed; pip install "linkstress[fast]"')):
        spd_solver()


def test_cholmod_is_the_default_where_it_is_installed(monkeypatch):
    cholmod_or_skip()
    monkeypatch.delenv(SOLVER_VARIABLE, raising=False)
    assert spd_solver() == "cholmod"


BEFORE = {
    "crank": ([37772258.19238448, 9171629.25820348, 9204561.307640374, 4886839.8225800935, 2297313.047016246,
               731700.7526208947, 518529.56161469157, 837378.8957291526, 1776016.2527441273, 4701880.39318981,
               14991552.351696433, 15846701.639727417], 37674742.3987809, 37475195.39484073),
    "coupler": ([1869766.4911169615, 1035134.4107341104, 458137.4326900461, 265791.7663673137, 289882.35605507874,
                 303142.6365808685, 313125.49229780096, 320577.28380234673, 348355.4891729158, 426464.78784660785,
                 654041.2077190558, 596388.4985844692], 1872049.4072768458, 1877077.469699954),
    "output": ([1184905.577245343, 466352.235928424, 236105.84242373877, 436691.32338831574, 518030.69615880534,
                545855.6741781782, 68993.02845604648, 65787.18032765311, 59894.370349965284, 85137.9817357793,
                386148.7141720333, 929207.1133385033], 1185084.5405335205, 1186232.1501281455),
}
"""The seed four-bar's FEA peaks [Pa] at 12 positions, 15 to 345 deg, and its two coarser checks at the
worst, as the vector assembly and SuperLU gave them (commit dc9631a, before this solver)."""


def test_the_seeds_peaks_over_a_sweep_are_todays_to_rounding(solver, tmp_path):
    (tmp_path / "ansys_four_bars.dxf").write_bytes((SEED / "ansys_four_bars.dxf").read_bytes())
    text = re.sub(r"(?m)^input_angle_deg = .*$", "input_angle_deg = { start = 15.0, stop = 345.0, num = 12 }",
                  (SEED / "scene.toml").read_text())
    (tmp_path / "scene.toml").write_text(text)
    scene = load_scene(tmp_path / "scene.toml")
    peaks = run_analysis(scene, plan_for(scene).with_peaks()).peaks
    for name, (sweep, coarser, coarsest) in BEFORE.items():
        np.testing.assert_allclose(peaks[name].peak, sweep, rtol=1e-9, atol=0)
        assert peaks[name].check.coarser == pytest.approx(coarser, rel=1e-9)
        assert peaks[name].check.coarsest == pytest.approx(coarsest, rel=1e-9)


@pytest.mark.parametrize("error", [3e-8, 1e-6])
def test_a_solve_just_above_the_tolerance_is_refined_to_rounding(error):
    """A factorisation whose solutions are off by a relative ``error`` (a simplicial LDL^T on an
    ill-conditioned link: the Jansen leg's lower rod under CHOLMOD came out at 1.1e-8) leaves a
    residual above SOLVE_TOLERANCE; iterative refinement, u += K^-1 (f - K u) with the same factors,
    shrinks it by about ``error`` per step, so two steps bring it to rounding."""
    plane = next(iter(plates()))
    model = plane_stress_model(plane, E, NU, T)
    fixed, _ = minimal_support(model)
    exact = factorise(model, fixed)
    sloppy = SPDFactors("sloppy", lambda rhs: exact.lu.solve(rhs) * (1 + error))
    loads = np.random.default_rng(1).standard_normal((model.n_dofs, 3))
    loads[fixed] = 0.0
    refined, _ = FactorisedStiffness(exact.stiffness, exact.fixed, exact.free, sloppy).solve(loads)
    plain, _ = exact.solve(loads)
    assert np.abs(refined - plain).max() <= 1e-10 * np.abs(plain).max()


def test_a_solve_that_refinement_cannot_mend_is_still_refused():
    plane = next(iter(plates()))
    model = plane_stress_model(plane, E, NU, T)
    fixed, _ = minimal_support(model)
    exact = factorise(model, fixed)
    wrong = SPDFactors("wrong", lambda rhs: exact.lu.solve(rhs) * 1.5)
    loads = np.random.default_rng(2).standard_normal((model.n_dofs, 2))
    with pytest.raises(FEAError, match="relative residual"):
        FactorisedStiffness(exact.stiffness, exact.fixed, exact.free, wrong).solve(loads)
