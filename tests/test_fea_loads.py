"""Load application: the kinetics' loads as nodal forces, with exact discrete resultants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from linkstress.geometry.builders import straight_bar
from linkstress.loads import LinkLoadCase, PointForce
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.link import solve_link
from linkstress.validation.fea.loads import (
    bearing_loads,
    body_loads,
    nodal_resultant,
    patch_loads,
    shaft_couple_loads,
)
from linkstress.validation.fea.mesh import MeshSettings, mesh_region
from linkstress.validation.fea.plane_stress import plane_stress_model

SETTINGS = MeshSettings(0.1, 0.004, stations=(0.5,))


@pytest.fixture(scope="module")
def crank():
    """The seed's crank: 1 m between 20 mm pin holes, 1.2 x 0.5 x 0.1 m steel; its model."""
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, STRUCTURAL_STEEL, hole_diameter=0.02, name="crank")
    plane = mesh_region(bar.local_outline(), SETTINGS, name="crank")
    return bar, plane_stress_model(plane, 200e9, 0.3, 0.1)


def balanced(bar, pin_at_a, omega, alpha, gravity=(0.0, 0.0), points=()):
    """Loads with the given pin force at A (joint 1), balanced by a pin force and torque at O2 (joint 0)."""
    n = len(omega)
    pins = np.zeros((n, 2, 2))
    pins[:, 1] = pin_at_a
    g = np.tile(gravity, (n, 1))
    open_case = LinkLoadCase((0, 1), pins, np.zeros((n, 2)), omega, alpha, np.zeros((n, 2)), g, tuple(points))
    force, moment = open_case.residual(bar)
    pins[:, 0] = -force
    return LinkLoadCase(
        (0, 1),
        pins,
        np.column_stack([-moment, np.zeros(n)]),
        omega,
        alpha,
        np.zeros((n, 2)),
        g,
        tuple(points),
    )


@settings(max_examples=15, deadline=None)
@given(angle=st.floats(0, 2 * math.pi), magnitude=st.floats(1e-3, 1e6))
def test_bearing_pressure_sums_to_the_pin_force_exactly_with_no_moment_about_the_pin(crank, angle, magnitude):
    _, model = crank
    force = magnitude * np.array([[math.cos(angle), math.sin(angle)]])
    nodal = bearing_loads(model, model.plane.holes[1], np.array([1.0, 0.0]), force)
    resultant, moment = nodal_resultant(model, nodal, about=np.array([1.0, 0.0]))
    np.testing.assert_allclose(resultant, force, rtol=1e-10, atol=1e-10 * magnitude)
    assert abs(moment[0]) <= 1e-12 * magnitude


def test_bearing_pressure_loads_only_the_half_of_the_hole_facing_the_force(crank):
    # Force along +x on the hole at A: the link is pushed at the hole's +x side (cos phi > 0) only.
    _, model = crank
    nodal = bearing_loads(model, model.plane.holes[1], np.array([1.0, 0.0]), np.array([[1000.0, 0.0]]))
    fx, fy = nodal[model.components[0], 0], nodal[model.components[1], 0]
    loaded = np.hypot(fx, fy) > 0
    x = model.scalar.doflocs[0]
    # only the elements holding the +-90 degree points reach past the hole's mid-line, by one element
    assert (x[loaded] >= 1.0 - SETTINGS.hole_size).all()
    assert (x[loaded] >= 1.0).sum() > 0.8 * loaded.sum()
    # pressure pushes radially outward from the pin centre into the material
    assert fx[loaded].sum() == pytest.approx(1000.0, rel=1e-12)
    assert abs(fy[loaded].sum()) < 1e-10 * 1000.0


def test_a_zero_pin_force_loads_nothing(crank):
    _, model = crank
    nodal = bearing_loads(model, model.plane.holes[0], np.zeros(2), np.zeros((1, 2)))
    assert not nodal.any()


@pytest.mark.parametrize("couple", [405.96, -2.0])
def test_shaft_couple_has_exactly_its_moment_and_no_net_force(crank, couple):
    _, model = crank
    nodal = shaft_couple_loads(model, model.plane.holes[0], np.zeros(2), np.array([couple]))
    force, moment = nodal_resultant(model, nodal, about=np.zeros(2))
    assert moment[0] == pytest.approx(couple, rel=1e-12)
    # r x t over a hole of radius 10 mm: the net force is rounding, 1e-10 of couple / radius
    assert np.abs(force).max() <= 1e-10 * abs(couple) / 0.01


def test_body_force_resultant_is_mass_times_the_dalembert_acceleration_of_the_centre(crank):
    # Crank turning about O2 at omega = 3 rad/s, alpha = 2 rad/s^2, gravity -9.81 in member y:
    # resultant = m (g - a_G), a_G = alpha k x r_G - omega^2 r_G, r_G = (0.5, 0); moment about O2
    # = r_G x m g - alpha I_O (Norton, eq. 11.1 with d'Alembert).
    bar, model = crank
    w, al, g = 3.0, 2.0, np.array([0.0, -9.81])
    loads = LinkLoadCase(
        (0, 1),
        np.zeros((1, 2, 2)),
        np.zeros((1, 2)),
        np.array([w]),
        np.array([al]),
        np.zeros((1, 2)),
        g[None],
    )
    force, moment = nodal_resultant(model, body_loads(model, loads, bar.density), about=np.zeros(2))
    m, r_g = bar.mass, np.array([0.5, 0.0])
    a_g = al * np.array([-r_g[1], r_g[0]]) - w * w * r_g
    i_o = bar.mass_moment_of_inertia + m * r_g @ r_g
    # The mesh's holes are circles of the drawing's hole area, drawn by quadratic element edges,
    # which cut O(h^4) of area: the plate's mass agrees with the drawing's to 1e-7.
    np.testing.assert_allclose(force[0], m * (g - a_g), rtol=1e-7)
    assert moment[0] == pytest.approx(r_g[0] * m * g[1] - al * i_o, rel=1e-7)


def test_point_force_on_a_patch_has_exactly_its_resultant_and_moment(crank):
    _, model = crank
    at, force = np.array([0.5, 0.2]), np.array([[120.0, -75.0]])
    nodal = patch_loads(model, at, force, radius=0.03)
    resultant, moment = nodal_resultant(model, nodal, about=np.zeros(2))
    np.testing.assert_allclose(resultant, force, rtol=1e-12)
    assert moment[0] == pytest.approx(at[0] * force[0, 1] - at[1] * force[0, 0], rel=1e-12)
    # spread over a patch, not a point load: many nodes share it
    assert (np.hypot(nodal[model.components[0], 0], nodal[model.components[1], 0]) > 0).sum() >= 10


def test_reactions_vanish_for_a_load_case_in_dynamic_equilibrium():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, STRUCTURAL_STEEL, hole_diameter=0.02, name="crank")
    phi = np.linspace(0, 2 * math.pi, 5, endpoint=False)
    loads = balanced(
        bar,
        800 * np.column_stack([np.cos(phi), np.sin(phi)]),
        np.full(5, -4.0),
        np.sin(phi),
        gravity=(0, -9.81),
        points=[PointForce(np.array([0.6, 0.1]), np.column_stack([50 * np.cos(phi), np.zeros(5)]))],
    )
    result = solve_link(bar, loads, SETTINGS)
    # what is left is the body force on the mesh's area, 1e-7 off the drawing's (see above)
    assert result.reaction_ratio.max() < 1e-8
    assert result.reactions.shape == (5, 3)


def test_reactions_show_a_load_case_out_of_equilibrium():
    # Drop the torque at O2 from a balanced case: the support must carry that torque, and says so.
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, STRUCTURAL_STEEL, hole_diameter=0.02, name="crank")
    loads = balanced(bar, np.array([[0.0, 500.0]]), np.zeros(1), np.zeros(1))
    torque = loads.joint_couples[0, 0]
    broken = LinkLoadCase(
        (0, 1),
        loads.pin_forces,
        np.zeros((1, 2)),
        loads.omega,
        loads.alpha,
        loads.origin_acceleration,
        loads.gravity,
    )
    result = solve_link(bar, broken, SETTINGS)
    assert result.reactions[0, 2] == pytest.approx(torque, rel=1e-9)
    assert result.reaction_ratio[0] > 0.1


def test_a_loaded_joint_without_a_hole_is_an_error_naming_the_link_and_joint():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, STRUCTURAL_STEEL, name="solid crank")
    loads = balanced(bar, np.array([[0.0, 500.0]]), np.zeros(1), np.zeros(1))
    with pytest.raises(
        FEAError, match=r"link 'solid crank': joint 0 carries a pin force of up to 500 N .* has no hole"
    ):
        solve_link(bar, loads, SETTINGS)


def test_an_unloaded_joint_without_a_hole_is_fine():
    bar = straight_bar(0.4, 0.04, 0.0, 0.01, STRUCTURAL_STEEL, name="spinner")
    loads = LinkLoadCase(
        (0, 1),
        np.zeros((1, 2, 2)),
        np.zeros((1, 2)),
        np.array([10.0]),
        np.zeros(1),
        np.array([[100 * 0.2, 0.0]]),
        np.zeros((1, 2)),
    )
    assert solve_link(bar, loads, MeshSettings(0.01)).reaction_ratio[0] < 1e-9


def test_a_load_case_of_the_wrong_shape_is_an_error():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, STRUCTURAL_STEEL, hole_diameter=0.02, name="crank")
    loads = LinkLoadCase(
        (0, 1),
        np.zeros((2, 3, 2)),
        np.zeros((2, 3)),
        np.zeros(2),
        np.zeros(2),
        np.zeros((2, 2)),
        np.zeros((2, 2)),
    )
    with pytest.raises(FEAError, match=r"pin_forces has shape \(2, 3, 2\), expected \(2, 2, 2\)"):
        solve_link(bar, loads, SETTINGS)


def test_a_link_without_elastic_constants_is_an_error():
    from linkstress.materials import Material

    bar = straight_bar(1.0, 0.5, 0.1, 0.1, Material("wood", 600.0), hole_diameter=0.02, name="wooden crank")
    loads = balanced(bar, np.array([[0.0, 1.0]]), np.zeros(1), np.zeros(1))
    with pytest.raises(FEAError, match="wooden crank.*youngs_modulus and poisson_ratio"):
        solve_link(bar, loads, SETTINGS)
