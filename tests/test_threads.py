"""Blocks of a sweep on threads: every block once, errors raised, the same stresses as one block."""

from __future__ import annotations

import multiprocessing
import os
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import linkstress.dynamics.section_stress as section_stress
from linkstress.analysis import Plan, run_analysis
from linkstress.kinematics.motion import angle_motion
from linkstress.scene import load_scene
from linkstress.threads import blas_alone, in_parallel

SEED = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar" / "scene.toml"


def test_in_parallel_runs_every_block_exactly_once():
    seen = np.zeros(40, int)

    def work(block):
        seen[block] += 1

    in_parallel(work, [slice(k, k + 4) for k in range(0, 40, 4)])
    assert (seen == 1).all()


def test_in_parallel_called_from_inside_a_block_runs_there_instead_of_waiting_for_the_pool(monkeypatch):
    import linkstress.threads as threads

    monkeypatch.setattr(threads, "cores", lambda: 2)
    threads._pool.cache_clear()
    seen = np.zeros((4, 8), int)

    def inner(cell):
        seen[cell] += 1

    def outer(row):
        # every outer block holds a pool thread; nested pool waits would deadlock with 2 threads
        in_parallel(inner, [(row, k) for k in range(8)])

    in_parallel(outer, [0, 1, 2, 3])
    threads._pool.cache_clear()
    assert (seen == 1).all()


def test_in_parallel_raises_what_a_block_raised():
    def work(k):
        if k == 3:
            raise ValueError("block 3")

    with pytest.raises(ValueError, match="block 3"):
        in_parallel(work, list(range(6)))


def _blocks_in_a_child() -> str:
    seen = np.zeros(8, int)

    def work(k):
        seen[k] += 1

    in_parallel(work, list(range(8)))
    return "every block" if (seen == 1).all() else "missing blocks"


@pytest.mark.skipif(sys.platform == "win32", reason="fork is POSIX")
def test_in_parallel_works_in_a_process_forked_after_the_pool_was_made():
    # validate and regress fork process pools; a child inherits the parent's pool object but none
    # of its threads, and work handed to that pool would never run.
    in_parallel(lambda k: None, list(range(8)))
    with multiprocessing.get_context("fork").Pool(1) as pool:
        assert pool.apply_async(_blocks_in_a_child).get(timeout=60) == "every block"


def test_blas_alone_keeps_products_exact():
    a = np.arange(12.0).reshape(3, 4)
    with blas_alone():
        np.testing.assert_array_equal(a @ a.T, np.einsum("ij,kj->ik", a, a))


def test_a_sweep_in_many_blocks_on_threads_equals_the_sweep_in_one_block(monkeypatch):
    # 37 positions of the seed four-bar: the three links' blocks of 4 (thirty blocks sharing the
    # cores), then each link alone in one block.
    # (Where a section's maximum is flat, its fibre may differ: the chord search samples more
    # densely when it has fewer entries, as in a block of 4.)
    scene = load_scene(SEED)
    scene = replace(scene, motion=angle_motion(np.linspace(3.0, 357.0, 37), -1.0, 0.0))
    plan = Plan(forces=True, stresses=("crank", "coupler", "output"), stations=61, validate=(), notes=())
    monkeypatch.setattr(section_stress, "THREADED_BLOCK", 4)
    monkeypatch.setattr(section_stress, "THREADED_PAIRS", 0)
    monkeypatch.setattr(section_stress, "cores", lambda: 2)
    calls = []

    def spy(work, items, threads=True):
        calls.append((len(items), threads))
        in_parallel(work, items, threads)

    monkeypatch.setattr(section_stress, "in_parallel", spy)
    blocks = run_analysis(scene, plan)
    assert calls == [(30, True)]
    monkeypatch.setattr(section_stress, "THREADED_PAIRS", 10**12)
    monkeypatch.setattr(section_stress, "POSITION_BLOCK", 1000)
    for name in plan.stresses:
        loads = blocks.forces.link_loads[name]
        a = blocks.stresses[name]
        b = section_stress.section_stresses(scene.links[name].profile, loads, a.x)
        scale = np.abs(b.von_mises).max()
        np.testing.assert_allclose(a.max_von_mises, b.max_von_mises, rtol=0, atol=1e-13 * scale)
        np.testing.assert_allclose(a.mismatch, b.forces.mismatch, rtol=0, atol=1e-15)
        along = [a.at(block) for block in a.blocks]
        np.testing.assert_allclose(np.concatenate([s.von_mises for s in along]), b.von_mises, rtol=0, atol=1e-13 * scale)
        # BLAS rounds a product differently with the number of rows: equal to rounding of the largest M
        moment = np.abs(b.forces.moment).max()
        np.testing.assert_allclose(np.concatenate([s.forces.moment for s in along]), b.forces.moment, rtol=0, atol=1e-14 * moment)


@pytest.mark.skipif(not hasattr(os, "sched_setaffinity"), reason="the system cannot hold a process to a core")
def test_the_benchmark_times_the_sweep_on_one_core_and_gives_the_cores_back():
    from linkstress.threads import cores
    from linkstress.validation.bench.dynamics import on_one_core

    before = os.sched_getaffinity(0)
    inside = on_one_core(lambda: (cores(), os.sched_getaffinity(0)))
    assert os.sched_getaffinity(0) == before
    if len(before) == 1:
        assert inside is None
    else:
        assert inside == (1, {min(before)})


def test_on_threads_a_link_gets_at_least_a_block_per_core_and_otherwise_blocks_of_the_cap(monkeypatch):
    monkeypatch.setattr(section_stress, "cores", lambda: 2)

    class Sweep:
        def __init__(self, count):
            self.coefficients = np.zeros((count, 3))

    def sizes(count, threaded):
        return [b.stop - b.start for b in section_stress._Sweep.blocks(Sweep(count), threaded)]

    # the seed's 3,600-position sweep: two blocks of 1,800 on two cores, eight of 450 on one
    assert sizes(3600, True) == [1800, 1800]
    assert sizes(3600, False) == [450] * 8
    assert sizes(10_000, True) == [2000] * 5  # at most THREADED_BLOCK = 2048
    assert sizes(1, True) == [1]
    assert sizes(0, True) == sizes(0, False) == []


def test_the_joint_forces_of_a_long_sweep_solved_on_every_core_equal_those_solved_on_one(monkeypatch):
    import linkstress.dynamics.newton_euler as newton_euler
    from linkstress.dynamics.machine_forces import machine_forces
    from linkstress.kinematics import solve_machine

    scene = load_scene(SEED)
    scene = replace(scene, motion=angle_motion(np.linspace(0.0, 360.0, 1200, endpoint=False), -1.0, 0.0))
    motion = solve_machine(scene.machine, scene.motion)
    monkeypatch.setattr(newton_euler, "cores", lambda: 3)
    calls = []

    def spy(work, items, threads=True):
        calls.append(len(items))
        in_parallel(work, items, threads)

    monkeypatch.setattr(newton_euler, "in_parallel", spy)
    split = machine_forces(scene, motion)
    monkeypatch.setattr(newton_euler, "THREADED_SYSTEMS", 10**9)
    whole = machine_forces(scene, motion)
    assert calls == [3, 1]
    assert not split.feasible[600] and split.feasible.sum() == 1199  # 180 deg: the toggle
    np.testing.assert_array_equal(split.feasible, whole.feasible)
    assert split.reasons == whole.reasons
    for name, force in whole.mechanisms["main"].forces.items():
        np.testing.assert_array_equal(split.mechanisms["main"].forces[name], force)
    np.testing.assert_array_equal(split.mechanisms["main"].driving_torque, whole.mechanisms["main"].driving_torque)


def test_linkstress_threads_caps_the_cores_a_process_uses(monkeypatch):
    from linkstress.threads import cores

    monkeypatch.delenv("LINKSTRESS_THREADS", raising=False)
    available = cores()
    monkeypatch.setenv("LINKSTRESS_THREADS", "1")
    assert cores() == 1
    monkeypatch.setenv("LINKSTRESS_THREADS", str(available + 5))
    assert cores() == available  # never more than the machine gives


@pytest.mark.parametrize("value", ["0", "two", "-1", "1.5"])
def test_a_bad_linkstress_threads_stops_any_command_with_exit_2_naming_it(value, monkeypatch, capsys):
    from linkstress.cli import main

    monkeypatch.setenv("LINKSTRESS_THREADS", value)
    assert main(["analyze", str(SEED)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "LINKSTRESS_THREADS" in err and "whole number" in err
