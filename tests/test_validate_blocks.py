"""validate splits a link's positions into blocks, each a task that meshes and factorises the link
once, and joins the blocks into exactly what one solve of them all gives.

The join is exact, not close: SuperLU solves SOLVE_COLUMNS (8) right-hand sides per call, and a
block holds a multiple of 8 positions, so every position meets the same arithmetic either way.
"""

from __future__ import annotations

import json
import textwrap
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from linkstress.analysis import plan_for
from linkstress.cli import main
from linkstress.executors import LocalExecutor
from linkstress.scene import load_scene
from linkstress.validation.stations import choose_stations, default_mesh
from linkstress.validation.fea.convergence import convergence_study, join_studies
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.link import join_results, solve_link
from linkstress.validation.fea.plane_stress import SOLVE_COLUMNS, factorise_spd, solve_columns
from linkstress.validation.validate_scene import MIN_BLOCK, position_blocks, validate_scene
from test_validate import SCENE, write_bars

SWEEP = SCENE.replace("input_angle_deg = 40.0", "input_angle_deg = {start = 0.0, stop = 355.0, num = 72}") + """
    input_acceleration_rad_s2 = 40.0
    [loads]
    gravity_m_s2 = [0.0, -9.81]
"""
"""test_validate's crank-rocker of 40 mm steel bars with pin holes (0.3 + 0.6 < 0.5 + 0.5: the crank
turns fully), at 72 distinct poses over a turn, accelerating, under gravity."""


@pytest.fixture(scope="module")
def bars(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("bars")
    write_bars(folder / "bars.dxf", coupler_holes=True)
    (folder / "scene.toml").write_text(textwrap.dedent(SWEEP))
    return folder / "scene.toml"


def without_timing(data):
    """``data`` less every key that holds a time (its name has "seconds")."""
    if isinstance(data, dict):
        return {k: without_timing(v) for k, v in data.items() if "seconds" not in k}
    if isinstance(data, list):
        return [without_timing(v) for v in data]
    return data


def test_links_that_fill_the_workers_are_one_task_each():
    (block,) = position_blocks(36, links=5, workers=2)
    assert block.tolist() == list(range(36))
    (block,) = position_blocks(200, links=2, workers=2)
    assert len(block) == 200


def test_idle_workers_get_blocks_of_a_multiple_of_eight_positions_covering_the_sweep_in_order():
    # 360 positions, one link, four workers: 90 each, rounded up to 96
    blocks = position_blocks(360, links=1, workers=4)
    assert [len(b) for b in blocks] == [96, 96, 96, 72]
    assert np.concatenate(blocks).tolist() == list(range(360))
    # two links on eight workers: four blocks each, 100 / 4 = 25 -> MIN_BLOCK
    assert [len(b) for b in position_blocks(100, links=2, workers=8)] == [MIN_BLOCK, 100 - MIN_BLOCK]
    # a short sweep is not split: each block would mesh the link again for few positions
    assert len(position_blocks(36, links=1, workers=8)) == 1


def test_a_block_size_given_is_rounded_up_to_the_solvers_columns():
    assert [len(b) for b in position_blocks(20, links=3, workers=1, size=5)] == [8, 8, 4]
    assert [len(b) for b in position_blocks(20, links=3, workers=1, size=17)] == [20]
    assert [b.tolist() for b in position_blocks(0, links=1, workers=1)] == [[]]


def test_solving_in_chunks_of_eight_gives_every_column_whatever_is_solved_beside_it():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(60, 60))
    lu = factorise_spd(sp.csc_matrix(a @ a.T + 60 * np.eye(60)))
    rhs = rng.normal(size=(60, 29))
    whole = solve_columns(lu, rhs)
    np.testing.assert_allclose(whole, lu.solve(rhs), rtol=1e-12)
    blocks = [solve_columns(lu, rhs[:, k:k + 2 * SOLVE_COLUMNS]) for k in range(0, 29, 2 * SOLVE_COLUMNS)]
    assert np.array_equal(np.concatenate(blocks, axis=1), whole)


@pytest.fixture(scope="module")
def coupler(bars):
    scene = load_scene(bars)
    from linkstress.analysis import run_analysis

    analysis = run_analysis(scene, plan_for(scene))
    link, loads = scene.links["coupler"].profile, analysis.forces.link_loads["coupler"]
    stations = choose_stations(link, loads.frame_joints)
    return link, loads.at(np.arange(20)), default_mesh(link, loads.frame_joints, stations.x)


def test_a_links_fea_in_blocks_joins_bit_for_bit_into_one_solve(coupler):
    link, loads, mesh = coupler
    whole = solve_link(link, loads, mesh)
    joined = join_results([solve_link(link, loads.at(rows), mesh) for rows in (np.arange(8), np.arange(8, 20))])
    for key in ("displacement", "nodal_stress", "reactions", "reaction_ratio", "applied_load"):
        assert np.array_equal(getattr(joined, key), getattr(whole, key)), key
    assert joined.n_positions == 20


def test_a_refinement_study_in_blocks_joins_into_the_same_changes_and_richardson_estimate(coupler):
    link, loads, mesh = coupler
    mesh = replace(mesh, size=2 * mesh.size, hole_size=2 * mesh.hole_size)
    points = np.array([[0.25, 0.015], [0.25, -0.015], [0.1, 0.02]])
    whole = convergence_study(link, loads.at(np.arange(12)), mesh, points)
    joined = join_studies([convergence_study(link, loads.at(rows), mesh, points) for rows in (np.arange(8), np.arange(8, 12))])
    for key in ("values", "change", "peaks", "resultants", "spacing", "dofs"):
        assert np.array_equal(getattr(joined, key), getattr(whole, key)), key
    for key in ("order", "extrapolated", "error", "gci", "determined"):
        assert np.array_equal(getattr(joined.richardson, key), getattr(whole.richardson, key)), key


def test_blocks_meshed_differently_are_refused_naming_the_link(coupler):
    link, loads, mesh = coupler
    coarse, fine = solve_link(link, loads.at([0]), mesh), solve_link(link, loads.at([1]), mesh.refined(1.5))
    with pytest.raises(FEAError, match="link 'coupler': its blocks of positions were meshed differently"):
        join_results([coarse, fine])


def test_validate_in_blocks_of_eight_writes_what_one_task_per_link_writes(bars, tmp_path, capsys):
    # the coupler at 12 positions in blocks of 8 and 4, three-level studies: two tasks against one
    scene = tmp_path / "scene.toml"
    scene.write_text(bars.read_text() + '\n[analysis]\nvalidate = ["coupler"]\n')
    (tmp_path / "bars.dxf").write_bytes((bars.parent / "bars.dxf").read_bytes())
    flags = ["--positions", "12", "--json"]
    assert main(["validate", str(scene), *flags, str(tmp_path / "whole.json")]) == 0
    whole_text = capsys.readouterr().out
    assert main(["validate", str(scene), *flags, str(tmp_path / "blocks.json"), "--positions-per-task", "8"]) == 0
    assert capsys.readouterr().out == whole_text
    whole, blocks = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("whole", "blocks"))
    assert without_timing(blocks) == without_timing(whole)
    assert len(whole["positions_compared"]) == 12 and list(whole["links"]) == ["coupler"]


@dataclass
class RecordingExecutor(LocalExecutor):
    """Runs the tasks here, one after another, as if ``jobs`` workers were waiting; keeps their labels."""

    labels: list[str] = field(default_factory=list)

    def map(self, work, tasks, labels=()):
        self.labels += list(labels)
        return super().map(work, tasks, labels)

    @property
    def workers(self) -> int:
        return self.jobs


def test_one_link_on_idle_workers_is_split_into_labelled_blocks_of_its_sweep(bars):
    scene = load_scene(bars)
    plan = plan_for(scene)
    plan = type(plan)(**{**plan.__dict__, "validate": ("coupler",)})
    where = RecordingExecutor(jobs=2)
    result = validate_scene(scene, plan, positions=72, levels=1, executor=where)
    # 72 positions, two idle workers: blocks of max(64, 36) = 64 and the 8 left
    assert where.labels == ["link coupler, positions 0-63", "link coupler, positions 64-71"]
    alone = validate_scene(scene, plan, positions=72, levels=1)
    a, b = result.comparisons["coupler"], alone.comparisons["coupler"]
    assert np.array_equal(a.fea.nodal_stress, b.fea.nodal_stress) and np.array_equal(a.fea_von_mises, b.fea_von_mises)
    assert np.array_equal(a.fea_resultants.moment, b.fea_resultants.moment)
    assert result.errors == {} and result.failures() == alone.failures() == []


def test_a_bad_block_size_exits_2_naming_the_option(bars, capsys):
    assert main(["validate", str(bars), "--positions-per-task", "0"]) == 2
    assert "--positions-per-task: must be 1 to" in capsys.readouterr().err
