"""Sections near pin holes carry nominal beam values; ``[analysis] body_load_near_holes`` adds the
body-load term there too (``dynamics/section_stress.py``)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from linkstress.analysis import plan_for, run_analysis
from linkstress.dynamics.section_stress import section_stresses
from linkstress.kinematics.motion import angle_motion
from linkstress.scene import load_scene
from linkstress.scene.model import Analysis
from linkstress.validation.validate_scene import validate_scene

SEED = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar" / "scene.toml"


def seed_over_a_turn(body_load_near_holes: bool):
    scene = load_scene(SEED)
    scene = replace(
        scene,
        motion=angle_motion(np.linspace(0.0, 350.0, 36), -1.0, 0.0),
        analysis=Analysis(forces=True, stresses=True, stations=200, body_load_near_holes=body_load_near_holes),
    )
    return scene, run_analysis(scene, plan_for(scene))


def test_near_hole_sections_are_nominal_unless_the_scene_asks_for_the_body_load_term():
    _, nominal = seed_over_a_turn(False)
    _, refined = seed_over_a_turn(True)
    assert not nominal.plan.body_load_near_holes and refined.plan.body_load_near_holes
    assert "body-load term near holes too" in refined.plan.describe()
    for name in ("coupler", "output"):
        a, b = nominal.stresses[name].at(slice(None)), refined.stresses[name].at(slice(None))
        away = ~a.near_hole
        assert 0 < away.sum() < len(away)
        # a section depth from every hole both are the same computation
        np.testing.assert_array_equal(a.von_mises[:, away], b.von_mises[:, away])
        # near the holes the seed's inertia loads make the term count (the coupler's rounded ends)
        change = np.abs(a.von_mises[:, ~away] - b.von_mises[:, ~away]).max() / b.von_mises.max()
        assert change > 1e-3
        # and the default's values there are elementary beam theory: sigma = N / A + M u / I
        table, f = a.sections, a.forces
        u = a.fibre_y - table.neutral_axis
        elementary = f.normal / table.area + f.moment * u / table.second_moment
        single = (table.n_chords == 1) & ~away
        np.testing.assert_allclose(a.sigma[:, single], elementary[:, single], rtol=1e-12, atol=1e-9)
    # the crank turns steadily about its pivot without gravity: no body load, nothing changes
    crank = nominal.stresses["crank"].at(slice(None)), refined.stresses["crank"].at(slice(None))
    np.testing.assert_array_equal(crank[0].von_mises, crank[1].von_mises)


def test_validate_compares_the_sections_the_scene_asks_for():
    scene, analysis = seed_over_a_turn(True)
    plan = replace(plan_for(scene), validate=("coupler",))
    result = validate_scene(scene, plan, positions=1, levels=1)
    c = result.comparisons["coupler"]
    loads = analysis.forces.link_loads["coupler"]
    expected = section_stresses(scene.links["coupler"].profile, loads.at(c.positions), c.stations, True)
    np.testing.assert_array_equal(c.beam.von_mises, expected.von_mises)
    default = section_stresses(scene.links["coupler"].profile, loads.at(c.positions), c.stations)
    assert not np.array_equal(c.beam.von_mises, default.von_mises)
