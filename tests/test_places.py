"""Places of a link named as a designer sees them on the drawing: pins by Norton's letters and the
links they join, points along an arm by their share of its length, junctions, bends, other holes;
joint forces by the links they act between."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from linkstress.analysis import plan_for, run_analysis
from linkstress.geometry.builders import straight_bar
from linkstress.geometry.members import link_members
from linkstress.geometry.profile import LinkProfile
from linkstress.materials import Material
from linkstress.report.places import JointName, force_names, joint_names, profile_places
from linkstress.scene import load_scene

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
STEEL = Material("steel", 7850.0, 200e9, 0.3)


def places_of(profile: LinkProfile, names: tuple[str, ...], frame=(0, 1)):
    """The places of ``profile`` with its joints named ``names`` (no links joined), 101 stations per member."""
    members = link_members(profile, frame)
    cuts = [(m.joints, m.length, m.cuts(m.stations(101))) for m in members]
    return profile_places(profile, frame, tuple(JointName(n) for n in names), cuts)


@pytest.mark.parametrize("spacing, height, hole", [(0.1, 0.02, 0.008), (1.0, 0.1, 0.02), (0.04, 0.006, 0.003)])
def test_points_along_a_bar_are_named_by_their_share_of_the_arm_and_the_pins_by_their_joints(spacing, height, hole):
    bar = straight_bar(spacing, height, height, 0.01, STEEL, hole)
    places = places_of(bar, ("O2", "A"))
    for share in (0.3, 0.5, 0.7):
        assert places.name(np.array([share * spacing, height / 2])) == f"arm O2-A at {100 * share:.0f} % of its length"
    # on a hole's rim, and a radius of material around it (where a pin's stress raiser lies)
    assert places.name(np.array([spacing + hole / 2, 0.0])) == "pin hole A"
    assert places.name(np.array([-0.75 * hole, 0.0])) == "pin hole O2"
    # a section within a depth of a pin gives a nominal beam value: said so; an FEA point there is on the arm
    assert places.name(np.array([0.0, height / 2])) == "arm O2-A beside pin hole O2 (nominal)"
    assert places.name(np.array([-0.9 * height, height / 2]), beam=False) == "arm O2-A past O2, toward its free end"


@pytest.mark.parametrize("bend_deg", [60.0, 90.0, 120.0])
def test_the_corner_between_two_arms_of_a_bell_crank_is_their_junction(bend_deg):
    arm, width, pin = 0.1, 0.02, 0.008
    b = (arm * math.cos(math.radians(bend_deg)), arm * math.sin(math.radians(bend_deg)))
    body = unary_union([LineString([(0, 0), (arm, 0)]).buffer(width / 2), LineString([(0, 0), b]).buffer(width / 2)])
    for joint in ((0, 0), b, (arm, 0)):
        body = body.difference(Point(joint).buffer(pin / 2, quad_segs=32))
    crank = LinkProfile(body, np.array([(0.0, 0.0), b, (arm, 0.0)]), 0.01, STEEL, name="bell")
    places = places_of(crank, ("O4", "B", "C"), frame=(0, 2))
    # in the corner between the arms, outside the pivot hole's two radii: within a depth of both axes
    corner = places.name(np.array([0.7 * width, 0.45 * width]))
    assert corner in ("junction of arms O4-C and O4-B", "junction of arms O4-B and O4-C")
    assert places.name(np.array([0.6 * arm, 0.45 * width])) == "arm O4-C at 60 % of its length"


def test_a_hole_no_joint_uses_is_named_by_where_it_is_on_the_drawing():
    bar = straight_bar(0.1, 0.03, 0.02, 0.01, STEEL, 0.008)
    lightened = LinkProfile(
        Polygon(bar.outline.exterior, [*bar.outline.interiors, Point(0.05, 0.0).buffer(0.005, quad_segs=32).exterior.coords[::-1]]),
        bar.joints, 0.01, STEEL,
    )
    places = places_of(lightened, ("O2", "A"))
    assert places.name(np.array([0.05, 0.0055])) == "hole at (0.05, 0) m of the drawing, no joint"


@pytest.mark.parametrize("sag", [0.02, 0.03])
def test_a_curved_arms_concave_side_is_its_inner_fillet(sag):
    span, width = 0.1, 0.024
    radius = (span**2 / 4 + sag**2) / (2 * sag)
    cx, cy = span / 2, sag - radius
    t = np.linspace(math.atan2(-cy, span - cx), math.atan2(-cy, -cx), 400)
    body = LineString(np.column_stack([cx + radius * np.cos(t), cy + radius * np.sin(t)])).buffer(width / 2, quad_segs=64)
    for joint in ((0.0, 0.0), (span, 0.0)):
        body = body.difference(Point(joint).buffer(0.004, quad_segs=64))
    places = places_of(LinkProfile(body, np.array([[0.0, 0.0], [span, 0.0]]), 0.008, STEEL), ("A", "B"))
    # radius 2.4-3.5 section depths: the arm bends (under ten depths); its centre of curvature is below
    inner, outer = np.array([span / 2, sag - 0.45 * width]), np.array([span / 2, sag + 0.45 * width])
    assert places.name(inner, beam=False) == "inner fillet of arm A-B at 50 % of its length"  # an FEA peak's place
    assert places.name(inner) == "inner edge of the bend of arm A-B at 50 % of its length"  # a beam value's
    assert places.name(outer) == "outer edge of the bend of arm A-B at 50 % of its length"


def test_joints_take_nortons_letters_and_the_links_their_pin_joins():
    seed = {name: [j.words() for j in joints] for name, joints in joint_names(load_scene(CASES / "seed_ansys_fourbar" / "scene.toml")).items()}
    assert seed["crank"] == ["O2 (crank-ground)", "A (crank-coupler)"]
    assert seed["coupler"] == ["A (crank-coupler)", "B (coupler-output)"]
    assert seed["output"] == ["O4 (output-ground)", "B (coupler-output)"]
    # two loops: the rocker's pivot is O4 of main and O2 of second; its joint 0 the second loop's A
    six = joint_names(load_scene(CASES / "six_bar" / "scene.toml"))
    assert [j.words() for j in six["rocker"]] == ["A (rocker-rod2)", "O4 (rocker-ground)", "B (coupler-rocker)"]
    # a slider-crank's ground has one pin; its other joint only marks the slider line
    engine = joint_names(load_scene(CASES / "slider_crank_curved_rod" / "scene.toml"))
    assert [j.label for j in engine["ground"]] == ["O2", "joint 1"]


@pytest.mark.parametrize("case", ["seed_ansys_fourbar", "six_bar", "slider_crank_curved_rod"])
def test_each_joint_force_is_named_by_the_link_it_acts_on_and_the_joint(case):
    """F_ij is the force of link i on link j (docs/design.md): the name's second link carries it at the
    named joint, so that link's load case has exactly that force at that joint (no other pin there)."""
    scene = load_scene(CASES / case / "scene.toml")
    result = run_analysis(scene, plan_for(scene))
    names = joint_names(scene)
    ok = result.feasible
    for mechanism, forces in force_names(scene).items():
        for label, words in forces.items():
            source, on = words.split(" at ")[0].split(",")[0].split(" on ")
            if on not in result.forces.link_loads or " at " not in words:
                continue  # the slide of an undrawn slider, or the ground's side
            joint = next(j for j, n in enumerate(names[on]) if n.label == words.split(" at ")[1])
            loads = result.forces.link_loads[on]
            c, s = np.cos(result.kinematics.links[on].angle), np.sin(result.kinematics.links[on].angle)
            ground = np.stack([c * loads.pin_forces[:, joint, 0] - s * loads.pin_forces[:, joint, 1],
                               s * loads.pin_forces[:, joint, 0] + c * loads.pin_forces[:, joint, 1]], axis=-1)
            force = result.forces.mechanisms[mechanism].forces[label]
            np.testing.assert_allclose(ground[ok], force[ok], atol=1e-9 * np.abs(force[ok]).max())
    assert force_names(scene)[scene.machine.main.name]["F32"].startswith(f"{scene.machine.main.coupler.link} on "
                                                                          f"{scene.machine.main.crank.link} at ")


def test_a_slot_is_named_along_its_whole_rim_and_a_point_beside_it_by_its_arm():
    """A bar with a 60 x 8 mm slot between its pins: a point at the slot's end (34 mm from its
    centre, beyond two equivalent radii of its area) is at the slot; a point on the bar's outer edge,
    11 mm from the slot's side, is on the arm."""
    bar = straight_bar(0.1, 0.03, 0.02, 0.01, STEEL, 0.008)
    slot = LineString([(0.02, 0.0), (0.08, 0.0)]).buffer(0.004, quad_segs=16).exterior.coords[::-1]
    slotted = LinkProfile(Polygon(bar.outline.exterior, [*bar.outline.interiors, slot]), bar.joints, 0.01, STEEL)
    places = places_of(slotted, ("O2", "A"))
    assert places.name(np.array([0.0845, 0.0])) == "slot at (0.05, 0) m of the drawing, no joint"
    assert places.name(np.array([0.05, 0.015])).startswith("arm O2-A")
