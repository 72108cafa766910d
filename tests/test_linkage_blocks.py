"""A linkage sweep is solved a block of path positions at a time: the blocks' size changes nothing.

Every shipped example linkage (dyads, a crank whose frame is not at its pivot, riders on sliders,
a triad solved by Newton, a stroke input), swept densely, coarsely, from away from the drawn pose
and through positions where it cannot close, gives the same link motions, feasibility, reasons
and flagged steps with blocks of 3, 7 and 64 path positions as in one block: a change point or a
gap found across a block's end, a fill of the rows that cannot close and the origins shared
between links all come out the same."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkstress.kinematics import angle_motion
from linkstress.kinematics.linkage import Input, Joint, LinkageGraph, solve_linkage, sweep
from linkstress.kinematics.linkage.examples import circles, jansen_leg, loader_arm, slotted_arm, triad_six_bar, whitworth
from linkstress.kinematics.motion import stroke_motion


def fourbar(o4, crank, coupler, output, angle_deg, pivot=0):
    """A four-bar drawn at crank angle ``angle_deg``, B left of A -> O4. ``pivot`` 1: the crank's
    joints are listed tip first, so its frame's origin is the moving tip, not the pivot."""
    o2, o4 = np.zeros(2), np.asarray(o4, float)
    a = crank * np.array([math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
    b = circles(a, coupler, o4, output, lambda p, q: p if (o4 - a)[0] * (p - a)[1] - (o4 - a)[1] * (p - a)[0] > 0 else q)
    crank_joints = [o2, a] if pivot == 0 else [a, o2]
    links = {"ground": [o2, o4], "crank": crank_joints, "coupler": [a, b], "output": [o4, b]}
    pins = ((Joint("ground", 0), Joint("crank", pivot)), (Joint("crank", 1 - pivot), Joint("coupler", 0)),
            (Joint("coupler", 1), Joint("output", 1)), (Joint("ground", 1), Joint("output", 0)))
    return LinkageGraph("main", links, "ground", pins, (), Input("crank", pivot, 1 - pivot))


CASES = {
    "Jansen's leg, 2 deg steps from 150 deg": (lambda: jansen_leg(0.0), lambda: angle_motion(np.arange(150.0, 510.0, 2.0), 3.0, 0.5)),
    "Jansen's leg, 30 deg steps": (lambda: jansen_leg(0.0), lambda: angle_motion(np.arange(0.0, 360.0, 30.0), 3.0)),
    "parallelogram through its change points": (lambda: fourbar((0.2, 0.0), 0.05, 0.2, 0.05, 20.0),
                                                lambda: angle_motion(np.arange(20.05, 730.0, 1.3), 2.0, -1.0)),
    "triple rocker through its gaps": (lambda: fourbar((0.2, 0.0), 0.1, 0.12, 0.1, 30.0),
                                       lambda: angle_motion(np.arange(30.0, 400.0, 1.5), 1.0, 0.2)),
    "triple rocker sampled across its gap": (lambda: fourbar((0.2, 0.0), 0.1, 0.12, 0.1, 30.0),
                                             lambda: angle_motion([30.0, 60.0, 300.0, 330.0, 150.0, 87.0], 1.0)),
    "crank whose frame origin is its tip": (lambda: fourbar((0.2, 0.0), 0.05, 0.18, 0.12, 30.0, pivot=1),
                                            lambda: angle_motion(np.arange(0.0, 360.0, 1.0), 4.0, 2.0)),
    "Whitworth quick-return (riders)": (whitworth, lambda: angle_motion(np.arange(0.0, 360.0, 1.0), 3.0, -1.0)),
    "slotted coupler": (slotted_arm, lambda: angle_motion(np.arange(0.0, 360.0, 1.0), 3.0, 1.0)),
    "triad six-bar (Newton)": (lambda: triad_six_bar(20.0), lambda: angle_motion(np.arange(20.0, 38.0, 0.25), 5.0, 2.0)),
    "loader arm (stroke)": (loader_arm, lambda: stroke_motion(np.linspace(0.32, 0.58, 120), 0.05, 0.3)),
}


def solved(make_graph, make_motion, block, monkeypatch):
    monkeypatch.setattr(sweep, "BLOCK", block)
    return solve_linkage(make_graph(), make_motion())


@pytest.mark.parametrize("name", CASES)
@pytest.mark.parametrize("block", [3, 7, 64])
def test_blocks_of_any_size_give_the_one_block_sweep(name, block, monkeypatch):
    whole = solved(*CASES[name], 1 << 20, monkeypatch)
    parts = solved(*CASES[name], block, monkeypatch)
    assert parts.feasible.tolist() == whole.feasible.tolist()
    assert parts.reasons == whole.reasons
    assert parts.crossings == whole.crossings
    for link, motion in whole.links.items():
        other = parts.links[link]
        for field in ("angle", "omega", "alpha", "origin", "origin_velocity", "origin_acceleration"):
            assert np.array_equal(getattr(other, field), getattr(motion, field)), (link, field)


def test_the_cases_cover_rows_that_cannot_close_and_flagged_steps(monkeypatch):
    """The sweeps above reach what block ends could disturb: rows that cannot close (the triple
    rocker closes only for |theta| <= 87.7 deg), a step flagged for passing that gap (60 -> 300 deg),
    and the parallelogram's steps over 180, 360, 540 and 720 deg flagged as change points."""
    rocker = solved(*CASES["triple rocker through its gaps"], 1 << 20, monkeypatch)
    assert 0 < rocker.feasible.sum() < len(rocker.feasible)
    jumps = solved(*CASES["triple rocker sampled across its gap"], 1 << 20, monkeypatch)
    assert jumps.feasible.tolist() == [True, True, True, True, False, True]
    assert [row for row, _ in jumps.crossings] == [2] and "cannot close" in jumps.crossings[0][1]
    parallelogram = solved(*CASES["parallelogram through its change points"], 1 << 20, monkeypatch)
    assert len(parallelogram.crossings) == 4 and all("change point" in t for _, t in parallelogram.crossings)


def test_a_crank_whose_frame_origin_is_its_tip_moves_its_origin_with_the_tip(monkeypatch):
    """The crank listed tip first: its frame's origin is the tip A = O2 + a (cos t, sin t), with
    v = a w (-sin t, cos t) and acc = a al (-sin t, cos t) - a w^2 (cos t, sin t) (circular motion);
    its angle is the input's plus pi (the frame points from the tip to the pivot)."""
    motion = solved(*CASES["crank whose frame origin is its tip"], 64, monkeypatch)
    t = np.radians(np.arange(0.0, 360.0, 1.0))
    w, al, a = 4.0, 2.0, 0.05
    c, s = np.cos(t), np.sin(t)
    crank = motion.links["crank"]
    assert np.abs(crank.origin - a * np.column_stack([c, s])).max() < 1e-15
    assert np.abs(crank.origin_velocity - a * w * np.column_stack([-s, c])).max() < 1e-14
    assert np.abs(crank.origin_acceleration - (a * al * np.column_stack([-s, c]) - a * w * w * np.column_stack([c, s]))).max() < 1e-13
    assert np.abs(np.cos(crank.angle) + c).max() < 1e-15 and np.abs(np.sin(crank.angle) + s).max() < 1e-15
    assert np.all(crank.omega == w) and np.all(crank.alpha == al)
