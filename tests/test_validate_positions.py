"""validate's compared positions: evenly spread over the feasible ones, each pose once.

A sweep ``{start, stop, num}`` includes both ends, so 0..360 deg with num 37 ends on the pose it
starts from (a crank-rocker closes in one turn): validate compares that pose once.
"""

from __future__ import annotations

import textwrap

import numpy as np

from linkstress.analysis import run_analysis
from linkstress.scene import load_scene
from linkstress.validation.validate_scene import compared_positions, distinct_poses

# A Grashof crank-rocker (crank 20 mm shortest, 20 + 70 <= 50 + 60 mm): every crank angle is
# feasible and one turn of the crank brings every link back where it was.
CRANK_ROCKER = """
[links.crank]
joints = [[0.0, 0.0], [0.02, 0.0]]
[links.coupler]
joints = [[0.0, 0.0], [0.07, 0.0]]
[links.output]
joints = [[0.0, 0.0], [0.05, 0.0]]
[links.ground]
joints = [[0.0, 0.0], [0.06, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = {angles}
"""


def analysed(tmp_path, angles: str, speed: str = "input_speed_rad_s = 10.0"):
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(CRANK_ROCKER).replace("{angles}", angles) + speed + "\n")
    return run_analysis(load_scene(path))


def test_a_sweep_over_0_to_360_deg_compares_36_distinct_poses_when_asked_36(tmp_path):
    # 37 angles, 0, 10, ..., 360 deg: 360 deg is the pose at 0 deg, so 36 distinct poses, every one
    # compared (spreading 36 over all 37 would take 0 and 360, one pose twice, and skip 180 deg).
    analysis = analysed(tmp_path, "{start = 0.0, stop = 360.0, num = 37}")
    chosen = compared_positions(analysis, 36)
    np.testing.assert_array_equal(chosen, np.arange(36))
    angles = analysis.scene.motion.angle_deg[chosen] % 360
    assert len(np.unique(angles)) == 36


def test_a_sweep_over_0_to_350_deg_is_unchanged(tmp_path):
    # 36 angles, 0, 10, ..., 350 deg, all distinct: all 36 asked, or 12 at linspace(0, 35, 12) rounded.
    analysis = analysed(tmp_path, "{start = 0.0, stop = 350.0, num = 36}")
    np.testing.assert_array_equal(compared_positions(analysis, 36), np.arange(36))
    np.testing.assert_array_equal(compared_positions(analysis, 12), [0, 3, 6, 10, 13, 16, 19, 22, 25, 29, 32, 35])


def test_the_closing_position_of_a_full_turn_is_left_out_before_spreading(tmp_path):
    # With the repeat at 360 deg dropped, 12 of the 0..360 sweep are the 12 of the 0..350 one.
    closed = analysed(tmp_path, "{start = 0.0, stop = 360.0, num = 37}")
    np.testing.assert_array_equal(compared_positions(closed, 12), [0, 3, 6, 10, 13, 16, 19, 22, 25, 29, 32, 35])


def test_two_turns_give_the_poses_of_the_first_turn_only(tmp_path):
    # 0, 10, ..., 720 deg: 73 angles, 36 poses (those of 0..350 deg); each later one repeats one of them.
    analysis = analysed(tmp_path, "{start = 0.0, stop = 720.0, num = 73}")
    np.testing.assert_array_equal(distinct_poses(analysis), np.arange(36))


def test_the_same_angle_at_the_opposite_speed_is_a_different_load_case(tmp_path):
    # theta = 90 sin(2 pi t) deg at t = 0, 0.25, 0.5, 0.75, 1 s: 0, 90, 0, -90, 0 deg. At t = 0.5 s
    # the crank passes 0 deg turning back (speed -pi^2 rad/s, +pi^2 at t = 0): kept. At t = 1 s
    # angle, speed and acceleration are those of t = 0: the pose repeats, left out.
    analysis = analysed(tmp_path, '{expression = "90*sin(2*pi*t)", t = {start = 0.0, stop = 1.0, num = 5}}', speed="")
    np.testing.assert_allclose(analysis.scene.motion.speed[[0, 2, 4]], [np.pi**2, -np.pi**2, np.pi**2])
    np.testing.assert_array_equal(distinct_poses(analysis), [0, 1, 2, 3])
