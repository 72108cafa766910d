"""Internal forces N, V, M from the free body of each cut, against closed-form beam results."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from linkstress.analysis import Plan, run_analysis
from linkstress.geometry.builders import straight_bar, stadium
from linkstress.dynamics.internal_forces import internal_forces
from linkstress.dynamics.section_stress import section_stresses
from linkstress.geometry.members import frame_member
from linkstress.kinematics.motion import angle_motion
from linkstress.loads import LinkLoadCase
from linkstress.materials import Material
from linkstress.scene import load_scene

STEEL = Material("steel", 7850.0, 200e9, 0.3)
CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"


def load_case(p, j, **kw):
    base = dict(
        frame_joints=(0, 1),
        pin_forces=np.zeros((p, j, 2)),
        joint_couples=np.zeros((p, j)),
        omega=np.zeros(p),
        alpha=np.zeros(p),
        origin_acceleration=np.zeros((p, 2)),
        gravity=np.zeros((p, 2)),
    )
    base.update(kw)
    return LinkLoadCase(**base)


def test_uniform_bar_spinning_about_its_middle_has_the_closed_form_normal_force():
    # N(xi) = rho A w^2 (L^2/4 - xi^2) / 2, xi measured from the spin centre (a free spinning bar).
    length, h, t = 1.0, 0.05, 0.01
    bar = straight_bar(length, h, 0.0, t, STEEL)
    w = np.array([10.0, 30.0])
    loads = load_case(2, 2, omega=w, origin_acceleration=np.column_stack([w**2 * length / 2, [0, 0]]))
    x = np.linspace(0.0, length, 21)
    forces = internal_forces(bar, loads, bar.sections(x))
    xi = x - length / 2
    expected = 7850 * h * t * w[:, None] ** 2 * (length**2 / 4 - xi**2) / 2
    np.testing.assert_allclose(forces.normal, expected, rtol=1e-9, atol=1e-9 * expected.max())
    np.testing.assert_allclose(forces.shear, 0, atol=1e-9 * expected.max())
    np.testing.assert_allclose(forces.moment, 0, atol=1e-9 * expected.max())
    assert (forces.mismatch < 1e-9).all()


def test_crank_accelerated_from_rest_by_a_torque_has_the_polynomial_moment():
    # Plate crank 0 <= x <= L, height h, pinned at x = 0, torque T there, omega = 0:
    # alpha = T / I_O with I_O = m (L^2 / 3 + h^2 / 12); pin force F = m alpha L / 2 (+y);
    # M(x) = T - x F + mu alpha (x^3 / 6 - x h^2 / 12), mu = m / L; V(x) = -(F - mu alpha x^2 / 2).
    length, h, t, torque = 0.8, 0.06, 0.02, 120.0
    bar = straight_bar(length, h, 0.0, t, STEEL)
    m = bar.mass
    mu = m / length
    alpha = torque / (m * (length**2 / 3 + h**2 / 12))
    f = m * alpha * length / 2
    pins = np.zeros((1, 2, 2))
    pins[0, 0] = [0.0, f]
    couples = np.array([[torque, 0.0]])
    loads = load_case(1, 2, pin_forces=pins, joint_couples=couples, alpha=np.array([alpha]))
    x = np.linspace(0.0, length, 17)
    forces = internal_forces(bar, loads, bar.sections(x))
    moment = torque - x * f + mu * alpha * (x**3 / 6 - x * h**2 / 12)
    np.testing.assert_allclose(forces.moment[0], moment, rtol=1e-9, atol=1e-9 * torque)
    assert forces.moment[0, 0] == pytest.approx(torque, rel=1e-12)
    assert forces.moment[0, -1] == pytest.approx(0.0, abs=1e-9 * torque)
    np.testing.assert_allclose(forces.shear[0], -(f - mu * alpha * x**2 / 2), rtol=1e-9, atol=1e-9 * f)
    np.testing.assert_allclose(forces.normal[0], 0.0, atol=1e-9 * f)
    assert forces.mismatch[0] < 1e-9


def test_two_force_link_has_constant_tension_between_its_pins_and_no_moment():
    # Static, weightless: -P at joint 0, +P at joint 1 along the axis; overhangs carry nothing.
    bar = straight_bar(1.0, 0.2, 0.1, 0.01, STEEL, hole_diameter=0.04)
    p = 5000.0
    pins = np.array([[[-p, 0.0], [p, 0.0]]])
    loads = load_case(1, 2, pin_forces=pins)
    x = np.array([-0.09, -0.01, 0.0, 0.3, 0.7, 0.99, 1.0, 1.05])
    forces = internal_forces(bar, loads, bar.sections(x))
    np.testing.assert_allclose(forces.normal[0], [0, 0, p, p, p, p, 0, 0], atol=1e-9 * p)
    np.testing.assert_allclose(forces.moment[0], 0.0, atol=1e-9 * p)
    np.testing.assert_allclose(forces.shear[0], 0.0, atol=1e-9 * p)
    assert forces.mismatch[0] < 1e-12


def test_cantilever_style_bending_stress_is_mc_over_i_and_shear_is_jourawski():
    # Weightless bar clamped at joint 0 (force -P, couple -P L) and loaded by +P (y) at joint 1.
    # The left part holds the reaction: V = P and M = -P (L - x); the outer fibre, where tau = 0,
    # carries sigma = |M| c / I.
    length, h, t, p = 1.0, 0.1, 0.01, 200.0
    bar = straight_bar(length, h, 0.0, t, STEEL)
    pins = np.array([[[0.0, -p], [0.0, p]]])
    couples = np.array([[-p * length, 0.0]])
    loads = load_case(1, 2, pin_forces=pins, joint_couples=couples)
    x = np.array([0.25, 0.5])
    result = section_stresses(bar, loads, x)
    i = t * h**3 / 12
    np.testing.assert_allclose(result.forces.moment[0], -p * (length - x), rtol=1e-12)
    np.testing.assert_allclose(result.forces.shear[0], p, rtol=1e-12)
    sigma = p * (length - x) * (h / 2) / i
    np.testing.assert_allclose(result.von_mises[0], sigma, rtol=1e-12)
    np.testing.assert_allclose(np.abs(result.fibre_y[0]), h / 2, rtol=1e-12)
    assert result.max_von_mises[0] == pytest.approx(sigma[0], rel=1e-12)
    assert result.max_at[0, 0] == pytest.approx(0.25, rel=1e-12)
    assert abs(result.max_at[0, 1]) == pytest.approx(h / 2, rel=1e-12)


def test_pure_shear_section_peaks_at_the_neutral_axis_with_1_5_v_over_a():
    # Equal and opposite transverse forces make V constant; at the mid station M = 0.
    length, h, t, p = 1.0, 0.1, 0.01, 200.0
    bar = straight_bar(length, h, 0.0, t, STEEL)
    pins = np.array([[[0.0, p], [0.0, -p]]])
    couples = np.array([[p * length / 2, p * length / 2]])
    loads = load_case(1, 2, pin_forces=pins, joint_couples=couples)
    result = section_stresses(bar, loads, np.array([0.5]))
    assert result.forces.moment[0, 0] == pytest.approx(0.0, abs=1e-9)
    assert result.von_mises[0, 0] == pytest.approx(np.sqrt(3) * 1.5 * p / (h * t), rel=1e-12)
    assert result.fibre_y[0, 0] == pytest.approx(0.0, abs=1e-15)


def test_default_stations_avoid_the_ends_where_a_round_link_has_no_depth():
    link = stadium(0.3, 0.06, 0.01, STEEL, hole_diameter=0.02)
    x = frame_member(link, (0, 1)).stations(50)
    lo, hi = link.x_extent()
    assert x[0] > lo and x[-1] < hi
    assert np.allclose(np.diff(x), (hi - lo) / 50)


def test_stations_within_one_depth_of_a_pin_hole_centre_are_flagged():
    # Stadium 0.06 m wide with holes at x = 0 and 0.3: flagged where |x - x_hole| < 0.06 m.
    link = stadium(0.3, 0.06, 0.01, STEEL, hole_diameter=0.02)
    x = np.array([0.0, 0.05, 0.059, 0.061, 0.15, 0.239, 0.25, 0.3])
    pins = np.array([[[-100.0, 0.0], [100.0, 0.0]]])
    result = section_stresses(link, load_case(1, 2, pin_forces=pins), x)
    np.testing.assert_array_equal(result.near_hole, [True, True, True, False, False, False, True, True])
    assert np.isfinite(result.von_mises).all()


def physical(bound):
    """Floats in [-bound, bound] that are 0 or at least 1e-6 in size (no denormal loads)."""
    return st.floats(-bound, bound).filter(lambda v: v == 0 or abs(v) > 1e-6)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(physical(1e4), min_size=4, max_size=4), physical(50), physical(20), physical(1e3), st.booleans(),
)
def test_section_maximum_is_exact_against_dense_fibres(pin, alpha, omega, ax, body_load_near_holes):
    # Random (not equilibrated) loads on a link with pin holes; sections with one and two chords.
    link = stadium(0.3, 0.06, 0.01, STEEL, hole_diameter=0.02)
    pins = np.array([[pin[:2], pin[2:]]])
    loads = load_case(1, 2, pin_forces=pins, alpha=np.array([alpha]), omega=np.array([omega]),
                      origin_acceleration=np.array([[ax, 0.0]]))
    # within 0.06 m (a depth) of the holes at 0 and 0.3 but x = 0.15
    x = np.array([-0.02, 0.004, 0.05, 0.15, 0.297, 0.32])
    result = section_stresses(link, loads, x, body_load_near_holes)
    table, f = result.sections, result.forces
    # body-load term on single-chord sections (near holes only when asked): b_y (v^3 - 0.6 c^2 v) / c^2,
    # b_y = -rho alpha x
    b_y = -7850.0 * alpha * table.x
    for s in range(len(x)):
        ys = np.concatenate([np.linspace(a, b, 4001) for a, b in table.chords(s)])
        sigma = f.normal[0, s] / table.area[s] + f.moment[0, s] * (ys - table.neutral_axis[s]) / table.second_moment[s]
        if table.n_chords[s] == 1 and (body_load_near_holes or s == 3):
            c, v = (table.top[s] - table.bottom[s]) / 2, ys - (table.top[s] + table.bottom[s]) / 2
            sigma = sigma + b_y[s] / c**2 * v * (v * v - 0.6 * c * c)
        q = table.first_moment(np.broadcast_to(ys, (len(x), len(ys))))[s]
        tau = f.shear[0, s] * q / (table.second_moment[s] * table.thickness)
        dense = np.sqrt(sigma**2 + 3 * tau**2).max()
        assert result.von_mises[0, s] >= dense * (1 - 1e-9)
        assert result.von_mises[0, s] <= dense * (1 + 1e-6) + 1e-9
        # and the reported fibre carries that von Mises
        vm_at = np.sqrt(result.sigma[0, s] ** 2 + 3 * result.tau[0, s] ** 2)
        assert vm_at == pytest.approx(result.von_mises[0, s], rel=1e-9, abs=1e-9)


def test_every_section_of_the_banana_coupler_takes_the_largest_von_mises_of_dense_fibres():
    # The banana coupler is sectioned normal to its curved centreline: its cuts between the pins take
    # Winkler-Bach's sigma (sampled fibres, the best refined by a parabola), the straight cuts past the
    # pins (through the lugs, split by the holes) the straight beam's closed-form chord maxima (those
    # with the body-load term are another test's). Each against 4001 fibres per chord at the first
    # positions of the shipped sweep: never above, and within 1e-4 below.
    scene = load_scene(CASES / "banana_coupler" / "scene.toml")
    result = run_analysis(scene, Plan(forces=True, stresses=("coupler",), stations=200, validate=(), notes=()))
    stress = result.stresses["coupler"].at(slice(None))
    table, f, curved = stress.sections, stress.forces, stress.curved
    assert 150 < len(curved.at) < 200
    split = np.flatnonzero(table.n_chords > 1)
    assert len(np.setdiff1d(split, curved.at)) > 0
    for s in np.flatnonzero(stress.shape.corrected_half == 0):
        chords = table.chords(s)
        ys = np.concatenate([np.linspace(a, b, 4001) for a, b in chords])
        # Q(y): first moment about the neutral axis of the material above y
        above = np.clip(chords[None, :, :], ys[:, None, None], None) - table.neutral_axis[s]
        q = table.thickness * ((above[:, :, 1] ** 2 - above[:, :, 0] ** 2) / 2).sum(axis=1)
        if s in curved.at:
            gain = curved.sections.gain(ys, np.full(len(ys), s))
        else:
            gain = (ys - table.neutral_axis[s]) / table.second_moment[s]
        for p in range(6):
            sigma = f.normal[p, s] / table.area[s] + f.moment[p, s] * gain
            tau = f.shear[p, s] * q / (table.second_moment[s] * table.thickness)
            dense = np.sqrt(sigma**2 + 3 * tau**2).max()
            assert dense * (1 - 1e-4) <= stress.von_mises[p, s] <= dense * (1 + 1e-6)


@pytest.mark.parametrize("body_load_near_holes", [False, True])
def test_seed_coupler_maximum_with_the_body_load_term_is_that_of_dense_fibres_over_a_turn(body_load_near_holes):
    # The seed coupler is a 0.5 m deep steel bar: near its free ends N and M fade and its own
    # d'Alembert load makes most of the stress, with peaks inside the section (the case where a
    # search from the linear stress's peak fell short by 6 % of the link's maximum). Those ends are
    # within a depth of a pin: by default their values are nominal (no body-load term), with
    # ``body_load_near_holes`` they take the term and the search.
    scene = load_scene(CASES / "seed_ansys_fourbar" / "scene.toml")
    scene = replace(scene, motion=angle_motion(np.linspace(0.0, 360.0, 72, endpoint=False), -1.0, 0.0))
    result = run_analysis(scene, Plan(forces=True, stresses=(), stations=200, validate=(), notes=()))
    link, loads = scene.links["coupler"].profile, result.forces.link_loads["coupler"]
    stress = section_stresses(link, loads, frame_member(link, loads.frame_joints).stations(200), body_load_near_holes)
    table, f = stress.sections, stress.forces
    rho = link.density
    b_y = rho * ((loads.gravity[:, 1] - loads.origin_acceleration[:, 1])[:, None] - loads.alpha[:, None] * table.x)
    v = np.linspace(-1.0, 1.0, 2001)
    inside = 0
    for s in np.flatnonzero(table.n_chords == 1):
        c = (table.top[s] - table.bottom[s]) / 2
        u = v * c
        term = (b_y[:, s, None] / c**2) * u * (u * u - 0.6 * c * c)
        sigma = f.normal[:, s, None] / table.area[s] + f.moment[:, s, None] * u / table.second_moment[s]
        if body_load_near_holes or not stress.near_hole[s]:
            sigma = sigma + term
        tau = f.shear[:, s, None] / (2 * table.second_moment[s]) * (c * c - u * u)
        dense = np.sqrt(sigma**2 + 3 * tau**2).max(axis=1)
        assert (stress.von_mises[:, s] >= dense * (1 - 1e-9)).all()
        assert (stress.von_mises[:, s] <= dense * (1 + 1e-6)).all()
        if body_load_near_holes or not stress.near_hole[s]:
            inside += int((np.abs(stress.fibre_y[:, s] - table.neutral_axis[s]) < 0.99 * c).sum())
    # the search decided the peak inside the section at some (position, station) pairs
    assert inside > (1000 if body_load_near_holes else 10)


def test_equilibrium_check_at_the_hull_corners_equals_the_check_at_every_cut(monkeypatch):
    # The moment of the whole link's resultant is affine in the cut point, so its largest size over
    # the cuts is reached at a corner of their convex hull (a long sweep takes those only).
    import linkstress.dynamics.internal_forces as internal

    scene = load_scene(CASES / "seed_ansys_fourbar" / "scene.toml")
    scene = replace(scene, motion=angle_motion(np.linspace(0.0, 179.0, 400), -1.0, 0.0))
    forces = run_analysis(scene, Plan(forces=True, stresses=(), stations=200, validate=(), notes=())).forces
    for name in ("crank", "coupler", "output"):
        link, loads = scene.links[name].profile, forces.link_loads[name]
        stations = frame_member(link, loads.frame_joints).stations(200)
        # an unbalanced force, so that the moment check varies along the link (and is not rounding)
        extra = np.zeros_like(loads.pin_forces)
        extra[:, 0] = [3.0, 40.0]
        loads = replace(loads, pin_forces=loads.pin_forces + extra)
        corners = section_stresses(link, loads, stations).forces.mismatch
        monkeypatch.setattr(internal, "EVERY_CUT_PAIRS", 10**12)
        every = section_stresses(link, loads, stations).forces.mismatch
        monkeypatch.undo()
        assert every.max() > 1e-3
        np.testing.assert_allclose(corners, every, rtol=1e-12)
