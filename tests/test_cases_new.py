"""The bell_crank and arc_coupler regression cases: their sketches, scenes and analyses.

bell_crank: a crank-rocker whose rocker is an L-shaped bell crank (pins C, O4, B; arms 150 mm at
90 deg, 35 mm wide, 10 mm thick steel); its pin C drives a second four-bar whose output carries
100 N m. arc_coupler: a four-bar whose coupler is a half-circle bar (R 60 mm, 20 mm deep).
"""

from __future__ import annotations

import math
import runpy
from pathlib import Path

import numpy as np
import pytest

from linkstress.analysis import plan_for, run_analysis
from linkstress.importers import read_sketch
from linkstress.report.records import position_records
from linkstress.scene import load_scene

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"
ARM, WIDTH, FILLET, HOLE = 0.15, 0.035, 0.010, 0.012  # the bell crank as make_sketch.py draws it [m]
OUTPUT_COUPLE, OUTPUT_ARM = 100.0, 0.12  # on the second loop's output [N m], its length [m]


@pytest.fixture(scope="module")
def bell_crank():
    scene = load_scene(CASES / "bell_crank" / "scene.toml")
    analysis = run_analysis(scene, plan_for(scene))
    return analysis, position_records(analysis)


@pytest.mark.parametrize("case, drawing", [("bell_crank", "bell_crank.dxf"), ("arc_coupler", "arc_coupler.dxf")])
def test_the_sketch_script_reproduces_the_committed_drawing(tmp_path, case, drawing):
    runpy.run_path(str(CASES / case / "make_sketch.py"))["write"](tmp_path / drawing)
    assert (tmp_path / drawing).read_bytes() == (CASES / case / drawing).read_bytes()


def test_the_bell_crank_outline_has_the_area_of_its_drawing():
    # Two arms (pivot to pin, 35 wide) overlapping in a 17.5 mm square, two half-disc ends, a
    # quarter disc about O4 on the outer corner, the fillet's corner piece, less three pin holes.
    r = WIDTH / 2
    area = 2 * ARM * WIDTH - r * r + math.pi * r * r * 1.25 + FILLET**2 * (1 - math.pi / 4) - 3 * math.pi * (HOLE / 2) ** 2
    link = read_sketch(CASES / "bell_crank" / "bell_crank.dxf").link("bellcrank")
    assert link.outline.area == pytest.approx(area, rel=1e-6)
    assert np.abs(link.joints - [[0.0, 0.17], [0.0, 0.32], [0.15, 0.32]]).max() <= 1e-12  # C, O4, B


def test_the_bell_crank_machine_analyses_every_position_with_forces_and_stresses(bell_crank):
    analysis, records = bell_crank
    assert len(records) == 24 and all(r["feasible"] for r in records)
    for r in records:
        assert set(r["mechanisms"]) == {"main", "second"}
        assert all(r["links"][name]["max_von_mises_pa"] > 0 for name in ("crank", "coupler", "bellcrank", "rod2", "out2"))
    assert analysis.forces.link_loads["bellcrank"].frame_joints == (1, 2)  # O4 -> B, the main loop's output
    # Straight arms: the bell crank's cuts a depth clear of O4 and B cross arm O4 -> B alone.
    assert not any(analysis.curved(name) for name in ("crank", "coupler", "bellcrank", "rod2", "out2"))


def test_the_bell_cranks_pin_c_carries_the_second_loops_load(bell_crank):
    analysis, records = bell_crank
    f_c = np.array([r["mechanisms"]["second"]["forces_n"]["F32"] for r in records])  # rod2 on the bell crank
    # The output's couple needs at least T / l = 833 N in the rod (more where the rod is not square
    # to the output); the links' inertia takes a few per cent of it.
    assert np.hypot(*f_c.T).min() >= 0.95 * OUTPUT_COUPLE / OUTPUT_ARM
    # The same force reaches the bell crank's load case at its joint 0, C (member frame O4 -> B).
    loads = analysis.forces.link_loads["bellcrank"]
    assert np.hypot(*loads.pin_forces[:, 0].T) == pytest.approx(np.hypot(*f_c.T), rel=1e-12)


def test_both_arms_of_the_bell_crank_bend_and_balance_about_its_pivot(bell_crank):
    analysis, records = bell_crank
    theta = np.radians([r["links"]["bellcrank"]["angle_deg"] for r in records])  # O4 -> B
    alpha = np.array([r["links"]["bellcrank"]["alpha_rad_s2"] for r in records])
    to_b = ARM * np.column_stack([np.cos(theta), np.sin(theta)])
    to_c = ARM * np.column_stack([np.sin(theta), -np.cos(theta)])  # 90 deg clockwise of O4 -> B
    f_b = -np.array([r["mechanisms"]["main"]["forces_n"]["F43"] for r in records])  # coupler on the bell crank
    f_c = np.array([r["mechanisms"]["second"]["forces_n"]["F32"] for r in records])
    moment_b = to_b[:, 0] * f_b[:, 1] - to_b[:, 1] * f_b[:, 0]
    moment_c = to_c[:, 0] * f_c[:, 1] - to_c[:, 1] * f_c[:, 0]
    # Rod2 stays within 37 deg of square to arm O4 -> C over the sweep (how the second loop is laid
    # out), so C's force bends that arm with at least 0.8 of its full lever.
    assert (np.abs(moment_c) >= 0.8 * ARM * np.hypot(*f_c.T)).all()
    # About the fixed pivot the two pins' moments differ by I_O4 alpha only; that inertia torque
    # (0.0077 kg m^2 x at most 220 rad/s^2 = 1.7 N m) is under 2 % of the 108-127 N m they carry.
    link = analysis.scene.links["bellcrank"].profile
    pivot_inertia = link.mass_moment_of_inertia + link.mass * float(np.sum((link.center_of_mass - link.joints[1]) ** 2))
    assert moment_b + moment_c == pytest.approx(pivot_inertia * alpha, abs=1e-9 * np.abs(moment_c).max())
    assert (np.abs(pivot_inertia * alpha) < 0.05 * np.abs(moment_c)).all()


def test_the_arc_coupler_four_bar_analyses_every_position_and_flags_its_coupler_curved(tmp_path):
    scene = load_scene(CASES / "arc_coupler" / "scene.toml")
    analysis = run_analysis(scene, plan_for(scene))
    records = position_records(analysis)
    assert len(records) == 12 and all(r["feasible"] for r in records)
    assert [analysis.curved(name) for name in ("crank", "coupler", "output")] == [False, True, False]
    link = scene.links["coupler"].profile
    assert np.abs(link.joints - [[0.0, 0.06], [0.12, 0.06]]).max() <= 1e-12  # A, B: 120 mm apart
    assert all(r["links"]["coupler"]["max_von_mises_pa"] > 0 for r in records)
