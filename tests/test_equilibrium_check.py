"""The equilibrium check (both free bodies of every cut agree) is relative to the link's load.

The right free body of a cut differs from the left's by the resultant of every load on the link
about the cut point (``linkstress.dynamics.internal_forces``). That difference is measured against
the link's load: its force against the gross force (the sum of |F_x| + |F_y| of every pin and
point force, and of the d'Alembert load's terms), its moment against the gross force times the
cuts' reach from the frame's origin plus the loads' own moments about it (couples, pin forces times
their lever arms). A balanced link then reads ~1e-16 whatever its section forces: a two-force link
in pure tension carries M ~ 1e-13 N m of rounding, and the check once divided the moment's rounding
by that rounding (a user's rocker read 0.61).

Loads are static and generated here (no speed, no gravity: the body-load terms are zero), on bars
and an L-shaped bell crank drawn with shapely.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import Polygon, box

from linkstress.dynamics.internal_forces import internal_forces
from linkstress.dynamics.section_stress import section_stresses
from linkstress.geometry.builders import straight_bar
from linkstress.geometry.curves import circle_points
from linkstress.geometry.members import link_members
from linkstress.geometry.profile import LinkProfile
from linkstress.loads import LinkLoadCase
from linkstress.materials import Material

STEEL = Material("steel", 7850.0, 200e9, 0.3)


def static(pins: np.ndarray, couples: np.ndarray | None = None, frame=(0, 1)) -> LinkLoadCase:
    """Static loads: pin forces (P, J, 2) [N, load frame] and joint couples (P, J) [N m]."""
    p, j = pins.shape[:2]
    zero = np.zeros((p, 2))
    return LinkLoadCase(frame, pins, np.zeros((p, j)) if couples is None else couples, np.zeros(p), np.zeros(p),
                        zero, zero)


@pytest.mark.parametrize("angle_deg", [17.0, 33.3, 71.0, 123.4])
@pytest.mark.parametrize("tension", [10.0, 5e3, 2e6])
def test_a_two_force_link_in_pure_tension_reads_zero_not_rounding_over_rounding(angle_deg, tension):
    # The pull along the axis as a ground-frame force turned into the load frame: its component
    # across the axis is rounding (~1e-16 of it), so M along the link is rounding too, of the same
    # size as the two free bodies' moment difference. Against the link's load (2 x tension) both
    # are ~1e-16.
    bar = straight_bar(0.3, 0.03, 0.015, 0.005, STEEL, hole_diameter=0.01)
    a = math.radians(angle_deg)
    ground = tension * np.array([math.cos(a), math.sin(a)])
    turn = np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])
    pull = turn @ ground
    pins = np.array([[-pull, pull]])
    forces = internal_forces(bar, static(pins), bar.sections(np.linspace(0.03, 0.27, 9)))
    np.testing.assert_allclose(forces.normal[0], tension, rtol=1e-12)
    assert np.abs(forces.moment).max() < 1e-12 * tension * 0.3
    assert forces.mismatch[0] < 1e-13


def test_an_unbalanced_pull_reads_its_imbalance_over_the_links_gross_force():
    # -1000 N at joint 0 and +999 N at joint 1, along the axis: 1 N of imbalance over a gross force
    # of 1,999 N; on the axis it has no moment about any cut point (y_na = 0).
    bar = straight_bar(1.0, 0.2, 0.1, 0.01, STEEL)
    pins = np.array([[[-1000.0, 0.0], [999.0, 0.0]]])
    forces = internal_forces(bar, static(pins), bar.sections([0.25, 0.5]))
    assert forces.mismatch[0] == pytest.approx(1.0 / 1999.0, rel=1e-12)


def bell_crank(arm: float = 0.3, width: float = 0.04, hole: float = 0.012) -> LinkProfile:
    """An L of ``width`` [m] wide arms, 10 mm steel: pivot O (0, 0), arm to B (``arm``, 0), arm to C
    (0, ``arm``), a pin hole at each."""
    w = width / 2
    shell = box(-w, -w, arm + w, w).union(box(-w, -w, w, arm + w))
    holes = [circle_points(c, hole / 2, 1e-7)[::-1] for c in ((0.0, 0.0), (arm, 0.0), (0.0, arm))]
    return LinkProfile(Polygon(shell.exterior, holes), np.array([(0.0, 0.0), (arm, 0.0), (0.0, arm)]), 0.01, STEEL, "bell")


@pytest.mark.parametrize("load", [1.0, 750.0, 4e5])
def test_a_balanced_bell_crank_reads_zero_on_both_arms(load):
    # P down at B (0.3, 0) and P toward -x at C (0, 0.3): moments -0.3 P and +0.3 P about O, which
    # takes (P, P).
    crank = bell_crank()
    p = load
    pins = np.array([[[p, p], [0.0, -p], [-p, 0.0]]])
    loads = static(pins)
    members = link_members(crank, (0, 1))
    assert {m.joints for m in members} == {(0, 1), (0, 2)}
    for member in members:
        stress = section_stresses(crank, loads, np.array([0.06, 0.12, 0.2]), member=member)
        assert np.abs(stress.forces.moment).max() > 0.09 * p  # the arms bend: P (0.3 - s)
        assert stress.forces.mismatch[0] < 1e-13


def test_an_unbalanced_bell_crank_reads_its_moment_imbalance_over_the_links_load():
    # The pivot's force is right but C's is 1 % short: 0.01 P along -x at (0, 0.3) leaves a force
    # 0.01 P and a moment 0.003 P about O. The gross force is |P| + |P| (O) + P (B) + 0.99 P (C) =
    # 3.99 P; the loads' own moments about O are 0.3 P (B) + 0.3 x 0.99 P (C) = 0.597 P. On the arm
    # O-B (cuts on y = 0 at s = 0.06 .. 0.2 m): the moment difference about a cut point (s, 0) is
    # M_O - s F_y + 0 F_x = 0.003 P - 0 (F_y = 0): 0.003 P over 3.99 P x 0.2 m + 0.597 P.
    crank = bell_crank()
    p = 1000.0
    pins = np.array([[[p, p], [0.0, -p], [-0.99 * p, 0.0]]])
    loads = static(pins)
    arm = next(m for m in link_members(crank, (0, 1)) if m.joints == (0, 1))
    s = np.array([0.06, 0.12, 0.2])
    stress = section_stresses(crank, loads, s, member=arm)
    np.testing.assert_allclose(stress.cuts.cut_points[:, 1], 0.0, atol=1e-12)
    force_part = 0.01 * p / (3.99 * p)
    moment_part = 0.003 * p / (3.99 * p * 0.2 + 0.597 * p)
    assert moment_part < force_part
    assert stress.forces.mismatch[0] == pytest.approx(force_part, rel=1e-9)


@pytest.mark.parametrize("torque", [0.5, 120.0, 3e4])
def test_a_crank_driven_by_a_couple_reads_zero_balanced_and_its_couple_imbalance_when_not(torque):
    # A couple T at the pivot (0, 0) against T / L across the axis at the crank pin (L, 0), the pivot
    # taking the opposite force: balanced. A couple 0.1 % too large leaves 0.001 T about every cut
    # point (no net force). The link's load: gross force 2 T / L, its moments' own sizes 1.001 T
    # (the couple) + T (the crank pin's T / L times L); the cuts reach 0.09 m from the pivot.
    length = 0.1
    bar = straight_bar(length, 0.02, 0.01, 0.005, STEEL, hole_diameter=0.006)
    f = torque / length
    pins = np.array([[[0.0, f], [0.0, -f]]])
    x = np.linspace(0.01, 0.09, 9)
    balanced = internal_forces(bar, static(pins, np.array([[torque, 0.0]])), bar.sections(x))
    assert balanced.mismatch[0] < 1e-13
    off = internal_forces(bar, static(pins, np.array([[1.001 * torque, 0.0]])), bar.sections(x))
    expected = 0.001 * torque / (2 * f * 0.09 + 1.001 * torque + torque)
    assert off.mismatch[0] == pytest.approx(expected, rel=1e-9)
