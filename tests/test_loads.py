"""Link load cases: the d'Alembert load and the equilibrium residual."""

from __future__ import annotations

import numpy as np

from linkstress.geometry.builders import straight_bar
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL


def test_bar_spinning_about_its_middle_is_in_equilibrium_without_pin_forces():
    # Origin (joint 0) is L/2 from the spin centre: a_O = omega^2 L / 2 toward the centre (+x).
    bar = straight_bar(1.0, 0.1, 0.0, 0.01, STRUCTURAL_STEEL)
    w = np.array([3.0, 10.0])
    loads = LinkLoadCase(
        frame_joints=(0, 1),
        pin_forces=np.zeros((2, 2, 2)),
        joint_couples=np.zeros((2, 2)),
        omega=w,
        alpha=np.zeros(2),
        origin_acceleration=np.column_stack([w**2 * 0.5, [0, 0]]),
        gravity=np.zeros((2, 2)),
    )
    force, moment = loads.residual(bar)
    np.testing.assert_allclose(force, 0, atol=1e-9 * bar.mass * 100)
    np.testing.assert_allclose(moment, 0, atol=1e-9 * bar.mass * 100)
    # The load density at the tip is rho omega^2 L/2 outward (+x), zero at the centre.
    b = loads.body_force_density(np.array([[1.0, 0.0], [0.5, 0.0]]), 7850.0)
    np.testing.assert_allclose(b[1], [[7850 * 100 * 0.5, 0], [0, 0]], atol=1e-9)


def test_crank_accelerated_from_rest_needs_torque_i_o_alpha():
    # Pivot at joint 0 held by a pin force; a couple T at the pivot gives alpha = T / I_O.
    bar = straight_bar(1.0, 0.1, 0.0, 0.01, STRUCTURAL_STEEL)
    m, i_o = bar.mass, bar.mass_moment_of_inertia + bar.mass * 0.25
    torque = 50.0
    alpha = torque / i_o
    pin = np.array([[[0.0, m * alpha * 0.5], [0.0, 0.0]]])  # F = m a_G with a_G = (0, alpha L / 2)
    loads = LinkLoadCase(
        frame_joints=(0, 1),
        pin_forces=pin,
        joint_couples=np.array([[torque, 0.0]]),
        omega=np.zeros(1),
        alpha=np.array([alpha]),
        origin_acceleration=np.zeros((1, 2)),
        gravity=np.zeros((1, 2)),
    )
    force, moment = loads.residual(bar)
    np.testing.assert_allclose(force, 0, atol=1e-9)
    np.testing.assert_allclose(moment, 0, atol=1e-9)
