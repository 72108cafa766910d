"""The link FEA result: section resultants, stresses at points, peak von Mises, sweeps and VTU output."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ElementTree

import meshio
import numpy as np
import pytest
from shapely.geometry import Polygon

from linkstress.geometry.builders import straight_bar
from linkstress.geometry.curves import arc_points, circle_points
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.geometry.profile import LinkProfile
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.link import solve_link
from linkstress.validation.fea.mesh import MeshSettings
from linkstress.stress_state import von_mises

STATIONS = (0.25, 0.5, 0.75)


def pinned_pair(link: LinkProfile, force_at_b: np.ndarray) -> LinkLoadCase:
    """Static loads: force (P, 2) [N] on joint 1 at (L, 0), the opposite force and a torque at joint 0.

    No motion and no gravity, so the free body of the part left of a cut x (0 < x < L) is exact
    (:func:`exact_resultants`); the torque T = -L Fy balances the pair.
    """
    length = float(np.hypot(*(link.joints[1] - link.joints[0])))
    n = len(force_at_b)
    pins = np.stack([-force_at_b, force_at_b], axis=1)
    couples = np.column_stack([-length * force_at_b[:, 1], np.zeros(n)])
    zero = np.zeros((n, 2))
    return LinkLoadCase((0, 1), pins, couples, np.zeros(n), np.zeros(n), zero, zero)


def exact_resultants(force_at_b, x, y_na, length):
    """Left free body of :func:`pinned_pair` about the cut point (x, y_na): (N, V, M) each (P, S)."""
    fx, fy = force_at_b[:, :1], force_at_b[:, 1:]
    torque = -length * fy
    # loads on the left part: -F at the origin and the torque; M = torque + (0 - c) x (-F)
    moment = torque + (-x[None, :]) * (-fy) - (-y_na[None, :]) * (-fx)
    shape = moment.shape
    return np.broadcast_to(fx, shape), np.broadcast_to(fy, shape), moment


@pytest.fixture(scope="module")
def crank_sweep():
    bar = straight_bar(1.0, 0.5, 0.1, 0.1, STRUCTURAL_STEEL, hole_diameter=0.02, name="crank")
    phi = np.linspace(0, 2 * math.pi, 6, endpoint=False)
    force = 1000.0 * np.column_stack([np.cos(phi), np.sin(phi)])
    result = solve_link(
        bar, pinned_pair(bar, force), MeshSettings(0.05, 0.004, stations=STATIONS, station_size=0.02)
    )
    return bar, force, result


def test_cut_resultants_are_the_free_body_of_the_left_part(crank_sweep):
    bar, force, result = crank_sweep
    resultants = result.section_resultants(STATIONS)
    x = np.array(STATIONS)
    n, v, m = exact_resultants(force, x, resultants.neutral_axis, 1.0)
    np.testing.assert_allclose(resultants.neutral_axis, 0.0, atol=1e-12)
    scale = 1000.0
    np.testing.assert_allclose(resultants.normal, n, atol=2e-3 * scale)
    np.testing.assert_allclose(resultants.shear, v, atol=2e-3 * scale)
    np.testing.assert_allclose(resultants.moment, m, atol=2e-3 * scale * 1.0)


def test_resultants_of_a_subset_of_stations_come_in_the_order_asked(crank_sweep):
    _, _, result = crank_sweep
    every = result.section_resultants(STATIONS)
    two = result.section_resultants([0.75, 0.25])
    np.testing.assert_array_equal(two.moment, every.moment[:, [2, 0]])


def test_a_station_that_was_not_meshed_is_an_error_that_says_so(crank_sweep):
    _, _, result = crank_sweep
    with pytest.raises(FEAError, match=r"x = 0.6 m was not meshed as a cut; put it in MeshSettings.stations"):
        result.section_resultants([0.6])


def test_stress_at_mid_span_is_n_over_a_plus_m_y_over_i(crank_sweep):
    # Position 1: F = 1000 N at 60 degrees on B, so N = 500 N and M(0.5) = -866 x 0.5 = -433 N m;
    # A = 0.05 m^2, I = 0.1 x 0.5^3 / 12 m^4: sigma_xx(y = +-0.25) = 10 kPa -+ 103.9 kPa.
    _, _, result = crank_sweep
    fx, fy = 1000.0 * math.cos(math.pi / 3), 1000.0 * math.sin(math.pi / 3)
    s = result.stress_at([[0.5, 0.25], [0.5, -0.25], [0.5, 0.0]])[1]
    area, i = 0.1 * 0.5, 0.1 * 0.5**3 / 12
    assert s[0, 0] == pytest.approx(fx / area - fy * 0.5 * 0.25 / i, rel=5e-3)
    assert s[1, 0] == pytest.approx(fx / area + fy * 0.5 * 0.25 / i, rel=5e-3)
    # Jourawski at the neutral axis: tau = 1.5 V / A
    assert s[2, 2] == pytest.approx(1.5 * fy / (0.1 * 0.5), rel=2e-2)


def test_stress_at_points_has_one_row_per_position_and_point(crank_sweep):
    _, _, result = crank_sweep
    nodes = result.nodes[:5]
    s = result.stress_at(nodes)
    assert s.shape == (6, 5, 3)
    np.testing.assert_allclose(s, result.nodal_stress[:, :5], rtol=1e-9, atol=1e-6)


def test_every_point_of_the_plate_is_found_in_a_graded_mesh(crank_sweep):
    # 4 mm elements at the holes grade to 50 mm: a point in a large element may have smaller
    # elements' centroids nearer to it than its own, so the search must widen until it finds it.
    bar, _, result = crank_sweep
    rng = np.random.default_rng(7)
    points = np.column_stack([rng.uniform(-0.1, 1.1, 3000), rng.uniform(-0.25, 0.25, 3000)])
    clear = np.min([np.hypot(*(points - j).T) for j in bar.joints], axis=0) > 0.0101
    s = result.stress_at(points[clear])
    assert s.shape == (6, clear.sum(), 3) and np.isfinite(s).all()


def test_peak_von_mises_is_at_a_pin_hole_and_is_the_largest_nodal_value(crank_sweep):
    bar, _, result = crank_sweep
    peak, where = result.von_mises_peak, result.von_mises_peak_at
    assert peak.shape == (6,) and where.shape == (6, 2)
    np.testing.assert_allclose(peak, von_mises(result.nodal_stress).max(axis=1))
    distance_to_pins = np.min([np.hypot(*(where - j).T) for j in bar.joints], axis=0)
    np.testing.assert_allclose(distance_to_pins, 0.01, rtol=1e-3)


def test_a_sweep_gives_each_position_what_solving_it_alone_gives(crank_sweep):
    bar, force, result = crank_sweep
    alone = solve_link(bar, pinned_pair(bar, force[3:4]), result.plane.settings)
    np.testing.assert_allclose(
        alone.nodal_stress[0], result.nodal_stress[3], rtol=1e-9, atol=1e-9 * alone.von_mises_peak[0]
    )
    assert result.mesh_seconds > 0 and result.solve_seconds > 0
    assert result.dofs == 2 * len(result.nodes) and result.n_elements > 0


def test_vtu_files_per_position_hold_displacement_stresses_and_von_mises(tmp_path, crank_sweep):
    _, _, result = crank_sweep
    paths = result.write_vtu(tmp_path / "out")
    assert [p.name for p in paths] == [f"crank_{p:04d}.vtu" for p in range(6)] + ["crank.pvd"]
    mesh = meshio.read(paths[2])
    assert mesh.cells[0].type == "triangle6"
    assert mesh.cells[0].data.shape == (result.n_elements, 6)
    np.testing.assert_allclose(mesh.point_data["von_mises"], von_mises(result.nodal_stress[2]))
    np.testing.assert_allclose(mesh.point_data["sigma_xx"], result.nodal_stress[2][:, 0])
    ux = mesh.point_data["displacement"][:, 0]
    np.testing.assert_allclose(ux, result.displacement[result.model.components[0], 2])
    datasets = ElementTree.parse(paths[-1]).getroot().iter("DataSet")
    assert [d.get("file") for d in datasets] == [p.name for p in paths[:-1]]
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == sorted(
        p.name for p in paths
    )  # no temp files


def banana(length=0.4, rise=0.15, half_width=0.02, hole=0.012) -> LinkProfile:
    """A coupler bent on a circular arc through its two joints (0, 0) and (length, 0), round ends."""
    c = np.array([length / 2, -rise])
    radius = math.hypot(length / 2, rise)
    a0, a1 = math.atan2(rise, length / 2), math.atan2(rise, -length / 2)
    tol = 1e-7
    outer = arc_points(tuple(c), radius + half_width, a0, a1, tol)
    left_cap = arc_points((0.0, 0.0), half_width, a1, a1 + math.pi, tol)
    inner = arc_points(tuple(c), radius - half_width, a1, a0, tol)
    right_cap = arc_points((length, 0.0), half_width, a0 + math.pi, a0 + 2 * math.pi, tol)
    shell = np.vstack([outer[:-1], left_cap[:-1], inner[:-1], right_cap[:-1]])
    holes = [circle_points(j, hole / 2, tol)[::-1] for j in ((0.0, 0.0), (length, 0.0))]
    return LinkProfile(
        Polygon(shell, holes), np.array([[0.0, 0.0], [length, 0.0]]), 0.01, STRUCTURAL_STEEL, "banana"
    )


def test_a_curved_coupler_meshes_from_its_arcs_and_its_cut_resultants_are_its_free_body():
    link = banana()
    force = np.array([[300.0, -120.0]])
    stations = (0.1, 0.2, 0.3)
    # Resultants of element stresses converge as h^2: 0.56 % of |F| at 12 elements across the cut,
    # 0.14 % at 25 (station_size 2 mm on this 50 mm inclined cut).
    result = solve_link(
        link, pinned_pair(link, force), MeshSettings(0.01, 0.002, stations=stations, station_size=0.002)
    )
    assert result.reaction_ratio[0] < 1e-9
    res = result.section_resultants(stations)
    assert (res.neutral_axis > 0.05).all()  # the crown sits well above the line of the joints
    n, v, m = exact_resultants(force, np.array(stations), res.neutral_axis, 0.4)
    np.testing.assert_allclose(res.normal, n, atol=3e-3 * 300)
    np.testing.assert_allclose(res.shear, v, atol=3e-3 * 300)
    np.testing.assert_allclose(res.moment, m, atol=3e-3 * 300 * 0.4)
