"""Bends sharper than beam theory (``linkstress.geometry.bends``): the stations across a dog-leg's
corner, or a bend of radius under a section depth, are nominal and flagged like junctions, so that no
"away from holes" figure comes from them; gentler bends are curved beams (Winkler-Bach).

The links are drawn here with shapely: two straight arms ``ARM`` long and ``H`` wide from pin a to a
corner and on to pin b, turning by ``turn`` degrees there (a rocker with an interior angle of 120
degrees turns by 60), round ends about the pins, pin holes of H / 2. A kinked link has a sharp outer
corner and an inner fillet (a closing of the outline by the fillet's radius rounds only its concave
corner); a bent link's centre line runs round an arc of radius R at the corner (edges concentric,
radii R -+ H / 2).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon

from linkstress.dynamics.section_stress import section_stresses
from linkstress.geometry.bends import BEND_WINDOW, SHARP_RADIUS, near_bends, sharp_arcs
from linkstress.geometry.curved_beam import theory_of
from linkstress.geometry.members import frame_member
from linkstress.geometry.profile import LinkProfile
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL

ARM, H, T = 0.15, 0.02, 0.01
"""Arm length from pin to corner, bar width, plate thickness [m]."""


def drilled(body: Polygon, pins: np.ndarray) -> LinkProfile:
    holes = [Point(p).buffer(H / 4, quad_segs=64).exterior.coords[::-1] for p in pins]
    return LinkProfile(Polygon(body.exterior, holes), pins, T, STRUCTURAL_STEEL, name="rocker")


def kinked(turn_deg: float, fillet: float) -> tuple[LinkProfile, np.ndarray]:
    """A dog-leg with a sharp outer corner and an inner fillet of radius ``fillet`` [m]; and its
    corner (the centre lines' meeting point) [m]."""
    turn = math.radians(turn_deg)
    corner = np.array([ARM, 0.0])
    pins = np.array([[0.0, 0.0], corner + ARM * np.array([math.cos(turn), math.sin(turn)])])
    body = LineString([pins[0], corner, pins[1]]).buffer(H / 2, join_style="mitre", quad_segs=64)
    if fillet > 0:
        body = body.buffer(fillet, join_style="round", quad_segs=64).buffer(-fillet, join_style="round", quad_segs=64)
    return drilled(body, pins), corner


def bent(turn_deg: float, radius: float) -> tuple[LinkProfile, np.ndarray]:
    """A dog-leg whose centre line turns round an arc of ``radius`` [m] (tangent to both arms, each
    ARM long from its pin to the arms' meeting point); and the arc's middle [m]."""
    turn = math.radians(turn_deg)
    corner = np.array([ARM, 0.0])
    pins = np.array([[0.0, 0.0], corner + ARM * np.array([math.cos(turn), math.sin(turn)])])
    back = radius * math.tan(turn / 2)
    centre = corner + np.array([-back, radius])
    t = np.linspace(-math.pi / 2, -math.pi / 2 + turn, 181)
    arc = centre + radius * np.column_stack([np.cos(t), np.sin(t)])
    body = LineString(np.vstack([pins[0], arc, pins[1]])).buffer(H / 2, quad_segs=64)
    return drilled(body, pins), arc[90]


def station_near(member, point: np.ndarray) -> float:
    """The arc length [m] of ``member``'s axis point nearest to ``point`` [m, load frame]."""
    return float(LineString(member.path).project(Point(point)))


def pulled(p: float) -> LinkLoadCase:
    """One position, no inertia: the pins pulled apart by ``p`` [N] along the line between them."""
    zero = np.zeros(1)
    return LinkLoadCase((0, 1), np.array([[[-p, 0.0], [p, 0.0]]]), np.zeros((1, 2)), zero, zero,
                        np.zeros((1, 2)), np.zeros((1, 2)))


def test_a_corner_or_a_radius_under_a_depth_is_sharp_and_a_gentler_bend_is_not():
    # The turn over a window w = BEND_WINDOW depths: a circle of radius R turns w / R, sharp when
    # R < SHARP_RADIUS depths; a corner turns its whole angle within any window that holds it.
    depth = H
    s = np.linspace(0.0, 0.2, 2001)
    for radius, sharp in ((0.9 * SHARP_RADIUS * depth, True), (1.1 * SHARP_RADIUS * depth, False), (3 * depth, False)):
        t = s / radius
        arc = radius * np.column_stack([np.sin(t), 1 - np.cos(t)])
        assert (len(sharp_arcs(arc, s, depth, (0.0, 0.2))) > 0) == sharp
    # a 15 deg corner at s = 0.1 m: sharp there and only there (within half a window)
    corner = np.where(s[:, None] < 0.1, [[1.0, 0.0]] * s[:, None],
                      [0.1, 0.0] + (s[:, None] - 0.1) * [math.cos(math.radians(15)), math.sin(math.radians(15))])
    found = sharp_arcs(corner, s, depth, (0.0, 0.2))
    assert len(found) and np.abs(found - 0.1).max() <= BEND_WINDOW * depth / 2
    assert near_bends([0.1 + 0.99 * depth, 0.1 + 1.01 * depth + BEND_WINDOW * depth / 2], [depth, depth], found).tolist() == [True, False]


@pytest.mark.parametrize(("turn_deg", "fillet"), [(60.0, 0.006), (60.0, 0.002), (90.0, 0.006), (30.0, 0.006)])
def test_the_stations_across_a_dog_legs_corner_are_nominal(turn_deg, fillet):
    # The rocker of issue 28 turns 60 deg (120 deg between its arms) with a 6 mm inner fillet. The
    # stations within a section depth of its corner (along the axis) are flagged ``bend`` and
    # nominal; those two depths clear of the corner and of the pins are not.
    link, corner = kinked(turn_deg, fillet)
    member = frame_member(link, (0, 1))
    assert member.curved
    at = station_near(member, link.frame(0, 1).to_local(corner))
    assert at == pytest.approx(ARM, rel=2e-2)
    stations = member.stations(151)
    cuts = member.cuts(stations)
    depth = cuts.table.top - cuts.table.bottom
    across = np.abs(stations - at) < H
    assert cuts.bend[across].all() and cuts.nominal[across].all()
    clear = (np.abs(stations - at) > 2 * H) & (stations > 2 * H) & (stations < member.length - 2 * H)
    assert clear.sum() > 60 and not cuts.nominal[clear].any()
    # every flagged station is within its depth of the corner's turning stretch, not elsewhere
    assert np.abs(stations[cuts.bend] - at).max() < depth[cuts.bend].max() + H


@pytest.mark.parametrize(("radius_in_depths", "sharp"), [(0.8, True), (1.5, False), (3.0, False)])
def test_a_bend_is_nominal_under_a_depths_radius_and_a_curved_beam_above(radius_in_depths, sharp):
    # A 90 deg bend: under a section depth's radius the stations round it are nominal (flagged bend);
    # above it they take Winkler-Bach (R < 10 depths) with the axis's curvature 1/R (within 3 %; the
    # circle through the axis a depth either side of a station spans the whole of a shorter bend).
    link, middle = bent(90.0, radius_in_depths * H)
    member = frame_member(link, (0, 1))
    at = station_near(member, link.frame(0, 1).to_local(middle))
    cuts = member.cuts([at])
    if not sharp:
        assert cuts.curvature[0] * radius_in_depths * H == pytest.approx(1.0, rel=3e-2)
    assert bool(cuts.bend[0]) == sharp and bool(cuts.nominal[0]) == sharp
    assert theory_of(cuts.curvature, cuts.table.top - cuts.table.bottom)[0] == "curved"


def test_no_away_from_holes_figure_comes_from_a_dog_legs_corner():
    # Pulled apart along the line between its pins, the 60 deg dog-leg bends most at its corner
    # (M = P times the corner's distance from the line of pull): the largest beam value is there,
    # and it is nominal. The largest value away from holes (and bends) is at a station more than a
    # depth from the corner, and is the largest over the stations that are not nominal.
    link, corner = kinked(60.0, 0.006)
    member = frame_member(link, (0, 1))
    at = station_near(member, link.frame(0, 1).to_local(corner))
    stations = member.stations(151)
    stress = section_stresses(link, pulled(1000.0), stations, member=member)
    nominal = stress.cuts.nominal
    assert np.array_equal(stress.near_hole, nominal)
    worst = int(np.argmax(stress.von_mises[0]))
    assert abs(stations[worst] - at) < H and nominal[worst]
    away = stress.max_away_from_holes
    assert away is not None and away[0] == stress.von_mises[0, ~nominal].max()
    where = np.flatnonzero(~nominal)[np.argmax(stress.von_mises[0, ~nominal])]
    assert abs(stations[where] - at) > H
    assert away[0] < stress.von_mises[0, worst]


@pytest.mark.parametrize("from_pin", [0.12, 0.25, 0.5])
def test_a_dog_leg_kinked_near_a_pin_is_not_taken_for_a_straight_bar(from_pin):
    # A 300 mm bar kinked by 30 deg (3 mm inner fillet) at 12, 25 or 50 % of its length: close to a
    # pin the kinked arm is only a few of the first midline's points, which a notch would move as
    # much (a notch narrows the section, a kink does not): the member is curved, its corner flagged.
    length, turn = 0.3, math.radians(30.0)
    corner = np.array([from_pin * length, 0.0])
    pins = np.array([[0.0, 0.0], corner + (1 - from_pin) * length * np.array([math.cos(turn), math.sin(turn)])])
    body = LineString([pins[0], corner, pins[1]]).buffer(H / 2, join_style="mitre", quad_segs=32)
    link = drilled(body.buffer(0.003, quad_segs=32).buffer(-0.003, quad_segs=32), pins)
    member = frame_member(link, (0, 1))
    assert member.curved
    at = station_near(member, link.frame(0, 1).to_local(corner))
    assert at == pytest.approx(from_pin * length, rel=2e-2)
    cuts = member.cuts(member.stations(101))
    assert cuts.bend[np.abs(cuts.s - at) < 0.5 * H].all()
