"""The analytic verification suite: the FEA against closed-form elasticity, case by case.

Each plate case loads its truncated boundary with the exact traction sigma_exact . n (so the exact
field is the exact solution of the finite problem too), removes the rigid modes with a minimal
support prescribed to the exact displacement where one is known, and compares the recovered
stresses at named points. The spinning bar runs the link pipeline itself (``solve_link``) on a bar
loaded by its own d'Alembert body force only.

Run ``python -m linkstress.validation.fea.verification`` to print the table.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from shapely.geometry import Polygon, box
from skfem import ElementTriP2, FacetBasis

from linkstress.geometry.builders import straight_bar
from linkstress.geometry.curves import arc_points, circle_points
from linkstress.loads import LinkLoadCase
from linkstress.materials import Material
from linkstress.tables import format_table
from linkstress.validation.fea import analytic
from linkstress.validation.fea.link import solve_link
from linkstress.validation.fea.mesh import MeshSettings, mesh_region
from linkstress.validation.fea.plane_stress import (
    PlaneStressModel,
    factorise,
    minimal_support,
    plane_stress_model,
    quadrature_weights,
    vector_loads,
)
from linkstress.validation.fea.recovery import interpolation_matrix, stress_recovery

E, NU, T = 200e9, 0.3, 0.01
"""Steel plate used by every case: E [Pa], nu [-], thickness [m]."""
SAGITTA = 1e-7
"""Flattening of the drawn circles [m]: far below any mesh size, so the mesher rebuilds exact curves."""


@dataclass(frozen=True)
class Comparison:
    """One FEA value against its reference, with other approximations shown ``beside`` it."""

    quantity: str
    fea: float
    reference: float
    tolerance: float
    beside: tuple[tuple[str, float], ...] = ()

    @property
    def error(self) -> float:
        """|fea - reference| / |reference| [-]."""
        return abs(self.fea - self.reference) / abs(self.reference)

    @property
    def passed(self) -> bool:
        return self.error <= self.tolerance


@dataclass(frozen=True)
class BenchmarkResult:
    case: str
    source: str
    dofs: int
    comparisons: tuple[Comparison, ...]

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.comparisons)


@dataclass(frozen=True)
class ExactTractionSolution:
    model: PlaneStressModel
    displacement: NDArray[np.float64]
    nodal_stress: NDArray[np.float64]

    def stress_at(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Recovered stresses (Q, 3) [Pa] at ``points`` (Q, 2) [m]."""
        return interpolation_matrix(self.model, points) @ self.nodal_stress[0]

    def displacement_at(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Displacements (Q, 2) [m] at ``points`` (Q, 2) [m]."""
        matrix = interpolation_matrix(self.model, points)
        return np.column_stack([matrix @ self.displacement[self.model.components[c], 0] for c in range(2)])


def solve_exact_traction(
    region: Polygon,
    settings: MeshSettings,
    stress: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    displacement: Callable[[NDArray[np.float64]], NDArray[np.float64]] | None = None,
) -> ExactTractionSolution:
    """Plane stress on ``region`` with traction stress(x) . n on its whole boundary (outline and holes).

    ``stress`` maps points (2, Q) [m] to (sigma_xx, sigma_yy, tau_xy) (3, Q) [Pa]; ``displacement``
    (points -> (2, Q) [m]), when given, prescribes the three support dofs so that the rigid-body
    motion matches the exact one.
    """
    plane = mesh_region(region, settings)
    model = plane_stress_model(plane, E, NU, T)
    facets = np.concatenate([plane.outline, *plane.holes])
    basis = FacetBasis(plane.mesh, ElementTriP2(), facets=facets, intorder=8)
    weights, points = quadrature_weights(basis)
    n = basis.normals.reshape(2, -1)
    sxx, syy, txy = stress(points)
    traction = np.array([sxx * n[0] + txy * n[1], txy * n[0] + syy * n[1]])
    loads = vector_loads(model, weights, traction[None])
    fixed, support = minimal_support(model)
    prescribed = None
    if displacement is not None:
        exact = displacement(support.T)
        prescribed = np.array([exact[0, 0], exact[1, 0], exact[1, 1]])
    u, _ = factorise(model, fixed).solve(loads, prescribed)
    return ExactTractionSolution(model, u, stress_recovery(model).nodal_stress(u))


def kirsch_plate(
    a: float = 0.01, half_width: float = 0.04, S: float = 100e6, refinement: float = 1.0
) -> BenchmarkResult:
    """Plate with a round hole under uniaxial tension: sigma_xx at the hole's top and bottom = 3 S."""
    region = Polygon(
        box(-half_width, -half_width, half_width, half_width).exterior, [circle_points((0, 0), a, SAGITTA)]
    )
    settings = MeshSettings(size=a, hole_size=a / 16).refined(refinement)
    solution = solve_exact_traction(region, settings, lambda p: analytic.kirsch_stress(p, S, a))
    top = solution.stress_at(np.array([[0.0, a], [0.0, -a]]))[:, 0] / S
    return BenchmarkResult(
        "Kirsch plate with a hole",
        "Timoshenko & Goodier section 35, eq. 61",
        solution.model.n_dofs,
        tuple(Comparison(f"Kt at (0, {s}a)", float(k), 3.0, 0.01) for s, k in zip("+-", top)),
    )


def timoshenko_cantilever(
    L: float = 0.5, D: float = 0.1, P: float = 1000.0, refinement: float = 1.0
) -> BenchmarkResult:
    """Cantilever with a parabolic end shear: root bending stress and tip deflection."""
    settings = MeshSettings(size=D / 4, hole_size=D / 4, station_size=D / 4).refined(refinement)
    solution = solve_exact_traction(
        box(0.0, -D / 2, L, D / 2),
        settings,
        lambda p: analytic.cantilever_stress(p, P, L, D, T),
        lambda p: analytic.cantilever_displacement(p, P, L, D, T, E, NU),
    )
    root = solution.stress_at(np.array([[0.0, D / 2], [L / 2, -D / 2]]))[:, 0]
    exact_root = analytic.cantilever_stress(np.array([[0.0, L / 2], [D / 2, -D / 2]]), P, L, D, T)[0]
    tip = solution.displacement_at(np.array([[L, 0.0]]))[0, 1]
    return BenchmarkResult(
        "Timoshenko cantilever",
        "Timoshenko & Goodier section 21; Augarde & Deeks (2008) eqs. 1-2",
        solution.model.n_dofs,
        (
            Comparison("sigma_xx at the root, top fibre [Pa]", float(root[0]), float(exact_root[0]), 0.005),
            Comparison(
                "sigma_xx at mid-span, bottom fibre [Pa]", float(root[1]), float(exact_root[1]), 0.005
            ),
            Comparison(
                "tip deflection [m]", float(tip), analytic.cantilever_tip_deflection(P, L, D, T, E, NU), 0.005
            ),
        ),
    )


def lame_ring(a: float = 0.05, b: float = 0.1, p: float = 50e6, refinement: float = 1.0) -> BenchmarkResult:
    """Thick ring under internal pressure: hoop stress at the bore, sampled round it."""
    region = Polygon(circle_points((0, 0), b, SAGITTA), [circle_points((0, 0), a, SAGITTA)])
    settings = MeshSettings(size=(b - a) / 4, hole_size=(b - a) / 16).refined(refinement)
    solution = solve_exact_traction(region, settings, lambda q: analytic.lame_stress(q, p, a, b))
    phi = np.linspace(0, 2 * math.pi, 8, endpoint=False)
    s = solution.stress_at(a * np.column_stack([np.cos(phi), np.sin(phi)]))
    hoop = s[:, 0] * np.sin(phi) ** 2 + s[:, 1] * np.cos(phi) ** 2 - 2 * s[:, 2] * np.sin(phi) * np.cos(phi)
    worst = hoop[np.argmax(np.abs(hoop - analytic.lame_hoop_stress(a, p, a, b)))]
    return BenchmarkResult(
        "Lame thick ring",
        "Timoshenko & Goodier section 28",
        solution.model.n_dofs,
        (
            Comparison(
                "hoop stress at the bore, worst of 8 points [Pa]",
                float(worst),
                float(analytic.lame_hoop_stress(a, p, a, b)),
                0.005,
            ),
        ),
    )


def curved_bar(a: float = 0.05, b: float = 0.1, M: float = 500.0, refinement: float = 1.0) -> BenchmarkResult:
    """Quarter-ring bar in pure bending: hoop stress at the inner and outer fibres, mid-angle."""
    outer = arc_points((0, 0), b, 0.0, math.pi / 2, SAGITTA)
    inner = arc_points((0, 0), a, math.pi / 2, 0.0, SAGITTA)
    settings = MeshSettings(size=(b - a) / 12, hole_size=(b - a) / 12, station_size=(b - a) / 12).refined(
        refinement
    )
    solution = solve_exact_traction(
        Polygon(np.vstack([outer, inner])), settings, lambda q: analytic.curved_bar_stress(q, M, a, b, T)
    )
    mid = math.pi / 4
    radii = np.array([a, b])
    s = solution.stress_at(np.column_stack([radii * math.cos(mid), radii * math.sin(mid)]))
    hoop = (
        s[:, 0] * math.sin(mid) ** 2
        + s[:, 1] * math.cos(mid) ** 2
        - 2 * s[:, 2] * math.sin(mid) * math.cos(mid)
    )
    exact = analytic.curved_bar_polar(radii, M, a, b, T)[1]
    winkler = analytic.winkler_bach_stress(radii, M, a, b, T)
    straight = analytic.straight_beam_stress(radii - (a + b) / 2, M, b - a, T)
    return BenchmarkResult(
        "Curved bar in pure bending",
        "Timoshenko & Goodier section 29 (Golovin); Winkler-Bach and Mc/I beside",
        solution.model.n_dofs,
        tuple(
            Comparison(
                f"hoop stress, {fibre} fibre [Pa]",
                float(h),
                float(x),
                0.01,
                (("Winkler-Bach", float(w)), ("Mc/I", float(m))),
            )
            for fibre, h, x, w, m in zip(("inner", "outer"), hoop, exact, winkler, straight)
        ),
    )


def spinning_bar(
    L: float = 0.4, h: float = 0.04, omega: float = 300.0, refinement: float = 1.0
) -> BenchmarkResult:
    """A bar spinning about its middle, loaded only by its d'Alembert body force: N(x) over FEA cuts."""
    steel = Material("steel", 7850.0, E, NU)
    bar = straight_bar(L, h, 0.0, T, steel, name="spinning bar")
    stations = (L / 8, L / 4, L / 2)
    loads = LinkLoadCase(
        frame_joints=(0, 1),
        pin_forces=np.zeros((1, 2, 2)),
        joint_couples=np.zeros((1, 2)),
        omega=np.array([omega]),
        alpha=np.zeros(1),
        origin_acceleration=np.array([[omega**2 * L / 2, 0.0]]),
        gravity=np.zeros((1, 2)),
    )
    settings = MeshSettings(size=h / 4, stations=stations).refined(refinement)
    result = solve_link(bar, loads, settings)
    normal = result.section_resultants(stations).normal[0]
    exact = analytic.spinning_bar_normal_force(np.array(stations) - L / 2, steel.density, h * T, omega, L)
    return BenchmarkResult(
        "Spinning bar",
        "free body of the outer part: N = rho A w^2 (L^2/4 - x^2) / 2",
        result.dofs,
        tuple(
            Comparison(f"N at x = {s:g} m [N]", float(n), float(x), 0.005)
            for s, n, x in zip(stations, normal, exact)
        ),
    )


CASES = (kirsch_plate, timoshenko_cantilever, lame_ring, curved_bar, spinning_bar)


def format_results(results: list[BenchmarkResult]) -> str:
    """A table: case, quantity, FEA, reference, error, tolerance, and the approximations beside."""
    rows = []
    for result in results:
        for c in result.comparisons:
            beside = ", ".join(
                f"{name} {value:.6g} ({abs(value - c.reference) / abs(c.reference):.2%} off)"
                for name, value in c.beside
            )
            rows.append(
                (
                    result.case,
                    c.quantity,
                    c.fea,
                    c.reference,
                    f"{c.error:.3%}",
                    f"{c.tolerance:.1%}",
                    result.dofs,
                    beside,
                )
            )
    return format_table(("case", "quantity", "FEA", "exact", "error", "tolerance", "dofs", "beside"), rows)


def main() -> None:
    print(format_results([case() for case in CASES]))


if __name__ == "__main__":
    main()
