"""Bad link geometry is refused with a ValueError that names what is wrong and where."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import Polygon

from linkstress.geometry.builders import straight_bar
from linkstress.errors import GeometryError
from linkstress.materials import Material
from linkstress.geometry.profile import LinkProfile

BAR = [(0, 0), (1, 0), (1, 0.2), (0, 0.2)]
JOINTS = np.array([[0.1, 0.1], [0.9, 0.1]])


def square(cx, cy, half):
    return [(cx - half, cy - half), (cx - half, cy + half), (cx + half, cy + half), (cx + half, cy - half)]


def test_geometry_errors_are_value_errors():
    assert issubclass(GeometryError, ValueError)


def test_self_intersecting_outline_is_refused_with_the_crossing_point():
    bowtie = Polygon([(0, 0), (1, 1), (1, 0), (0, 1)])
    with pytest.raises(GeometryError, match=r"link 'bow': the outline is not a simple closed curve \(Self-intersection\[0.5 0.5\]\)"):
        LinkProfile(bowtie, np.array([[0.1, 0.5]]), 0.01, name="bow")


def test_hole_crossing_the_outline_is_refused_with_where():
    with pytest.raises(GeometryError, match=r"hole 0 crosses or touches the outline near \(0\.\d+, 0\.2\) m"):
        LinkProfile(Polygon(BAR, [square(0.9, 0.18, 0.05)]), JOINTS, 0.01)


def test_overlapping_holes_are_refused():
    with pytest.raises(GeometryError, match="holes overlap"):
        LinkProfile(Polygon(BAR, [square(0.5, 0.1, 0.05), square(0.55, 0.1, 0.05)]), JOINTS, 0.01)


def test_joint_outside_the_material_is_refused_with_its_index_and_position():
    with pytest.raises(GeometryError, match=r"joint 1 at \(1\.5, 0\.1\) m is outside the link's material"):
        LinkProfile(Polygon(BAR), np.array([[0.1, 0.1], [1.5, 0.1]]), 0.01)


def test_joint_in_a_hole_must_sit_at_its_centre():
    outline = Polygon(BAR, [square(0.9, 0.1, 0.05)])
    LinkProfile(outline, np.array([[0.1, 0.1], [0.9, 0.1]]), 0.01)  # at the centre: a pin hole
    with pytest.raises(GeometryError, match=r"joint 1 at \(0\.93, 0\.1\) m is inside hole 0 but not at its centre \(0\.9, 0\.1\)"):
        LinkProfile(outline, np.array([[0.1, 0.1], [0.93, 0.1]]), 0.01)


def test_joint_holes_map_each_joint_to_its_pin_hole():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, hole_diameter=0.02)
    assert bar.joint_holes == (0, 1)
    assert straight_bar(1.0, 0.5, 0.1, 0.1).joint_holes == (None, None)


@pytest.mark.parametrize("thickness", [0.0, -0.1, float("nan"), float("inf")])
def test_non_positive_or_non_finite_thickness_is_refused(thickness):
    with pytest.raises(GeometryError, match="link 'crank': thickness must be > 0 m"):
        LinkProfile(Polygon(BAR), JOINTS, thickness, name="crank")


@pytest.mark.parametrize("density", [0.0, -7850.0, float("nan")])
def test_non_positive_density_is_refused(density):
    with pytest.raises(GeometryError, match="material 'steel': density must be a finite number > 0"):
        Material("steel", density)


@pytest.mark.parametrize("fatigue, message", [
    ({"endurance_limit": -1.0, "ultimate_strength": 500e6}, "endurance_limit must be a finite number > 0, got -1.0"),
    ({"surface_factor": float("nan")}, "surface_factor must be a finite number > 0, got nan"),
    ({"size_factor": 1.6}, r"size_factor must lie in \(0, 1.5\] \(a Marin factor\), got 1.6"),
    ({"endurance_limit": 600e6, "ultimate_strength": 500e6}, r"endurance_limit must be below ultimate_strength \(500000000.0 Pa\)"),
    ({"yield_strength": 600e6, "ultimate_strength": 500e6}, r"yield_strength must not exceed ultimate_strength \(500000000.0 Pa\)"),
])
def test_impossible_fatigue_data_is_refused(fatigue, message):
    with pytest.raises(GeometryError, match=f"material 'steel': {message}"):
        Material("steel", 7850.0, **fatigue)


def test_fatigue_strength_needs_both_endurance_limit_and_ultimate_strength():
    assert Material("steel", 7850.0, ultimate_strength=500e6).fatigue_strength is None
    assert Material("steel", 7850.0, endurance_limit=250e6).fatigue_strength is None
    strength = Material("steel", 7850.0, yield_strength=350e6, endurance_limit=250e6, ultimate_strength=500e6,
                        surface_factor=0.8).fatigue_strength
    assert strength.corrected_endurance_limit == pytest.approx(200e6, rel=1e-15)
    assert strength.yield_strength == 350e6


def test_mass_without_material_says_what_is_missing():
    link = LinkProfile(Polygon(BAR), JOINTS, 0.01, name="crank")
    assert link.area == pytest.approx(0.2)
    with pytest.raises(GeometryError, match="link 'crank' has no material"):
        link.mass


def test_member_frame_needs_two_distinct_existing_joints():
    link = LinkProfile(Polygon(BAR), np.array([[0.1, 0.1], [0.1, 0.1]]), 0.01, name="crank")
    with pytest.raises(ValueError, match="two distinct joints"):
        link.frame()
    with pytest.raises(GeometryError, match="link 'crank' has 2 joints, no joint 5"):
        link.frame(0, 5)


def test_profile_is_immutable():
    link = LinkProfile(Polygon(BAR), JOINTS, 0.01)
    with pytest.raises(ValueError):
        link.joints[0, 0] = 3.0
    with pytest.raises(AttributeError):
        link.thickness = 2.0
