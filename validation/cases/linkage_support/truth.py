"""A case's independent truth, from its positions function: rates by finite differences, forces by
Newton-Euler, the power balance, written to ``truth.json`` beside the case's scene.

The case gives ``place(x)``: every link's joints (P, n, 2) [m] in the sketch's joint order (x then
y as drawn) at inputs x (P,) [rad for a crank, m for a stroke], computed step by step from its
published lengths (``geometry``). What the mechanism is made of and how it is loaded is read from
the case's ``scene.toml`` with ``tomllib`` (its pins, sliders, input, motion and loads) and its
drawing (mass, inertia and centre of mass of each plate from linkstress's ``LinkProfile``, which are
exact and tested). Nothing here calls linkstress's kinematics or dynamics.

Conventions (those of the ``type = "linkage"`` scene): a link's frame runs from its joint 0 to its
joint 1, a one-joint block's from its joint along its slider's line (from the line's joint i toward
j); ``angle_deg`` is that frame's direction, counter-clockwise from the ground's +x, in (-180, 180];
a pin's ``forces_n`` are the forces it puts on each joint's link; a slider's ``normal_force_n`` is the
guide's push on the block along the line's left normal, ``couple_nm`` its couple on the block,
``pin_force_n`` the force the pin at the point puts on the block; the input is a torque on the crank
or a force along the input slider's line on its block.
"""

from __future__ import annotations

import json
import math
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from linkstress.importers import read_sketch
from linkstress.materials import Material

from linkage_support import forces as ne
from linkage_support.geometry import distance
from linkage_support.rates import angle_derivatives, derivatives, in_time, stencil

FloatArray = NDArray[np.float64]
Place = Callable[[FloatArray], dict[str, FloatArray]]
TRUTH_FILE = "truth.json"


def linked(points: Callable[[FloatArray], dict[str, FloatArray]], links: dict[str, tuple[str, ...]]) -> Place:
    """A ``place`` from named points: ``links`` gives each link's joints by name, in the drawing's order."""
    def place(x: FloatArray) -> dict[str, FloatArray]:
        p = points(np.asarray(x, float))
        return {link: np.stack([p[name] for name in names], axis=1) for link, names in links.items()}

    return place


@dataclass(frozen=True)
class Case:
    """A case folder's scene (as TOML), its linkage table and drawn joints."""

    folder: Path
    scene: dict

    @classmethod
    def read(cls, folder: Path) -> Case:
        return cls(folder, tomllib.loads((folder / "scene.toml").read_text(encoding="utf-8")))

    @property
    def name(self) -> str:
        return self.folder.name

    @property
    def mechanism(self) -> dict:
        (table,) = [m for m in self.scene["mechanisms"].values() if m.get("type") == "linkage"]
        return table

    @property
    def ground(self) -> str:
        return self.mechanism["ground"]

    @property
    def sliders(self) -> list[dict]:
        return list(self.mechanism.get("sliders", []))

    @property
    def blocks(self) -> dict[str, dict]:
        return {s["block"]: s for s in self.sliders if "block" in s}

    @property
    def moving(self) -> list[str]:
        return [name for name in self.scene["links"] if name != self.ground]

    def drawn(self, link: str) -> FloatArray:
        """The link's joints as drawn (n, 2) [m]: the sketch's (x then y), or the bare ones."""
        entry = self.scene["links"][link]
        if "joints" in entry:
            return np.array(entry["joints"], float)
        return np.asarray(_sketch(self.folder / entry["sketch"]).link(entry.get("layer")).joints, float)

    def pins(self) -> list[list[str]]:
        """The scene's pins, each block's joint 0 added to the pin that holds its slider's point (or
        a pin of their own after the others, in slider order)."""
        pins = [list(pin) for pin in self.mechanism["pins"]]
        for slider in self.sliders:
            if "block" not in slider:
                continue
            holder = next((pin for pin in pins if slider["point"] in pin), None)
            if holder is None:
                pins.append([slider["point"], f"{slider['block']}:0"])
            else:
                holder.append(f"{slider['block']}:0")
        return pins

    def mass_data(self, link: str) -> tuple[float, float, FloatArray]:
        """(mass [kg], inertia about G [kg m^2], G in the link's frame [m])."""
        entry = self.scene["links"][link]
        if "mass" in entry:
            return float(entry["mass"]), float(entry["inertia"]), np.array(entry["center_of_mass"], float)
        density = self.scene["materials"][entry["material"]]["density"]
        sketch = _sketch(self.folder / entry["sketch"]).link(entry.get("layer"))
        profile = sketch.profile(entry["thickness"], Material(entry["material"], density))
        origin, angle = self.drawn_frame(link)
        c, s = math.cos(angle), math.sin(angle)
        d = profile.center_of_mass - origin
        return profile.mass, profile.mass_moment_of_inertia, np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1]])

    def drawn_frame(self, link: str) -> tuple[FloatArray, float]:
        """The link's frame as drawn: origin and angle [rad]."""
        joints = self.drawn(link)
        if link in self.blocks:
            slider = self.blocks[link]
            guide = self.drawn(slider["on"])
            i, j = slider["line"]
            d = guide[j] - guide[i]
            return joints[0], math.atan2(d[1], d[0])
        d = joints[1] - joints[0]
        return joints[0], math.atan2(d[1], d[0])


@cache
def _sketch(path: Path):
    """The drawing at ``path``, read once."""
    return read_sketch(path)


def motion(scene: dict) -> tuple[str, FloatArray, FloatArray, FloatArray]:
    """(kind "angle" or "stroke", inputs [rad or m], speeds, accelerations) from ``[motion]``."""
    table = scene["motion"]
    if "input_stroke_m" in table:
        kind, keys, scale = "stroke", ("input_stroke_m", "input_speed_m_s", "input_acceleration_m_s2"), 1.0
    else:
        kind, keys, scale = "angle", ("input_angle_deg", "input_speed_rad_s", "input_acceleration_rad_s2"), math.pi / 180
    values = table[keys[0]]
    if isinstance(values, dict):
        x = np.linspace(values["start"], values["stop"], values["num"])
    else:
        x = np.atleast_1d(np.asarray(values, float))
    rates = [np.broadcast_to(np.asarray(table.get(key, 0.0), float), x.shape).copy() for key in keys[1:]]
    return kind, x * scale, rates[0], rates[1]


@dataclass(frozen=True)
class Kinematics:
    """Every link's joints (P, n, 2), their velocities and accelerations, its angle (P,), omega,
    alpha; each moving link's G (P, 2) and its rates; each applied force's point and velocity."""

    joints: dict[str, FloatArray]
    joint_velocity: dict[str, FloatArray]
    joint_acceleration: dict[str, FloatArray]
    angle: dict[str, FloatArray]
    omega: dict[str, FloatArray]
    alpha: dict[str, FloatArray]
    com: dict[str, FloatArray]
    com_velocity: dict[str, FloatArray]
    com_acceleration: dict[str, FloatArray]
    load_points: list[FloatArray]
    load_velocity: list[FloatArray]


def kinematics(case: Case, place: Place, x: FloatArray, speed: FloatArray, acceleration: FloatArray, step: float) -> Kinematics:
    """Positions at ``x`` and rates by the eighth-order central differences with ``step``."""
    shape = (9, len(x))
    samples = {name: joints.reshape(shape + joints.shape[1:]) for name, joints in place(stencil(x, step).ravel()).items()}
    angles = {name: _angles(case, name, samples) for name in samples}
    com = {}
    for name in case.moving:
        _, _, local = case.mass_data(name)
        com[name] = _point(samples[name][..., 0, :], angles[name], local)
    load_points = [_point(samples[f["link"]][..., 0, :], angles[f["link"]], np.array(f["at_m"], float))
                   for f in case.scene.get("loads", {}).get("forces", [])]

    def rates(values):
        first, second = derivatives(values, step)
        return in_time(first, second, speed, acceleration)

    joint_rates = {name: rates(s) for name, s in samples.items()}
    angle_rates = {}
    for name, a in angles.items():
        first, second = angle_derivatives(a, step)
        angle_rates[name] = in_time(first, second, speed, acceleration)
    com_rates = {name: rates(g) for name, g in com.items()}
    return Kinematics(
        {name: s[4] for name, s in samples.items()},
        {name: r[0] for name, r in joint_rates.items()},
        {name: r[1] for name, r in joint_rates.items()},
        {name: a[4] for name, a in angles.items()},
        {name: r[0] for name, r in angle_rates.items()},
        {name: r[1] for name, r in angle_rates.items()},
        {name: g[4] for name, g in com.items()},
        {name: r[0] for name, r in com_rates.items()},
        {name: r[1] for name, r in com_rates.items()},
        [p[4] for p in load_points],
        [rates(p)[0] for p in load_points],
    )


def _angles(case: Case, name: str, samples: dict[str, FloatArray]) -> FloatArray:
    """The link's frame angle (9, P) [rad]: joint 0 -> 1, a block's slider line i -> j."""
    if name in case.blocks:
        slider = case.blocks[name]
        guide = samples[slider["on"]]
        i, j = slider["line"]
        d = guide[..., j, :] - guide[..., i, :]
    else:
        joints = samples[name]
        if joints.shape[-2] < 2:
            return np.zeros(joints.shape[:-2])
        d = joints[..., 1, :] - joints[..., 0, :]
    return np.arctan2(d[..., 1], d[..., 0])


def _point(origin: FloatArray, angle: FloatArray, local: FloatArray) -> FloatArray:
    """A link's material point at ``local`` (its frame) in the ground frame."""
    c, s = np.cos(angle), np.sin(angle)
    return origin + np.stack([c * local[0] - s * local[1], s * local[0] + c * local[1]], axis=-1)


def joint_of(kin_values: dict[str, FloatArray], label: str) -> FloatArray:
    """``"LINK:i"``'s entry (P, 2) in a per-link table of (P, n, 2)."""
    link, index = label.rsplit(":", 1)
    return kin_values[link][:, int(index)]


def forces(case: Case, kin: Kinematics, speed: FloatArray, massless: bool = False
           ) -> tuple[ne.Forces, ne.Power, list[ne.PinJoint], list[ne.Slide]]:
    """The Newton-Euler solution over the sweep and its power balance; ``massless``: every link's
    mass and inertia taken as zero (a hand check: a binary link without loads is then a two-force
    member)."""
    scene = case.scene
    bodies = []
    for name in case.moving:
        mass, inertia, _ = (0.0, 0.0, None) if massless else case.mass_data(name)
        bodies.append(ne.Body(name, mass, inertia, kin.com[name], kin.com_acceleration[name], kin.alpha[name]))
    pins = [ne.PinJoint(tuple(pin), tuple(label.rsplit(":", 1)[0] for label in pin), joint_of(kin.joints, pin[0]))
            for pin in case.pins()]
    slides = []
    for slider in case.sliders:
        guide = kin.joints[slider["on"]]
        i, j = slider["line"]
        d = guide[:, j] - guide[:, i]
        u = d / distance(guide[:, i], guide[:, j])[:, None]
        point = joint_of(kin.joints, slider["point"])
        carrier = slider.get("block", slider["point"].rsplit(":", 1)[0])
        slides.append(ne.Slide(carrier, slider["on"], point, u, "block" in slider))
    entry = case.mechanism["input"]
    drive = ("force", entry["slider"]) if "slider" in entry else ("torque", entry["link"])
    loads_table = scene.get("loads", {})
    gravity = np.array(loads_table.get("gravity_m_s2", [0.0, 0.0]), float)
    n = len(speed)
    loads = [ne.Load(f["link"], force=np.tile(np.array(f["force_n"], float), (n, 1)), at=at)
             for f, at in zip(loads_table.get("forces", []), kin.load_points)]
    velocities: list[FloatArray | None] = list(kin.load_velocity)
    for link, value in loads_table.get("couples", {}).items():
        value = value["value"] if isinstance(value, dict) else value
        loads.append(ne.Load(link, couple=np.full(n, float(value))))
        velocities.append(None)
    solution = ne.solve(bodies, case.ground, pins, slides, drive, loads, gravity)
    power = ne.power_balance(bodies, kin.com_velocity, kin.omega, loads, velocities, gravity, solution.drive * speed)
    return solution, power, pins, slides


def closure(case: Case, kin: Kinematics) -> dict[str, float]:
    """The largest gaps [m] over the sweep: between the joints of a pin, of a slider's point off its
    line, and of a link's joint distances against the drawing's."""
    pin_gap = max(float(distance(joint_of(kin.joints, pin[0]), joint_of(kin.joints, label)).max())
                  for pin in case.pins() for label in pin)
    line_gap = 0.0
    for slider in case.sliders:
        guide = kin.joints[slider["on"]]
        i, j = slider["line"]
        d = guide[:, j] - guide[:, i]
        w = joint_of(kin.joints, slider["point"]) - guide[:, i]
        line_gap = max(line_gap, float(np.abs(d[:, 0] * w[:, 1] - d[:, 1] * w[:, 0]).max() / distance(guide[:, i], guide[:, j]).min()))
    rigid = 0.0
    for name, joints in kin.joints.items():
        drawn = case.drawn(name)
        for a in range(len(drawn)):
            for b in range(a + 1, len(drawn)):
                rigid = max(rigid, float(np.abs(distance(joints[:, a], joints[:, b]) - distance(drawn[a], drawn[b])).max()))
    return {"pins_m": pin_gap, "sliders_m": line_gap, "links_m": rigid}


def largest_change(a: Kinematics, b: Kinematics, ground: str) -> dict[str, float]:
    """The largest change between two steps' rates, each kind of quantity (joint velocities, G
    velocities, omegas; the same for accelerations) over the moving links relative to its largest
    size over the links and the sweep (a crank's alpha of zero is judged against the others')."""
    def relative(x: dict, y: dict) -> float:
        names = [k for k in x if k != ground]
        scale = max(float(np.abs(x[k]).max()) for k in names)
        return max(float(np.abs(x[k] - y[k]).max()) for k in names) / scale

    return {
        "velocity": max(relative(a.joint_velocity, b.joint_velocity), relative(a.com_velocity, b.com_velocity),
                        relative(a.omega, b.omega)),
        "acceleration": max(relative(a.joint_acceleration, b.joint_acceleration),
                            relative(a.com_acceleration, b.com_acceleration), relative(a.alpha, b.alpha)),
    }


def record(folder: Path, place: Place, step: float) -> dict:
    """The case's truth over its scene's sweep, as ``truth.json`` holds it."""
    case = Case.read(folder)
    kind, x, speed, acceleration = motion(case.scene)
    kin = kinematics(case, place, x, speed, acceleration, step)
    check = kinematics(case, place, x, speed, acceleration, step / 2)
    solution, power, pins, slides = forces(case, kin, speed)
    return {
        "case": case.name,
        "input": {
            "kind": kind,
            "values": (np.degrees(x) if kind == "angle" else x).tolist(),
            "unit": "deg" if kind == "angle" else "m",
            "speed": speed.tolist(),
            "acceleration": acceleration.tolist(),
        },
        "finite_differences": {"step": step, "step_unit": "rad" if kind == "angle" else "m", "order": 8,
                               "largest_change_at_half_step": largest_change(kin, check, case.ground)},
        "closure": closure(case, kin),
        "ground": {"name": case.ground, "joints_m": case.drawn(case.ground).tolist()},
        "positions": _positions(case, kin, solution, power, pins, slides, kind, x),
    }


def run(folder: Path, place: Place, step: float) -> dict:
    """``record`` written to ``truth.json`` in ``folder`` (whole or not at all); returns it."""
    truth = record(folder, place, step)
    path = folder / TRUTH_FILE
    temporary = path.with_suffix(".json.tmp")
    temporary.write_text(json.dumps(truth, indent=1) + "\n", encoding="utf-8")
    temporary.replace(path)
    return truth


def _positions(case: Case, kin: Kinematics, solution: ne.Forces, power: ne.Power, pins: list[ne.PinJoint],
               slides: list[ne.Slide], kind: str, x: FloatArray) -> list[dict]:
    records = []
    drive_key = "driving_torque_nm" if kind == "angle" else "driving_force_n"
    for p in range(len(x)):
        links = {}
        for name in case.moving:
            links[name] = {
                "joints_m": kin.joints[name][p].tolist(),
                "angle_deg": math.degrees(kin.angle[name][p]),
                "omega_rad_s": float(kin.omega[name][p]),
                "alpha_rad_s2": float(kin.alpha[name][p]),
                "G_m": kin.com[name][p].tolist(),
                "acc_G_m_s2": kin.com_acceleration[name][p].tolist(),
            }
        pin_records = [{"joints": list(pin.joints), "at_m": pin.at[p].tolist(),
                        "forces_n": {label: f[p].tolist() for label, f in on.items()}}
                       for pin, on in zip(pins, solution.pins)]
        slider_records = []
        for s, (slider, slide) in enumerate(zip(case.sliders, slides)):
            guide = kin.joints[slider["on"]][p]
            pin_force = _block_pin_force(slider, pin_records)
            slider_records.append({
                "point": slider["point"], "on": slider["on"],
                "stroke_m": float(slide.direction[p] @ (slide.at[p] - guide[slider["line"][0]])),
                "normal_force_n": float(solution.normals[s][p]), "couple_nm": float(solution.couples[s][p]),
                "friction_force_n": 0.0, "pin_force_n": pin_force,
            })
        records.append({
            "input": float(np.degrees(x[p]) if kind == "angle" else x[p]),
            "links": links, "pins": pin_records, "sliders": slider_records,
            drive_key: float(solution.drive[p]),
            "power_w": {"input": float(power.input[p]), "kinetic_energy_rate": float(power.kinetic[p]),
                        "applied_loads": float(power.applied[p]), "mismatch": float(power.mismatch[p])},
        })
    return records


def _block_pin_force(slider: dict, pins: list[dict]) -> list[float] | None:
    """The force the pin at the slider's point puts on its block (None without a block)."""
    if "block" not in slider:
        return None
    label = f"{slider['block']}:0"
    return next(pin["forces_n"][label] for pin in pins if label in pin["forces_n"])


def summary(truth: dict) -> str:
    """A few lines on the truth: sweep, closure, finite-difference change, power balance, extremes."""
    positions = truth["positions"]
    drive_key = "driving_torque_nm" if truth["input"]["kind"] == "angle" else "driving_force_n"
    drive = np.array([p[drive_key] for p in positions])
    power = np.array([p["power_w"]["input"] for p in positions])
    mismatch = np.array([p["power_w"]["mismatch"] for p in positions])
    pin_force = max(math.hypot(*f) for p in positions for pin in p["pins"] for f in pin["forces_n"].values())
    values = truth["input"]["values"]
    fd = truth["finite_differences"]["largest_change_at_half_step"]
    lines = [
        f"{truth['case']}: {len(positions)} positions, input {values[0]:g} to {values[-1]:g} {truth['input']['unit']}",
        "  closure: pins {pins_m:.1e} m, sliders {sliders_m:.1e} m, link lengths {links_m:.1e} m".format(**truth["closure"]),
        f"  finite differences (step {truth['finite_differences']['step']:g} {truth['finite_differences']['step_unit']}): "
        f"largest change at half the step: velocities {fd['velocity']:.1e}, accelerations {fd['acceleration']:.1e} (relative)",
        f"  power balance: largest mismatch {np.abs(mismatch).max():.2e} W = {np.abs(mismatch).max() / np.abs(power).max():.1e} "
        f"of the largest input power {np.abs(power).max():.4g} W",
        f"  {drive_key}: {drive.min():.6g} to {drive.max():.6g}; largest pin force {pin_force:.6g} N",
    ]
    return "\n".join(lines)
