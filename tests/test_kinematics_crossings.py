"""A sweep never steps over a toggle or change point silently.

The closed form keeps one root; at a change point the two assembly modes meet, so a sweep that
samples either side of it continues in the other mode. The step is flagged on the row after it.
"""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

from linkstress.cli import main
from linkstress.kinematics import (
    Drive,
    FourBar,
    Loop,
    Machine,
    Role,
    SliderCrank,
    angle_motion,
    solve_fourbar,
    solve_machine,
    solve_slider_crank,
)
from linkstress.kinematics.crossings import wrapped_steps
from linkstress.scene import load_scene

REPO = Path(__file__).resolve().parents[1]


def four_bar_machine(crank: float, coupler: float, output: float, ground: float, branch: str = "open") -> Machine:
    links = {
        "ground": [[0.0, 0.0], [ground, 0.0]],
        "crank": [[0.0, 0.0], [crank, 0.0]],
        "coupler": [[0.0, 0.0], [coupler, 0.0]],
        "output": [[0.0, 0.0], [output, 0.0]],
    }
    loop = Loop("main", "four-bar", Role("crank"), Role("coupler"), Role("ground"), output=Role("output"), branch=branch)
    return Machine(links, (loop,))


def flagged(result) -> dict[float, tuple[str, ...]]:
    """Input angle [deg] -> warnings, for the rows that have any."""
    angles = np.degrees(result.input_angle)
    return {round(float(angles[k]), 9): w for k, w in enumerate(result.warnings) if w}


# A parallelogram: crank = output = 0.05 m, coupler = ground = 0.1 m. Change points at 0 and 180 deg.
PARALLELOGRAM = (0.05, 0.1, 0.05, 0.1)


def test_a_parallelogram_swept_over_its_change_point_is_flagged_on_the_row_after_it():
    result = solve_machine(four_bar_machine(*PARALLELOGRAM), angle_motion(np.arange(170.5, 191.0, 1.0), 1.0))
    ratio = result.loops["main"].omega4  # omega2 = 1 rad/s
    # The user's report: every row feasible, omega4 / omega2 = +1 up to 179.5 deg, then the
    # antiparallelogram's -0.333 (= -(d - a) / (d + a) at the aligned position) from 180.5 deg.
    assert result.feasible.all()
    assert ratio[:10] == pytest.approx(1.0, abs=1e-9)
    assert ratio[10] == pytest.approx(-1 / 3, abs=1e-4)
    assert set(flagged(result)) == {180.5}
    (message,) = flagged(result)[180.5]
    assert message.startswith("mechanism main: change point at input 180 deg crossed between input 179.5 and 180.5 deg")
    assert "(parallelogram or antiparallelogram)" in message
    assert "rows from here follow the open root (B left of A -> O4), which is the antiparallelogram mode" in message
    (crossing,) = result.loops["main"].crossings
    assert (crossing.position, crossing.kind, crossing.angle) == (10, "change point", pytest.approx(math.pi))
    # What the message advises: the crossed root past the change point is the parallelogram again.
    assert message.endswith('analyze the rows from here with mechanisms.main.branch = "crossed"')
    past = solve_machine(four_bar_machine(*PARALLELOGRAM, branch="crossed"), angle_motion(np.arange(180.5, 191.0, 1.0), 1.0))
    assert past.loops["main"].omega4 == pytest.approx(1.0, abs=1e-9) and not past.crossings


def test_a_parallelogram_swept_backwards_over_its_change_point_lands_in_the_parallelogram_mode():
    result = solve_machine(four_bar_machine(*PARALLELOGRAM), angle_motion(np.arange(190.5, 170.0, -1.0), 1.0))
    assert set(flagged(result)) == {179.5}
    (message,) = flagged(result)[179.5]
    assert "crossed between input 180.5 and 179.5 deg" in message
    assert "which is the parallelogram mode" in message
    assert result.loops["main"].omega4[11] == pytest.approx(1.0, abs=1e-9)  # 179.5 deg


def test_the_seeds_change_point_four_bar_swept_over_180_deg_is_flagged_with_the_other_mode():
    # The seed four-bar (crank 1, coupler 1.5, output 1.5, ground 2 m: 1 + 2 = 1.5 + 1.5, Barker
    # III-2) has unnamed modes. omega4 / omega2 jumps 0.805 -> -0.138 over the step; the crossed
    # root past it continues the smooth 0.805, as the message says.
    machine = four_bar_machine(1.0, 1.5, 1.5, 2.0)
    result = solve_machine(machine, angle_motion([178.5, 179.5, 180.5, 181.5], 1.0))
    omega4 = result.loops["main"].omega4
    assert omega4[1] == pytest.approx(0.8047, abs=1e-4) and omega4[2] == pytest.approx(-0.1381, abs=1e-4)
    assert set(flagged(result)) == {180.5}
    (message,) = flagged(result)[180.5]
    assert "either assembly mode; rows from here follow the open root" in message
    assert "which is the other assembly mode than the rows before" in message
    smooth = solve_machine(four_bar_machine(1.0, 1.5, 1.5, 2.0, "crossed"), angle_motion([180.5], 1.0))
    assert smooth.loops["main"].omega4[0] == pytest.approx(omega4[1], abs=1e-3)


@pytest.mark.parametrize(
    "lengths, modes, mode_after",
    [
        ((0.05, 0.1, 0.1, 0.05), "kite (convex) or dart (concave)", "kite (convex)"),  # crank = ground
        ((0.05, 0.05, 0.1, 0.1), "kite or folded (B held at O2, output still)", "kite"),  # crank = coupler
    ],
)
def test_a_kite_swept_over_0_deg_is_flagged_between_minus_and_plus_half_a_degree(lengths, modes, mode_after):
    result = solve_machine(four_bar_machine(*lengths), angle_motion(np.arange(-10.5, 11.0, 1.0), 1.0))
    assert result.feasible.all()
    assert set(flagged(result)) == {0.5}
    (message,) = flagged(result)[0.5]
    assert message.startswith("mechanism main: change point at input 0 deg crossed between input -0.5 and 0.5 deg")
    assert f"({modes})" in message and f"which is the {mode_after} mode" in message


def test_the_kite_modes_are_named_by_their_geometry():
    # a = d, b = c: at 0.5 deg the open root's B is on the far side of A -> O4 from O2 (convex).
    kite = solve_fourbar(FourBar((0.0, 0.0), (0.05, 0.0), 0.05, 0.1, 0.1), np.radians([-0.5, 0.5]))
    a, b = kite.joints["A"].position[1], kite.joints["B"].position[1]
    to_o4 = np.array([0.05, 0.0]) - a
    side_o2 = to_o4[0] * -a[1] - to_o4[1] * -a[0]
    side_b = to_o4[0] * (b - a)[1] - to_o4[1] * (b - a)[0]
    assert side_o2 * side_b < 0 and kite.crossings[0].mode == "kite (convex)"
    # a = b, c = d: at 180.5 deg the open root is B = O2, the output still.
    folded = solve_fourbar(FourBar((0.0, 0.0), (0.1, 0.0), 0.05, 0.05, 0.1), np.radians([179.5, 180.5]))
    assert folded.joints["B"].position[1] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert folded.crossings[0].mode.startswith("folded")


def test_sweeps_that_approach_a_change_point_or_turn_a_crank_rocker_fully_are_not_flagged():
    parallelogram = four_bar_machine(*PARALLELOGRAM)
    for angles in (np.arange(170.5, 180.0, 1.0), np.arange(0.5, 180.0, 1.0), np.arange(180.5, 360.0, 1.0)):
        result = solve_machine(parallelogram, angle_motion(angles, 1.0))
        assert result.feasible.all() and not result.crossings
    # Crank-rocker (S + L = 0.02 + 0.09 < P + Q = 0.15), two full turns at 1 deg, samples half a
    # degree off the ground line: no branch point anywhere.
    crank_rocker = solve_machine(four_bar_machine(0.02, 0.08, 0.07, 0.09), angle_motion(np.arange(0.5, 721.0), 1.0))
    assert crank_rocker.feasible.all() and not crank_rocker.crossings
    assert crank_rocker.warnings == ((),) * 721


@pytest.mark.parametrize("at", [180.0, 180.0 - 1e-7, 180.0 + 1e-7])
def test_a_sample_exactly_at_the_change_point_is_infeasible_with_its_reason_and_not_also_flagged(at):
    # 1e-7 deg off, 1 + cos(mu) ~ 1e-18 is far below CHANGE_POINT_REACH: the sample is at the point.
    result = solve_machine(four_bar_machine(*PARALLELOGRAM), angle_motion([179.5, at, 180.5], 1.0))
    assert result.feasible.tolist() == [True, False, True]
    assert result.reasons[1].startswith("change point: all four links aligned")
    assert result.warnings == ((), (), ()) and not result.loops["main"].crossings


def test_a_non_grashof_sweep_that_jumps_its_infeasible_gap_is_flagged_at_both_toggles():
    # Triple rocker a = 0.1, b = 0.04, c = 0.05, d = 0.06 (S + L = 0.14 > P + Q = 0.11). Toggles
    # where |A O4| = b + c: cos(phi) = (a^2 + d^2 - (b + c)^2) / (2 a d) = 0.0055 / 0.012, phi = 62.72 deg.
    result = solve_machine(four_bar_machine(0.1, 0.04, 0.05, 0.06), angle_motion([40.0, 60.0, 300.0, 320.0], 1.0))
    assert result.feasible.all()
    assert set(flagged(result)) == {300.0}
    first, second = flagged(result)[300.0]
    phi = math.degrees(math.acos(0.0055 / 0.012))
    assert first.startswith(f"mechanism main: toggle at input {phi:.6g} deg crossed between input 60 and 300 deg")
    assert second.startswith(f"mechanism main: toggle at input {360 - phi:.6g} deg crossed")
    assert "the crank cannot turn this way from the row before to this one" in first


def test_a_centred_slider_crank_with_crank_equal_to_rod_is_flagged_at_its_change_point():
    # a = b, e = 0: sin(psi) = -sin(phi) touches -1 at phi = 90 deg, where B reaches O2.
    links = {
        "ground": [[0.0, 0.0], [1.0, 0.0]],
        "crank": [[0.0, 0.0], [0.05, 0.0]],
        "rod": [[0.0, 0.0], [0.05, 0.0]],
        "piston": [[0.0, 0.0]],
    }
    loop = Loop("engine", "slider-crank", Role("crank"), Role("rod"), Role("ground"), slider=Role("piston", (0, 0)))
    result = solve_machine(Machine(links, (loop,)), angle_motion(np.arange(80.5, 100.0, 1.0), 1.0))
    assert result.feasible.all()
    assert set(flagged(result)) == {90.5}
    (message,) = flagged(result)[90.5]
    assert message.startswith("mechanism engine: change point at input 90 deg crossed between input 89.5 and 90.5 deg")
    assert "the open root (slider ahead of the crank pin along the line)" in message
    # The standalone solver carries the same crossing, and an offset slider-crank has none.
    alone = solve_slider_crank(SliderCrank((0.0, 0.0), 0.05, 0.05), np.radians(np.arange(80.5, 100.0, 1.0)))
    assert [c.position for c in alone.crossings] == [10]
    offset = solve_slider_crank(SliderCrank((0.0, 0.0), 0.05, 0.2, 0.01), np.radians(np.arange(0.0, 360.0)))
    assert offset.feasible.all() and not offset.crossings


def chained_machine(phase_deg: float) -> Machine:
    """A crank-rocker main loop whose crank turns, through a coupling with ``phase_deg``, the crank
    of a parallelogram (crank = output = 0.03 m, coupler = ground = 0.08 m)."""
    links = {
        "ground": [[0.0, 0.0], [0.09, 0.0], [0.3, 0.0], [0.38, 0.0]],
        "crank": [[0.0, 0.0], [0.02, 0.0]],
        "coupler": [[0.0, 0.0], [0.08, 0.0]],
        "rocker": [[0.0, 0.0], [0.07, 0.0]],
        "crank2": [[0.0, 0.0], [0.03, 0.0]],
        "link2": [[0.0, 0.0], [0.08, 0.0]],
        "out2": [[0.0, 0.0], [0.03, 0.0]],
    }
    loops = (
        Loop("main", "four-bar", Role("crank"), Role("coupler"), Role("ground", (0, 1)), output=Role("rocker")),
        Loop("second", "four-bar", Role("crank2"), Role("link2"), Role("ground", (2, 3)), output=Role("out2"),
             driven_by=Drive("main", "crank", math.radians(phase_deg))),
    )
    return Machine(links, loops)


def test_a_driven_loop_crossing_its_change_point_flags_the_row_and_names_the_loop():
    # The second loop's crank is the input + 90 deg: it reaches its change point (180 deg) at input 90.
    result = solve_machine(chained_machine(90.0), angle_motion(np.arange(80.5, 100.0, 1.0), 1.0))
    assert result.feasible.all()
    assert set(flagged(result)) == {90.5}
    (message,) = flagged(result)[90.5]
    assert message.startswith("mechanism second: change point (its crank at 180 deg) crossed between input 89.5 and 90.5 deg")
    assert "antiparallelogram mode" in message
    assert not result.loops["main"].crossings and len(result.loops["second"].crossings) == 1


def test_a_driven_loop_is_not_flagged_where_its_driver_does_not_assemble():
    # Main a triple rocker (feasible |phi| <= 62.72 deg) coupled to the parallelogram with phase
    # 180 deg: the step 60 -> 300 jumps the main loop's gap (flagged for it) and turns the second
    # crank from 240 to 480 deg, over its change point at 360, which is flagged too. The step
    # 60 -> 190 turns the second crank over 360 deg as well, but the main loop does not assemble
    # at 190 deg, so no row there is a position of the machine: nothing is flagged.
    machine = chained_machine(180.0)
    links = dict(machine.links)
    links.update({"crank": [[0.0, 0.0], [0.1, 0.0]], "coupler": [[0.0, 0.0], [0.04, 0.0]],
                  "rocker": [[0.0, 0.0], [0.05, 0.0]], "ground": [[0.0, 0.0], [0.06, 0.0], [0.3, 0.0], [0.38, 0.0]]})
    machine = Machine(links, machine.loops)
    jump = solve_machine(machine, angle_motion([60.0, 300.0], 1.0))
    assert [m.split(":")[0] for m in jump.warnings[1]] == ["mechanism main", "mechanism main", "mechanism second"]
    gap = solve_machine(machine, angle_motion([60.0, 190.0], 1.0))
    assert gap.feasible.tolist() == [True, False] and gap.loops["second"].feasible.all()
    assert not gap.crossings and not gap.loops["second"].crossings


def test_a_loop_driven_by_a_rocker_swinging_through_180_deg_is_flagged_where_its_crank_passes_it():
    # Main crank-rocker (crank 0.02, coupler 0.14, rocker 0.07, ground 0.1 m at 110 deg): its rocker
    # swings between about 150 and 202 deg, so its angle (atan2) wraps from -180 to 180 deg. The
    # parallelogram it drives (phase 0) has a change point at crank 180 deg: crossed once per swing.
    links = {
        "ground": [[0.0, 0.0], [0.1 * math.cos(math.radians(110)), 0.1 * math.sin(math.radians(110))],
                   [0.3, 0.0], [0.38, 0.0]],
        "crank": [[0.0, 0.0], [0.02, 0.0]],
        "coupler": [[0.0, 0.0], [0.14, 0.0]],
        "rocker": [[0.0, 0.0], [0.07, 0.0]],
        "crank2": [[0.0, 0.0], [0.03, 0.0]],
        "link2": [[0.0, 0.0], [0.08, 0.0]],
        "out2": [[0.0, 0.0], [0.03, 0.0]],
    }
    loops = (
        Loop("main", "four-bar", Role("crank"), Role("coupler"), Role("ground", (0, 1)), output=Role("rocker")),
        Loop("second", "four-bar", Role("crank2"), Role("link2"), Role("ground", (2, 3)), output=Role("out2"),
             driven_by=Drive("main", "output")),
    )
    result = solve_machine(Machine(links, loops), angle_motion(np.arange(0.0, 360.0, 5.0), 1.0))
    # Where the rocker passes 180 deg, independently: its unwrapped angle changes turn about 180 deg.
    swing = np.unwrap(result.loops["main"].theta4)
    passes = np.flatnonzero(np.diff(np.floor((swing - math.pi) / (2 * math.pi)))) + 1
    assert passes.tolist() == [11, 45]
    assert [c.position for c in result.loops["second"].crossings] == [11, 45]
    assert set(flagged(result)) == {55.0, 225.0}
    assert flagged(result)[55.0][0].startswith(
        "mechanism second: change point (its crank at 180 deg) crossed between input 50 and 55 deg"
    )


def test_an_output_angle_steps_the_short_way_round():
    # From 179 deg-ish to -179 deg-ish is +0.2 rad, not -2 pi + 0.2; then on by +0.4 rad.
    assert wrapped_steps(np.array([math.pi - 0.1, -math.pi + 0.1, -math.pi + 0.5])) == pytest.approx([0.2, 0.4])


PARALLELOGRAM_SCENE = """
[links.ground]
joints = [[0.0, 0.0], [0.1, 0.0]]
[links.crank]
joints = [[0.0, 0.0], [0.05, 0.0]]
[links.coupler]
joints = [[0.0, 0.0], [0.1, 0.0]]
[links.output]
joints = [[0.0, 0.0], [0.05, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = {{start = {start}, stop = {stop}, num = 21}}
input_speed_rad_s = 1.0
"""


def test_analyze_json_and_text_carry_the_crossing_on_its_row(tmp_path, capsys):
    scene = tmp_path / "parallelogram.toml"
    scene.write_text(textwrap.dedent(PARALLELOGRAM_SCENE.format(start=170.5, stop=190.5)))
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene), "--json", str(out)]) == 0
    positions = json.loads(out.read_text())["positions"]
    assert all(p["feasible"] for p in positions)
    # Only the row after the crossing has the key (as only feasible rows have transmission angles).
    warned = {p["input_angle_deg"]: p["warnings"] for p in positions if "warnings" in p}
    assert list(warned) == [180.5] and len(warned[180.5]) == 1
    assert "crossed between input 179.5 and 180.5 deg" in warned[180.5][0]
    text = capsys.readouterr().out
    assert f"warning: {warned[180.5][0]}" in text


def test_the_html_report_carries_the_crossing_as_a_warning(tmp_path, capsys):
    scene = tmp_path / "parallelogram.toml"
    scene.write_text(textwrap.dedent(PARALLELOGRAM_SCENE.format(start=170.5, stop=190.5)))
    page = tmp_path / "report.html"
    assert main(["analyze", str(scene), "--html", str(page)]) == 0
    assert "crossed between input 179.5 and 180.5 deg" in page.read_text()


def test_analyze_json_has_no_warnings_for_a_sweep_that_stops_short(tmp_path, capsys):
    scene = tmp_path / "parallelogram.toml"
    scene.write_text(textwrap.dedent(PARALLELOGRAM_SCENE.format(start=159.5, stop=179.5)))
    out = tmp_path / "out.json"
    assert main(["analyze", str(scene), "--json", str(out)]) == 0
    positions = json.loads(out.read_text())["positions"]
    assert len(positions) == 21 and not any("warnings" in p for p in positions)
    assert "crossed between" not in capsys.readouterr().out


@pytest.mark.parametrize("scene", sorted((REPO / "validation" / "cases").glob("*/scene.toml")), ids=lambda p: p.parent.name)
def test_the_shipped_cases_cross_no_toggle_or_change_point(scene):
    loaded = load_scene(scene)
    result = solve_machine(loaded.machine, loaded.motion)
    assert result.crossings == ()
