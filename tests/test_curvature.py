"""Is a link curved? The neutral axis's spread about a straight line, in section depths (> 0.1)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon

from linkstress.builders import stadium, straight_bar
from linkstress.curvature import CURVED, is_curved, link_curvature, neutral_axis_wander
from linkstress.dynamics.section_stress import default_stations, near_holes
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.profile import LinkProfile
from linkstress.scene import load_scene

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
SPAN = 0.2
"""Joint spacing [m] of the generated links: joints at (0, 0) and (SPAN, 0)."""


def circle(centre: tuple[float, float], radius: float) -> np.ndarray:
    t = np.linspace(0.0, 2 * np.pi, 256, endpoint=False)[::-1]
    return np.column_stack([centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)])


def plate(shell, holes=()) -> LinkProfile:
    """A 8 mm steel plate with pin holes of 8 mm at both joints and ``holes`` besides."""
    pins = [circle((0.0, 0.0), 0.004), circle((SPAN, 0.0), 0.004)]
    return LinkProfile(Polygon(shell, pins + list(holes)), np.array([[0.0, 0.0], [SPAN, 0.0]]), 0.008, STRUCTURAL_STEEL)


def banana(sag: float, width: float = 0.024) -> LinkProfile:
    """A banana like validation/cases/drawing.py's: centre line a circular arc through both joints
    bulging ``sag`` [m], edges ``width`` [m] apart, round ends, 8 mm pin holes."""
    radius = (SPAN**2 / 4 + sag**2) / (2 * sag)
    cx, cy = SPAN / 2, sag - radius
    t = np.linspace(math.atan2(-cy, SPAN - cx), math.atan2(-cy, -cx), 400)
    body = LineString(np.column_stack([cx + radius * np.cos(t), cy + radius * np.sin(t)])).buffer(width / 2, quad_segs=64)
    for joint in ((0.0, 0.0), (SPAN, 0.0)):
        body = body.difference(Point(joint).buffer(0.004, quad_segs=64))
    return LinkProfile(body, np.array([[0.0, 0.0], [SPAN, 0.0]]), 0.008, STRUCTURAL_STEEL)


def depths(link: LinkProfile) -> float:
    curvature = link_curvature(link, (0, 1))
    assert curvature is not None
    return curvature.depths


@pytest.mark.parametrize("hole", [None, 0.008, 0.02])
def test_straight_bars_with_and_without_pin_holes_are_not_curved(hole):
    curvature = link_curvature(straight_bar(SPAN, 0.03, 0.02, 0.008, STRUCTURAL_STEEL, hole_diameter=hole), (0, 1))
    assert curvature.wander == pytest.approx(0.0, abs=1e-12)
    assert curvature.depth == pytest.approx(0.03, rel=1e-9)
    assert not curvature.curved


def test_lightening_holes_off_the_axis_do_not_make_a_bar_curved():
    # Two 12 mm holes 4 mm above and below the axis, and a 100 x 13 mm slot 1.5 mm off it: each moves
    # the centroid of the cuts through it, which are split (two chords) or within a depth of a hole.
    shell = [(-0.02, -0.015), (0.22, -0.015), (0.22, 0.015), (-0.02, 0.015)]
    holes = [circle((0.07, 0.004), 0.006), circle((0.13, -0.004), 0.006)]
    slot = np.array([(0.05, -0.005), (0.05, 0.008), (0.15, 0.008), (0.15, -0.005)])[::-1]
    assert depths(plate(shell, holes)) == pytest.approx(0.0, abs=1e-12)
    assert depths(plate(shell, [slot])) == pytest.approx(0.0, abs=1e-12)


def test_a_taper_along_one_straight_edge_tilts_the_neutral_axis_but_is_not_curved():
    # Flat bottom at y = -10 mm, top from +30 mm down to +10 mm over 240 mm: the neutral axis (the
    # mid-depth of a solid cut) falls 20 mm x 0.14 / 0.24 / 2 = 5.83 mm between x = 30 and 170 mm,
    # a quarter of the depths there, but along a straight line.
    tapered = plate([(-0.02, -0.01), (0.22, -0.01), (0.22, 0.01), (-0.02, 0.03)])
    table = tapered.sections(np.linspace(0.03, 0.17, 15))
    assert np.ptp(table.neutral_axis) == pytest.approx(0.02 * 0.14 / 0.24 / 2, rel=1e-9)
    assert depths(tapered) == pytest.approx(0.0, abs=1e-12)
    symmetric = plate([(-0.02, -0.02), (0.22, -0.01), (0.22, 0.01), (-0.02, 0.02)])
    assert depths(symmetric) == pytest.approx(0.0, abs=1e-12)


def test_the_tip_of_a_lug_beyond_its_pin_does_not_make_a_bar_curved():
    # The right end is cut on a slant from (230, -15) to (260, +15) mm: beyond the pin at 200 mm the
    # cuts shrink to nothing while their centroid climbs to the top edge. validate judges a link on
    # cuts over its whole extent, as here; the engine on cuts between the joints.
    slanted = plate([(-0.02, -0.015), (0.23, -0.015), (0.26, 0.015), (-0.02, 0.015)])
    table = slanted.sections(default_stations(slanted, (0, 1), 101))
    near = near_holes(slanted, (0, 1), table)
    tip = (table.x > 0.23) & ~near
    assert np.ptp(table.neutral_axis[tip]) > 0.005 and (table.top - table.bottom)[tip].min() < 0.002
    assert neutral_axis_wander(table, near)[0] == pytest.approx(0.0, abs=1e-12)
    assert not is_curved(table, near)


@pytest.mark.parametrize("width", [0.012, 0.03, 0.08])
def test_stadium_links_are_not_curved(width):
    assert not link_curvature(stadium(SPAN, width, 0.008, STRUCTURAL_STEEL, hole_diameter=width / 3), (0, 1)).curved


@pytest.mark.parametrize("sag, expected", [(0.005, 0.119), (0.010, 0.237), (0.025, 0.551), (0.040, 0.797), (0.060, 0.985)])
def test_arc_links_are_curved_and_the_more_so_the_deeper_the_arc(sag, expected):
    # 200 mm between pins, 24 mm wide; the values are the measured spread over the cuts a depth
    # from each pin (the shipped curved rod bulges 25 mm).
    measured = depths(banana(sag))
    assert measured == pytest.approx(expected, abs=2e-3)
    assert measured > CURVED


def test_a_slight_bow_stays_below_the_threshold():
    # 3 mm on 200 mm, 24 mm wide: the cut-to-cut tilt of the bar is under 4 deg.
    assert depths(banana(0.003)) == pytest.approx(0.0715, abs=2e-3)
    assert not link_curvature(banana(0.003), (0, 1)).curved


def test_a_link_that_is_all_near_hole_region_is_undecided():
    # 40 mm between 30 mm pin holes in a 50 mm deep bar: every cut is within a depth of a pin.
    link = straight_bar(0.04, 0.05, 0.03, 0.008, STRUCTURAL_STEEL, hole_diameter=0.03)
    assert link_curvature(link, (0, 1)) is None


@pytest.mark.parametrize("case, curved", [
    ("banana_coupler", {"crank": False, "coupler": True, "output": False}),
    ("slider_crank_curved_rod", {"crank": False, "rod": True}),
    ("six_bar", {"crank": False, "coupler": False, "rocker": False, "rod2": False, "out2": False}),
])
def test_the_shipped_cases_curved_links_are_found(case, curved):
    scene = load_scene(CASES / case / "scene.toml")
    frames = {"rocker": (1, 2)}  # the six-bar's ternary rocker, as analyze takes it: pivot 1 -> B (2)
    found = {name: link_curvature(scene.links[name].profile, frames.get(name, (0, 1))).curved for name in curved}
    assert found == curved


def test_validate_judges_the_shipped_banana_on_its_cuts_as_the_engine_does():
    # validate's cuts (101 over the extent) and the engine's (201 between the joints) see the same
    # bar: 0.43 and 0.46 section depths.
    scene = load_scene(CASES / "banana_coupler" / "scene.toml")
    coupler = scene.links["coupler"].profile
    table = coupler.sections(default_stations(coupler, (0, 1), 101))
    wander, depth = neutral_axis_wander(table, near_holes(coupler, (0, 1), table))
    assert wander / depth == pytest.approx(0.433, abs=2e-3)
    assert link_curvature(coupler, (0, 1)).depths == pytest.approx(0.458, abs=2e-3)


def test_validate_uses_the_engines_criterion():
    from linkstress.validation import report

    assert report.is_curved is is_curved
    assert report.neutral_axis_wander is neutral_axis_wander
