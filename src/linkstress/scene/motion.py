"""The [motion] table: the main crank's input angles, speed, acceleration, and the actuator.

``input_angle_deg`` is a number, a list of numbers, a range ``{start, stop, num}`` or a function of
time ``{expression = "90*sin(2*pi*t)", t = {start, stop, num}}`` (``t`` may also be a list of times
[s]). A range is ``num`` evenly spaced values from ``start`` to ``stop``, both ends included: a turn
in 10 deg steps is ``{start = 0.0, stop = 350.0, num = 36}``; ``stop = 360.0, num = 37`` ends on the
pose it starts from (``validate`` compares that pose once). Angles are the main crank's,
counter-clockwise from the ground frame's +x. ``input_speed_rad_s`` and ``input_acceleration_rad_s2``
are numbers or one per angle (default 0: a quasi-static sweep); with an expression they are its exact
time derivatives and may not be given; the expression's angles, speeds and accelerations are held to
the ranges of plain values (``linkstress.scene.keys.RANGES``). ``actuator`` names the link that carries the unknown driving torque (default: the
main loop's crank).
"""

from __future__ import annotations

import numpy as np

from linkstress.kinematics.expression import QUOTED, Expression
from linkstress.kinematics.machine import Machine
from linkstress.kinematics.motion import InputMotion, angle_motion, angle_range, timed_motion
from linkstress.messages import capped, quoted
from linkstress.scene.keys import RANGES, Table

MOTION_KEYS = ("input_angle_deg", "input_speed_rad_s", "input_acceleration_rad_s2", "actuator")
RANGE_KEYS = ("start", "stop", "num")
EXPRESSION_KEYS = ("expression", "t")
"""The keys of ``input_angle_deg = {expression = "...", t = ...}``."""
RANGE_WORDS = {
    "deg": "start, stop and num: num angles from start to stop, both included, e.g. {start = 0.0, stop = 350.0, "
    "num = 36} for a turn in 10 deg steps (stop = 360.0 would end on the pose at 0.0 again)",
    "s": "start, stop and num: num times from start to stop, both included, e.g. {start = 0.0, stop = 1.0, num = 101} "
    "for 1 s in 10 ms steps",
}
"""What a range needs, per unit: angles of a sweep [deg] or times [s]."""
MAX_POSITIONS = 10_000_000


def read_motion(table: Table) -> InputMotion:
    table.allow(MOTION_KEYS)
    table.require(
        "input_angle_deg", "a number, a list, {start, stop, num} (num angles from start to stop, both included) "
        "or {expression, t}",
    )
    value = table.data["input_angle_deg"]
    if isinstance(value, dict) and "expression" in value:
        return _timed(table)
    if isinstance(value, dict):
        angles = _range(table.table("input_angle_deg"), "deg")
    elif isinstance(value, list):
        angles = table.numbers("input_angle_deg", "deg")
    else:
        angles = np.array([table.number("input_angle_deg", unit="deg")])
    speed = _rate(table, "input_speed_rad_s", len(angles), "rad/s")
    acceleration = _rate(table, "input_acceleration_rad_s2", len(angles), "rad/s^2")
    return angle_motion(angles, speed, acceleration)


def read_actuator(table: Table, machine: Machine) -> str:
    """The actuated link: a crank, an output or a slider of some loop (default: the main crank)."""
    default = machine.main.crank.link
    name = table.string("actuator", default)
    grounded = [r.link for loop in machine.loops for k, r in loop.roles.items() if k in ("crank", "output", "slider")]
    if name not in grounded:
        raise table.error(
            "actuator", f"link {name!r} is not a crank, output or slider of any mechanism; the driving torque "
            f"acts on a link pivoted on (or sliding on) the ground: {capped(dict.fromkeys(grounded))}"
        )
    return name


def _timed(table: Table) -> InputMotion:
    spec = table.table("input_angle_deg")
    spec.allow(EXPRESSION_KEYS)
    spec.require(
        "t", "the times in seconds: t = {start = 0.0, stop = 1.0, num = 101} (101 times from 0 to 1 s, both "
        "included) or a list",
    )
    for key in ("input_speed_rad_s", "input_acceleration_rad_s2"):
        if table.has(key):
            raise table.error(key, "not allowed with an expression: it is the expression's time derivative")
    expression = Expression(spec.string("expression"), "t", spec.key_path("expression"))
    if isinstance(spec.data["t"], dict):
        times = _range(spec.table("t"), "s")
    else:
        times = spec.numbers("t", "s")
    motion = timed_motion(expression, times)
    _check_ranges(spec, expression, motion)
    return motion


TIMED_QUANTITIES = (
    ("angle_deg", "deg", "an input angle"),
    ("speed", "rad/s", "an input speed (its time derivative)"),
    ("acceleration", "rad/s^2", "an input acceleration (its second time derivative)"),
)
"""What an expression gives, each held to the range of a plain value of its unit: (the motion's
field, unit, what it is)."""


def _check_ranges(spec: Table, expression: Expression, motion: InputMotion) -> None:
    """Refuse an expression whose angle, speed or acceleration at some time leaves the range a plain
    ``input_angle_deg``, ``input_speed_rad_s`` or ``input_acceleration_rad_s2`` is held to."""
    for field, unit, what in TIMED_QUANTITIES:
        values = getattr(motion, field)
        largest = RANGES[unit][1]
        outside = np.flatnonzero(np.abs(values) > largest)
        if outside.size:
            k = int(outside[0])
            raise spec.error(
                "expression",
                f"{quoted(expression.text, QUOTED)} gives {what} of {values[k]:.6g} {unit} at t = {motion.time[k]:.6g} "
                f"s, more than the {largest:g} {unit} a plain value may be (check the unit: degrees of angle, seconds)",
            )


def _range(spec: Table, unit: str) -> np.ndarray:
    """``num`` evenly spaced values [``unit``] from ``start`` to ``stop``, both included."""
    spec.allow(RANGE_KEYS)
    for key in RANGE_KEYS:
        spec.require(key, RANGE_WORDS[unit])
    start, stop = spec.number("start", unit=unit), spec.number("stop", unit=unit)
    num = spec.integer("num", minimum=1, maximum=MAX_POSITIONS)
    return angle_range(start, stop, num)


def _rate(table: Table, key: str, n: int, unit: str):
    if not table.has(key):
        return 0.0
    if isinstance(table.data[key], list):
        values = table.numbers(key, unit)
        if len(values) != n:
            raise table.error(key, f"give one number, or a list of {n} numbers (one per input angle)")
        return values
    return table.number(key, unit=unit)
