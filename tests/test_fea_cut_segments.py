"""FEA section resultants over cut segments at any angle: a member's section, normal to its axis,
from outline to outline, stopping short of material its infinite line would cross."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from shapely.geometry import LineString, Polygon, box

from linkstress.geometry.builders import straight_bar
from linkstress.geometry.curves import circle_points
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.geometry.profile import LinkProfile
from linkstress.validation.fea.convergence import convergence_study
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.link import solve_link
from linkstress.validation.fea.mesh import MeshSettings, mesh_region

SPACING, DEPTH = 0.4, 0.05
CENTRES = (0.12, 0.2, 0.28)
TILTS_DEG = (0.0, 20.0, 45.0)


def static_pair(n_joints: int, loaded: int, at: np.ndarray, force: np.ndarray) -> LinkLoadCase:
    """Static loads (no motion, no gravity): force (P, 2) [N] on joint ``loaded`` at ``at`` (2,) [m],
    -force on joint 0 at the origin with the couple T = -(at x force) there that balances the pair."""
    n = len(force)
    pins = np.zeros((n, n_joints, 2))
    pins[:, 0], pins[:, loaded] = -force, force
    couples = np.zeros((n, n_joints))
    couples[:, 0] = -(at[0] * force[:, 1] - at[1] * force[:, 0])
    zero = np.zeros((n, 2))
    return LinkLoadCase((0, 1), pins, couples, np.zeros(n), np.zeros(n), zero, zero)


def free_body(force, couple, tangent, reference):
    """Resultants (P, S) of the part behind each cut (joint 0's side, -tangent), which carries -force
    at the origin and the couple: N = t.F, V = n.F, M = T + r_ref x F (the beam's signs)."""
    t = np.asarray(tangent)
    n = np.column_stack([-t[:, 1], t[:, 0]])
    r = np.asarray(reference)
    moment = couple[:, None] + r[None, :, 0] * force[:, 1:] - r[None, :, 1] * force[:, :1]
    return force @ t.T, force @ n.T, moment


def tilted_cut(centre, tilt_deg, half_depth):
    """Tangent t at ``tilt_deg`` to the bar's axis and the cut through ``centre`` normal to it,
    from y = -half_depth to y = +half_depth (the bar's edges)."""
    tilt = math.radians(tilt_deg)
    t = np.array([math.cos(tilt), math.sin(tilt)])
    n = np.array([-t[1], t[0]])
    reach = half_depth / n[1] * n
    return t, np.array([centre - reach, centre + reach])


@pytest.fixture(scope="module")
def tilted_bar():
    """A steel bar, pins 0.4 m apart, 50 mm deep, 16 mm pin holes, pulled and bent through its pins in
    four directions; cuts through the axis at x = 0.12, 0.2, 0.28 m tilted 0, 20 and 45 degrees,
    and the station x = 0.12 m on the same mesh."""
    bar = straight_bar(SPACING, DEPTH, 0.03, 0.01, STRUCTURAL_STEEL, hole_diameter=0.016, name="bar")
    phi = np.radians([0.0, 60.0, 135.0, 250.0])
    force = 2000.0 * np.column_stack([np.cos(phi), np.sin(phi)])
    cuts = [tilted_cut(np.array([x, 0.0]), tilt, DEPTH / 2) for x, tilt in zip(CENTRES, TILTS_DEG)]
    tangents = np.array([t for t, _ in cuts])
    segments = np.array([s for _, s in cuts])
    # 50 elements along the 45-degree cut: N, V, M within 0.03 % of |F| (0.1 % at 25, 0.4 % at 12;
    # the error falls as h^2)
    settings = MeshSettings(
        0.01, 0.002, stations=(CENTRES[0],), cuts=tuple(map(tuple, segments.tolist())), station_size=0.001
    )
    loads = static_pair(2, 1, np.array([SPACING, 0.0]), force)
    return bar, force, loads, tangents, segments, solve_link(bar, loads, settings)


def test_a_cut_tilted_0_20_or_45_degrees_across_a_bar_carries_the_free_body_of_the_part_behind_it(tilted_bar):
    _, force, loads, tangents, segments, result = tilted_bar
    centres = segments.mean(axis=1)  # the chords' centroids: the bar's axis
    res = result.cut_resultants(segments, tangents, centres)
    n, v, m = free_body(force, loads.joint_couples[:, 0], tangents, centres)
    # The moment at x is T + x Fy = -(0.4 - x) Fy for each tilt (the cut's centre is on the axis);
    # N and V are the pin force resolved on the tilted cut's axes.
    np.testing.assert_allclose(m, -(SPACING - np.array(CENTRES))[None, :] * force[:, 1:], atol=1e-9)
    assert result.reaction_ratio.max() < 1e-9
    scale = 2000.0
    np.testing.assert_allclose(res.normal, n, atol=5e-3 * scale)
    np.testing.assert_allclose(res.shear, v, atol=5e-3 * scale)
    np.testing.assert_allclose(res.moment, m, atol=5e-3 * scale * (SPACING - CENTRES[0]))


def test_a_vertical_cut_segment_gives_the_station_resultants_to_rounding(tilted_bar):
    _, _, _, tangents, segments, result = tilted_bar
    station = result.section_resultants([CENTRES[0]])
    reference = [[CENTRES[0], station.neutral_axis[0]]]
    # the same cut given either end first
    for ends in (segments[:1], segments[:1, ::-1]):
        cut = result.cut_resultants(ends, tangents[:1], reference)
        for got, expected in ((cut.normal, station.normal), (cut.shear, station.shear), (cut.moment, station.moment)):
            np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-9)


def test_refined_settings_keep_the_cut_segments():
    settings = MeshSettings(0.01, cuts=(((0.1, -0.1), (0.1, 0.1)),), stations=(0.2,))
    finer = settings.refined(1.5)
    assert finer.cuts == settings.cuts == (((0.1, -0.1), (0.1, 0.1)),)
    assert finer.stations == (0.2,) and finer.size == pytest.approx(0.01 / 1.5)


def l_plate() -> LinkProfile:
    """An L of 40 mm wide arms, 10 mm steel: a horizontal arm along y = 0 from the pin hole at the
    origin to the corner at (0.3, 0), a vertical arm up to the pin hole at (0.3, 0.27) (12 mm holes)."""
    shell = box(-0.03, -0.02, 0.32, 0.02).union(box(0.28, -0.02, 0.32, 0.3))
    holes = [circle_points(c, 0.006, 1e-7)[::-1] for c in ((0.0, 0.0), (0.3, 0.27))]
    joints = np.array([[0.0, 0.0], [0.3, 0.0], [0.3, 0.27]])
    return LinkProfile(Polygon(shell.exterior, holes), joints, 0.01, STRUCTURAL_STEEL, "L")


def test_a_cut_across_one_arm_of_an_l_carries_that_arms_statics_though_its_line_crosses_the_other():
    link = l_plate()
    # 45 degrees across the horizontal arm at x = 0.15: its infinite line y = x - 0.15 also crosses
    # the vertical arm (at y = 0.13 to 0.17); the segment stops at the horizontal arm's edges.
    tangent, ends = tilted_cut(np.array([0.15, 0.0]), -45.0, 0.02)
    line = LineString(ends[0] + np.outer([-10.0, 10.0], ends[1] - ends[0]))
    assert line.intersection(link.outline).intersects(box(0.28, 0.1, 0.32, 0.2))
    force = np.array([[1500.0, 400.0], [-300.0, 1200.0]])
    at = np.array([0.3, 0.27])
    # 56 elements along the cut: within 0.02 % of |F| (0.08 % at 28)
    settings = MeshSettings(0.01, 0.0015, cuts=(tuple(map(tuple, ends.tolist())),), station_size=0.001)
    result = solve_link(link, static_pair(3, 2, at, force), settings)
    facets = result.plane.segment_cuts[0]
    ends_y = result.plane.mesh.p[1, result.plane.mesh.facets[:, facets]]
    assert np.abs(ends_y).max() == pytest.approx(0.02, abs=1e-9)  # only the horizontal arm's chord
    centre = ends.mean(axis=0)
    res = result.cut_resultants(ends[None], tangent[None], centre[None])
    couple = -(at[0] * force[:, 1] - at[1] * force[:, 0])
    n, v, m = free_body(force, couple, tangent[None], centre[None])
    scale = 1500.0
    np.testing.assert_allclose(res.normal, n, atol=5e-3 * scale)
    np.testing.assert_allclose(res.shear, v, atol=5e-3 * scale)
    np.testing.assert_allclose(res.moment, m, atol=5e-3 * scale * 0.4)


def test_a_cut_that_misses_the_material_is_an_error_naming_it():
    region = Polygon(box(0, -0.05, 1, 0.05).exterior, [circle_points((0.5, 0.0), 0.02, 1e-7)[::-1]])
    inside_hole = ((0.49, 0.0), (0.51, 0.0))
    with pytest.raises(FEAError, match=r"plate: cut 1 from \(0\.49, 0\) to \(0\.51, 0\) m misses the material"):
        mesh_region(region, MeshSettings(0.02, cuts=(((0.2, -0.05), (0.2, 0.05)), inside_hole)), name="plate")


def test_a_cut_that_ends_inside_the_material_is_an_error_naming_it_and_the_end():
    with pytest.raises(FEAError, match=r"plate: cut 0 from .* ends inside the material at \(0\.3, 0\.01\) m"):
        mesh_region(box(0, -0.05, 1, 0.05), MeshSettings(0.02, cuts=(((0.3, -0.05), (0.3, 0.01)),)), name="plate")


def test_resultants_over_a_cut_that_was_not_meshed_or_across_a_slanted_tangent_are_errors(tilted_bar):
    _, _, _, tangents, segments, result = tilted_bar
    with pytest.raises(FEAError, match=r"link 'bar': the cut .* was not meshed; put it in MeshSettings.cuts"):
        result.cut_resultants(segments[:1] + 0.01, tangents[:1], segments[:1].mean(axis=1))
    with pytest.raises(FEAError, match=r"link 'bar': the tangent .* is not normal to it"):
        result.cut_resultants(segments[1:2], tangents[:1], segments[1:2].mean(axis=1))


def test_a_refinement_study_follows_the_resultants_over_the_cut_segments_after_the_stations(tilted_bar):
    bar, force, loads, tangents, segments, result = tilted_bar
    settings = replace(result.plane.settings, station_size=0.004)
    centres = segments.mean(axis=1)
    study = convergence_study(bar, loads, settings, np.zeros((0, 2)), cut_axes=(tangents, centres))
    assert study.resultants.shape == (3, 3, len(force), 1 + len(segments))  # levels, N V M, P, station + cuts
    finest = study.finest.cut_resultants(segments, tangents, centres)
    np.testing.assert_array_equal(study.resultants[-1, 2, :, 1:], finest.moment)
    with pytest.raises(FEAError, match="cut segments needs their tangents and reference points"):
        convergence_study(bar, loads, settings, np.zeros((0, 2)))
