"""A sample within round-off of a change point is the change point; one near a toggle keeps its value.

Near a change point the factor of sin^2(mu) that vanishes there (1 + cos(mu) where a + d = b + c,
1 - cos(mu) where |a - d| = |b - c|; 1 -+ sin(psi) of a slider-crank's rod) is a double zero,
~(crank angle off the point)^2. The rounding of the crank pin's coordinates moves it by ~1e-16, so
well before it vanishes the accelerations lose their digits, and so do the joint forces, which grow
as 1 / (angle off the point) there. The seed swept at 1,000,000 samples puts one 1.8e-4 deg from its
change point (1 + cos(mu) = 4.4e-12): its crank "maximum" came out 9.2e10 Pa where exact kinematics
give 9.8e6 Pa. Near a toggle (a simple zero) the motion's own rates grow as fast as their rounding,
and the forces keep their digits however close the sample is.

Each sample is solved twice: as linkstress solves it, and with the coupler's and output's angular
velocities and accelerations replaced by exact ones (the same closed form in 60-digit decimal
arithmetic, from the same double crank angle), through the same Newton-Euler solve. The difference
of the joint forces, over the largest exact one, is the error the kinematics' rounding makes. It
sets ``CHANGE_POINT_REACH``: above it every force keeps about four digits, below it they go.
"""

from __future__ import annotations

import decimal
import math
import re
import textwrap
from dataclasses import replace
from decimal import Decimal
from pathlib import Path

import numpy as np
import pytest

import linkstress.kinematics.solve as kinematics_solve
from linkstress.analysis import plan_for, run_analysis
from linkstress.kinematics import fourbar, slider_crank
from linkstress.kinematics.crossings import describe, distinct_digits
from linkstress.kinematics.fourbar import CHANGE_POINT_REACH, TOGGLE_TOLERANCE
from linkstress.kinematics.results import Crossing
from linkstress.scene import load_scene

SEED = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar"
DIGITS = 60


def _sin_cos(x: Decimal) -> tuple[Decimal, Decimal]:
    """sin and cos of ``x`` [rad] by their Taylor series (|x| <= 2 pi here: ~60 terms)."""
    sin, cos, term, k = Decimal(0), Decimal(0), Decimal(1), 0
    while True:
        part = term if k % 4 in (0, 1) else -term
        if k % 2:
            sin += part
        else:
            cos += part
        k += 1
        term = term * x / k
        if abs(term) < Decimal(10) ** -(DIGITS + 5):
            return sin, cos


def exact_fourbar_rates(a, b, c, d, theta2, omega2, alpha2) -> np.ndarray:
    """Coupler and output omega, alpha and 1 -/+ cos(mu) (P, 4 + 1) of the open four-bar O2 (0, 0),
    O4 (d, 0) at the double crank angles ``theta2`` [rad], Norton's closed form (the same as
    ``fourbar``) in DIGITS-digit decimals: omega3, omega4, alpha3, alpha4, min(1 - cos, 1 + cos)."""
    rows = []
    with decimal.localcontext() as ctx:
        ctx.prec = DIGITS
        a, b, c, d, w2, al2 = (Decimal(float(v)) for v in (a, b, c, d, omega2, alpha2))
        for theta in theta2:
            s, co = _sin_cos(Decimal(float(theta)))
            ax, ay = a * co, a * s
            dx, dy = d - ax, -ay
            s2 = dx * dx + dy * dy
            omc, opc = (s2 - (b - c) ** 2) / (2 * b * c), ((b + c) ** 2 - s2) / (2 * b * c)
            sin_mu = (omc * opc).sqrt()
            along, across = s2 + b * b - c * c, 2 * b * c * sin_mu
            r3x, r3y = (along * dx - across * dy) / (2 * s2), (along * dy + across * dx) / (2 * s2)
            r4x, r4y = r3x - dx, r3y - dy
            cross = b * c * sin_mu
            vax, vay = -w2 * ay, w2 * ax
            w3 = -(vax * r4x + vay * r4y) / cross
            w4 = -(vax * r3x + vay * r3y) / cross
            aax, aay = -al2 * ay - w2 * w2 * ax, al2 * ax - w2 * w2 * ay
            dot = r3x * r4x + r3y * r4y
            al3 = (w3 * w3 * dot - w4 * w4 * c * c - (aax * r4x + aay * r4y)) / cross
            al4 = (w3 * w3 * b * b - w4 * w4 * dot - (aax * r3x + aay * r3y)) / cross
            rows.append([float(v) for v in (w3, w4, al3, al4, min(omc, opc))])
    return np.array(rows)


def exact_slider_rates(a, b, theta2, omega2, alpha2) -> np.ndarray:
    """The rod's omega, alpha and min(1 -/+ sin(psi)) (P, 3) of the open centred slider-crank on
    +x (Norton eqs. 4.17, 6.20, 7.16) in DIGITS-digit decimals."""
    rows = []
    with decimal.localcontext() as ctx:
        ctx.prec = DIGITS
        a, b, w2, al2 = (Decimal(float(v)) for v in (a, b, omega2, alpha2))
        for theta in theta2:
            s, co = _sin_cos(Decimal(float(theta)))
            sin_psi = -a * s / b
            cos_psi = ((1 - sin_psi) * (1 + sin_psi)).sqrt()
            w3 = -(w2 * a * co) / (b * cos_psi)
            aay = al2 * a * co - w2 * w2 * a * s
            al3 = (w3 * w3 * b * sin_psi - aay) / (b * cos_psi)
            rows.append([float(w3), float(al3), float(min(1 - sin_psi, 1 + sin_psi))])
    return np.array(rows)


def force_errors(scene_text: str, angles_deg, exact, monkeypatch, roles=("coupler", "output")) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The loop ``main``'s joint forces of ``scene_text`` (``ANGLES`` replaced by ``angles_deg``)
    as solved, against the same solve with ``exact`` (P, 2 per role: omega, alpha columns) rates
    for ``roles``: (feasible (P,), largest exact force (P,) [N], largest difference / it (P,)). The
    files are written in the current folder (each test's own)."""
    Path("scene.toml").write_text(scene_text.replace("ANGLES", ", ".join(repr(float(a)) for a in angles_deg)))
    if "ansys_four_bars.dxf" in scene_text:
        Path("ansys_four_bars.dxf").write_bytes((SEED / "ansys_four_bars.dxf").read_bytes())
    scene = load_scene(Path("scene.toml"))
    solved = run_analysis(scene, plan_for(scene))
    name = "solve_fourbar" if "four-bar" in scene_text else "solve_slider_crank"
    original = getattr(kinematics_solve, name)

    def with_exact_rates(*args, **kwargs):
        loop = original(*args, **kwargs)
        links = dict(loop.links)
        for k, role in enumerate(roles):
            links[role] = replace(links[role], omega=exact[:, 2 * k].copy(), alpha=exact[:, 2 * k + 1].copy())
        return replace(loop, links=links)

    with monkeypatch.context() as patch:
        patch.setattr(kinematics_solve, name, with_exact_rates)
        reference = run_analysis(scene, plan_for(scene))
    got = np.stack(list(solved.forces.mechanisms["main"].forces.values()), axis=1)
    want = np.stack(list(reference.forces.mechanisms["main"].forces.values()), axis=1)
    scale = np.abs(want).max(axis=(1, 2))
    difference = np.abs(got - want).max(axis=(1, 2))
    return solved.feasible, scale, np.divide(difference, scale, out=np.zeros_like(scale), where=solved.feasible)


def seed_text() -> str:
    text = (SEED / "scene.toml").read_text()
    return re.sub(r"(?m)^input_angle_deg = .*$", "input_angle_deg = [ANGLES]", text)


def bare_four_bar(a: float, b: float, c: float, d: float) -> str:
    """A four-bar of bare joints with mass data, 3 rad/s and 2 rad/s^2 at the crank, 5 N m on the output."""
    return textwrap.dedent(f"""\
        [links.crank]
        joints = [[0.0, 0.0], [{a}, 0.0]]
        mass = 2.0
        inertia = 0.3
        center_of_mass = [{a / 2}, 0.0]
        [links.coupler]
        joints = [[0.0, 0.0], [{b}, 0.0]]
        mass = 1.5
        inertia = 0.2
        center_of_mass = [{b / 2}, 0.05]
        [links.output]
        joints = [[0.0, 0.0], [{c}, 0.0]]
        mass = 2.5
        inertia = 0.5
        center_of_mass = [{c / 2}, -0.05]
        [links.ground]
        joints = [[0.0, 0.0], [{d}, 0.0]]
        [mechanisms.main]
        type = "four-bar"
        crank = "crank"
        coupler = "coupler"
        output = "output"
        ground = "ground"
        [motion]
        input_angle_deg = [ANGLES]
        input_speed_rad_s = 3.0
        input_acceleration_rad_s2 = 2.0
        [loads.couples]
        output = 5.0
        """)


OFF = np.array([1e-2, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6])
"""Crank angles off the change point [rad]: 1 -/+ cos(mu) ~ 0.5 x these squared."""

CHANGE_POINT_FOUR_BARS = [
    # (scene, (a, b, c, d), speed, acceleration, change point [deg], side)
    ("seed", (1.0, 1.5, 1.5, 2.0), -1.0, 0.0, 180.0, -1),
    ("seed", (1.0, 1.5, 1.5, 2.0), -1.0, 0.0, 180.0, 1),
    ("parallelogram", (1.0, 2.0, 1.0, 2.0), 3.0, 2.0, 180.0, -1),
    ("parallelogram", (1.0, 2.0, 1.0, 2.0), 3.0, 2.0, 0.0, 1),
    ("kite", (1.0, 1.0, 3.0, 3.0), 3.0, 2.0, 180.0, -1),
]


@pytest.mark.parametrize("name, lengths, speed, acceleration, point, side", CHANGE_POINT_FOUR_BARS)
def test_near_a_four_bars_change_point_the_forces_keep_their_digits_down_to_the_reach_and_lose_them_below(
        name, lengths, speed, acceleration, point, side, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    angles = point + side * np.degrees(OFF)
    exact = exact_fourbar_rates(*lengths, np.radians(angles), speed, acceleration)
    factor = exact[:, 4]
    text = seed_text() if name == "seed" else bare_four_bar(*lengths)
    # As solved before the reach: every sample down to TOGGLE_TOLERANCE is reported.
    monkeypatch.setattr(fourbar, "CHANGE_POINT_REACH", TOGGLE_TOLERANCE)
    monkeypatch.setattr(slider_crank, "CHANGE_POINT_REACH", TOGGLE_TOLERANCE)
    feasible, scale, error = force_errors(text, angles, exact[:, [0, 2, 1, 3]], monkeypatch)
    assert feasible.all()
    kept = factor >= CHANGE_POINT_REACH
    assert error[kept].max() < 1e-4
    assert error[factor > 4 * CHANGE_POINT_REACH].max() < 1e-5
    # An order of magnitude inside the reach the worst of them has lost three digits or more; under
    # 1e-10 every one is off by more than 1 %, and under 1e-11 (3e-6 rad off) by more than itself.
    assert error[factor < CHANGE_POINT_REACH / 10].max() > 1e-3
    assert error[factor < 1e-10].min() > 0.01
    assert error[factor < 1e-11].min() > 1.0
    # The forces themselves grow toward the point, as 1 / (angle off) once it dominates.
    assert scale[1] > 2 * scale[0] and scale[-1] > 50 * scale[0]


def test_with_the_reach_those_samples_are_the_change_point_and_the_rest_keep_their_exact_forces(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    angles = 180.0 - np.degrees(OFF)
    exact = exact_fourbar_rates(1.0, 1.5, 1.5, 2.0, np.radians(angles), -1.0, 0.0)
    feasible, _, error = force_errors(seed_text(), angles, exact[:, [0, 2, 1, 3]], monkeypatch)
    np.testing.assert_array_equal(feasible, exact[:, 4] >= CHANGE_POINT_REACH)
    assert feasible[:2].all() and not feasible[2:].any()  # 0.057 deg off is outside, 0.017 deg inside
    assert error[feasible].max() < 1e-5


def test_a_million_sample_sweep_of_the_seed_never_takes_the_sample_next_to_its_change_point_as_its_maximum(tmp_path):
    # numpy.linspace(0, 360, 1_000_000) puts a sample at 179.99981999982 deg, 1.8e-4 deg off.
    near = float(np.linspace(0.0, 360.0, 1_000_000)[499_999])
    assert near == pytest.approx(180.0 - 1.8e-4, abs=1e-9)
    (tmp_path / "ansys_four_bars.dxf").write_bytes((SEED / "ansys_four_bars.dxf").read_bytes())
    (tmp_path / "scene.toml").write_text(seed_text().replace("ANGLES", f"170.0, {near!r}, 179.9, 190.0"))
    scene = load_scene(tmp_path / "scene.toml")
    result = run_analysis(scene, plan_for(scene))
    assert result.feasible.tolist() == [True, False, True, True]
    assert result.reasons[1].startswith("change point: all four links aligned, or too nearly")
    crank = result.stresses["crank"].max_von_mises[result.feasible]
    # 0.1 deg off the point the crank's true 5e4 Pa (forces ~ 1 / angle off) is kept, and is the
    # sweep's largest: the 9.2e10 Pa the rounding made 1.8e-4 deg off is gone.
    assert crank.max() == pytest.approx(result.stresses["crank"].max_von_mises[2]) and crank.max() < 1e5


def test_near_a_toggle_the_forces_keep_their_digits_however_large_they_grow(tmp_path, monkeypatch):
    # A triple rocker (a 1.2, b 1.0, c 1.5, d 2.0: S + L = 3.0 > P + Q = 2.7) approaching its toggle
    # where |A O4| = b + c from inside: the forces grow as 1 / (1 + cos mu)^2 to 1.7e20 N at 1.6e-10,
    # all of them real, and stay within 1e-5 of the exact kinematics' forces.
    monkeypatch.chdir(tmp_path)
    a, b, c, d = 1.2, 1.0, 1.5, 2.0
    toggle = math.acos((a * a + d * d - (b + c) ** 2) / (2 * a * d))
    angles = np.degrees(toggle - np.array([1e-2, 1e-4, 1e-6, 1e-8, 1e-10]))
    exact = exact_fourbar_rates(a, b, c, d, np.radians(angles), 3.0, 2.0)
    feasible, scale, error = force_errors(bare_four_bar(a, b, c, d), angles, exact[:, [0, 2, 1, 3]], monkeypatch)
    assert feasible.all() and exact[-1, 4] < 1e-9
    assert scale[-1] > 1e19 and error.max() < 1e-5


def test_a_slider_cranks_change_point_has_the_same_reach(tmp_path, monkeypatch):
    # a = b = 1, e = 0: 1 + sin(psi) touches zero at 90 deg. Measured below the reach: forces 2e-6
    # off at 4.5e-8 and 1.7e-3 at 4.5e-10 (tests above hold the four-bars' worse figures).
    monkeypatch.chdir(tmp_path)
    text = textwrap.dedent("""\
        [links.crank]
        joints = [[0.0, 0.0], [1.0, 0.0]]
        mass = 2.0
        inertia = 0.3
        center_of_mass = [0.5, 0.0]
        [links.rod]
        joints = [[0.0, 0.0], [1.0, 0.0]]
        mass = 1.5
        inertia = 0.2
        center_of_mass = [0.5, 0.05]
        [links.ground]
        joints = [[0.0, 0.0], [1.0, 0.0]]
        [mechanisms.main]
        type = "slider-crank"
        crank = "crank"
        coupler = "rod"
        ground = "ground"
        [motion]
        input_angle_deg = [ANGLES]
        input_speed_rad_s = 3.0
        input_acceleration_rad_s2 = 2.0
        [loads.couples]
        rod = 5.0
        """)
    angles = 90.0 - np.degrees(OFF)
    exact = exact_slider_rates(1.0, 1.0, np.radians(angles), 3.0, 2.0)
    feasible, _, error = force_errors(text, angles, exact, monkeypatch, roles=("coupler",))
    np.testing.assert_array_equal(feasible, exact[:, 2] >= CHANGE_POINT_REACH)
    assert error[feasible].max() < 1e-6
    monkeypatch.setattr(slider_crank, "CHANGE_POINT_REACH", TOGGLE_TOLERANCE)
    feasible, _, error = force_errors(text, angles, exact, monkeypatch, roles=("coupler",))
    assert feasible.all() and error[exact[:, 2] < 1e-10].max() > 1e-3


def test_a_crossing_message_prints_enough_digits_to_tell_its_two_angles_apart():
    assert distinct_digits(179.99999999, 180.00000001) == ("179.99999999", "180.00000001")
    assert distinct_digits(60.0, 300.0) == ("60", "300")
    crossing = Crossing(5, math.pi, "change point", "open")
    text = describe("main", "four-bar", crossing, 179.9999999, 180.0000001, True)
    assert "crossed between input 179.9999999 and 180.0000001 deg" in text
