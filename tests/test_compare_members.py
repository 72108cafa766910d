"""Beam against FEA along each member of a link: stations clear of pins and junctions, resultants
over the member's cut segments (normal to its axis), von Mises at the beam's critical fibre."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import Point, Polygon, box

from linkstress.geometry.builders import straight_bar
from linkstress.geometry.curves import circle_points
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.geometry.members import link_members
from linkstress.geometry.profile import LinkProfile
from linkstress.validation.compare import compare_link, resultant_error
from linkstress.validation.stations import hole_circles, member_stations
from linkstress.validation.report import member_record, member_words


def bell_crank() -> LinkProfile:
    """An L of 40 mm wide arms, 10 mm steel: an arm along y = 0 from the pin hole at the pivot (0, 0)
    to the corner joint (0.3, 0), an arm up from there to the pin hole at (0.3, 0.27) (12 mm holes)."""
    shell = box(-0.03, -0.02, 0.32, 0.02).union(box(0.28, -0.02, 0.32, 0.3))
    holes = [circle_points(c, 0.006, 1e-7)[::-1] for c in ((0.0, 0.0), (0.3, 0.27))]
    joints = np.array([[0.0, 0.0], [0.3, 0.0], [0.3, 0.27]])
    return LinkProfile(Polygon(shell.exterior, holes), joints, 0.01, STRUCTURAL_STEEL, "crank")


def static_pair(n_joints: int, loaded: int, at: np.ndarray, force: np.ndarray) -> LinkLoadCase:
    """Static loads: force (P, 2) [N] on joint ``loaded`` at ``at`` (2,) [m], -force on joint 0 at the
    origin with the couple there that balances the pair; no motion, no gravity."""
    n = len(force)
    pins = np.zeros((n, n_joints, 2))
    pins[:, 0], pins[:, loaded] = -force, force
    couples = np.zeros((n, n_joints))
    couples[:, 0] = -(at[0] * force[:, 1] - at[1] * force[:, 0])
    zero = np.zeros((n, 2))
    return LinkLoadCase((0, 1), pins, couples, np.zeros(n), np.zeros(n), zero, zero)


def test_a_bell_cranks_arms_are_compared_five_radii_from_pins_and_a_depth_from_the_other_arm():
    # Arm (0, 1): cell centres 0.01 .. 0.29 m; past five 6 mm radii of the pivot (s >= 0.03 m: the
    # equal-area radius of the drawn hole is a hair under 6 mm) and a depth (40 mm) short of the
    # other arm's axis x = 0.3 m. Arm (1, 2), 0.27 m from the corner up: a depth from the first arm's
    # axis y = 0 (s >= 0.04 m) and five radii short of the hole at its end (s < 0.24 m).
    first, second = link_members(bell_crank(), (0, 1))
    assert (first.joints, second.joints) == ((0, 1), (1, 2))
    np.testing.assert_allclose(member_stations(first).x, np.arange(0.03, 0.26, 0.02))
    np.testing.assert_allclose(member_stations(second).x, 0.27 * (np.arange(2, 13) + 0.5) / 15)
    assert member_stations(first).note == member_stations(second).note == ""


def test_a_member_too_short_for_its_holes_is_compared_at_its_midpoint_and_says_so():
    # 60 mm between 13 mm holes: every cell centre is within 4.62 radii of a hole's centre.
    (member,) = link_members(straight_bar(0.06, 0.04, 0.02, 0.005, hole_diameter=0.013), (0, 1))
    chosen = member_stations(member)
    np.testing.assert_allclose(chosen.x, [0.03])
    assert "short for its holes" in chosen.note and "4.62 radii" in chosen.note


def test_a_member_whose_midpoint_cut_crosses_a_hole_is_skipped_and_the_rest_of_the_link_still_compared():
    # Joints 20 mm apart: a 30 mm hole at the first spans past the midpoint at 10 mm, so the member
    # has no cut to compare; 1 kN through its pins at 30 deg still gives an FEA peak (at a hole's
    # rim, above the 1 kN / (60 mm x 5 mm) = 3.3 MPa of the gross section) and pin-hole peaks.
    shell = Polygon([(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)])
    holes = [Point(0.0, 0.0).buffer(0.015, 64).exterior.coords, Point(0.02, 0.0).buffer(0.002, 64).exterior.coords]
    link = LinkProfile(Polygon(shell.exterior.coords, holes), np.array([[0.0, 0.0], [0.02, 0.0]]), 0.005,
                       STRUCTURAL_STEEL, "lug")
    members = link_members(link, (0, 1))
    chosen = member_stations(members[0])
    assert chosen.skipped and "link 'lug', member [0, 1]: not compared with the FEA" in chosen.note
    assert "passes through a hole (0.67 hole radii from its centre)" in chosen.note
    loads = pinned_pair(1000.0 * np.array([[np.cos(np.radians(30.0)), np.sin(np.radians(30.0))]]), 0.02)
    c = compare_link("lug", link, loads, np.array([0]), levels=1, members=members)
    assert c.members == () and [s.joints for s in c.skipped] == [(0, 1)] and c.skipped[0].note == chosen.note
    assert c.resultant_error is None and c.nominal_error is None and c.worst_nominal() is None
    assert not c.frame_compared and c.stations.shape == (0,)
    assert c.fea_peak[0] > 1000.0 / (0.06 * 0.005)
    assert [h.joint for h in c.hole_peaks] == [0, 1]


def pinned_pair(force: np.ndarray, length: float) -> LinkLoadCase:
    return static_pair(2, 1, np.array([length, 0.0]), force)


@pytest.fixture(scope="module")
def bar_case():
    """A straight bar under static pin loads at two positions, and its one member."""
    bar = straight_bar(0.4, 0.05, 0.03, 0.01, STRUCTURAL_STEEL, hole_diameter=0.016)
    phi = np.radians([30.0, 200.0])
    loads = pinned_pair(1500.0 * np.column_stack([np.cos(phi), np.sin(phi)]), 0.4)
    return bar, loads, link_members(bar, (0, 1))


def test_a_straight_bars_one_member_over_its_cut_segments_gives_what_the_stations_give(bar_case):
    # Its member's stations and cut segments are the frame's stations and vertical cuts: the
    # member's errors are the stations' to rounding, and the link's.
    bar, loads, members = bar_case
    c = compare_link("bar", bar, loads, np.arange(2), levels=1, members=members)
    (member,) = c.members
    np.testing.assert_allclose(member.beam.cuts.s, c.stations, atol=1e-12)
    f, b = c.fea_resultants, c.beam.forces
    depth = float((c.beam.sections.top - c.beam.sections.bottom).max())
    by_stations = resultant_error(np.stack([f.normal, f.shear, f.moment]), np.stack([b.normal, b.shear, b.moment]), depth)
    np.testing.assert_allclose(member.resultant_error, by_stations, rtol=1e-9)
    np.testing.assert_allclose(member.fea_von_mises, c.fea_von_mises, rtol=1e-9)
    np.testing.assert_array_equal(c.resultant_error, member.resultant_error)
    np.testing.assert_array_equal(c.nominal_error, member.nominal_error)
    assert member.joints == (0, 1) and member.resultant_error.max() < 5e-3


def test_a_refinement_study_judges_the_members_resultants_over_their_cuts(bar_case):
    bar, loads, members = bar_case
    c = compare_link("bar", bar, loads, np.arange(2), levels=3, members=members)
    (member,) = c.members
    cuts = slice(len(c.stations), None)  # the study's resultants: the stations', then the members' cuts
    expected = resultant_error(c.study.resultants[-1][..., cuts], c.study.resultants[-2][..., cuts], member.beam.depth)
    np.testing.assert_allclose(c.convergence["resultants"].change, expected, rtol=1e-12)
    assert c.convergence["nominal"] is not None


def test_each_arm_of_a_bell_crank_carries_its_free_body_in_the_fea_and_the_link_reports_the_worst():
    # Static: a force on the arm's end hole, its reaction and the balancing couple at the pivot. Each
    # arm's beam resultants (the free body of its cut's own piece) against the FEA over its cuts:
    # within 0.32 % on this mesh (0.07 % three refinements on); nominal von Mises within 3.2 % (the
    # short arm's stations are 1.1 to 5 depths from the corner).
    link = bell_crank()
    force = np.array([[1500.0, 400.0], [-300.0, 1200.0]])
    c = compare_link("crank", link, static_pair(3, 2, np.array([0.3, 0.27]), force), np.arange(2), levels=1,
                     members=link_members(link, (0, 1)))
    assert [m.joints for m in c.members] == [(0, 1), (1, 2)]
    assert c.fea.reaction_ratio.max() < 1e-9
    for m in c.members:
        assert m.resultant_error.max() < 5e-3
        assert m.nominal_error.max() < 0.04
    np.testing.assert_array_equal(c.resultant_error, np.maximum(*(m.resultant_error for m in c.members)))
    np.testing.assert_array_equal(c.nominal_error, np.maximum(*(m.nominal_error for m in c.members)))
    # the second arm's cuts are horizontal segments across it alone, never across the first arm
    # (from v = bottom to top along its normal, -x for an arm running up +y)
    ends = c.members[1].beam.cuts.ends
    np.testing.assert_allclose(ends[:, :, 0], [[0.32, 0.28]] * len(ends), atol=1e-9)
    assert (ends[:, :, 1] > 0.02).all()


def test_each_member_reports_its_joints_beam_maximum_and_worst_errors(bar_case):
    bar, loads, members = bar_case
    (compared,) = compare_link("bar", bar, loads, np.arange(2), levels=1, members=members).members
    record = member_record(compared)
    assert record == {
        "joints": [0, 1],
        "beam_max_von_mises_pa": float(compared.beam.von_mises.max()),
        "nominal_error_pct": float(100 * compared.nominal_error.max()),
        "resultant_error_pct": float(100 * compared.resultant_error.max()),
    }
    words = member_words(compared)
    assert words.startswith(f"member joints 0-1: beam maximum {compared.beam.von_mises.max() / 1e6:.4g} MPa")
    assert f"resultants within {record['resultant_error_pct']:.3g} %" in words


def test_hole_circles_are_the_pin_holes_in_the_load_frame():
    bar = straight_bar(0.4, 0.05, 0.03, 0.01, hole_diameter=0.016)
    centres, radii = hole_circles(bar, (1, 0))  # the frame from joint 1 towards joint 0
    np.testing.assert_allclose(centres, [[0.4, 0.0], [0.0, 0.0]], atol=1e-9)
    np.testing.assert_allclose(radii, 0.008, rtol=1e-4)  # equal-area radius of the flattened circle
