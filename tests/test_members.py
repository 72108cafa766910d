"""A link's members: the arms between its joints, their axes (straight or curved), and the sections
and free bodies of the cuts across them (``linkstress.geometry.members``)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import split, unary_union

from linkstress.geometry.builders import stadium, straight_bar
from linkstress.geometry.curved_beam import CURVED_BEAM_LIMIT
from linkstress.dynamics.section_stress import section_stresses
from linkstress.errors import GeometryError
from linkstress.loads import LinkLoadCase
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.geometry.centreline import CURVED_WANDER
from linkstress.geometry.members import check_members, frame_member, link_members, member_tree
from linkstress.geometry.profile import LinkProfile
from linkstress.geometry.region_moments import region_moments

SPAN = 0.2
"""Joint spacing [m] of the generated two-joint links: joints at (0, 0) and (SPAN, 0)."""
ARM, WIDTH, PIN = 0.15, 0.035, 0.01
"""Bell cranks: arms of 150 mm between pins, 35 mm wide, 10 mm pin holes."""


def circle(centre, radius: float) -> np.ndarray:
    t = np.linspace(0.0, 2 * np.pi, 256, endpoint=False)[::-1]
    return np.column_stack([centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)])


def plate(shell, holes=()) -> LinkProfile:
    """A 8 mm steel plate with 8 mm pin holes at both joints and ``holes`` besides."""
    pins = [circle((0.0, 0.0), 0.004), circle((SPAN, 0.0), 0.004)]
    return LinkProfile(Polygon(shell, pins + list(holes)), np.array([[0.0, 0.0], [SPAN, 0.0]]), 0.008, STRUCTURAL_STEEL)


def banana(sag: float, width: float = 0.024) -> LinkProfile:
    """Centre line a circular arc through both joints bulging ``sag`` [m], edges ``width`` [m] apart,
    round ends, 8 mm pin holes."""
    radius = (SPAN**2 / 4 + sag**2) / (2 * sag)
    cx, cy = SPAN / 2, sag - radius
    t = np.linspace(math.atan2(-cy, SPAN - cx), math.atan2(-cy, -cx), 400)
    body = LineString(np.column_stack([cx + radius * np.cos(t), cy + radius * np.sin(t)])).buffer(width / 2, quad_segs=64)
    for joint in ((0.0, 0.0), (SPAN, 0.0)):
        body = body.difference(Point(joint).buffer(0.004, quad_segs=64))
    return LinkProfile(body, np.array([[0.0, 0.0], [SPAN, 0.0]]), 0.008, STRUCTURAL_STEEL)


def bell_crank(bend_deg: float = 90.0) -> LinkProfile:
    """Two arms of ARM between pins from the pivot O4 at the origin, along +x (to C) and at
    ``bend_deg`` from it (to B); joints [O4, B, C], 10 mm steel."""
    b = (ARM * math.cos(math.radians(bend_deg)), ARM * math.sin(math.radians(bend_deg)))
    c = (ARM, 0.0)
    body = unary_union([LineString([(0, 0), c]).buffer(WIDTH / 2), LineString([(0, 0), b]).buffer(WIDTH / 2)])
    for joint in ((0, 0), b, c):
        body = body.difference(Point(joint).buffer(PIN / 2, quad_segs=32))
    return LinkProfile(body, np.array([(0.0, 0.0), b, c]), 0.01, STRUCTURAL_STEEL, name="bell")


def static_loads(joints: int, forces: dict[int, tuple[float, float]], frame=(0, 1)) -> LinkLoadCase:
    """One position, no inertia, pin forces [N] (load frame) at the given joints."""
    pins = np.zeros((1, joints, 2))
    for j, f in forces.items():
        pins[0, j] = f
    zero = np.zeros(1)
    return LinkLoadCase(frame, pins, np.zeros((1, joints)), zero, zero, np.zeros((1, 2)), np.zeros((1, 2)))


def test_a_bar_is_one_member_and_a_bell_crank_two_arms_from_its_pivot():
    assert member_tree(stadium(SPAN, 0.03, 0.008, STRUCTURAL_STEEL, hole_diameter=0.01)) == ((0, 1),)
    # O4 -> B and O4 -> C, not the hypotenuse B -> C, which runs outside the material
    assert member_tree(bell_crank(), (0, 1)) == ((0, 1), (0, 2))
    assert member_tree(bell_crank(), (1, 0)) == ((1, 0), (0, 2))
    # three pins in a row: two members meeting at the middle one
    row = straight_bar(0.2, 0.03, 0.0, 0.006, STRUCTURAL_STEEL)
    in_line = LinkProfile(row.outline, np.array([[0.0, 0.0], [0.2, 0.0], [0.1, 0.0]]), 0.006, STRUCTURAL_STEEL)
    assert member_tree(in_line, (2, 1)) == ((2, 1), (2, 0))


def test_members_named_by_a_scene_must_join_every_joint_without_a_loop():
    crank = bell_crank()
    assert check_members(crank, [[0, 1], [1, 2]]) == ((0, 1), (1, 2))
    with pytest.raises(GeometryError, match="close a loop"):
        check_members(crank, [[0, 1], [1, 0]])
    with pytest.raises(GeometryError, match="do not join all 3 joints"):
        check_members(crank, [[0, 1]])
    with pytest.raises(GeometryError, match="two different joints among 0..2"):
        check_members(crank, [[0, 3], [0, 1]])


def test_a_straight_bars_sections_and_left_pieces_are_those_of_vertical_cuts():
    bar = stadium(SPAN, 0.03, 0.008, STRUCTURAL_STEEL, hole_diameter=0.01)
    member = frame_member(bar, (0, 1))
    assert member.extent == bar.x_extent(0, 1) and not member.curved
    x = member.stations(101)
    cuts, table = member.cuts(x), bar.sections(x)
    for name in ("area", "neutral_axis", "second_moment", "top", "bottom", "n_chords"):
        np.testing.assert_allclose(getattr(cuts.table, name), getattr(table, name), rtol=1e-12, atol=1e-15)
    left = region_moments(bar.boundary(0, 1), x)
    expected = np.array([left.area, left.first_x, left.first_y, left.polar])
    np.testing.assert_allclose(cuts.left_moments, expected, rtol=1e-12, atol=1e-15 * np.abs(expected).max())


def test_an_arm_of_a_bell_crank_is_cut_across_its_own_depth():
    crank = bell_crank()
    c_arm = link_members(crank, (0, 1))[1]
    assert c_arm.joints == (0, 2) and c_arm.extent[0] == 0.0 and c_arm.extent[1] > ARM
    cuts = c_arm.cuts(c_arm.stations(101))
    depth = cuts.table.top - cuts.table.bottom
    clear = ~cuts.nominal & (cuts.s < ARM)
    # between the junction and the pin every cut is the arm's 35 mm
    assert clear.sum() > 30
    np.testing.assert_allclose(depth[clear], WIDTH, rtol=1e-9)
    # the cuts closer to O4 than a depth run along the other arm: a junction, nominal only
    assert cuts.junction[cuts.s < WIDTH * 0.99].all() and not cuts.junction[cuts.s > WIDTH * 1.01].any()


@pytest.mark.parametrize("bend_deg", [90.0, 60.0])
def test_the_free_body_of_a_cut_across_an_arm_is_that_arm_beyond_it(bend_deg):
    # On a 60 deg bell crank the cut line across the C arm also crosses the B arm: the piece beyond the
    # section is found by splitting the outline along the section's segment, not by the half-plane.
    crank = bell_crank(bend_deg)
    c_arm = next(m for m in link_members(crank, (0, 1)) if m.joints == (0, 2))
    s = np.array([0.06, 0.1, 0.13])
    cuts = c_arm.cuts(s)
    outline = crank.local_outline(0, 1)
    for k in range(len(s)):
        a, b = cuts.ends[k]
        reach = 1e-9 * (b - a) / np.hypot(*(b - a))
        pieces = split(outline, LineString([a - reach, b + reach])).geoms
        beyond = next(p for p in pieces if p.contains(Point(crank.frame(0, 1).to_local(crank.joints[2]) + [0.0, PIN])))
        assert cuts.left_moments[0, k] == pytest.approx(outline.area - beyond.area, rel=1e-9)
    if bend_deg == 60.0:
        assert cuts.right_pieces  # these cuts needed the split
    assert cuts.on_left(crank.frame(0, 1).to_local(crank.joints)).tolist() == [[True, True, False]] * len(s)


def test_a_bell_crank_arm_carries_the_statics_of_the_pin_beyond_it():
    # A force P across the C arm at C, balanced by P across the B arm at B and the pivot O4 (load frame
    # O4 -> C, B at (0, ARM)): beyond a cut at s along either arm the free body holds that arm's pin
    # alone, so N = 0, V = P . n and M = -(r_pin - c) x P about the section's centroid c, exactly: a
    # cantilever's M = P (L - s); sigma = 6 M / (t w^2) of the 35 x 10 mm arm, the hand value at
    # the arm's root.
    crank = bell_crank()
    p = 1000.0
    loads = static_loads(3, {2: (0.0, -p), 1: (-p, 0.0), 0: (p, p)}, frame=(0, 2))
    s = np.array([0.05, 0.08, 0.12])
    for member in link_members(crank, (0, 2)):
        stress = section_stresses(crank, loads, s, member=member)
        pin = crank.frame(0, 2).to_local(crank.joints[member.joints[1]])
        force = loads.pin_forces[0, member.joints[1]]
        lever = pin - stress.cuts.cut_points
        np.testing.assert_allclose(stress.forces.normal[0], stress.cuts.tangent @ force, atol=1e-9 * p)
        np.testing.assert_allclose(stress.forces.shear[0], stress.cuts.normal @ force, atol=1e-9 * p)
        np.testing.assert_allclose(stress.forces.moment[0], -(lever[:, 0] * force[1] - lever[:, 1] * force[0]), rtol=1e-12)
        np.testing.assert_allclose(np.abs(stress.forces.moment[0]), p * (ARM - s), rtol=1e-9)
        np.testing.assert_allclose(stress.von_mises[0], p * (ARM - s) * 6 / (0.01 * WIDTH**2), rtol=1e-9)
        assert stress.forces.mismatch.max() < 1e-12


@pytest.mark.parametrize("hole", [None, 0.008, 0.02])
def test_straight_bars_with_and_without_pin_holes_are_not_curved(hole):
    member = frame_member(straight_bar(SPAN, 0.03, 0.02, 0.008, STRUCTURAL_STEEL, hole_diameter=hole), (0, 1))
    assert member.wander == pytest.approx(0.0, abs=1e-9) and not member.curved


def test_lightening_holes_and_a_taper_do_not_make_a_bar_curved():
    shell = [(-0.02, -0.015), (0.22, -0.015), (0.22, 0.015), (-0.02, 0.015)]
    holes = [circle((0.07, 0.004), 0.006), circle((0.13, -0.004), 0.006)]
    assert not frame_member(plate(shell, holes), (0, 1)).curved
    # a flat bottom and a sloping top: the midline tilts, along a straight line
    tapered = plate([(-0.02, -0.01), (0.22, -0.01), (0.22, 0.01), (-0.02, 0.03)])
    assert frame_member(tapered, (0, 1)).wander == pytest.approx(0.0, abs=1e-9)


def test_a_notch_across_the_axis_does_not_make_a_bar_curved():
    # 20 mm deep, a notch 4 mm wide and 12 mm deep from the top at mid-span: the cuts under it move
    # their midpoints 6 mm down, and the line through the joints runs 2 mm above the material there
    notched = plate([(-0.02, -0.01), (0.22, -0.01), (0.22, 0.01), (0.102, 0.01), (0.102, -0.002),
                     (0.098, -0.002), (0.098, 0.01), (-0.02, 0.01)])
    member = frame_member(notched, (0, 1))
    assert not member.curved and member.wander < 0.01


@pytest.mark.parametrize("width", [0.012, 0.03, 0.08])
def test_stadium_links_are_not_curved(width):
    assert not frame_member(stadium(SPAN, width, 0.008, STRUCTURAL_STEEL, hole_diameter=width / 3), (0, 1)).curved


@pytest.mark.parametrize("sag", [0.01, 0.025, 0.04, 0.06])
def test_arc_links_are_curved_and_follow_their_arc(sag):
    # 200 mm between pins, 24 mm wide: the axis found is the arc itself, its curvature 1/R
    link = banana(sag)
    member = frame_member(link, (0, 1))
    assert member.curved and member.wander > CURVED_WANDER
    radius = (SPAN**2 / 4 + sag**2) / (2 * sag)
    assert member.length == pytest.approx(2 * radius * math.asin(SPAN / 2 / radius), rel=1e-4)
    cuts = member.cuts(np.linspace(0.25, 0.75, 11) * member.length)
    np.testing.assert_allclose(cuts.curvature * radius, -1.0, atol=3e-3)
    np.testing.assert_allclose(cuts.table.top - cuts.table.bottom, 0.024, rtol=1e-4)
    centre = np.array([SPAN / 2, sag - radius])
    np.testing.assert_allclose(np.hypot(*(cuts.origin - centre).T), radius, rtol=1e-4)


def test_a_slight_bow_stays_straight():
    # 3 mm on 200 mm, 24 mm wide: the midline strays 0.07 depths
    assert not frame_member(banana(0.003), (0, 1)).curved


def ring_segment(inner: float, outer: float, degrees: float, lug: float, hole: float) -> LinkProfile:
    """A ring segment about the origin, symmetric about +y, with round lugs (radius ``lug``) and pin
    holes at the ends of its centre line; joints at the two pins."""
    half = math.radians(degrees) / 2
    t = np.linspace(math.pi / 2 - half, math.pi / 2 + half, 1201)
    ring = Polygon(np.vstack([np.column_stack([outer * np.cos(t), outer * np.sin(t)]),
                              np.column_stack([inner * np.cos(t), inner * np.sin(t)])[::-1]]))
    mean = (inner + outer) / 2
    pins = [(mean * math.cos(a), mean * math.sin(a)) for a in (math.pi / 2 - half, math.pi / 2 + half)]
    body = unary_union([ring, *(Point(p).buffer(lug, quad_segs=64) for p in pins)])
    for p in pins:
        body = body.difference(Point(p).buffer(hole / 2, quad_segs=64))
    return LinkProfile(body, np.array(pins), 0.01, STRUCTURAL_STEEL, name="ring")


def test_a_ring_segment_pulled_at_its_pins_takes_winkler_bachs_stress_at_its_crown():
    # ri = 40, ro = 60 mm (R / h = 2.5), 120 deg: pins pulled 1000 N apart along the chord. In the load
    # frame (joint 0 -> 1) the ring bulges to -y and its centre of curvature lies on the +v side of
    # the crown's cut (curvature +1/R). There the free body gives N = P and M = +P d, d the crown
    # centroid's distance from the chord (R - R cos 60 = 25 mm): an opening moment, the inner fibres
    # (toward the centre) in tension. Winkler-Bach for a rectangle: r_n = h / ln(ro / ri),
    # e = R - r_n, sigma(r) = N / A + M (r_n - r) / (A e r) for an opening M.
    ri, ro, p = 0.04, 0.06, 1000.0
    link = ring_segment(ri, ro, 120.0, 0.012, 0.006)
    member = frame_member(link, (0, 1))
    assert member.curved
    loads = static_loads(2, {0: (-p, 0.0), 1: (p, 0.0)})
    stress = section_stresses(link, loads, np.array([member.length / 2]), member=member)
    h, area, radius = ro - ri, (ro - ri) * 0.01, (ri + ro) / 2
    arm = radius - radius * math.cos(math.radians(60.0))
    assert stress.forces.normal[0, 0] == pytest.approx(p, rel=1e-4)
    assert stress.forces.moment[0, 0] == pytest.approx(p * arm, rel=1e-4)
    assert stress.curved is not None and stress.cuts.curvature[0] * radius == pytest.approx(1.0, abs=3e-3)
    r_n = h / math.log(ro / ri)
    e = radius - r_n
    closed = {r: p / area + p * arm * (r_n - r) / (area * e * r) for r in (ri, ro)}
    # the inner fibre is the largest, at the top of the cut (+v, toward the centre)
    assert stress.von_mises[0, 0] == pytest.approx(abs(closed[ri]), rel=1e-4)
    assert stress.fibre_y[0, 0] == pytest.approx(stress.sections.top[0], abs=1e-9)
    assert abs(closed[ri]) > abs(closed[ro]) and CURVED_BEAM_LIMIT < h / radius
    straight = p / area + p * arm * (h / 2) * 12 / (0.01 * h**3)
    assert abs(closed[ri]) > 1.1 * straight


def test_each_pin_hole_of_a_bell_crank_reports_the_depth_of_its_arm():
    # Through O4 a cut square to either arm runs along the other (185 mm): the depth there is the
    # arms' 35 mm; at B and C, the cut across the arm through the pin.
    from linkstress.dynamics.pin_holes import pin_hole_estimates
    from linkstress.dynamics.section_stress import member_depths

    crank = bell_crank()
    members = link_members(crank, (0, 1))
    loads = static_loads(3, {2: (0.0, -1000.0), 1: (1000.0, 0.0), 0: (-1000.0, 1000.0)})
    holes = pin_hole_estimates(crank, loads, member_depths(members))
    assert [h.joint for h in holes] == [0, 1, 2]
    assert [h.depth for h in holes] == pytest.approx([WIDTH] * 3, rel=1e-6)


def u_link(gap: float) -> LinkProfile:
    """Two 100 mm legs 20 mm wide with ``gap`` [m] between them, joined by a half circle, 6 mm pin
    holes at the legs' feet."""
    spread = gap + 0.02
    legs = [LineString([(0, 0), (0, 0.1)]), LineString([(spread, 0), (spread, 0.1)])]
    t = np.linspace(math.pi, 0.0, 181)
    bend = LineString(np.column_stack([spread / 2 + spread / 2 * np.cos(t), 0.1 + spread / 2 * np.sin(t)]))
    body = unary_union([g.buffer(0.01, quad_segs=32) for g in (*legs, bend)])
    body = body.difference(Point(0, 0).buffer(0.003)).difference(Point(spread, 0).buffer(0.003))
    return LinkProfile(body, np.array([[0.0, 0.0], [spread, 0.0]]), 0.005, STRUCTURAL_STEEL, name="u")


def test_a_bend_tighter_than_its_depth_is_nominal_there():
    # A U with a 2 mm gap: its bend's centreline radius is 11 mm, 0.55 of its 20 mm depth, and its
    # inner edge 1 mm from the centre (the cuts there reach 91 % of the way to it, where Winkler-Bach's
    # section would pass through the centre). A radius under a section depth is sharper than the
    # curved-beam range: the stations within a depth of the bend are nominal (flagged ``bend``), the
    # legs' are not, and nothing fails.
    link = u_link(0.002)
    member = frame_member(link, (0, 1))
    assert member.curved and member.length == pytest.approx(0.2 + math.pi * 0.011, rel=2e-3)
    stations = member.stations(101)
    cuts = member.cuts(stations)
    bend = (stations > 0.1) & (stations < 0.1 + math.pi * 0.011)
    assert cuts.bend[bend].all() and cuts.nominal[bend].all() and cuts.nominal[cuts.tight].all()
    legs = (stations > 0.03) & (stations < 0.07) | (stations > 0.165) & (stations < 0.2)
    assert not cuts.nominal[legs].any()
    stress = section_stresses(link, static_loads(2, {0: (-100.0, 0.0), 1: (100.0, 0.0)}), stations, member=member)
    assert np.isfinite(stress.von_mises).all()
    assert stress.curved is None or not np.isin(np.flatnonzero(cuts.tight), stress.curved.at).any()


def test_a_u_shaped_link_is_traced_round_its_bend():
    # Two 100 mm legs 60 mm apart joined by a half circle, 20 mm wide, pins at the legs' feet: the
    # line between the pins runs outside the material, the centreline up one leg, round the bend and
    # down the other (2 x 100 + pi x 30 = 294 mm).
    link = u_link(0.04)
    member = frame_member(link, (0, 1))
    assert member.curved and member.length == pytest.approx(0.2 + math.pi * 0.03, rel=5e-3)
    cuts = member.cuts(member.stations(101))
    clear = ~cuts.nominal
    np.testing.assert_allclose((cuts.table.top - cuts.table.bottom)[clear], 0.02, rtol=5e-3)


def test_two_joints_at_one_point_are_refused_naming_them():
    bar = stadium(SPAN, 0.03, 0.008, STRUCTURAL_STEEL, hole_diameter=0.01)
    doubled = LinkProfile(bar.outline, np.array([[0.0, 0.0], [SPAN, 0.0], [SPAN, 0.0]]), 0.008, STRUCTURAL_STEEL, name="bar")
    with pytest.raises(GeometryError, match=r"link 'bar': joints 1 and 2 are at the same point \(0.2, 0\) m"):
        link_members(doubled, (0, 1))


def test_the_centreline_median_is_numpys_median_for_odd_and_even_counts():
    from linkstress.geometry.centreline import median

    rng = np.random.default_rng(7)
    for count in range(1, 30):
        values = rng.normal(size=count)
        assert median(values) == float(np.median(values))
    assert median(np.array([3.0, 1.0, 2.0, 10.0])) == 2.5
