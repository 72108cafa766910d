"""Meshing: exact curves behind flattened rings, physical groups, size field, determinism, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, Polygon, box
from shapely.geometry.polygon import orient

from linkstress.geometry.builders import stadium, straight_bar
from linkstress.geometry.curves import circle_points
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.mesh import MeshSettings, mesh_region
from linkstress.validation.fea.ring_curves import Arc, Circle, Line, Spline, ring_curves


@settings(max_examples=40, deadline=None)
@given(
    cx=st.floats(-10, 10),
    cy=st.floats(-10, 10),
    radius=st.floats(1e-3, 1.0),
    relative_sagitta=st.floats(1e-9, 1e-4),
)
def test_a_finely_flattened_circle_is_read_back_as_the_circle_of_equal_area(cx, cy, radius, relative_sagitta):
    ring = circle_points((cx, cy), radius, relative_sagitta * radius)
    curve = ring_curves(ring, short=radius)
    assert isinstance(curve, Circle)
    area = Polygon(ring).area
    assert curve.radius == pytest.approx(math.sqrt(area / math.pi), rel=1e-12)
    # the equal-area circle lies between the polygon's inscribed chords and the drawn circle
    assert radius * (1 - relative_sagitta) <= curve.radius <= radius
    assert np.hypot(*(curve.centre - (cx, cy))) <= 1e-9 * max(1.0, abs(cx), abs(cy))


def test_an_octagon_stays_eight_lines():
    phi = np.linspace(0, 2 * math.pi, 9)[:-1]
    pieces = ring_curves(np.column_stack([np.cos(phi), np.sin(phi)]), short=0.1)
    assert len(pieces) == 8 and all(isinstance(p, Line) for p in pieces)


def test_a_stadium_outline_is_two_lines_and_its_half_circles_in_arcs_below_120_degrees():
    link = stadium(0.2, 0.05, 0.01)
    pieces = ring_curves(np.asarray(link.outline.exterior.coords), short=0.002)
    assert sorted(type(p).__name__ for p in pieces) == ["Arc"] * 4 + ["Line"] * 2
    for arc in (p for p in pieces if isinstance(p, Arc)):
        r0, r1 = np.hypot(*(arc.start - arc.centre)), np.hypot(*(arc.end - arc.centre))
        assert r0 == pytest.approx(0.025, rel=1e-9) and r1 == pytest.approx(0.025, rel=1e-9)
        chord = np.hypot(*(arc.end - arc.start))
        assert 2 * math.asin(chord / (2 * r0)) <= 2 * math.pi / 3
    # consecutive pieces share their ends and the chain closes
    ends = [(p.start, p.end) if not isinstance(p, Spline) else (p.points[0], p.points[-1]) for p in pieces]
    for (_, end), (start, _) in zip(ends, ends[1:] + ends[:1]):
        np.testing.assert_array_equal(end, start)


def test_a_wavy_edge_of_short_chords_becomes_a_spline_and_long_edges_stay_lines():
    x = np.linspace(0, 1, 400)
    top = np.column_stack([x, 0.1 + 0.01 * np.sin(20 * x)])
    ring = np.vstack([[[0.0, -0.1], [1.0, -0.1]], top[::-1]])
    pieces = ring_curves(ring, short=0.01)
    kinds = [type(p).__name__ for p in pieces]
    assert kinds.count("Spline") == 1 and kinds.count("Line") == 3
    spline = next(p for p in pieces if isinstance(p, Spline))
    assert len(spline.points) == 400


@pytest.fixture(scope="module")
def crank_mesh():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, hole_diameter=0.02)
    return mesh_region(bar.local_outline(), MeshSettings(0.1, 0.004, stations=(0.25, 0.5)), name="crank")


def facet_points(plane, facets):
    mesh = plane.mesh
    return mesh.p[:, mesh.facets[:, facets]]  # (2, 2, F): both ends of each facet


def test_hole_facets_lie_on_their_circle_and_ring_it(crank_mesh):
    for hole, centre in zip(crank_mesh.holes, [(0.0, 0.0), (1.0, 0.0)]):
        ends = facet_points(crank_mesh, hole)
        radius = np.hypot(ends[0] - centre[0], ends[1] - centre[1])
        # the equal-area circle of the drawing's polygon: within its flattening (1.2 um) of 10 mm
        np.testing.assert_allclose(radius, 0.01, atol=1.2e-6)
        # facets about hole_size long, and together the full circumference
        assert len(hole) == pytest.approx(2 * math.pi * 0.01 / 0.004, abs=3)


def test_cut_facets_run_along_their_station_through_the_whole_depth(crank_mesh):
    for station, cut in zip(crank_mesh.stations, crank_mesh.cuts):
        ends = facet_points(crank_mesh, cut)
        np.testing.assert_allclose(ends[0], station, atol=1e-12)
        assert np.abs(np.diff(ends[1], axis=0)).sum() == pytest.approx(0.5, rel=1e-12)
        assert (crank_mesh.mesh.f2t[1, cut] >= 0).all()  # interior facets: elements on both sides


def test_outline_facets_cover_the_perimeter(crank_mesh):
    ends = facet_points(crank_mesh, crank_mesh.outline)
    length = np.hypot(*(ends[:, 1] - ends[:, 0])).sum()
    assert length == pytest.approx(2 * (1.2 + 0.5), rel=1e-12)


def test_elements_are_fine_at_holes_and_coarse_far_from_them(crank_mesh):
    mesh = crank_mesh.mesh
    corners = mesh.p[:, mesh.t]
    a, b = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    size = np.sqrt(
        np.abs(a[0] * b[1] - a[1] * b[0]) * 2
    )  # side of the equilateral triangle of that area, roughly
    centre = corners.mean(axis=1)
    near_hole = np.hypot(*centre) < 0.015
    far = (np.abs(centre[0] - 0.5) < 0.1) & (np.abs(centre[0] - 0.25) > 0.1) & (np.abs(centre[1]) < 0.15)
    assert size[near_hole].max() < 2 * 0.004
    assert size[far].mean() > 0.05


def test_the_same_region_and_settings_give_the_same_mesh():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, hole_diameter=0.02)
    meshes = [mesh_region(bar.local_outline(), MeshSettings(0.1, 0.005, stations=(0.5,))) for _ in range(2)]
    np.testing.assert_array_equal(meshes[0].mesh.doflocs, meshes[1].mesh.doflocs)
    np.testing.assert_array_equal(meshes[0].mesh.t, meshes[1].mesh.t)
    for a, b in zip(meshes[0].holes + meshes[0].cuts, meshes[1].holes + meshes[1].cuts):
        np.testing.assert_array_equal(a, b)


def test_finer_flattening_of_the_drawing_does_not_refine_the_mesh():
    sizes = MeshSettings(0.01, 0.003)
    counts = [
        mesh_region(stadium(0.2, 0.05, 0.01, hole_diameter=0.02, sagitta=s).local_outline(), sizes).n_elements
        for s in (1e-5, 1e-9)
    ]
    # 1e-9 m flattening has ~100 times more vertices than 1e-5 m; the mesh stays the same size.
    assert abs(counts[1] - counts[0]) <= 0.05 * counts[0]


def test_a_link_thinner_than_two_elements_is_an_error_naming_it_and_the_size():
    with pytest.raises(
        FEAError, match=r"thin bar: a part of the outline .* narrower than 2 elements of size = 20 mm"
    ):
        mesh_region(box(0, 0, 1, 0.03), MeshSettings(0.02), name="thin bar")


def test_a_neck_too_narrow_for_the_size_is_an_error():
    region = Polygon([(0, 0), (0.4, 0), (0.4, 0.045), (0.6, 0.045), (0.6, 0), (1, 0), (1, 0.1), (0, 0.1)])
    with pytest.raises(FEAError, match=r"near \(0\.5, .*narrower"):
        mesh_region(region, MeshSettings(0.04, 0.01))


def test_a_hole_touching_the_outline_is_an_error_naming_the_hole():
    region = Polygon(box(0, 0, 1, 0.2).exterior, [circle_points((0.5, 0.1), 0.1, 1e-6)[::-1]])
    with pytest.raises(FEAError, match=r"between hole 0 and the outline is 0\.\d+ mm wide near \(0\.\d+, "):
        mesh_region(region, MeshSettings(0.05, 0.01), name="link")


def test_a_ligament_narrower_than_two_hole_elements_is_an_error():
    region = Polygon(box(0, 0, 1, 0.2).exterior, [circle_points((0.5, 0.1), 0.095, 1e-6)[::-1]])
    with pytest.raises(FEAError, match=r"5 mm wide .* hole_size = 4 mm"):
        mesh_region(region, MeshSettings(0.05, 0.004))


def test_a_self_intersecting_region_is_refused_before_gmsh_sees_it():
    with pytest.raises(
        FEAError, match=r"bow tie: the region to mesh is not a valid polygon \(Self-intersection"
    ):
        mesh_region(Polygon([(0, 0), (1, 1), (1, 0), (0, 1)]), MeshSettings(0.1), name="bow tie")


def test_a_station_outside_the_link_is_an_error():
    with pytest.raises(FEAError, match="station x = 1.5 m is not inside"):
        mesh_region(box(0, 0, 1, 0.2), MeshSettings(0.05, stations=(0.5, 1.5)))


def test_bad_sizes_are_errors():
    with pytest.raises(FEAError, match="hole_size must be a finite number > 0"):
        MeshSettings(0.05, hole_size=-1.0)
    with pytest.raises(FEAError, match="size must be a finite number > 0"):
        MeshSettings(float("nan"))


def test_a_clockwise_outline_meshes_its_cuts_as_a_counter_clockwise_one_does():
    # An L with pin holes whose outline runs clockwise (as shapely's union returns it): gmsh's
    # fragment used to leave the cut out of the surface, and reading the mesh failed.
    shell = box(-0.03, -0.02, 0.3, 0.02).union(box(0.26, -0.02, 0.3, 0.3)).exterior
    region = Polygon(shell, [circle_points(c, 0.006, 1e-7)[::-1] for c in ((0.0, 0.0), (0.28, 0.27))])
    assert not region.exterior.is_ccw
    sizes = MeshSettings(0.01, stations=(0.15,), cuts=(((0.13, -0.02), (0.17, 0.02)),))
    meshes = [mesh_region(r, sizes) for r in (region, orient(region, 1.0))]
    for plane in meshes:
        for cut in plane.cuts:
            assert (plane.mesh.f2t[1, cut] >= 0).all()  # interior facets: elements on both sides
    assert len(meshes[0].cuts[0]) == len(meshes[1].cuts[0]) > 0


@pytest.mark.parametrize("stations", [(0.05, 0.55), (0.085, 0.515), (0.1, 0.5)])
def test_cuts_beside_and_at_the_ends_of_a_slot_are_meshed_as_lines_of_nodes(stations):
    """A slotted bar (a 0.4 m obround slot, 30 mm wide, from x = 0.085 to 0.515 m): cuts in the
    solid beyond the slot's ends, tangent to them and through the slot all mesh, each a line of
    nodes across the material. gmsh's isInside missed the solid right of the slot, and embedding
    the cut there failed."""
    region = box(-0.02, -0.03, 0.62, 0.03).difference(LineString([(0.1, 0.0), (0.5, 0.0)]).buffer(0.015, 64))
    meshed = mesh_region(region, MeshSettings(0.01, stations=stations))
    for x in stations:
        on = np.abs(meshed.mesh.p[0] - x) < 1e-9
        assert on.sum() >= 5
        assert meshed.mesh.p[1, on].min() == pytest.approx(-0.03) and meshed.mesh.p[1, on].max() == pytest.approx(0.03)
