"""Beam against FEA along each member of a link: stations clear of pins and junctions, resultants
over the member's cut segments, von Mises at the beam's critical fibre."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from linkstress.builders import straight_bar
from linkstress.dynamics.section_stress import section_stresses
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.sections import SectionTable
from linkstress.validation.compare import (
    choose_stations,
    compare_link,
    MemberBeam,
    hole_circles,
    member_stations,
    resultant_error,
)
from linkstress.validation.errors import FEAError
from linkstress.validation.report import member_record, member_words


@dataclass(frozen=True)
class AxisCuts:
    """What ``members.py``'s MemberCuts holds, for a member on a straight axis: stations ``s`` along
    it from ``start``, the axis point ``origin``, ``tangent``, ``normal``, the section ``table`` (v
    along the normal), the cut segments ``ends`` and the flags."""

    s: np.ndarray
    origin: np.ndarray
    tangent: np.ndarray
    normal: np.ndarray
    table: object
    ends: np.ndarray
    near_hole: np.ndarray
    junction: np.ndarray


def frame_cuts(table: SectionTable, near_hole: np.ndarray) -> AxisCuts:
    """The cuts of a member along the frame's x axis (the vertical stations x of ``table``)."""
    x = table.x
    ones = np.ones((len(x), 1))
    ends = np.stack([np.column_stack([x, table.bottom]), np.column_stack([x, table.top])], axis=1)
    return AxisCuts(
        x, np.column_stack([x, 0 * x]), ones * [1.0, 0.0], ones * [0.0, 1.0], table, ends, near_hole,
        np.zeros(len(x), bool),
    )


@dataclass(frozen=True)
class StraightArm:
    """A straight member of constant ``depth`` from ``a`` to ``b`` (load frame), centred on its axis."""

    a: np.ndarray
    b: np.ndarray
    depth: float

    @property
    def length(self) -> float:
        return float(np.hypot(*(self.b - self.a)))

    def cuts(self, s: np.ndarray) -> AxisCuts:
        t = (self.b - self.a) / self.length
        n = np.array([-t[1], t[0]])
        origin = self.a + s[:, None] * t
        half = np.full(len(s), self.depth / 2)
        table = type("Table", (), {"top": half, "bottom": -half, "neutral_axis": 0 * half})()
        ends = np.stack([origin - half[:, None] * n, origin + half[:, None] * n], axis=1)
        flags = np.zeros(len(s), bool)
        return AxisCuts(s, origin, np.tile(t, (len(s), 1)), np.tile(n, (len(s), 1)), table, ends, flags, flags)


def test_member_stations_keep_five_radii_from_pins_and_a_depth_from_the_other_arm():
    # A bell crank's arm from the pivot (0, 0) to the corner (0.3, 0), 40 mm deep; the other arm
    # runs up from the corner; 12 mm holes at the pivot and at (0.3, 0.27). Cell centres 0.01 ..
    # 0.29 m: five radii from the pivot's hole is s > 0.03 m, a depth from the other arm's axis
    # x = 0.3 is s <= 0.26 m.
    arm = StraightArm(np.array([0.0, 0.0]), np.array([0.3, 0.0]), 0.04)
    other = np.array([[0.3, 0.0], [0.3, 0.27]])
    holes = (np.array([[0.0, 0.0], [0.3, 0.27]]), np.array([0.006, 0.006]))
    chosen = member_stations(arm.cuts, arm.length, holes, [other])
    np.testing.assert_allclose(chosen.x, np.arange(0.05, 0.26, 0.02))
    assert chosen.note == ""


def test_a_member_too_short_for_its_holes_is_compared_at_its_midpoint_and_says_so():
    # 60 mm between 13 mm holes: every cell centre is within 4.62 radii of a hole's centre.
    arm = StraightArm(np.array([0.0, 0.0]), np.array([0.06, 0.0]), 0.04)
    holes = (np.array([[0.0, 0.0], [0.06, 0.0]]), np.array([0.0065, 0.0065]))
    chosen = member_stations(arm.cuts, arm.length, holes)
    np.testing.assert_allclose(chosen.x, [0.03])
    assert "short for its holes" in chosen.note and "4.62 radii" in chosen.note


def test_a_member_whose_midpoint_cut_crosses_a_hole_has_nowhere_to_compare():
    arm = StraightArm(np.array([0.0, 0.0]), np.array([0.02, 0.0]), 0.06)
    holes = (np.array([[0.0, 0.0]]), np.array([0.015]))
    with pytest.raises(FEAError, match="midpoint cut at s = 0.01 m passes 0.667 hole radii"):
        member_stations(arm.cuts, arm.length, holes)


def pinned_pair(force: np.ndarray, length: float) -> LinkLoadCase:
    """Static: force (P, 2) [N] at joint 1 (length, 0), -force and the balancing couple at joint 0."""
    n = len(force)
    couples = np.column_stack([-length * force[:, 1], np.zeros(n)])
    zero = np.zeros((n, 2))
    return LinkLoadCase((0, 1), np.stack([-force, force], axis=1), couples, np.zeros(n), np.zeros(n), zero, zero)


@pytest.fixture(scope="module")
def bar_case():
    """A straight bar under static pin loads at two positions, its stations and its beam there."""
    bar = straight_bar(0.4, 0.05, 0.03, 0.01, STRUCTURAL_STEEL, hole_diameter=0.016)
    phi = np.radians([30.0, 200.0])
    loads = pinned_pair(1500.0 * np.column_stack([np.cos(phi), np.sin(phi)]), 0.4)
    stations = choose_stations(bar, (0, 1)).x
    beam = section_stresses(bar, loads, stations)
    forces = np.stack([beam.forces.normal, beam.forces.shear, beam.forces.moment])
    member = MemberBeam((0, 1), frame_cuts(beam.sections, beam.near_hole), forces, beam.von_mises, beam.fibre_y)
    return bar, loads, stations, member


def test_a_straight_member_over_its_cut_segments_gives_what_the_stations_give(bar_case):
    # The one member of a straight bar, its cuts the vertical stations, both meshed on one mesh:
    # the member's resultant and nominal errors are the stations' (and the link's, the worst member's).
    bar, loads, stations, member = bar_case
    c = compare_link("bar", bar, loads, np.arange(2), levels=1, stations=stations, members=[member])
    (compared,) = c.members
    f = c.fea_resultants
    depth = float((c.beam.sections.top - c.beam.sections.bottom).max())
    by_stations = resultant_error(
        np.stack([f.normal, f.shear, f.moment]), np.stack([c.beam.forces.normal, c.beam.forces.shear, c.beam.forces.moment]), depth,
    )
    np.testing.assert_allclose(compared.resultant_error, by_stations, rtol=1e-9)
    np.testing.assert_allclose(compared.fea_von_mises, c.fea_von_mises, rtol=1e-12)
    np.testing.assert_array_equal(c.resultant_error, compared.resultant_error)
    np.testing.assert_array_equal(c.nominal_error, compared.nominal_error)
    np.testing.assert_array_equal(compared.beam_max, c.beam_max)
    assert compared.joints == (0, 1) and compared.resultant_error.max() < 5e-3


def test_a_refinement_study_judges_the_members_resultants_over_their_cuts(bar_case):
    bar, loads, stations, member = bar_case
    c = compare_link("bar", bar, loads, np.arange(2), levels=3, stations=stations, members=[member])
    finer, coarser = c.study.resultants[-1][..., len(stations):], c.study.resultants[-2][..., len(stations):]
    expected = resultant_error(finer, coarser, member.depth)
    np.testing.assert_allclose(c.convergence["resultants"].change, expected, rtol=1e-12)
    assert c.convergence["nominal"] is not None and c.converged is not None


def test_hole_circles_are_the_pin_holes_in_the_load_frame():
    bar = straight_bar(0.4, 0.05, 0.03, 0.01, hole_diameter=0.016)
    centres, radii = hole_circles(bar, (1, 0))  # the frame from joint 1 towards joint 0
    np.testing.assert_allclose(centres, [[0.4, 0.0], [0.0, 0.0]], atol=1e-9)
    np.testing.assert_allclose(radii, 0.008, rtol=1e-4)  # equal-area radius of the flattened circle


def test_each_member_reports_its_joints_beam_maximum_and_worst_errors(bar_case):
    bar, loads, stations, member = bar_case
    c = compare_link("bar", bar, loads, np.arange(2), levels=1, stations=stations, members=[member])
    (compared,) = c.members
    record = member_record(compared)
    assert record == {
        "joints": [0, 1],
        "beam_max_von_mises_pa": float(member.von_mises.max()),
        "nominal_error_pct": float(100 * compared.nominal_error.max()),
        "resultant_error_pct": float(100 * compared.resultant_error.max()),
    }
    words = member_words(compared)
    assert words.startswith(f"member joints 0-1: beam maximum {member.von_mises.max() / 1e6:.4g} MPa")
    assert f"resultants within {record['resultant_error_pct']:.3g} %" in words
