"""The [loads] and [analysis] tables.

[loads]: ``gravity_m_s2 = [gx, gy]`` (ground frame; default none); ``[loads.couples]`` with
``LINK = value`` [N m, counter-clockwise] or ``LINK = {value = 2.0, at_joint = 1}`` (default joint:
the origin of the link's member frame); ``[[loads.forces]]`` with ``link``, ``at_m`` (member frame)
and ``force_n`` (ground frame), at a point of the link's material or in one of its holes (a pin's
load: in a hole it bears on the hole as a pin force; off a drawn link's outline it is an error);
``[loads.friction]`` with ``SLIDER = mu``, SLIDER being a slider's link name or its slider-crank's
mechanism name; in a linkage, a slider's block, or its point (``"LINK:i" = mu``).

[analysis]: ``kinematics``, ``forces``, ``stresses`` (booleans, default false once the table
exists), ``stations`` (>= 2), ``validate`` (link names with profiles), ``mesh_size_m`` (> 0),
``element_order`` (1 or 2, default 2), ``body_load_near_holes`` (boolean, default false: sections
within a depth of a hole get nominal beam values, without the body-load term), ``peaks`` (boolean,
default false: FEA peaks over the sweep by superposition of unit loads, and fatigue),
``fatigue_criterion`` ("goodman", "gerber" or "asme-elliptic"; default "goodman"), ``accuracy``
(0.001-0.5, default 0.05: the governing stress within 5 %, which picks each stressed link's stress
model, ``linkstress.model_choice``).
"""

from __future__ import annotations

import numpy as np
import shapely

from linkstress.fatigue import CRITERIA
from linkstress.kinematics.linkage.graph import LinkageGraph
from linkstress.kinematics.machine import Machine
from linkstress.messages import capped
from linkstress.model_choice import accuracy_problem
from linkstress.loads import distance_outside
from linkstress.scene.keys import MAX_STATIONS, Table, shown_value
from linkstress.scene.model import Analysis, CoupleLoad, Loads, PointLoad, SceneLink

LOAD_KEYS = ("gravity_m_s2", "couples", "forces", "friction")
ANALYSIS_KEYS = (
    "kinematics", "forces", "stresses", "stations", "validate", "mesh_size_m", "element_order", "body_load_near_holes",
    "peaks", "fatigue_criterion", "accuracy",
)
COUPLE_KEYS = ("value", "at_joint")
"""The keys of a couple given as an inline table: ``LINK = {value = 2.0, at_joint = 1}``."""
FORCE_KEYS = ("link", "at_m", "force_n")
"""The keys of each ``[[loads.forces]]`` entry."""


def read_loads(table: Table | None, machine: Machine, links: dict[str, SceneLink]) -> Loads:
    if table is None:
        return Loads(np.zeros(2))
    table.allow(LOAD_KEYS)
    gravity = table.point("gravity_m_s2", "m/s^2") if table.has("gravity_m_s2") else np.zeros(2)
    moving = _moving(machine)
    couples = []
    couple_table = table.table("couples")
    for name in couple_table.data if couple_table else ():
        link = _moving_link(couple_table, name, moving, "a couple")
        value = couple_table.data[name]
        if isinstance(value, dict):
            spec = couple_table.table(name)
            spec.allow(COUPLE_KEYS)
            spec.require("value", "the couple in N m, counter-clockwise positive")
            amount = spec.number("value", unit="N m")
            joint = spec.integer("at_joint", links[link].frame_joints[0], minimum=0)
            if joint >= len(links[link].joints):
                raise spec.error("at_joint", f"link {link!r} has joints 0..{len(links[link].joints) - 1}, no joint {joint}")
        else:
            amount = couple_table.number(name, unit="N m")
            joint = links[link].frame_joints[0]
        couples.append(CoupleLoad(link, amount, joint))
    forces = []
    if table.has("forces"):
        raw = table.data["forces"]
        if not isinstance(raw, list):
            raise table.error("forces", "must be an array of tables: [[loads.forces]] with link, at_m, force_n")
        for k, item in enumerate(raw):
            spec = Table(item, f"{table.key_path('forces')}[{k}]", table.source)
            spec.allow(FORCE_KEYS)
            for key, what in (("link", "the link's name"), ("at_m", "[x, y] in the link's member frame, metres"),
                              ("force_n", "[Fx, Fy] in the ground frame, newtons")):
                spec.require(key, what)
            link = spec.string("link")
            if link not in moving:
                raise spec.error("link", f"no moving link named {link!r}; moving links are: {capped(moving)}")
            at = spec.point("at_m", "m")
            _check_on_link(spec, links[link], at)
            forces.append(PointLoad(link, at, spec.point("force_n", "N")))
    return Loads(gravity, tuple(couples), tuple(forces), _friction(table.table("friction"), machine))


def read_analysis(table: Table | None, links: dict[str, SceneLink]) -> Analysis | None:
    if table is None:
        return None
    table.allow(ANALYSIS_KEYS)
    validate: tuple[str, ...] = ()
    if table.has("validate"):
        raw = table.data["validate"]
        if not isinstance(raw, list) or not all(isinstance(v, str) for v in raw):
            raise table.error("validate", f"must be a list of link names, got {shown_value(raw)}")
        for name in raw:
            if name not in links:
                raise table.error("validate", f"no link named {name!r}; links are: {capped(links)}")
            if links[name].profile is None:
                raise table.error("validate", f"link {name!r} has bare joints; only links drawn in a sketch can be checked by FEA")
        validate = tuple(raw)
    accuracy = table.number("accuracy")
    if accuracy is not None and (problem := accuracy_problem(accuracy)) is not None:
        raise table.error("accuracy", problem)
    order = table.integer("element_order", 2)
    if order not in (1, 2):
        raise table.error("element_order", f"must be 1 (linear) or 2 (quadratic triangles), got {order}")
    return Analysis(
        kinematics=table.boolean("kinematics", False),
        forces=table.boolean("forces", False),
        stresses=table.boolean("stresses", False),
        stations=table.integer("stations", None, minimum=2, maximum=MAX_STATIONS),
        validate=validate,
        mesh_size=table.number("mesh_size_m", positive=True, unit="m"),
        element_order=order,
        body_load_near_holes=table.boolean("body_load_near_holes", False),
        peaks=table.boolean("peaks", False),
        fatigue_criterion=table.string("fatigue_criterion", "goodman", CRITERIA),
        accuracy=accuracy,
    )


def _moving(machine: Machine) -> list[str]:
    if isinstance(machine, LinkageGraph):
        return list(machine.moving)
    names = [r.link for loop in machine.loops for k, r in loop.roles.items() if k != "ground"]
    return list(dict.fromkeys(names))


def _moving_link(table: Table, name: str, moving: list[str], what: str) -> str:
    if name not in moving:
        raise table.error(name, f"no moving link named {name!r} for {what}; moving links are: {capped(moving)}")
    return name


def _check_on_link(spec: Table, link: SceneLink, at: np.ndarray) -> None:
    """A point force ``at`` (2,) [m, member frame] must act on the link: in its material or in one
    of its holes. Links with bare joints have no outline to check against."""
    if link.profile is None:
        return
    outline = shapely.transform(link.profile.outline, link.to_member)
    gap = distance_outside(outline, at)
    if gap > 0:
        i, j = link.frame_joints
        raise spec.error(
            "at_m",
            f"[{at[0]:.6g}, {at[1]:.6g}] m is {gap:.6g} m outside the outline of link {link.name!r} "
            f"(member frame: origin at joint {i}, +x toward joint {j}); a force must act on the link: put "
            "at_m in its material, or in a pin hole for the load of a pin (at the hole's centre for a pin "
            "force), or give the force to the link it acts on",
        )


def _friction(table: Table | None, machine: Machine) -> dict[str, float]:
    if table is None:
        return {}
    if isinstance(machine, LinkageGraph):
        sliders = {str(s.point): slider_key(machine, k) for k, s in enumerate(machine.sliders)}
        sliders.update({s.block: slider_key(machine, k) for k, s in enumerate(machine.sliders) if s.block})
        return _coefficients(table, sliders, "a slider's block or its point \"LINK:i\"")
    sliders = {loop.name: loop.name for loop in machine.loops if loop.kind == "slider-crank"}
    sliders.update({loop.slider.link: loop.name for loop in machine.loops if loop.slider is not None})
    return _coefficients(table, sliders, "a slider's link or slider-crank's name")


def slider_key(machine: LinkageGraph, k: int) -> str:
    """The ``Loads.friction`` key of a linkage's slider k: "NAME.sliders[k]"."""
    return f"{machine.name}.sliders[{k}]"


def _coefficients(table: Table, sliders: dict[str, str], what: str) -> dict[str, float]:
    friction = {}
    for name in table.data:
        if name not in sliders:
            known = capped(sliders) or "none: the scene has no slider"
            raise table.error(name, f"no slider named {name!r}; give {what}: {known}")
        friction[sliders[name]] = table.number(name, minimum=0.0)
    return friction
