"""Lightening holes are holes, not member hubs: a link's members join only the joints its scene uses
(``linkstress.geometry.members.link_members``'s ``used_joints``, ``linkstress.analysis.used_joints``).

A sketch link without POINTs takes the centres of its circular holes as its joints, a lightening hole's
too. The plates here are triangles of pins with a lightening hole at their centroid, drawn with shapely
(and, for the scene, written as a DXF with ezdxf): pins A (0, 0), B (SPAN, 0) and C (SPAN / 2, RISE),
the plate the triangle grown by EDGE with round corners, pin holes of PIN, the lightening hole of
LIGHTENING diameter at the centroid.
"""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon

from linkstress.analysis import run_analysis, scene_link_members, used_joints
from linkstress.errors import GeometryError
from linkstress.geometry.members import link_members, member_tree
from linkstress.geometry.profile import LinkProfile
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.scene import load_scene

SPAN, RISE, EDGE, PIN = 0.12, 0.08, 0.015, 0.008
"""Pin spacing A-B, height of C above AB, the plate's margin round the pins, pin hole diameter [m]."""


def triangle_points(span: float = SPAN, rise: float = RISE) -> np.ndarray:
    return np.array([[0.0, 0.0], [span, 0.0], [span / 2, rise]])


def plate(lightening: float, span: float = SPAN, rise: float = RISE) -> tuple[LinkProfile, np.ndarray]:
    """The plate with its joints as a sketch without POINTs gives them (every hole's centre: the three
    pins, then the lightening hole), and the lightening hole's centre [m]."""
    pins = triangle_points(span, rise)
    centroid = pins.mean(axis=0)
    body = Polygon(pins).buffer(EDGE, quad_segs=32)
    holes = [Point(p).buffer(PIN / 2, quad_segs=32).exterior.coords[::-1] for p in (*pins, centroid)]
    holes[-1] = Point(centroid).buffer(lightening / 2, quad_segs=64).exterior.coords[::-1]
    joints = np.vstack([pins, centroid])
    return LinkProfile(Polygon(body.exterior, holes), joints, 0.008, STRUCTURAL_STEEL, name="plate"), centroid


@pytest.mark.parametrize(("span", "rise", "lightening"), [(0.12, 0.08, 0.024), (0.12, 0.08, 0.012), (0.2, 0.1, 0.03)])
def test_a_plates_members_join_its_pins_and_its_lightening_hole_is_sectioned_as_a_hole(span, rise, lightening):
    link, centroid = plate(lightening, span, rise)
    # over every joint the tree runs to the lightening hole's centre, the middle of the plate
    assert any(3 in pair for pair in member_tree(link, (0, 1)))
    members = link_members(link, (0, 1), used_joints=(0, 1, 2))
    # the tree of the pins alone: the two shorter sides, A-C and C-B (AB is the longest)
    assert sorted(tuple(sorted(m.joints)) for m in members) == [(0, 2), (1, 2)]
    outline = link.local_outline(0, 1)
    lightening_hole = Point(link.frame(0, 1).to_local(centroid)).buffer(lightening / 2)
    centre = link.frame(0, 1).to_local(centroid)
    for member in members:
        # the cut square to each side through the lightening hole's centre runs into the plate across
        # the hole: its section is the material along the cut (shapely's intersection), the hole left
        # out, and nominal
        start, end = member.path[0], member.path[-1]
        across = (centre - start) @ (end - start) / member.length
        cuts = member.cuts([across])
        segment = LineString(cuts.ends[0])
        assert segment.distance(Point(centre)) < 1e-9 and segment.intersects(lightening_hole)
        assert cuts.table.n_chords[0] >= 2
        assert cuts.table.area[0] / link.thickness == pytest.approx(segment.intersection(outline).length, rel=1e-6)
        assert cuts.near_hole[0] and cuts.nominal[0]


def test_members_a_scene_names_must_join_the_joints_it_uses():
    link, _ = plate(0.024)
    # the scene's arms A-B and A-C: the lightening hole (joint 3) joins none
    assert [m.joints for m in link_members(link, (0, 1), [[0, 1], [0, 2]], used_joints=(0, 1, 2))] == [(0, 1), (0, 2)]
    with pytest.raises(GeometryError, match=r"do not join the joints \[0, 1, 2\] that its mechanisms, loads and members use"):
        link_members(link, (0, 1), [[0, 1]], used_joints=(0, 1, 2))
    with pytest.raises(GeometryError, match="do not join all 4 joints"):
        link_members(link, (0, 1), [[0, 1], [0, 2]])


def write_sketch(path, lightening_mm: float) -> None:
    """The triangular coupler on layer ``coupler``, in millimetres: its outline a closed polyline, its
    three pin holes and its lightening hole circles, no POINTs."""
    import ezdxf

    doc = ezdxf.new()
    doc.header["$INSUNITS"] = 4
    doc.layers.add("coupler")
    pins = triangle_points() * 1e3
    outline = Polygon(pins).buffer(EDGE * 1e3, quad_segs=32)
    msp = doc.modelspace()
    msp.add_lwpolyline(list(outline.exterior.coords)[:-1], close=True, dxfattribs={"layer": "coupler"})
    for p in pins:
        msp.add_circle(tuple(p), PIN * 1e3 / 2, dxfattribs={"layer": "coupler"})
    msp.add_circle(tuple(pins.mean(axis=0)), lightening_mm / 2, dxfattribs={"layer": "coupler"})
    doc.saveas(path)


SCENE = """
[materials.steel]
density = 7850.0
youngs_modulus = 200e9
poisson_ratio = 0.3
yield_strength = 250e6

[links.crank]
joints = [[0.0, 0.0], [0.04, 0.0]]
mass = 0.1
inertia = 2e-5
center_of_mass = [0.02, 0.0]
[links.coupler]
sketch = "plate.dxf"
layer = "coupler"        # joints by x then y: 0 A, 1 the lightening hole, 2 C, 3 B
thickness = 0.008
material = "steel"
[links.output]
joints = [[0.0, 0.0], [0.1, 0.0]]
mass = 0.2
inertia = 2e-4
center_of_mass = [0.05, 0.0]
[links.ground]
joints = [[0.0, 0.0], [0.13, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = {link = "coupler", joints = [0, 3]}
output = "output"
ground = "ground"

[motion]
input_angle_deg = {start = 0.0, stop = 330.0, num = 12}
input_speed_rad_s = 30.0

[[loads.forces]]
link = "coupler"
at_m = [0.06, 0.08]      # in pin C's hole: a pin's load
force_n = [0.0, -200.0]
"""


def test_a_scenes_triangular_coupler_has_members_between_its_pins_only(tmp_path):
    # The four-bar pins the coupler at A and B; a load acts in pin C's hole. Those are the joints it
    # uses: its members join A, B and C, and the lightening hole (joint 1) is a plain hole that the
    # analysis sections as such.
    write_sketch(tmp_path / "plate.dxf", 24.0)
    (tmp_path / "scene.toml").write_text(SCENE)
    scene = load_scene(tmp_path / "scene.toml")
    profile = scene.links["coupler"].profile
    assert np.allclose(profile.joints[1], triangle_points().mean(axis=0), atol=1e-9)
    assert used_joints(scene, "coupler") == (0, 2, 3)
    members = scene_link_members(scene, "coupler", (0, 3))
    assert {k for m in members for k in m.joints} == {0, 2, 3}
    result = run_analysis(scene)
    analysed = result.stresses["coupler"].members
    assert [m.joints for m in analysed] == [m.joints for m in members]
    assert np.isfinite(result.stresses["coupler"].max_von_mises).all()


def test_a_couple_at_a_joint_uses_it(tmp_path):
    # The same plate with a couple at the lightening hole's centre instead: that joint is used (a
    # mechanism may name any joint), and a member runs to it.
    write_sketch(tmp_path / "plate.dxf", 24.0)
    scene_text = SCENE.replace('[[loads.forces]]\nlink = "coupler"\nat_m = [0.06, 0.08]      # in pin C\'s hole: a pin\'s load\n'
                               'force_n = [0.0, -200.0]\n', '[loads.couples]\ncoupler = {value = 2.0, at_joint = 1}\n')
    (tmp_path / "scene.toml").write_text(scene_text)
    scene = load_scene(tmp_path / "scene.toml")
    assert used_joints(scene, "coupler") == (0, 1, 3)
    assert 1 in {k for m in scene_link_members(scene, "coupler", (0, 3)) for k in m.joints}


def test_a_linkage_uses_the_joints_its_pins_sliders_and_input_name(tmp_path):
    """A four-bar written as a linkage whose coupler lists a fourth joint no pin names (the centre of
    a lightening hole): the coupler's used joints are its two pins; the crank's its input pivot and pin."""
    from linkage_scenes import link_table, linkage_scene

    links = (
        link_table("ground", [[0.0, 0.0], [0.2, 0.0]])
        + link_table("crank", [[0.0, 0.0], [0.05, 0.0]], 0.1, (0.025, 0.0), 1e-4)
        + link_table("coupler", [[0.05, 0.0], [0.22, 0.12], [0.13, 0.03]], 0.2, (0.08, 0.0), 1e-3)
        + link_table("rocker", [[0.2, 0.0], [0.22, 0.12]], 0.1, (0.06, 0.0), 1e-4)
    )
    pins = [["ground:0", "crank:0"], ["crank:1", "coupler:0"], ["coupler:1", "rocker:1"], ["ground:1", "rocker:0"]]
    scene = linkage_scene(tmp_path, links, pins, "input_angle_deg = 0.0")
    assert used_joints(scene, "coupler") == (0, 1)
    assert used_joints(scene, "crank") == (0, 1)
    assert used_joints(scene, "rocker") == (0, 1)
