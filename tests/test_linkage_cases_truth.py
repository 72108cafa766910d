"""The linkage cases of issue 29 (validation/cases): each one's drawing, scene and independent truth.

stephenson3_press (a four-bar with a dyad hung from its coupler point), watt2_sixbar (the bell crank
machine as one linkage), whitworth_shaper (a crank-shaper quick-return: a collar sliding in a
moving lever, a ram on the frame's guide), jansen_leg (Jansen's published lengths), klann_leg (the
example of Klann's patent), triad_sixbar (a floating ternary link held by three binary links) and
loader_arm_cylinder (a hydraulic cylinder's stroke as the input). Each truth.py computes positions
by circle and line intersections from the lengths, rates by eighth-order central differences and
forces by its own Newton-Euler assembly (validation/cases/linkage_support), never by linkstress's
kinematics or dynamics. The last test compares linkstress's analysis of each scene with its truth
within issue 29's bounds; it needs the linkage engine.
"""

from __future__ import annotations

import dataclasses
import json
import math
import runpy
import sys
import tomllib
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from linkstress.importers import read_sketch

CASES_DIR = Path(__file__).resolve().parents[1] / "validation" / "cases"
sys.path.insert(0, str(CASES_DIR))

from linkage_support import truth as support  # noqa: E402
from linkage_support.rates import derivatives, stencil  # noqa: E402

CASES = (
    "stephenson3_press", "watt2_sixbar", "whitworth_shaper", "jansen_leg", "klann_leg", "triad_sixbar",
    "loader_arm_cylinder",
)


@cache
def module(case: str) -> dict:
    """The globals of the case's truth.py (its lengths, ``points``, ``place``, ``STEP``...)."""
    return runpy.run_path(str(CASES_DIR / case / "truth.py"))


@cache
def scene(case: str) -> dict:
    return tomllib.loads((CASES_DIR / case / "scene.toml").read_text(encoding="utf-8"))


@cache
def stored(case: str) -> dict:
    return json.loads((CASES_DIR / case / "truth.json").read_text(encoding="utf-8"))


def linkage(case: str) -> dict:
    (table,) = [m for m in scene(case)["mechanisms"].values() if m["type"] == "linkage"]
    return table


def drawing(case: str) -> Path:
    (sketch,) = {entry["sketch"] for entry in scene(case)["links"].values()}
    return CASES_DIR / case / sketch


def joint_at(joints: dict[str, np.ndarray], label: str) -> np.ndarray:
    link, index = label.rsplit(":", 1)
    return np.asarray(joints[link], float)[..., int(index), :]


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


# -- drawings and scenes --------------------------------------------------------------------------


@pytest.mark.parametrize("case", CASES)
def test_the_sketch_script_reproduces_the_committed_drawing(tmp_path, case):
    path = drawing(case)
    runpy.run_path(str(CASES_DIR / case / "make_sketch.py"))["write"](tmp_path / path.name)
    assert (tmp_path / path.name).read_bytes() == path.read_bytes()


@pytest.mark.parametrize("case", CASES)
def test_the_drawing_imports_every_scene_link_with_the_joints_the_truth_places(case):
    # Every link of the scene is a layer of the drawing and nothing else is; its joints, numbered by
    # x then y as the importer numbers them, are where truth.py puts them at the drawn input.
    sketch = read_sketch(drawing(case))
    assert sorted(link.layer for link in sketch.links) == sorted(entry["layer"] for entry in scene(case)["links"].values())
    truth = module(case)
    placed = truth["place"](np.array([truth["DRAWN_INPUT"]]))
    for name, entry in scene(case)["links"].items():
        joints = sketch.link(entry["layer"]).joints
        assert joints.shape == placed[name][0].shape, name
        assert np.abs(joints - placed[name][0]).max() <= 1e-12, name


@pytest.mark.parametrize("case", CASES)
def test_the_scene_pins_and_slides_coinciding_joints_of_the_drawing(case):
    sketch = read_sketch(drawing(case))
    joints = {name: sketch.link(entry["layer"]).joints for name, entry in scene(case)["links"].items()}
    table = linkage(case)
    for pin in table["pins"]:
        spread = max(np.hypot(*(joint_at(joints, label) - joint_at(joints, pin[0]))) for label in pin)
        assert spread <= 1e-9, pin
    for slider in table.get("sliders", []):
        i, j = slider["line"]
        q, r = joints[slider["on"]][i], joints[slider["on"]][j]
        off = abs(cross(r - q, joint_at(joints, slider["point"]) - q)) / np.hypot(*(r - q))
        assert off <= 1e-9, slider
        if "block" in slider:
            assert np.hypot(*(joints[slider["block"]][0] - joint_at(joints, slider["point"]))) <= 1e-9
    if "link" in table["input"]:
        pivot = f"{table['input']['link']}:{table['input'].get('pivot', 0)}"
        assert any(pivot in pin and any(label.startswith(table["ground"] + ":") for label in pin) for pin in table["pins"])


@pytest.mark.parametrize("case", CASES)
def test_each_scene_has_one_degree_of_freedom_by_grueblers_count(case):
    # Uicker, Pennock & Shigley, Theory of Machines and Mechanisms, sec. 1.10: F = 3 (n - 1) - 2 j1 - j2,
    # a pin of k links k - 1 full joints; a slider with a block is a pin and a slide, without one a half joint.
    table = linkage(case)
    sliders = table.get("sliders", [])
    n = len(scene(case)["links"])
    j1 = sum(len(pin) - 1 for pin in table["pins"]) + 2 * sum("block" in s for s in sliders)
    j2 = sum("block" not in s for s in sliders)
    assert 3 * (n - 1) - 2 * j1 - j2 == 1


# -- the truths ----------------------------------------------------------------------------------


@pytest.mark.parametrize("case", CASES)
def test_the_truth_closes_every_loop_at_every_listed_position(case):
    # At every position of truth.json: each link keeps its drawn joint distances, each pin's joints
    # meet, each slider's point is on its line, and the input is at the listed value; within 1e-12 m.
    truth = stored(case)
    drawn = {name: read_sketch(drawing(case)).link(entry["layer"]).joints for name, entry in scene(case)["links"].items()}
    table = linkage(case)
    ground = table["ground"]
    for k, position in enumerate(truth["positions"]):
        joints = {name: np.array(link["joints_m"]) for name, link in position["links"].items()}
        joints[ground] = np.array(truth["ground"]["joints_m"])
        for name, points in joints.items():
            gaps = np.hypot(*(points[:, None] - points[None]).T) - np.hypot(*(drawn[name][:, None] - drawn[name][None]).T)
            assert np.abs(gaps).max() <= 1e-12, (k, name)
        for pin in table["pins"]:
            assert max(np.hypot(*(joint_at(joints, label) - joint_at(joints, pin[0]))) for label in pin) <= 1e-12, (k, pin)
        for s, slider in enumerate(table.get("sliders", [])):
            i, j = slider["line"]
            q, r = joints[slider["on"]][i], joints[slider["on"]][j]
            assert abs(cross((r - q) / np.hypot(*(r - q)), joint_at(joints, slider["point"]) - q)) <= 1e-12, (k, slider)
        value = truth["input"]["values"][k]
        if "slider" in table["input"]:
            assert abs(position["sliders"][table["input"]["slider"]]["stroke_m"] - value) <= 1e-12
        else:
            spec = table["input"]
            d = joint_at(joints, f"{spec['link']}:{spec.get('to', 1)}") - joint_at(joints, f"{spec['link']}:{spec.get('pivot', 0)}")
            assert abs(math.remainder(math.atan2(d[1], d[0]) - math.radians(value), 2 * math.pi)) <= 1e-12


@pytest.mark.parametrize("case", CASES)
def test_the_committed_truth_is_what_truth_py_computes(case):
    fresh = support.record(CASES_DIR / case, module(case)["place"], module(case)["STEP"])
    assert _largest_difference(fresh, stored(case)) <= 1e-9


def _largest_difference(a, b) -> float:
    """The largest difference between the numbers of two like structures, each relative to the
    larger of 1 and its own size (strings and structure must match)."""
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        return max((_largest_difference(a[k], b[k]) for k in a), default=0.0)
    if isinstance(a, list):
        assert len(a) == len(b)
        return max((_largest_difference(x, y) for x, y in zip(a, b)), default=0.0)
    if isinstance(a, (int, float)) and not isinstance(a, bool):
        return abs(a - b) / max(1.0, abs(a))
    assert a == b
    return 0.0


@pytest.mark.parametrize("case", CASES)
def test_the_truths_rates_agree_between_two_finite_difference_steps(case):
    # Velocities and accelerations by the eighth-order central differences (Fornberg 1988) with the
    # case's step and half of it: each kind of quantity changes by less than 1e-8 of its largest size.
    folder, truth = CASES_DIR / case, module(case)
    c = support.Case.read(folder)
    _, x, speed, acceleration = support.motion(c.scene)
    a = support.kinematics(c, truth["place"], x, speed, acceleration, truth["STEP"])
    b = support.kinematics(c, truth["place"], x, speed, acceleration, truth["STEP"] / 2)
    change = support.largest_change(a, b, c.ground)
    assert change["velocity"] < 1e-8 and change["acceleration"] < 1e-8
    # and a step twenty times larger is caught by the same comparison:
    coarse = support.kinematics(c, truth["place"], x, speed, acceleration, 20 * truth["STEP"])
    assert support.largest_change(coarse, a, c.ground)["acceleration"] > 1e-6


@pytest.mark.parametrize("case", CASES)
def test_the_truths_forces_pass_the_power_balance(case):
    # Input power = d/dt KE - power of the applied loads (gravity included) at every position, to
    # 1e-9 of the largest input power; the input power is the driving torque (force) times its speed.
    truth = stored(case)
    key = "driving_torque_nm" if truth["input"]["kind"] == "angle" else "driving_force_n"
    drive = np.array([p[key] for p in truth["positions"]])
    power = {k: np.array([p["power_w"][k] for p in truth["positions"]]) for k in ("input", "kinetic_energy_rate", "applied_loads")}
    np.testing.assert_allclose(power["input"], drive * np.array(truth["input"]["speed"]), rtol=1e-12)
    mismatch = power["input"] - (power["kinetic_energy_rate"] - power["applied_loads"])
    assert np.abs(mismatch).max() <= 1e-9 * np.abs(power["input"]).max()
    assert np.abs(power["input"]).max() > 0


@pytest.mark.parametrize("case", CASES)
def test_the_truths_forces_hold_every_link_in_equilibrium(case):
    # From truth.json alone, link by link: the pins' forces at its joints, the slides' normal forces
    # and couples, the input, the applied loads and gravity give m a_G and I_G alpha (Newton-Euler).
    truth, c = stored(case), support.Case.read(CASES_DIR / case)
    table = linkage(case)
    loads = scene(case).get("loads", {})
    gravity = np.array(loads.get("gravity_m_s2", [0.0, 0.0]))
    for k, position in enumerate(truth["positions"]):
        links = position["links"]
        force = {name: np.zeros(2) for name in links}
        moment = {name: 0.0 for name in links}

        def push(name: str, f, at, couple: float = 0.0) -> None:
            if name in links:
                force[name] += f
                moment[name] += cross(np.asarray(at) - links[name]["G_m"], np.asarray(f)) + couple

        for pin in position["pins"]:
            for label, f in pin["forces_n"].items():
                push(label.rsplit(":", 1)[0], np.array(f), pin["at_m"])
        for s, (slider, record) in enumerate(zip(table.get("sliders", []), position["sliders"])):
            on = np.array(links[slider["on"]]["joints_m"]) if slider["on"] in links else np.array(truth["ground"]["joints_m"])
            u = on[slider["line"][1]] - on[slider["line"][0]]
            u /= np.hypot(*u)
            n = np.array([-u[1], u[0]])
            at = joint_at({n_: np.array(l["joints_m"]) for n_, l in links.items()}, slider["point"])
            carrier = slider.get("block", slider["point"].rsplit(":", 1)[0])
            drive = position.get("driving_force_n", 0.0) if table["input"].get("slider") == s else 0.0
            push(carrier, record["normal_force_n"] * n + drive * u, at, record["couple_nm"])
            push(slider["on"], -record["normal_force_n"] * n - drive * u, at, -record["couple_nm"])
        if "link" in table["input"]:
            moment[table["input"]["link"]] += position["driving_torque_nm"]
        for f in loads.get("forces", []):
            link = links[f["link"]]
            origin, angle = np.array(link["joints_m"][0]), math.radians(link["angle_deg"])
            rotation = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
            push(f["link"], np.array(f["force_n"]), origin + rotation @ np.array(f["at_m"]))
        for name, value in loads.get("couples", {}).items():
            moment[name] += value["value"] if isinstance(value, dict) else value
        for name, link in links.items():
            mass, inertia, _ = c.mass_data(name)
            scale = max(1.0, np.hypot(*force[name]))
            assert np.abs(force[name] + mass * gravity - mass * np.array(link["acc_G_m_s2"])).max() <= 1e-9 * scale, (k, name)
            assert abs(moment[name] - inertia * link["alpha_rad_s2"]) <= 1e-9 * max(1.0, abs(moment[name])), (k, name)


def _two_force_members() -> list[tuple[str, str]]:
    """(case, link): moving links with two joints, each in a pin, carrying no applied load, that
    are neither the input nor a slider's guide."""
    pairs = []
    for case in CASES:
        table, loads = linkage(case), scene(case).get("loads", {})
        loaded = {f["link"] for f in loads.get("forces", [])} | set(loads.get("couples", {}))
        guides = {s["on"] for s in table.get("sliders", [])}
        pinned = {label for pin in table["pins"] for label in pin} | {s["point"] for s in table.get("sliders", [])}
        for name in scene(case)["links"]:
            if name in loaded | guides or name in (table["ground"], table["input"].get("link")):
                continue
            if len(module(case)["LINKS"][name]) == 2 and {f"{name}:0", f"{name}:1"} <= pinned:
                pairs.append((case, name))
    return pairs


@pytest.mark.parametrize("case, link", _two_force_members())
def test_a_massless_binary_link_without_loads_is_a_two_force_member(case, link):
    # Statics (Uicker, Pennock & Shigley, sec. 12.5): a link with forces at two points only carries
    # them equal, opposite and along the line through the points. With every mass set to zero the
    # truth's assembly must give exactly that: a check of the pin forces beside the power balance.
    folder, truth = CASES_DIR / case, module(case)
    c = support.Case.read(folder)
    _, x, speed, acceleration = support.motion(c.scene)
    kin = support.kinematics(c, truth["place"], x, speed, acceleration, truth["STEP"])
    solution, _, pins, _ = support.forces(c, kin, speed, massless=True)
    on = {}
    for pin, forces in zip(pins, solution.pins):
        for label, f in forces.items():
            if label.startswith(link + ":"):
                on[label] = f
    f0, f1 = on[f"{link}:0"], on[f"{link}:1"]
    axis = kin.joints[link][:, 1] - kin.joints[link][:, 0]
    axis /= np.hypot(*axis.T)[:, None]
    scale = np.hypot(*f0.T).max()
    assert scale > 1.0
    assert np.abs(f0 + f1).max() <= 1e-9 * scale
    assert np.abs(cross(axis, f0)).max() <= 1e-9 * scale


# -- what each mechanism is known for -------------------------------------------------------------


def test_the_crank_shaper_returns_quicker_by_the_textbook_time_ratio():
    # Crank and slotted lever (Uicker, Pennock & Shigley, sec. 1.12; Shigley's quick-return): the
    # ram stops where the crank is square to the lever, so the crank turns 180 + 2 asin(r/c) deg for
    # one stroke and 180 - 2 asin(r/c) for the other. Here the ram's stops are found from the truth's
    # positions alone, by the zeros of its velocity (eighth-order differences of its x).
    truth = module("whitworth_shaper")
    r, c = truth["CRANK"], float(np.hypot(*(truth["O2"] - truth["O4"])))
    step = 1e-3

    def ram_speed(theta: float) -> float:
        samples = truth["points"](stencil(np.array([theta]), step).ravel())["R"][:, 0].reshape(9, 1)
        return float(derivatives(samples, step)[0][0])

    grid = np.radians(np.arange(0.0, 361.0, 5.0))
    speeds = [ram_speed(t) for t in grid]
    stops = [brentq(ram_speed, grid[k], grid[k + 1], xtol=1e-14) for k in range(len(grid) - 1) if speeds[k] * speeds[k + 1] < 0]
    assert len(stops) == 2
    arc = (stops[1] - stops[0]) % (2 * math.pi)  # from the first stop to the second, counter-clockwise
    over_the_top = 2 * math.pi - arc if (math.pi / 2 - stops[0]) % (2 * math.pi) > arc else arc
    s = math.degrees(math.asin(r / c))
    assert over_the_top / (2 * math.pi - over_the_top) == pytest.approx((180 + 2 * s) / (180 - 2 * s), rel=1e-9)
    assert (180 + 2 * s) / (180 - 2 * s) == pytest.approx(1.5521, abs=1e-4)  # r / c = 1/3
    # With the crank straight up or down the lever is upright and turns at omega r / (c + r) and
    # -omega r / (c - r): 1.5 and -3 rad/s at the scene's 6 rad/s.
    by_input = {round(p["input"]): p for p in stored("whitworth_shaper")["positions"]}
    omega = scene("whitworth_shaper")["motion"]["input_speed_rad_s"]
    assert by_input[90]["links"]["lever"]["omega_rad_s"] == pytest.approx(omega * r / (c + r), rel=1e-9)
    assert by_input[270]["links"]["lever"]["omega_rad_s"] == pytest.approx(-omega * r / (c - r), rel=1e-9)
    # The slow stroke, with the crank over the top, drives the ram toward -x: the cutting stroke the
    # scene's 3 kN resists.
    top = truth["points"](np.array([math.pi / 2 - 1e-3, math.pi / 2 + 1e-3]))["R"][:, 0]
    assert top[1] < top[0]


def test_jansens_foot_path_has_its_flat_bottom():
    # Jansen's leg at his lengths (Theo Jansen, The Great Pretender, 2007; strandbeest.com): the foot
    # runs along a nearly flat bottom for about half the crank's turn, then lifts. Over a 0.5 deg sweep
    # of the truth's positions: the longest run of crank angles where the foot is within 1 cm of its
    # lowest point covers at least 150 deg and 0.5 m of travel, out of a path about 22 cm high.
    truth = module("jansen_leg")
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    foot = truth["points"](theta)["G"]
    low = foot[:, 1] <= foot[:, 1].min() + 0.01
    start = int(np.argmin(low))  # a raised position: runs of low ones start after it
    order = (start + np.arange(len(theta))) % len(theta)
    best, run, run_start = 0, 0, 0
    for k, index in enumerate(order):
        run = run + 1 if low[index] else 0
        if run > best:
            best, run_start = run, k - run + 1
    arc = order[run_start:run_start + best]
    assert best * 0.5 >= 150.0
    assert np.ptp(foot[arc, 0]) >= 0.5
    assert 0.2 <= np.ptp(foot[:, 1]) <= 0.25


def test_the_klann_foot_moves_along_a_nearly_straight_line_for_half_the_turn():
    # Klann's leg (US patent 6,260,862; mechanicalspider.com): 180 deg of the crank give the foot's
    # straight stride, the rest lifts and returns it. At the patent's proportions (250 mm per unit)
    # the foot stays within 7 mm of the straight line that fits it best over crank angles 0 to 180 deg
    # while it moves 250 mm, the line within 1 deg of the ground's horizontal.
    truth = module("klann_leg")
    foot = truth["points"](np.radians(np.arange(0.0, 180.5, 0.5)))["F"]
    centred = foot - foot.mean(axis=0)
    _, _, axes = np.linalg.svd(centred)
    off_line = np.abs(centred @ axes[1]).max()
    stride = np.ptp(centred @ axes[0])
    assert off_line <= 0.007
    assert stride >= 0.25
    assert abs(math.remainder(math.atan2(axes[0][1], axes[0][0]), math.pi)) <= math.radians(1.0)
    # and over the other half it lifts well clear:
    other = truth["points"](np.radians(np.arange(180.5, 360.0, 0.5)))["F"]
    assert other[:, 1].max() - foot[:, 1].max() >= 0.05


def test_the_watt_ii_truth_agrees_with_linkstress_on_the_bell_crank_machine():
    # watt2_sixbar is bell_crank's machine (same lengths, plates, speed and load) drawn assembled.
    # linkstress's four-bar chain solves bell_crank in closed form: the truth, built without it,
    # must give the same motion and driving torque (the bell crank's and rod's frames run the other
    # way here: their angles differ by 180 deg).
    from linkstress.analysis import plan_for, run_analysis
    from linkstress.report.records import position_records
    from linkstress.scene import load_scene

    bell = load_scene(CASES_DIR / "bell_crank" / "scene.toml")
    records = position_records(run_analysis(bell, dataclasses.replace(plan_for(bell), stresses=(), validate=())))
    truth = stored("watt2_sixbar")["positions"]
    assert [r["input_angle_deg"] for r in records] == pytest.approx([p["input"] for p in truth], abs=1e-12)
    names = {"crank": ("crank", 0), "coupler": ("coupler", 0), "bellcrank": ("bellcrank", 180), "rod2": ("rod", 180), "out2": ("output", 0)}
    omega = max(abs(p["links"][n]["omega_rad_s"]) for p in truth for n, _ in names.values())
    alpha = max(abs(p["links"][n]["alpha_rad_s2"]) for p in truth for n, _ in names.values())
    for r, p in zip(records, truth):
        for old, (new, turn) in names.items():
            a, b = r["links"][old], p["links"][new]
            assert abs(math.remainder(a["angle_deg"] - b["angle_deg"] - turn, 360.0)) <= 1e-9
            assert abs(a["omega_rad_s"] - b["omega_rad_s"]) <= 1e-9 * omega
            assert abs(a["alpha_rad_s2"] - b["alpha_rad_s2"]) <= 1e-8 * alpha
    torque = np.array([r["mechanisms"]["main"]["driving_torque_nm"] for r in records])
    assert np.abs(torque - [p["driving_torque_nm"] for p in truth]).max() <= 1e-9 * np.abs(torque).max()


# -- linkstress against the truths ---------------------------------------------------------------


@pytest.mark.parametrize("case", CASES)
def test_linkstress_analyses_each_case_as_its_independent_truth(case):
    # Issue 29's bounds: positions within 1e-9 m, angular velocities and accelerations within 1e-7
    # and forces within 1e-6 of their largest size over the sweep, the power balance within 1e-9 of
    # the input power.
    from linkstress.analysis import plan_for, run_analysis
    from linkstress.report.records import position_records
    from linkstress.scene import load_scene

    loaded = load_scene(CASES_DIR / case / "scene.toml")
    records = position_records(run_analysis(loaded, dataclasses.replace(plan_for(loaded), stresses=(), validate=())))
    truth = stored(case)
    positions = truth["positions"]
    assert len(records) == len(positions) and all(r["feasible"] for r in records)
    (name,) = scene(case)["mechanisms"]
    mechanisms = [r["mechanisms"][name] for r in records]
    links = list(positions[0]["links"])
    omega = max(abs(p["links"][n]["omega_rad_s"]) for p in positions for n in links)
    alpha = max(abs(p["links"][n]["alpha_rad_s2"]) for p in positions for n in links)
    for r, p in zip(records, positions):
        for n in links:
            a, b = r["links"][n], p["links"][n]
            assert np.abs(np.array(a["joints_m"]) - b["joints_m"]).max() <= 1e-9, n
            assert abs(math.remainder(a["angle_deg"] - b["angle_deg"], 360.0)) <= math.degrees(1e-9), n
            assert abs(a["omega_rad_s"] - b["omega_rad_s"]) <= 1e-7 * omega, n
            assert abs(a["alpha_rad_s2"] - b["alpha_rad_s2"]) <= 1e-7 * alpha, n

    force = max(math.hypot(*f) for p in positions for pin in p["pins"] for f in pin["forces_n"].values())
    for m, p in zip(mechanisms, positions):
        found = {frozenset(pin["joints"]): pin for pin in m["pins"]}
        for pin in p["pins"]:
            engine = found[frozenset(pin["joints"])]
            assert np.abs(np.array(engine["at_m"]) - pin["at_m"]).max() <= 1e-9
            for label, f in pin["forces_n"].items():
                assert np.abs(np.array(engine["forces_n"][label]) - f).max() <= 1e-6 * force, label
        for engine, slider in zip(m.get("sliders", []), p["sliders"]):
            assert (engine["point"], engine["on"]) == (slider["point"], slider["on"])
            assert abs(engine["stroke_m"] - slider["stroke_m"]) <= 1e-9
            assert abs(engine["normal_force_n"] - slider["normal_force_n"]) <= 1e-6 * force
            if slider["pin_force_n"] is not None:
                assert np.abs(np.array(engine["pin_force_n"]) - slider["pin_force_n"]).max() <= 1e-6 * force
        assert len(m.get("sliders", [])) == len(p["sliders"])
    for k, slider in enumerate(positions[0]["sliders"]):
        couples = np.array([p["sliders"][k]["couple_nm"] for p in positions])
        engine = np.array([m["sliders"][k]["couple_nm"] for m in mechanisms])
        assert np.abs(engine - couples).max() <= 1e-6 * max(np.abs(couples).max(), 1e-300)

    key = "driving_torque_nm" if truth["input"]["kind"] == "angle" else "driving_force_n"
    drive = np.array([m[key] for m in mechanisms])
    expected = np.array([p[key] for p in positions])
    assert np.abs(drive - expected).max() <= 1e-6 * np.abs(expected).max()
    # The engine's input power against the truth's rate of kinetic energy less the applied loads' power.
    power = drive * np.array(truth["input"]["speed"])
    balance = np.array([p["power_w"]["kinetic_energy_rate"] - p["power_w"]["applied_loads"] for p in positions])
    assert np.abs(power - balance).max() <= 1e-9 * np.abs(power).max()
