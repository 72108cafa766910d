"""Centrelines that follow the material: S-shaped connecting rods with round bosses about their pins
(``linkstress.geometry.centreline``, ``linkstress.geometry.medial_axis``).

Each rod is drawn here with shapely: its centre line a straight lead from each pin, then two opposite
arcs of radius R (the first turning left by ``SWEEP``, the second right by as much), the bar ``h`` wide
about it, a round boss of diameter D about each pin (D = h: the bar's own round end) and a pin hole
of h / 2. The truth is the drawing: the centre line's length between the pins, the arcs' curvature
+-1/R, and at each arc's middle the Winkler-Bach stress of a rectangle h x t bent to radius R
(Shigley, Mechanical Engineering Design, 10th ed., section 3-18; Boresi & Schmidt eqs. 9.19-9.23):
r_n = h / ln(r_o / r_i), e = R - r_n, sigma(r) = N / A + M (r_n - r) / (A e r), M > 0 straightening
the bar (the inner fibre r_i in tension).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from linkstress.dynamics.section_stress import section_stresses
from linkstress.geometry.curved_beam import theory_of
from linkstress.geometry.members import frame_member
from linkstress.geometry.profile import LinkProfile
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL

H = 0.02
"""The bar's width [m]."""
T = 0.01
"""The plate's thickness [m]."""
SWEEP = math.radians(45.0)
"""Each arc's turn [rad]."""


def s_centre_line(radius: float, lead: float, points: int = 721) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The drawn centre line (K, 2) [m] from pin a at the origin, heading +x; the middles of its two
    arcs (2, 2) [m] and their centres (2, 2) [m]."""
    first_centre = np.array([lead, radius])
    t = np.linspace(-math.pi / 2, -math.pi / 2 + SWEEP, points)
    first = first_centre + radius * np.column_stack([np.cos(t), np.sin(t)])
    second_centre = first[-1] + radius * np.array([math.sin(SWEEP), -math.cos(SWEEP)])
    t = np.linspace(math.pi / 2 + SWEEP, math.pi / 2, points)
    second = second_centre + radius * np.column_stack([np.cos(t), np.sin(t)])
    line = np.vstack([[0.0, 0.0], first, second[1:], second[-1] + [lead, 0.0]])
    middles = np.array([first[points // 2], second[points // 2]])
    return line, middles, np.array([first_centre, second_centre])


def s_rod(radius: float, bosses: tuple[float, float], lead: float) -> tuple[LinkProfile, float, np.ndarray, np.ndarray]:
    """The rod, the centre line's length between its pins [m], its arcs' middles and centres [m]."""
    line, middles, centres = s_centre_line(radius, lead)
    pins = line[[0, -1]]
    body = unary_union([
        LineString(line).buffer(H / 2, quad_segs=64, cap_style="flat"),
        *(Point(p).buffer(d / 2, quad_segs=64) for p, d in zip(pins, bosses)),
    ])
    holes = [Point(p).buffer(H / 4, quad_segs=64).exterior.coords[::-1] for p in pins]
    link = LinkProfile(Polygon(body.exterior, holes), pins, T, STRUCTURAL_STEEL, name="rod")
    return link, 2 * lead + 2 * radius * SWEEP, middles, centres


def station_near(member, point: np.ndarray) -> float:
    """The arc length [m] along ``member``'s axis of its point nearest to ``point`` [m, load frame]."""
    return float(LineString(member.path).project(Point(point)))


BOSSES = [(1.2, 1.2), (1.6, 1.6), (2.5, 2.5), (2.5, 1.0)]
"""Boss diameters about pins a and b, in bar widths (1.0: the bar's own round end)."""


def rod_in_load_frame(radius_in_depths: float, bosses: tuple[float, float], lead_in_bosses: float):
    """An S-rod whose arcs are ``radius_in_depths`` bar widths in radius, with bosses of ``bosses``
    widths and leads of ``lead_in_bosses`` of the larger boss's diameter (0.5: the arcs start at its
    edge), and its truths, in the load frame (pin a at the origin, pin b on +x)."""
    boss = np.array(bosses) * H
    link, length, middles, centres = s_rod(radius_in_depths * H, tuple(boss), lead_in_bosses * boss.max())
    frame = link.frame(0, 1)
    return link, length, frame.to_local(middles), frame.to_local(centres)


@pytest.mark.parametrize("lead_in_bosses", [0.5, 1.0])
@pytest.mark.parametrize("bosses", BOSSES)
@pytest.mark.parametrize("radius_in_depths", [3.0, 6.75])
def test_an_s_rods_centreline_runs_through_its_bosses_and_round_both_bends(radius_in_depths, bosses, lead_in_bosses):
    # The traced length is the drawn centre line's between the pins (within 1 %), and at each arc's
    # middle the axis passes through the drawn centre line with curvature -+1/R (within 2 %): the
    # first arc turns left (toward +normal, curvature > 0), the second right.
    link, length, middles, centres = rod_in_load_frame(radius_in_depths, bosses, lead_in_bosses)
    radius = radius_in_depths * H
    member = frame_member(link, (0, 1))
    assert member.curved
    assert member.length == pytest.approx(length, rel=1e-2)
    for middle, centre, sign in zip(middles, centres, (1.0, -1.0)):
        at = station_near(member, middle)
        assert np.hypot(*(member.point_at([at])[0] - middle)) < 2e-3 * H
        cuts = member.cuts([at])
        assert cuts.curvature[0] * radius == pytest.approx(sign, rel=2e-2)
        assert np.hypot(*(cuts.origin[0] + cuts.normal[0] / cuts.curvature[0] - centre)) < 2e-2 * radius
        np.testing.assert_allclose(cuts.table.top - cuts.table.bottom, H, rtol=1e-3)
        assert not cuts.nominal[0]


def pulled(link: LinkProfile, p: float) -> LinkLoadCase:
    """One position, no inertia: the pins pulled apart by ``p`` [N] along the line between them (load
    frame (0, 1): pin b at +x)."""
    pins = np.array([[[-p, 0.0], [p, 0.0]]])
    zero = np.zeros(1)
    return LinkLoadCase((0, 1), pins, np.zeros((1, 2)), zero, zero, np.zeros((1, 2)), np.zeros((1, 2)))


def winkler_bach(n: float, m: float, radius: float) -> tuple[float, float]:
    """sigma at the inner and outer fibre [Pa] of an h x t rectangle bent to centroid ``radius`` [m]
    under N = ``n`` [N] and M = ``m`` [N m] (> 0 straightening the bar): Shigley eq. 3-65."""
    inner, outer = radius - H / 2, radius + H / 2
    area = H * T
    r_n = H / math.log(outer / inner)
    e = radius - r_n
    return n / area + m * (r_n - inner) / (area * e * inner), n / area + m * (r_n - outer) / (area * e * outer)


@pytest.mark.parametrize("lead_in_bosses", [0.5, 1.0])
@pytest.mark.parametrize("bosses", [(1.6, 1.6), (2.5, 1.0)])
@pytest.mark.parametrize("radius_in_depths", [3.0, 6.75, 12.0])
def test_an_s_rods_bends_take_winkler_bach_within_ten_depths(radius_in_depths, bosses, lead_in_bosses):
    # Pulled apart by P along the line between its pins, the rod's section at each arc's middle carries,
    # from the statics of the drawing, N = P cos(phi) (phi: the centre line's angle to the pull there)
    # and M = P d (d: the section's centroid's distance from the line of pull, which runs on the
    # inner side of both arcs, so M straightens them). Under ten depths the von Mises stress there is
    # the larger Winkler-Bach fibre stress (free edges: no shear), within 0.2 %; at twelve depths the
    # section is straight: N / A + M (h / 2) / I.
    link, _, middles, centres = rod_in_load_frame(radius_in_depths, bosses, lead_in_bosses)
    radius, p = radius_in_depths * H, 1000.0
    member = frame_member(link, (0, 1))
    stations = np.array([station_near(member, middle) for middle in middles])
    stress = section_stresses(link, pulled(link, p), stations, member=member)
    tangent = np.column_stack([-(middles - centres)[:, 1], (middles - centres)[:, 0]]) / radius
    n = p * np.abs(tangent[:, 0])
    m = p * np.abs(middles[:, 1])
    np.testing.assert_allclose(stress.forces.normal[0], n, rtol=1e-3)
    np.testing.assert_allclose(np.abs(stress.forces.moment[0]), m, rtol=2e-3)
    curved = theory_of(stress.cuts.curvature, stress.sections.top - stress.sections.bottom) == "curved"
    assert curved.all() == (radius_in_depths < 10) and curved.any() == (radius_in_depths < 10)
    if radius_in_depths < 10:
        assert stress.curved is not None and set(stress.curved.at.tolist()) == {0, 1}
        expected = [max(abs(v) for v in winkler_bach(n[k], m[k], radius)) for k in range(2)]
        # the inner fibre, toward the centre of curvature, carries it, in tension
        inner = np.where(stress.cuts.curvature > 0, stress.sections.top, stress.sections.bottom)
        np.testing.assert_allclose(stress.fibre_y[0], inner, atol=1e-9)
        assert (stress.sigma[0] > 0).all()
    else:
        assert stress.curved is None
        expected = n / (H * T) + m * (H / 2) / (T * H**3 / 12)
    np.testing.assert_allclose(stress.von_mises[0], expected, rtol=2e-3)


@pytest.mark.parametrize("lead_in_bosses", [0.5, 1.0])
@pytest.mark.parametrize("bosses", BOSSES)
def test_an_s_rods_stations_stay_inside_its_outline(bosses, lead_in_bosses):
    # Past each pin the axis runs straight on to the outline (the boss's far edge): the stations cover
    # the rod from end to end and none lies outside it.
    link, _, _, _ = rod_in_load_frame(6.75, bosses, lead_in_bosses)
    member = frame_member(link, (0, 1))
    shell = Polygon(link.local_outline(0, 1).exterior)
    stations = member.stations(200)
    assert shapely.contains_xy(shell, *member.point_at(stations).T).all()
    ends = member.point_at(np.array(member.extent))
    assert np.allclose(shapely.distance(shell.exterior, shapely.points(ends)), 0.0, atol=1e-6 * H)
    # the far edges of the bosses, a radius beyond each pin along the rod
    assert -member.extent[0] == pytest.approx(bosses[0] * H / 2, rel=1e-3)
    assert member.extent[1] - member.length == pytest.approx(bosses[1] * H / 2, rel=1e-3)
