"""Fatigue from the superposed FEA's stress history, against stresses known by hand: a bar under a
cyclic axial load (closed-form Goodman factor) and a crank spinning at constant speed under a force
fixed in the ground (mean and alternating stress from beam statics)."""

from __future__ import annotations

import math

import numpy as np

from linkstress.geometry.builders import straight_bar
from linkstress.fatigue import node_fatigue, safety_factor
from linkstress.loads import LinkLoadCase
from linkstress.materials import Material
from linkstress.validation.fea.mesh import MeshSettings
from linkstress.validation.peaks import sweep_peaks
from linkstress.validation.fea.unit_loads import unit_load_cases

STEEL = Material("steel", 7850.0, 200e9, 0.3, 350e6, endurance_limit=200e6, ultimate_strength=400e6)
STRENGTH = STEEL.fatigue_strength
THETA = np.deg2rad(np.arange(0.0, 360.0, 10.0))  # 36 positions of one cycle, 90 and 270 deg among them


def nodes_near(nodes: np.ndarray, point: tuple[float, float], radius: float) -> np.ndarray:
    return np.flatnonzero(np.hypot(*(nodes - np.asarray(point)).T) <= radius)


def test_a_bar_under_a_cyclic_axial_load_has_the_closed_form_goodman_factor_away_from_its_holes():
    # F(theta) = 8 kN + 12 kN sin(theta) on a 60 x 5 mm bar: sigma_m = 8e3 / 3e-4 = 26.7 MPa, sigma_a = 40 MPa;
    # Goodman (Shigley ch. 6): 1 / n = sigma_a / S_e + sigma_m / S_ut = 0.2 + 0.0667, n = 3.75.
    bar = straight_bar(0.6, 0.06, 0.04, 0.005, STEEL, hole_diameter=0.012, name="bar")
    force = 8e3 + 12e3 * np.sin(THETA)
    pins = np.zeros((len(THETA), 2, 2))
    pins[:, 1, 0], pins[:, 0, 0] = force, -force
    zero = np.zeros(len(THETA))
    loads = LinkLoadCase((0, 1), pins, np.zeros((len(THETA), 2)), zero, zero, np.zeros((len(THETA), 2)), np.zeros((len(THETA), 2)))
    peaks = sweep_peaks(unit_load_cases(bar, loads, MeshSettings(0.01, 0.0015)), loads)
    area = 0.06 * 0.005
    sigma_a, sigma_m = 12e3 / area, 8e3 / area
    n = 1 / (sigma_a / 200e6 + sigma_m / 400e6)
    assert n == np.float64(safety_factor("goodman", sigma_a, sigma_m, STRENGTH))
    middle = nodes_near(peaks.cases.nodes, (0.3, 0.0), 0.03)  # five depths from either hole
    fatigue = node_fatigue(peaks.largest[middle], peaks.smallest[middle], STRENGTH)
    assert abs(fatigue.sigma_a / sigma_a - 1) <= 2e-3 and abs(fatigue.sigma_m / sigma_m - 1) <= 2e-3
    assert abs(fatigue.factor / n - 1) <= 2e-3
    whole = node_fatigue(peaks.largest, peaks.smallest, STRENGTH)
    critical = peaks.cases.nodes[whole.critical_node]
    assert whole.factor < n / 2  # the pin holes concentrate the stress (Kt ~ 2-3 for a lug)
    assert min(np.hypot(*(critical - joint)) for joint in bar.joints) <= 0.012  # at a hole's rim


def test_a_crank_spinning_under_a_force_fixed_in_the_ground_has_the_hand_mean_and_alternating_stress():
    # A crank 0.5 m between pins, 50 x 10 mm, turning at 100 rad/s about joint 0; the tip pin carries
    # F = 400 N fixed in the ground (x), which turns in the crank's frame; the pivot carries the rest.
    # Beam statics of the piece beyond the cut (hand, below).
    # At the top-fibre node nearest mid-span, x0:
    #   N = F_x(theta) + rho t omega^2 Q (Q: first moment about the pivot of the piece's area),
    #   M = (L - x0) F_y(theta), sigma_top = N / A - M (h / 2) / I.
    length, depth, thickness, overhang, hole = 0.5, 0.05, 0.01, 0.03, 0.015
    crank = straight_bar(length, depth, overhang, thickness, STEEL, hole_diameter=hole, name="crank")
    omega, force = 100.0, 400.0
    p = len(THETA)
    tip = force * np.column_stack([np.cos(-THETA), np.sin(-THETA)])  # (F, 0) in the ground, crank at theta
    mass = crank.mass
    r_g = crank.center_of_mass
    pins = np.stack([-tip - mass * omega**2 * r_g, tip], axis=1)
    couples = np.column_stack([-length * tip[:, 1], np.zeros(p)])  # the driving torque through the pivot
    loads = LinkLoadCase((0, 1), pins, couples, np.full(p, omega), np.zeros(p), np.zeros((p, 2)), np.zeros((p, 2)))
    residual_force, residual_moment = loads.residual(crank)
    assert np.abs(residual_force).max() < 1e-9 and np.abs(residual_moment).max() < 1e-9
    peaks = sweep_peaks(unit_load_cases(crank, loads, MeshSettings(0.006, 0.0015)), loads)

    nodes = peaks.cases.nodes
    on_top = np.flatnonzero(np.abs(nodes[:, 1] - depth / 2) <= 1e-9)
    node = on_top[np.argmin(np.abs(nodes[on_top, 0] - length / 2))]  # the top-fibre node nearest mid-span
    x0 = float(nodes[node, 0])
    assert abs(x0 - length / 2) <= 0.006
    beyond_length = length + overhang - x0
    beyond_area = depth * beyond_length - math.pi * hole**2 / 4
    first_moment = depth * beyond_length * (x0 + beyond_length / 2) - math.pi * hole**2 / 4 * length
    area, inertia = depth * thickness, thickness * depth**3 / 12
    normal = tip[:, 0] + STEEL.density * thickness * omega**2 * first_moment
    moment = (length - x0) * tip[:, 1]
    top = normal / area - moment * (depth / 2) / inertia
    hand_a, hand_m = (top.max() - top.min()) / 2, (top.max() + top.min()) / 2
    assert beyond_area > 0 and hand_m > 0.3 * hand_a  # both matter: 26 MPa alternating, 8.6 MPa mean

    fea_a = (peaks.largest[node] - peaks.smallest[node]) / 2
    fea_m = (peaks.largest[node] + peaks.smallest[node]) / 2
    assert abs(fea_a - hand_a) <= 0.01 * hand_a and abs(fea_m - hand_m) <= 0.01 * hand_a
    fatigue = node_fatigue(peaks.largest[[node]], peaks.smallest[[node]], STRENGTH)
    assert abs(fatigue.factor / float(safety_factor("goodman", hand_a, hand_m, STRENGTH)) - 1) <= 0.01
