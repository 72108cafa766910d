"""Kinematics of general linkages against independent truths: circle and line intersections done
another way, scipy's root finder on a triad's loop equations, the Whitworth time ratio, central
finite differences of positions, and the assembly followed along sweeps sampled any way."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from linkstress.kinematics import angle_motion
from linkstress.kinematics.linkage import Input, Joint, LinkageGraph, Slider, solve_linkage
from linkstress.kinematics.linkage.examples import (
    JANSEN_CM, circles, jansen_leg, jansen_pose, loader_arm, slotted_arm, triad_six_bar, whitworth,
)
from linkstress.kinematics.motion import stroke_motion

RNG = np.random.default_rng(29)


def fourbar_graph(o4, crank, coupler, output, angle_deg, upper=True):
    """A four-bar drawn at crank angle ``angle_deg``, B above (``upper``) or below the line A -> O4."""
    o2, o4 = np.zeros(2), np.asarray(o4, float)
    a = crank * np.array([math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
    def left(p):
        return (o4 - a)[0] * (p - a)[1] - (o4 - a)[1] * (p - a)[0] > 0

    side = (lambda p, q: p if left(p) == upper else q)
    b = circles(a, coupler, o4, output, side)
    links = {"ground": [o2, o4], "crank": [o2, a], "coupler": [a, b], "output": [o4, b]}
    pins = ((Joint("ground", 0), Joint("crank", 0)), (Joint("crank", 1), Joint("coupler", 0)),
            (Joint("coupler", 1), Joint("output", 1)), (Joint("ground", 1), Joint("output", 0)))
    return LinkageGraph("main", links, "ground", pins, (), Input("crank", 0, 1))


@pytest.mark.parametrize("seed", range(4))
def test_an_rrr_dyad_is_the_circle_intersection_on_its_drawn_side(seed):
    """B of random Grashof crank-rockers over a turn: the law of cosines at A (the angle between
    A -> O4 and A -> B is acos((b^2 + s^2 - c^2) / (2 b s))) on the side B is drawn, not the
    engine's x/h construction."""
    rng = np.random.default_rng(seed)
    crank, ground = rng.uniform(0.02, 0.05), rng.uniform(0.15, 0.2)
    coupler, output = rng.uniform(0.16, 0.22), rng.uniform(0.12, 0.18)
    upper = bool(seed % 2)
    graph = fourbar_graph((ground, 0.0), crank, coupler, output, 40.0, upper)
    angles = np.linspace(0.0, 360.0, 73)
    motion = solve_linkage(graph, angle_motion(angles))
    assert motion.feasible.all()
    for k, angle in enumerate(angles):
        a = crank * np.array([math.cos(math.radians(angle)), math.sin(math.radians(angle))])
        d = np.array([ground, 0.0]) - a
        s = math.hypot(*d)
        turn = math.acos((coupler**2 + s**2 - output**2) / (2 * coupler * s)) * (1 if upper else -1)
        base = math.atan2(d[1], d[0]) + turn
        b = a + coupler * np.array([math.cos(base), math.sin(base)])
        assert np.abs(motion.linkage.joints["output:1"].position[k] - b).max() < 1e-12


def test_an_rrp_dyad_is_the_root_of_the_circle_line_quadratic():
    """A slider-crank whose slider runs on a tilted, offset ground line: the point's parameter t
    along the line from numpy.roots of t^2 + 2 t u.(Q - A) + |Q - A|^2 - r^2 (the reference's
    RRP), the root on the drawn side."""
    u = np.array([math.cos(0.3), math.sin(0.3)])
    q = np.array([0.02, -0.03])
    crank, rod = 0.04, 0.13
    a0 = crank * np.array([math.cos(1.0), math.sin(1.0)])
    w = q - a0
    t0 = max(np.roots([1.0, 2 * u @ w, w @ w - rod**2]).real)
    b0 = q + t0 * u
    links = {"ground": [[0, 0], q, q + u], "crank": [[0, 0], a0], "rod": [a0, b0]}
    graph = LinkageGraph("sc", links, "ground", ((Joint("ground", 0), Joint("crank", 0)),
                                                 (Joint("crank", 1), Joint("rod", 0))),
                         (Slider(Joint("rod", 1), "ground", (1, 2)),), Input("crank", 0, 1))
    angles = np.linspace(0.0, 720.0, 97)
    motion = solve_linkage(graph, angle_motion(angles))
    for k, angle in enumerate(np.radians(angles)):
        a = crank * np.array([math.cos(angle), math.sin(angle)])
        w = q - a
        t = max(np.roots([1.0, 2 * u @ w, w @ w - rod**2]).real)
        assert np.abs(motion.linkage.joints["rod:1"].position[k] - (q + t * u)).max() < 1e-12


@pytest.mark.parametrize("crank,centres", [(0.05, 0.12), (0.03, 0.1), (0.08, 0.11)])
def test_whitworth_quick_return_time_ratio(crank, centres):
    """The slotted lever reverses where the crank is square to it; the forward stroke lasts
    180 + 2 asin(r / c) deg of crank, the return 180 - 2 asin(r / c) (reference file,
    Whitworth / crank-shaper quick-return). Read from the sign changes of the lever's omega over a
    0.01 deg sweep."""
    graph = whitworth(crank, centres)
    angles = np.arange(0.0, 360.0, 0.01)
    motion = solve_linkage(graph, angle_motion(angles, 1.0))
    assert motion.feasible.all() and not motion.crossings
    omega = motion.links["lever"].omega
    at = np.flatnonzero(np.diff(np.sign(omega)) != 0)
    flips = angles[at] + 0.01 * omega[at] / (omega[at] - omega[at + 1])  # where omega crosses zero
    assert len(flips) == 2
    long, short = sorted([flips[1] - flips[0], 360.0 - (flips[1] - flips[0])], reverse=True)
    half = math.degrees(math.asin(crank / centres))
    assert long / short == pytest.approx((180 + 2 * half) / (180 - 2 * half), rel=1e-6)


def test_a_triad_matches_scipy_on_its_loop_equations():
    """The six-bar whose plate floats on three binary links: at each crank angle, the four link
    angles solve the three loop closures (plate corners reached through l1, l2, l3) by
    scipy.optimize.fsolve from the previous angle's answer, tolerance 1e-13."""
    graph = triad_six_bar(20.0)
    L = {name: graph.local[name] for name in graph.links}
    length = {name: float(np.hypot(*(L[name][1] - L[name][0]))) for name in ("l1", "l2", "l3")}
    plate = graph.links["plate"]
    g1, g2 = graph.links["ground"][1], graph.links["ground"][2]
    corner = plate - plate[0]
    angles = np.linspace(20.0, 38.0, 37)
    motion = solve_linkage(graph, angle_motion(angles))
    assert motion.feasible.all()

    def direction(t):
        return np.array([math.cos(t), math.sin(t)])

    def unknowns_of(k):
        j = motion.linkage.joints
        return np.array([math.atan2(*(j["l1:1"].position[k] - j["l1:0"].position[k])[::-1]),
                         math.atan2(*(j["l2:1"].position[k] - j["l2:0"].position[k])[::-1]),
                         math.atan2(*(j["l3:1"].position[k] - j["l3:0"].position[k])[::-1]),
                         motion.links["plate"].angle[k]])

    start = np.array([*(math.atan2(*(graph.links[n][1] - graph.links[n][0])[::-1]) for n in ("l1", "l2", "l3")),
                      math.atan2(*(plate[1] - plate[0])[::-1])])
    drawn_plate = math.atan2(*(plate[1] - plate[0])[::-1])
    guess = start
    for k, angle in enumerate(np.radians(angles)):
        a = 0.05 * direction(angle)

        def loops(v):
            t1, t2, t3, tp = v
            rot = tp - drawn_plate
            c, s = math.cos(rot), math.sin(rot)
            p0 = a + length["l1"] * direction(t1)
            p1 = p0 + np.array([c * corner[1][0] - s * corner[1][1], s * corner[1][0] + c * corner[1][1]])
            p2 = p0 + np.array([c * corner[2][0] - s * corner[2][1], s * corner[2][0] + c * corner[2][1]])
            return [*(p1 - g1 - length["l2"] * direction(t2))[:2], *(p2 - g2 - length["l3"] * direction(t3))[:2]]

        # four unknowns, four equations: the closures through l2 and l3 (l1 places the plate's corner 0)
        guess = fsolve(loops, guess, xtol=1e-14)
        assert np.allclose(np.cos(unknowns_of(k)), np.cos(guess), atol=1e-10)
        assert np.allclose(np.sin(unknowns_of(k)), np.sin(guess), atol=1e-10)


MECHANISMS = {
    "Jansen's leg": (lambda: jansen_leg(0.0), lambda: angle_motion(np.linspace(0, 350, 36), 2.0, 0.7), 1e-6),
    "Whitworth": (whitworth, lambda: angle_motion(np.linspace(0, 350, 36), 3.0, -1.0), 1e-6),
    "slotted coupler (RRP on a turning guide)": (slotted_arm, lambda: angle_motion(np.linspace(0, 355, 72), 3.0, 1.0),
                                                 1e-6),
    "triad six-bar": (lambda: triad_six_bar(20.0), lambda: angle_motion(np.linspace(20, 34, 15), 5.0, 2.0), 1e-6),
    "loader arm": (loader_arm, lambda: stroke_motion(np.linspace(0.32, 0.58, 14), 0.05, 0.3), 1e-6),
}


@pytest.mark.parametrize("name", MECHANISMS)
def test_rates_match_central_differences_of_positions(name):
    """Every joint's velocity and acceleration, every link's omega and alpha, against central
    differences of positions in the input x (Richardson-extrapolated from steps h and h/2, error
    O(h^4)): velocity = dp/dx xdot, acceleration = d2p/dx2 xdot^2 + dp/dx xddot; within 1e-7 of
    the largest value over the sweep."""
    make_graph, make_motion, h = MECHANISMS[name]
    h *= 1e3
    graph, motion = make_graph(), make_motion()
    x = motion.angle if motion.is_stroke else motion.angle_deg
    unit = 1.0 if motion.is_stroke else math.degrees(1.0)

    def at(shift):
        values = x + shift * unit
        return solve_linkage(graph, stroke_motion(values) if motion.is_stroke else angle_motion(values))

    base = solve_linkage(graph, motion)
    assert base.feasible.all()
    runs = {k: at(k * h / 2) for k in (-2, -1, 1, 2)}

    def derivatives(value):
        """Richardson's d/dx and d2/dx2 of ``value(motion)`` at every sample."""
        f0 = value(base)
        fm2, fm1, fp1, fp2 = (value(runs[k]) for k in (-2, -1, 1, 2))
        d1 = (4 * (fp1 - fm1) / h - (fp2 - fm2) / (2 * h)) / 3
        d2 = (4 * (fp1 - 2 * f0 + fm1) / (h / 2) ** 2 - (fp2 - 2 * f0 + fm2) / h**2) / 3
        return d1, d2

    w, a = motion.speed, motion.acceleration
    for joint in base.linkage.joints:
        d1, d2 = derivatives(lambda m: m.linkage.joints[joint].position)
        got = base.linkage.joints[joint]
        v, acc = d1 * w[:, None], d2 * (w * w)[:, None] + d1 * a[:, None]
        assert np.abs(got.velocity - v).max() <= 1e-7 * max(np.abs(got.velocity).max(), 1e-6), joint
        assert np.abs(got.acceleration - acc).max() <= 1e-7 * max(np.abs(got.acceleration).max(), 1e-6), joint
    for link in graph.moving:
        d1, d2 = derivatives(lambda m: np.unwrap(m.links[link].angle))
        got = base.links[link]
        omega, alpha = d1 * w, d2 * w * w + d1 * a
        assert np.abs(got.omega - omega).max() <= 1e-7 * max(np.abs(got.omega).max(), 1e-6), link
        assert np.abs(got.alpha - alpha).max() <= 1e-7 * max(np.abs(got.alpha).max(), 1e-6), link


@pytest.mark.parametrize("make", [lambda: jansen_leg(0.0), lambda: triad_six_bar(20.0), whitworth])
def test_30_deg_samples_follow_the_same_assembly_as_1_deg(make):
    """The path between samples 30 deg apart is filled in: every sample equals the 1 deg sweep's
    row at that angle, so no group switches assembly for being sampled coarsely."""
    graph = make()
    fine = np.arange(0.0, 361.0, 1.0) if graph.name != "triad" else np.arange(20.0, 37.0, 1.0)
    coarse = fine[::30] if graph.name != "triad" else fine[::10]
    a, b = solve_linkage(graph, angle_motion(fine)), solve_linkage(graph, angle_motion(coarse))
    step = 30 if graph.name != "triad" else 10
    for joint in b.linkage.joints:
        assert np.abs(b.linkage.joints[joint].position - a.linkage.joints[joint].position[::step]).max() < 1e-11


def test_a_sweep_that_starts_away_from_the_drawn_angle_keeps_the_drawn_assembly():
    """Jansen's leg drawn at 0 deg, swept from 150 deg: the same positions as the sweep drawn at
    150 deg (the path runs from the drawn angle to the first sample first); and the triad drawn at
    20 deg swept from 36 deg down to 20 equals the sweep from 20 up."""
    angles = np.arange(150.0, 300.0, 7.0)
    a = solve_linkage(jansen_leg(0.0), angle_motion(angles))
    b = solve_linkage(jansen_leg(150.0), angle_motion(angles))
    for joint in a.linkage.joints:
        assert np.abs(a.linkage.joints[joint].position - b.linkage.joints[joint].position).max() < 1e-11
    down = solve_linkage(triad_six_bar(20.0), angle_motion(np.arange(36.0, 19.0, -4.0)))
    up = solve_linkage(triad_six_bar(20.0), angle_motion(np.arange(20.0, 37.0, 4.0)))
    assert np.abs(down.linkage.joints["plate:2"].position[::-1] - up.linkage.joints["plate:2"].position).max() < 1e-11


def test_jansen_leg_assembles_as_drawn_over_a_whole_turn():
    """Jansen's published lengths (reference file): every position of a turn closes, the foot
    matches the step-by-step circle intersections of ``jansen_pose`` (upper C, lower D, E left of
    BC, F left, G lowest), and it walks: its path's lowest tenth spans roughly half the turn."""
    angles = np.linspace(0.0, 360.0, 721)
    motion = solve_linkage(jansen_leg(0.0), angle_motion(angles))
    assert motion.feasible.all() and not motion.crossings
    foot = motion.linkage.joints["leg:2"].position
    truth = np.array([jansen_pose(a)["G"] for a in angles])
    assert np.abs(foot - truth).max() < 1e-12
    y = foot[:, 1]
    low = y < y.min() + 0.1 * (y.max() - y.min())
    assert 0.35 < low.mean() < 0.6
    assert JANSEN_CM["m"] == 15.0


def test_a_parallelogram_crossing_its_change_point_is_flagged_on_that_row():
    """A parallelogram four-bar (crank = output, coupler = ground) passes its change point where
    all four links line up, at crank angles 0 and 180 deg (mod 360). Swept in 7 deg steps from
    20 deg, exactly the steps that pass 180 and 360 deg are flagged, naming the dyad's links; the
    rows stay feasible."""
    graph = fourbar_graph((0.2, 0.0), 0.05, 0.2, 0.05, 20.0, upper=True)
    angles = np.arange(20.0, 370.0, 7.0)
    motion = solve_linkage(graph, angle_motion(angles))
    assert motion.feasible.all()
    passing = {float(b) for a, b in zip(angles[:-1], angles[1:]) if np.floor(a / 180.0) != np.floor(b / 180.0)}
    assert passing == {181.0, 363.0}
    assert {float(angles[row]) for row, _ in motion.crossings} == passing
    assert all("RRR dyad (coupler, output)" in text and "change point" in text for _, text in motion.crossings)


def test_a_group_that_cannot_close_is_infeasible_naming_it_and_a_step_over_the_gap_is_flagged():
    """A triple rocker (crank 0.1, coupler 0.12, output 0.1, ground 0.2 m) closes only where
    |A - O4| <= 0.22 m: 0.05 - 0.04 cos(theta) <= 0.0484, |theta| <= 87.7 deg. At 150, 180, 210 deg
    it is infeasible, naming the RRR dyad; a step from 60 to 300 deg (through 180) is flagged on
    the row it reaches, which stays feasible; the step on from 300 to 330 deg is not."""
    graph = fourbar_graph((0.2, 0.0), 0.1, 0.12, 0.1, 30.0)
    motion = solve_linkage(graph, angle_motion([30.0, 150.0, 180.0, 210.0, 87.0, 88.0]))
    assert motion.feasible.tolist() == [True, False, False, False, True, False]
    assert all("the RRR dyad (coupler, output) cannot close" == motion.reasons[k] for k in (1, 2, 3, 5))
    jump = solve_linkage(graph, angle_motion([30.0, 60.0, 300.0, 330.0]))
    assert jump.feasible.all()
    assert [row for row, _ in jump.crossings] == [2]
    assert "cannot close" in jump.crossings[0][1] and "60 deg to input 300 deg" in jump.crossings[0][1]


def test_a_stroke_input_drives_a_cylinder_loader_arm():
    """The loader arm: the rod's pin P is where the circles (O1, 0.3 m) and (O2, stroke) meet (the
    input is P's distance from O2 along the barrel), on the drawn side; the rod block turns with
    the barrel; the stroke read back equals the input."""
    strokes = np.linspace(0.3, 0.6, 31)
    motion = solve_linkage(loader_arm(), stroke_motion(strokes, 0.1, 0.0))
    assert motion.feasible.all()
    o2 = np.array([0.1, -0.35])
    truth = np.array([circles(np.zeros(2), 0.3, o2, s, lambda a, b: a if a[0] > b[0] else b) for s in strokes])
    assert np.abs(motion.linkage.joints["arm:1"].position - truth).max() < 1e-12
    assert np.allclose(motion.links["rod"].angle, motion.links["barrel"].angle, atol=1e-12)
    assert np.abs(motion.linkage.strokes[0][0] - strokes).max() < 1e-12
    assert np.abs(motion.linkage.strokes[0][1] - 0.1).max() < 1e-12


def test_the_input_path_runs_from_the_drawn_angle_the_short_way_in_steps_of_at_most_2_deg():
    """Drawn at 350 deg, sampled at 10 and 40 deg: the path starts at -10 deg (350 the short way
    to 10), reaches 10 in 10 steps of 2 deg and 40 in 15 more; the samples are exactly on it."""
    from linkstress.kinematics.linkage.sweep import input_path, refined

    path = input_path(math.radians(350.0), np.radians([10.0, 40.0]), math.radians(2.0), periodic=True)
    assert np.degrees(path.x[0]) == pytest.approx(-10.0)
    assert path.rows.tolist() == [10, 25] and path.x[path.rows].tolist() == np.radians([10.0, 40.0]).tolist()
    assert np.abs(np.diff(np.degrees(path.x))).max() <= 2.0 + 1e-12
    assert path.step_of.tolist() == [-1] + [0] * 10 + [1] * 15
    finer = refined(path, np.array([25]))
    assert finer.rows.tolist() == [10, 26] and np.degrees(finer.x[25]) == pytest.approx(39.0)
