"""The analytic verification suite: FEA against closed-form elasticity, and the formulas themselves."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from linkstress.validation.fea import analytic, verification


@pytest.mark.parametrize("case", verification.CASES, ids=lambda c: c.__name__)
def test_fea_matches_the_exact_solution_within_its_tolerance(case):
    # Tolerances (issue 6): Kirsch Kt 1 %, Timoshenko stress and tip deflection 0.5 %, Lame hoop
    # 0.5 %, curved bar 1 %, spinning bar N(x) 0.5 %.
    result = case()
    for c in result.comparisons:
        assert math.isfinite(c.fea)
        assert c.passed, (result.case, c.quantity, c.fea, c.reference, c.error)


def test_curved_bar_reports_winkler_bach_close_and_straight_beam_far():
    # b / a = 2: Winkler-Bach is within about 1 % of the elasticity solution, Mc/I about 22 % off
    # at the inner fibre (Timoshenko & Goodier section 29 table, Boresi & Schmidt table 9.1).
    result = verification.curved_bar()
    inner = result.comparisons[0]
    beside = dict(inner.beside)
    assert abs(beside["Winkler-Bach"] / inner.reference - 1) < 0.01
    assert abs(beside["Mc/I"] / inner.reference - 1) > 0.2
    assert "Winkler-Bach" in verification.format_results([result])


def test_the_results_table_lists_every_comparison():
    results = [verification.timoshenko_cantilever(), verification.spinning_bar()]
    table = verification.format_results(results)
    assert len(table.splitlines()) == 2 + 3 + 3
    assert "tip deflection [m]" in table


def test_kirsch_field_is_free_at_the_hole_and_uniaxial_far_away():
    a, s = 0.01, 1.0
    phi = np.linspace(0, 2 * math.pi, 13)
    on_hole = analytic.kirsch_stress(a * np.array([np.cos(phi), np.sin(phi)]), s, a)
    traction = np.array(
        [
            on_hole[0] * np.cos(phi) + on_hole[2] * np.sin(phi),
            on_hole[2] * np.cos(phi) + on_hole[1] * np.sin(phi),
        ]
    )
    np.testing.assert_allclose(traction, 0, atol=1e-14)
    np.testing.assert_allclose(
        analytic.kirsch_stress(np.array([[1e3 * a], [7e2 * a]]), s, a)[:, 0], [s, 0, 0], atol=1e-5
    )
    assert analytic.kirsch_stress(np.array([[0.0], [a]]), s, a)[0, 0] == pytest.approx(3 * s)


def test_cantilever_displacements_strain_to_its_stresses_and_clamp_the_root_axis():
    p, length, depth, t, e, nu = 1000.0, 0.5, 0.1, 0.01, 200e9, 0.3
    x, y, h = 0.3, 0.02, 1e-6

    def u(px, py):
        return analytic.cantilever_displacement(np.array([[px], [py]]), p, length, depth, t, e, nu)[:, 0]

    exx = (u(x + h, y)[0] - u(x - h, y)[0]) / (2 * h)
    eyy = (u(x, y + h)[1] - u(x, y - h)[1]) / (2 * h)
    gxy = (u(x, y + h)[0] - u(x, y - h)[0] + u(x + h, y)[1] - u(x - h, y)[1]) / (2 * h)
    sxx, syy, txy = analytic.cantilever_stress(np.array([[x], [y]]), p, length, depth, t)[:, 0]
    assert exx == pytest.approx((sxx - nu * syy) / e, rel=1e-6)
    assert eyy == pytest.approx((syy - nu * sxx) / e, rel=1e-6)
    assert gxy == pytest.approx(2 * (1 + nu) * txy / e, rel=1e-6)
    np.testing.assert_allclose(u(0.0, 0.0), 0.0, atol=1e-20)
    i = t * depth**3 / 12
    tip = -p * length**3 / (3 * e * i) - (4 + 5 * nu) * p * depth**2 * length / (24 * e * i)
    assert analytic.cantilever_tip_deflection(p, length, depth, t, e, nu) == pytest.approx(tip, rel=1e-12)
    # the end shear sums to the load P (downward)
    shear = quad(
        lambda yy: analytic.cantilever_stress(np.array([[length], [yy]]), p, length, depth, t)[2, 0],
        -depth / 2,
        depth / 2,
    )[0]
    assert shear * t == pytest.approx(-p, rel=1e-12)


def test_lame_ring_has_the_pressure_at_the_bore_and_a_free_outside():
    p, a, b = 50e6, 0.05, 0.1
    s_bore = analytic.lame_stress(np.array([[a], [0.0]]), p, a, b)[:, 0]
    s_out = analytic.lame_stress(np.array([[0.0], [b]]), p, a, b)[:, 0]
    assert s_bore[0] == pytest.approx(-p)  # sigma_r at (a, 0) is sigma_xx
    assert s_out[1] == pytest.approx(0.0, abs=1e-6)  # sigma_r at (0, b) is sigma_yy
    assert analytic.lame_hoop_stress(a, p, a, b) == pytest.approx(p * (a * a + b * b) / (b * b - a * a))


def test_golovin_stresses_are_free_on_the_arcs_and_resolve_to_the_moment_alone():
    m, a, b, t = 500.0, 0.05, 0.1, 0.01
    s_rr, _ = analytic.curved_bar_polar(np.array([a, b]), m, a, b, t)
    np.testing.assert_allclose(s_rr, 0.0, atol=1e-6)
    force = quad(lambda r: analytic.curved_bar_polar(r, m, a, b, t)[1], a, b, epsabs=1e-3)[0] * t
    moment = quad(lambda r: analytic.curved_bar_polar(r, m, a, b, t)[1] * r, a, b)[0] * t
    assert abs(force) < 1e-9 * m / (b - a)
    # sigma_theta about the centre of curvature: M > 0 loads the inner fibre in tension
    assert moment == pytest.approx(-m, rel=1e-10)
    assert analytic.curved_bar_polar(a, m, a, b, t)[1] > 0


def test_winkler_bach_resolves_to_the_moment_with_no_net_force():
    m, a, b, t = 500.0, 0.05, 0.1, 0.01
    force = quad(lambda r: analytic.winkler_bach_stress(r, m, a, b, t), a, b, epsabs=1e-3)[0] * t
    moment = quad(lambda r: analytic.winkler_bach_stress(r, m, a, b, t) * r, a, b)[0] * t
    assert abs(force) < 1e-9 * m / (b - a)
    assert moment == pytest.approx(-m, rel=1e-10)


def test_spinning_bar_force_is_largest_at_the_middle_and_zero_at_the_ends():
    assert analytic.spinning_bar_normal_force(0.0, 7850.0, 4e-4, 300.0, 0.4) == pytest.approx(
        7850 * 4e-4 * 9e4 * 0.04 / 2
    )
    assert analytic.spinning_bar_normal_force(0.2, 7850.0, 4e-4, 300.0, 0.4) == pytest.approx(0.0, abs=1e-9)
