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
from linkstress.kinematics.linkage.graph import LinkageGraph
from linkstress.kinematics.motion import InputMotion, angle_motion, angle_range, stroke_motion, timed_motion, timed_stroke
from linkstress.messages import capped, quoted
from linkstress.scene.keys import RANGES, Table

MOTION_KEYS = ("input_angle_deg", "input_speed_rad_s", "input_acceleration_rad_s2", "actuator")
STROKE_KEYS = ("input_stroke_m", "input_speed_m_s", "input_acceleration_m_s2")
"""The [motion] keys of a linkage driven by a slider's stroke."""
RANGE_KEYS = ("start", "stop", "num")
EXPRESSION_KEYS = ("expression", "t")
"""The keys of ``input_angle_deg = {expression = "...", t = ...}``."""
RANGE_WORDS = {
    "deg": "start, stop and num: num angles from start to stop, both included, e.g. {start = 0.0, stop = 350.0, "
    "num = 36} for a turn in 10 deg steps (stop = 360.0 would end on the pose at 0.0 again)",
    "s": "start, stop and num: num times from start to stop, both included, e.g. {start = 0.0, stop = 1.0, num = 101} "
    "for 1 s in 10 ms steps",
    "m": "start, stop and num: num strokes from start to stop, both included, e.g. {start = 0.0, stop = 0.2, num = 101} "
    "for 0.2 m in 2 mm steps",
}
"""What a range needs, per unit: angles of a sweep [deg] or times [s]."""
MAX_POSITIONS = 10_000_000


def read_motion(table: Table, machine=None) -> InputMotion:
    """The input's motion; a linkage driven by a slider's stroke (``machine``) reads the stroke keys."""
    if isinstance(machine, LinkageGraph):
        if table.has("actuator"):
            raise table.error("actuator", f"a linkage's input is its actuator: mechanisms.{machine.name}.input says which")
        if machine.input.is_stroke:
            return _stroke(table, machine)
        for key in STROKE_KEYS:
            if table.has(key):
                raise table.error(key, f"for a linkage driven by a slider's stroke; mechanisms.{machine.name}.input "
                                       "turns a crank: give input_angle_deg")
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


def _stroke(table: Table, machine: LinkageGraph) -> InputMotion:
    table.allow(STROKE_KEYS)
    slider = machine.sliders[machine.input.slider]
    table.require(
        "input_stroke_m", f"the stroke of slider {machine.input.slider} ({slider.point} on {slider.on!r}) along its line "
        "from its joint i, + toward j [m]: a number, a list, {start, stop, num} or {expression, t}",
    )
    value = table.data["input_stroke_m"]
    if isinstance(value, dict) and "expression" in value:
        spec = table.table("input_stroke_m")
        spec.allow(EXPRESSION_KEYS)
        spec.require("t", "the times in seconds: t = {start = 0.0, stop = 1.0, num = 101} or a list")
        for key in ("input_speed_m_s", "input_acceleration_m_s2"):
            if table.has(key):
                raise table.error(key, "not allowed with an expression: it is the expression's time derivative")
        expression = Expression(spec.string("expression"), "t", spec.key_path("expression"))
        times = _range(spec.table("t"), "s") if isinstance(spec.data["t"], dict) else spec.numbers("t", "s")
        motion = timed_stroke(expression, times)
        _check_ranges(spec, expression, motion, STROKE_QUANTITIES)
        return motion
    if isinstance(value, dict):
        strokes = _range(table.table("input_stroke_m"), "m")
    elif isinstance(value, list):
        strokes = table.numbers("input_stroke_m", "m")
    else:
        strokes = np.array([table.number("input_stroke_m", unit="m")])
    speed = _rate(table, "input_speed_m_s", len(strokes), "m/s")
    acceleration = _rate(table, "input_acceleration_m_s2", len(strokes), "m/s^2")
    return stroke_motion(strokes, speed, acceleration)


def read_actuator(table: Table, machine: Machine) -> str:
    """The actuated link: a crank, an output or a slider of some loop (default: the main crank); a
    linkage's input link (its crank, or the input slider's block, else the slider's point's link)."""
    if isinstance(machine, LinkageGraph):
        if not machine.input.is_stroke:
            return machine.input.link
        slider = machine.sliders[machine.input.slider]
        return slider.block or slider.point.link
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
    _check_ranges(spec, expression, motion, TIMED_QUANTITIES)
    return motion


TIMED_QUANTITIES = (
    ("angle_deg", "deg", "an input angle"),
    ("speed", "rad/s", "an input speed (its time derivative)"),
    ("acceleration", "rad/s^2", "an input acceleration (its second time derivative)"),
)
"""What an angle expression gives, each held to the range of a plain value of its unit: (the
motion's field, unit, what it is)."""
STROKE_QUANTITIES = (
    ("angle_deg", "m", "an input stroke"),
    ("speed", "m/s", "an input stroke speed (its time derivative)"),
    ("acceleration", "m/s^2", "an input stroke acceleration (its second time derivative)"),
)
"""The same for a stroke expression (a stroke motion holds its stroke [m] in ``angle_deg``)."""


UNIT_HINTS = {"deg": "degrees of angle", "m": "metres of stroke"}
"""What the units of an expression are, by the unit of its value (the first of its quantities)."""


def _check_ranges(spec: Table, expression: Expression, motion: InputMotion, quantities) -> None:
    """Refuse an expression whose value, speed or acceleration at some time leaves the range a plain
    value of the same key is held to (``quantities``: TIMED_QUANTITIES or STROKE_QUANTITIES)."""
    for field, unit, what in quantities:
        values = getattr(motion, field)
        largest = RANGES[unit][1]
        outside = np.flatnonzero(np.abs(values) > largest)
        if outside.size:
            k = int(outside[0])
            raise spec.error(
                "expression",
                f"{quoted(expression.text, QUOTED)} gives {what} of {values[k]:.6g} {unit} at t = {motion.time[k]:.6g} "
                f"s, more than the {largest:g} {unit} a plain value may be (check the unit: {UNIT_HINTS[quantities[0][1]]}, seconds)",
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
