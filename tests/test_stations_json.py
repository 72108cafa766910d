"""``analyze --stations``: where each station is, named as what it is. ``x_m`` and ``s_m`` are the arc
length from the member's joint i along its axis, ``at_member_m`` the axis point and ``normal_member``
the cut's normal in the link's member frame (docs/design.md, "JSON fields").

On the shipped banana coupler (a circular arc of R = 121.25 mm through pins 180 mm apart, 30 mm wide:
validation/cases/banana_coupler/make_sketch.py) the axis is that arc, so the stations' points lie on
it and the arc length between them is R times the angle they subtend; on its straight crank they are
(x, 0).
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import shapely

from linkstress.cli import main
from linkstress.scene import load_scene

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
RADIUS, CENTRE = 0.12125, (0.09, 0.04 - 0.12125)
"""The banana coupler's centre line, member frame A -> B [m]."""


@pytest.fixture(scope="module")
def banana(tmp_path_factory) -> tuple[dict, object]:
    """The first position's link records of ``analyze --stations`` on the banana coupler, and the scene."""
    folder = tmp_path_factory.mktemp("banana")
    for name in ("banana_coupler.dxf", "scene.toml"):
        shutil.copy(CASES / "banana_coupler" / name, folder)
    out = folder / "out.json"
    assert main(["analyze", str(folder / "scene.toml"), "--json", str(out), "--stations"]) == 0
    positions = json.loads(out.read_text(), parse_constant=pytest.fail)["positions"]
    return positions[0]["links"], load_scene(folder / "scene.toml")


def test_a_curved_members_stations_are_arc_lengths_along_its_axis_and_points_on_it(banana):
    links, scene = banana
    stations = links["coupler"]["stations"]
    s, at, normal = (np.array(stations[k]) for k in ("s_m", "at_member_m", "normal_member"))
    assert stations["x_m"] == stations["s_m"]
    # the points between the lugs lie on the drawn arc, their normals along its radius
    between = (s > 0.03) & (s < s[-1] - 0.03)
    radial = at - CENTRE
    np.testing.assert_allclose(np.hypot(*radial[between].T), RADIUS, rtol=1e-3)
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->i", normal, radial) / np.hypot(*radial.T))[between], 1.0, rtol=1e-6)
    # the arc length between two of them is R times the angle they subtend (not their x difference)
    angle = np.unwrap(np.arctan2(radial[:, 1], radial[:, 0]))
    k = np.flatnonzero(between)[[0, -1]]
    assert s[k[1]] - s[k[0]] == pytest.approx(RADIUS * abs(angle[k[1]] - angle[k[0]]), rel=1e-3)
    assert s[k[1]] - s[k[0]] > 1.01 * abs(at[k[1], 0] - at[k[0], 0])
    # every station's point is in the coupler's material (holes filled), none past its outline
    profile = scene.links["coupler"].profile
    shell = shapely.Polygon(profile.local_outline(*scene.links["coupler"].frame_joints).exterior)
    assert shapely.contains_xy(shell, *at.T).all()
    # the critical fibre lies on the station's cut, inside the material
    fibre = at + np.array(stations["fibre_y_m"])[:, None] * normal
    assert shapely.covers(shell.buffer(1e-9), shapely.points(fibre)).all()


def test_a_straight_members_stations_are_its_member_frames_x(banana):
    links, _ = banana
    stations = links["crank"]["stations"]
    at = np.array(stations["at_member_m"])
    np.testing.assert_allclose(at[:, 0], stations["x_m"], atol=1e-12)
    np.testing.assert_allclose(at[:, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(stations["normal_member"], [[0.0, 1.0]] * len(at), atol=1e-12)
    assert math.isclose(stations["s_m"][0], stations["x_m"][0])
