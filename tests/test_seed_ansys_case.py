"""The seed's ANSYS four-bar (docs/reference/seed-ansys-fourbar.md) through the whole engine.

The original program printed the right kinematics and forces (the reference below) but wrong
section stresses: it applied the far joint's force at every station, added T12 to every link's
moment and ignored the cut-off part's inertia. These tests pin the correct free-body results.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from linkstress.analysis import run_analysis
from linkstress.dynamics.section_stress import section_stresses
from linkstress.scene import load_scene

SCENE = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar" / "scene.toml"
REFERENCE_FORCES = {"F12": (-869.94, -694.86), "F32": (752.19, 490.91), "F43": (246.60, 87.01), "F14": (-92.19, -27.97)}
REFERENCE_T12 = 405.96


@pytest.fixture(scope="module")
def seed():
    return run_analysis(load_scene(SCENE))


def test_seed_sketch_bars_have_the_reference_masses_less_their_pin_holes(seed):
    # 7850 x 0.1 x (L x 0.5 - 2 pi 0.01^2): crank 471.0 - 0.493 kg, coupler and output 667.25 - 0.493 kg
    hole = 7850 * 0.1 * 2 * np.pi * 0.01**2
    for name, solid in (("crank", 471.0), ("coupler", 667.25), ("output", 667.25)):
        assert seed.scene.links[name].mass_data.mass == pytest.approx(solid - hole, rel=1e-6)


def test_seed_accelerations_match_the_reference(seed):
    # a_G (m/s^2) and alpha (rad/s^2) as printed by the original program (3 decimals)
    expected = {"crank": ((-0.250, -0.433), 0.0), "coupler": ((-0.758, -0.605), 0.459), "output": ((-0.508, -0.172), 0.695)}
    for name, (acc, alpha) in expected.items():
        motion = seed.kinematics.links[name]
        a_g = motion.point(seed.scene.links[name].center_of_mass)[2][0]
        np.testing.assert_allclose(a_g, acc, atol=6e-4)
        assert motion.alpha[0] == pytest.approx(alpha, abs=6e-4)


def test_seed_joint_forces_and_torque_within_the_pin_holes_mass_of_the_reference(seed):
    # The reference bars were solid (tests/test_dynamics_machine.py matches them to 0.1 % per
    # component); the drawn bars have pin holes, 0.105 % less mass, which moves each force by up to
    # 0.15 % of its magnitude and T12 by 0.08 %.
    main = seed.forces.mechanisms["main"]
    for name, value in REFERENCE_FORCES.items():
        got = main.forces[name][0]
        assert np.hypot(*(got - value)) <= 1.5e-3 * np.hypot(*value), (name, got)
    assert main.driving_torque[0] == pytest.approx(REFERENCE_T12, rel=1e-3)


def test_crank_internal_moment_at_o2_equals_the_driving_torque(seed):
    loads = seed.forces.link_loads["crank"]
    at_o2 = section_stresses(seed.scene.links["crank"].profile, loads, np.array([0.0]))
    assert at_o2.forces.moment[0, 0] == pytest.approx(seed.forces.mechanisms["main"].driving_torque[0], rel=1e-9)


def test_coupler_and_output_carry_their_own_loads_not_the_crank_torque(seed):
    # Two pins and no couple on the coupler: at its joints M is only the 0.1 m overhang's inertia
    # (39 kg at about 0.8 m/s^2, a few N m), and along it the bending of its own d'Alembert load
    # (667 kg, about 1 m/s^2 over 1.5 m: tens of N m), not the crank's 406 N m that the original
    # program added, so its stress is far below the 152730 Pa it printed.
    torque = seed.forces.mechanisms["main"].driving_torque[0]
    coupler = seed.stresses["coupler"].at(slice(None))
    assert np.abs(coupler.forces.moment).max() < 0.1 * torque
    at_joints = section_stresses(seed.scene.links["coupler"].profile, seed.forces.link_loads["coupler"], np.array([0.0, 1.5]))
    assert np.abs(at_joints.forces.moment).max() < 0.01 * torque
    assert coupler.max_von_mises[0] < 0.2 * 152730
    # the output carries the 2 N m couple at O4: its moment there is 2 N m plus its overhang's
    # inertia (under 1 N m)
    output_at_o4 = section_stresses(seed.scene.links["output"].profile, seed.forces.link_loads["output"], np.array([0.0]))
    assert output_at_o4.forces.moment[0, 0] == pytest.approx(2.0, abs=1.0)


def test_seed_stresses_are_in_equilibrium_from_both_ends(seed):
    for name in ("crank", "coupler", "output"):
        assert seed.stresses[name].mismatch[0] < 1e-9


def test_crank_von_mises_is_the_free_body_value_not_the_seed_programs(seed):
    # At O2 the section through the hole carries M = T12 and the axial part of F12:
    # N = -F12 . (cos 60, sin 60) = 1036.7 N (tension), A = 0.1 (0.5 - 0.02), I = 0.1 (0.5^3 - 0.02^3) / 12,
    # sigma = N / A + M c / I = 21.6 + 97.4 = 119 kPa (the original printed 221073 Pa).
    f12 = np.array(REFERENCE_FORCES["F12"])
    normal = -f12 @ [np.cos(np.pi / 3), np.sin(np.pi / 3)]
    expected = normal / (0.1 * 0.48) + REFERENCE_T12 * 0.25 / (0.1 * (0.5**3 - 0.02**3) / 12)
    assert seed.stresses["crank"].max_von_mises[0] == pytest.approx(expected, rel=0.01)
