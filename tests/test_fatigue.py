"""Fatigue safety factors against the closed forms of Shigley's fatigue criteria.

Budynas & Nisbett, Shigley's Mechanical Engineering Design, 10th ed., ch. 6 (fatigue failure
criteria for fluctuating stress; Marin endurance-limit modifying factors). The strengths below are
chosen so that each criterion's equation gives a round n by hand.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from linkstress.fatigue import (
    CRITERIA,
    FatigueStrength,
    alternating_and_mean,
    criteria_available,
    node_fatigue,
    safety_factor,
    signed_von_mises,
)

MPA = 1e6
# S_e' = 200 MPa, S_ut = 600 MPa, S_y = 400 MPa, no Marin correction: S_e = 200 MPa.
STEEL = FatigueStrength(200 * MPA, 600 * MPA, 400 * MPA)


@pytest.fixture(autouse=True)
def _numpy_warnings_are_errors():
    """No criterion may divide by zero or make nan: any numpy warning fails the test."""
    with warnings.catch_warnings(), np.errstate(all="raise"):
        warnings.simplefilter("error")
        yield


def gerber_textbook(sigma_a, sigma_m, strength):
    """Shigley's closed form: n = (1/2) (S_ut/sigma_m)^2 (sigma_a/S_e) [-1 + sqrt(1 + (2 sigma_m S_e / (S_ut sigma_a))^2)]."""
    s_e, s_ut = strength.corrected_endurance_limit, strength.ultimate_strength
    return 0.5 * (s_ut / sigma_m) ** 2 * (sigma_a / s_e) * (-1 + np.sqrt(1 + (2 * sigma_m * s_e / (s_ut * sigma_a)) ** 2))


@pytest.mark.parametrize("criterion", CRITERIA)
def test_fully_reversed_every_criterion_gives_endurance_limit_over_amplitude_exactly(criterion):
    sigma_a = np.array([1.0, 37.5, 123.456789, 199.0, 1234.5]) * MPA
    n = safety_factor(criterion, sigma_a, 0.0, STEEL)
    assert np.array_equal(n, 200 * MPA / sigma_a)


@pytest.mark.parametrize("sigma_a, sigma_m, n", [
    (50, 150, 2.0),     # 50/200 + 150/600 = 1/2
    (75, 150, 1.6),     # 75/200 + 150/600 = 0.625
    (100, 300, 1.0),    # on the line
    (20, 60, 5.0),      # 0.1 + 0.1
])
def test_goodman_is_one_over_the_sum_of_the_strength_ratios(sigma_a, sigma_m, n):
    assert safety_factor("goodman", sigma_a * MPA, sigma_m * MPA, STEEL) == pytest.approx(n, rel=1e-15)


@pytest.mark.parametrize("sigma_a, sigma_m, n", [
    (75, 150, 2.0),     # 2 (75/200) + (2 x 150/600)^2 = 0.75 + 0.25
    (37.5, 75, 4.0),    # 4 (37.5/200) + (4 x 75/600)^2 = 0.75 + 0.25
    (100, 0, 2.0),      # fully reversed
    (0, 300, 2.0),      # static: S_ut / sigma_m
])
def test_gerber_solves_its_parabola(sigma_a, sigma_m, n):
    assert safety_factor("gerber", sigma_a * MPA, sigma_m * MPA, STEEL) == pytest.approx(n, rel=1e-15)


@pytest.mark.parametrize("sigma_a, sigma_m, n", [
    (60, 160, 2.0),     # (2 x 60/200)^2 + (2 x 160/400)^2 = 0.36 + 0.64
    (30, 80, 4.0),      # (4 x 30/200)^2 + (4 x 80/400)^2 = 0.36 + 0.64
    (0, 100, 4.0),      # static: S_y / sigma_m
])
def test_asme_elliptic_solves_its_ellipse(sigma_a, sigma_m, n):
    assert safety_factor("asme-elliptic", sigma_a * MPA, sigma_m * MPA, STEEL) == pytest.approx(n, rel=1e-15)


def test_gerber_stable_form_matches_the_textbook_form_where_that_is_well_conditioned():
    sigma_a, sigma_m = np.meshgrid(np.geomspace(1, 500, 40) * MPA, np.geomspace(1, 500, 40) * MPA)
    ratio = sigma_m / sigma_a
    # The textbook form cancels in -1 + sqrt(1 + x^2) when x = 2 sigma_m S_e / (S_ut sigma_a) is small;
    # with x >= 0.1 it keeps all but about two digits.
    well = 2 * ratio * 200 / 600 >= 0.1
    stable = safety_factor("gerber", sigma_a, sigma_m, STEEL)[well]
    np.testing.assert_allclose(stable, gerber_textbook(sigma_a, sigma_m, STEEL)[well], rtol=1e-12)
    assert well.sum() > 1000


def test_gerber_keeps_its_digits_where_the_textbook_form_cancels():
    """sigma_m = 1 Pa against sigma_a = 100 MPa: n = S_e / sigma_a within 1e-17, where the textbook
    form gives 0 (its -1 + sqrt(1 + x^2) with x = 6.7e-9 keeps no digit of x^2 / 2)."""
    n = safety_factor("gerber", 100 * MPA, 1.0, STEEL)
    assert n == pytest.approx(2.0, rel=1e-15)
    assert gerber_textbook(100 * MPA, 1.0, STEEL) == 0.0


def test_gerber_is_never_below_goodman_under_a_tensile_mean():
    sigma_a, sigma_m = np.meshgrid(np.linspace(0, 400, 81) * MPA, np.linspace(1, 800, 81) * MPA)
    assert np.all(safety_factor("gerber", sigma_a, sigma_m, STEEL) >= safety_factor("goodman", sigma_a, sigma_m, STEEL))


def test_a_static_tensile_stress_gives_the_static_strength_over_it():
    sigma_m = np.array([50.0, 300.0, 900.0]) * MPA
    np.testing.assert_allclose(safety_factor("goodman", 0.0, sigma_m, STEEL), 600 * MPA / sigma_m, rtol=1e-15)
    np.testing.assert_allclose(safety_factor("gerber", 0.0, sigma_m, STEEL), 600 * MPA / sigma_m, rtol=1e-15)
    np.testing.assert_allclose(safety_factor("asme-elliptic", 0.0, sigma_m, STEEL), 400 * MPA / sigma_m, rtol=1e-15)


@pytest.mark.parametrize("criterion", CRITERIA)
def test_a_compressive_mean_does_not_lower_the_factor(criterion):
    sigma_a = np.array([10.0, 50.0, 100.0]) * MPA
    n = safety_factor(criterion, sigma_a, -300 * MPA, STEEL)
    assert np.array_equal(n, 200 * MPA / sigma_a)


@pytest.mark.parametrize("criterion", CRITERIA)
def test_nothing_that_cycles_gives_infinity_never_nan(criterion):
    n = safety_factor(criterion, np.zeros(3), np.array([0.0, -0.0, -5 * MPA]), STEEL)
    assert np.all(np.isposinf(n))


def test_asme_elliptic_needs_a_yield_strength():
    no_yield = FatigueStrength(200 * MPA, 600 * MPA)
    assert criteria_available(no_yield) == ("goodman", "gerber")
    assert criteria_available(STEEL) == CRITERIA
    with pytest.raises(ValueError, match="asme-elliptic needs a yield strength"):
        safety_factor("asme-elliptic", 1.0, 1.0, no_yield)


def test_an_unknown_criterion_is_refused():
    with pytest.raises(ValueError, match="criterion must be one of goodman, gerber, asme-elliptic"):
        safety_factor("soderberg", 1.0, 1.0, STEEL)


def test_a_negative_amplitude_is_refused():
    with pytest.raises(ValueError, match="sigma_a is half a range and must be >= 0"):
        safety_factor("goodman", [1.0, -1.0], 0.0, STEEL)


def test_marin_factors_multiply_the_specimen_endurance_limit():
    strength = FatigueStrength(200 * MPA, 600 * MPA, surface_factor=0.75, size_factor=0.8)
    assert strength.corrected_endurance_limit == pytest.approx(0.6 * 200 * MPA, rel=1e-15)
    # Fully reversed at 60 MPa: n = 0.75 x 0.8 x 200 / 60 = 2.
    assert safety_factor("goodman", 60 * MPA, 0.0, strength) == pytest.approx(2.0, rel=1e-15)


def test_alternating_and_mean_are_half_the_range_and_the_mid_value():
    sigma_a, sigma_m = alternating_and_mean([300.0, 100.0, -20.0], [-100.0, 100.0, -80.0])
    np.testing.assert_array_equal(sigma_a, [200.0, 0.0, 30.0])
    np.testing.assert_array_equal(sigma_m, [100.0, 100.0, -50.0])
    with pytest.raises(ValueError, match="largest must be >= smallest"):
        alternating_and_mean([1.0], [2.0])


@pytest.mark.parametrize("sigma", [250 * MPA, -250 * MPA, 1e-3])
def test_signed_von_mises_of_a_uniaxial_stress_is_the_stress(sigma):
    assert signed_von_mises([sigma, 0.0, 0.0]) == sigma
    assert signed_von_mises([0.0, sigma, 0.0]) == sigma


@pytest.mark.parametrize("tau", [80 * MPA, -80 * MPA])
def test_signed_von_mises_of_pure_shear_is_root_three_tau_counted_as_tension(tau):
    assert signed_von_mises([0.0, 0.0, tau]) == pytest.approx(math.sqrt(3) * abs(tau), rel=1e-15)
    # The same shear in principal axes: +tau and -tau, equal magnitudes, trace 0 -> tension.
    assert signed_von_mises([tau, -tau, 0.0]) == pytest.approx(math.sqrt(3) * abs(tau), rel=1e-15)


def test_signed_von_mises_of_equal_biaxial_compression_is_minus_its_size():
    assert signed_von_mises([-120 * MPA, -120 * MPA, 0.0]) == -120 * MPA


def test_signed_von_mises_takes_the_sign_of_the_larger_principal():
    # sigma_xx = 10, sigma_yy = -30, tau = 0: principals 10 and -30, von Mises sqrt(100 + 300 + 900).
    assert signed_von_mises([10.0, -30.0, 0.0]) == pytest.approx(-math.sqrt(1300.0), rel=1e-15)


def test_signed_von_mises_is_vectorised_over_positions_and_nodes():
    rng = np.random.default_rng(7)
    stress = rng.normal(size=(4, 6, 3)) * 100 * MPA
    values = signed_von_mises(stress)
    assert values.shape == (4, 6)
    sxx, syy, txy = stress[2, 3]
    centre, radius = (sxx + syy) / 2, math.hypot((sxx - syy) / 2, txy)
    s1, s2 = centre + radius, centre - radius
    larger = s1 if abs(s1) >= abs(s2) else s2
    assert values[2, 3] == pytest.approx(math.copysign(math.sqrt(s1 * s1 - s1 * s2 + s2 * s2), larger), rel=1e-13)
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 3\)"):
        signed_von_mises(np.zeros((4, 2)))


def test_node_fatigue_finds_the_critical_node_and_every_criterion_there():
    # Node 0: static; 1: fully reversed 50 MPa (n = 4 everywhere); 2: Goodman's n = 2 point
    # (sigma_a 50, sigma_m 150); 3: the same, tied (the lowest index wins); 4: nothing.
    largest = np.array([100.0, 50.0, 200.0, 200.0, 0.0]) * MPA
    smallest = np.array([100.0, -50.0, 100.0, 100.0, 0.0]) * MPA
    result = node_fatigue(largest, smallest, STEEL)
    assert result.critical_node == 2
    assert (result.sigma_a, result.sigma_m) == (50 * MPA, 150 * MPA)
    assert result.factor == pytest.approx(2.0, rel=1e-15)
    assert set(result.factors) == set(CRITERIA)
    np.testing.assert_allclose(result.factors["goodman"], [6.0, 4.0, 2.0, 2.0, np.inf], rtol=1e-15)
    # Gerber at node 2: n (50/200) + (n 150/600)^2 = 1, whose positive root is 2 / (1/4 + sqrt(1/16 + 1/4)).
    assert result.critical_factors["gerber"] == pytest.approx(2 / (0.25 + math.sqrt(0.0625 + 0.25)), rel=1e-15)
    assert result.critical_factors["asme-elliptic"] == pytest.approx(1 / math.hypot(0.25, 150 / 400), rel=1e-15)


def test_node_fatigue_by_another_criterion_and_without_a_yield_strength():
    largest, smallest = np.array([200.0, 90.0]) * MPA, np.array([100.0, -90.0]) * MPA
    # Node 0 (sigma_a 50, sigma_m 150): Goodman 2, Gerber 2.47; node 1 fully reversed 90 MPa: 2.22 for all.
    assert node_fatigue(largest, smallest, STEEL).critical_node == 0
    assert node_fatigue(largest, smallest, STEEL, "gerber").critical_node == 1
    no_yield = FatigueStrength(200 * MPA, 600 * MPA)
    result = node_fatigue(largest, smallest, no_yield)
    assert set(result.critical_factors) == {"goodman", "gerber"}
    with pytest.raises(ValueError, match="criterion must be one of goodman, gerber for this material"):
        node_fatigue(largest, smallest, no_yield, "asme-elliptic")
