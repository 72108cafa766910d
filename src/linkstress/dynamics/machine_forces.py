"""Joint forces and driving torques of a whole machine, and the loads each link carries.

The scene's machine becomes one Newton-Euler assembly (``newton_euler``): every moving link is a
body; each loop adds its pins O2 (crank-ground), A (crank-coupler), B (coupler-output, or
coupler-slider) and O4 (output-ground), or for a slider-crank a slide of its slider on the ground
(a massless slider body when the scene names no slider link). The main loop's actuator is an unknown
torque between the ground and the scene's actuator link (the main crank by default). A loop driven
through a coupling gets an unknown torque between its crank and the link that drives it; a loop
whose crank is its driver's link (rigid drive) shares that link's pivot and needs no torque.

Forces are named per loop in Norton's numbering (1 ground, 2 crank, 3 coupler, 4 output or slider):
``Fij`` is the force of link i on link j, ground frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.newton_euler import (
    GROUND, Actuator, AppliedCouple, AppliedForce, Assembly, Body, ForceActuator, ForceSolution, Pin, Slide,
    solve_forces,
)
from linkstress.errors import SceneError
from linkstress.kinematics.results import LinkMotion, MachineMotion
from linkstress.loads import LinkLoadCase, PointForce
from linkstress.scene.model import Scene

SINGULAR_REASON = "toggle: the joint forces are unbounded (singular Newton-Euler system)"


@dataclass(frozen=True)
class MechanismForces:
    """One loop's joint forces (P, 2) [N] by Norton name, and what drives it: ``driving_torque``
    (P,) [N m] named ``torque_name`` ("T12" at an actuated crank, "T14" at an actuated output,
    "T<driver>" through a coupling from loop <driver>), or ``driving_force`` (P,) [N] of an actuated
    slider along its line; both None for a loop driven through its driver's own link or not actuated."""

    forces: dict[str, NDArray[np.float64]]
    torque_name: str | None
    driving_torque: NDArray[np.float64] | None
    driving_force: NDArray[np.float64] | None = None
    linkage: object | None = None
    """A linkage's pins and sliders (``linkage_forces.LinkageForces``); None for a loop. Its
    ``forces`` are named by pin: "pin crank:1-rod:0" the force of the first joint's link on the
    second's ("pin A:i-B:j-C:k on B:j" for each joint but the first of a pin of three or more),
    "slider crank:1 on lever" the guide's push on the block."""
    force_name: str = "P14"
    """What the text and HTML reports call ``driving_force``."""


@dataclass(frozen=True)
class MachineForces:
    """Forces over P positions: ``feasible`` where the kinematics is and the system is solvable."""

    feasible: NDArray[np.bool_]
    reasons: tuple[str, ...]
    mechanisms: dict[str, MechanismForces]
    link_loads: dict[str, LinkLoadCase]
    solution: ForceSolution


@dataclass(frozen=True)
class _Contact:
    """Where a pin's or slide's force reaches a link: the link and its joint index, and the sign."""

    link: str
    joint: int
    sign: float


def machine_forces(scene: Scene, motion: MachineMotion) -> MachineForces:
    """Newton-Euler forces of ``scene``'s machine over the sweep ``motion`` (a linkage's:
    ``linkage_forces``)."""
    if scene.linkage is not None:
        from linkstress.dynamics.linkage_forces import linkage_forces

        return linkage_forces(scene, motion)
    builder = _AssemblyBuilder(scene, motion)
    assembly = builder.assembly()
    solution = solve_forces(assembly, motion.feasible)
    feasible = motion.feasible & solution.solved
    reasons = list(motion.reasons)
    for k in np.flatnonzero(~feasible).tolist():
        reasons[k] = reasons[k] or SINGULAR_REASON
    return MachineForces(
        feasible, tuple(reasons), builder.mechanisms(solution), builder.link_loads(solution), solution,
    )


class _AssemblyBuilder:
    """Turns a scene and its kinematics into bodies, joints, actuators and loads, remembering which
    link joint each unknown acts on."""

    def __init__(self, scene: Scene, motion: MachineMotion) -> None:
        self.scene, self.motion = scene, motion
        self.n = len(motion.input_angle)
        self.bodies: list[Body] = []
        self.index: dict[str, int] = {}
        self.pins: list[Pin] = []
        self.slides: list[Slide] = []
        self.actuators: list[Actuator] = []
        self.contacts: dict[str, list[_Contact]] = {}
        self.couple_at: dict[str, list[_Contact]] = {}
        self.force_actuators: list[ForceActuator] = []
        self.names: dict[str, dict[str, str]] = {}
        self.drives: dict[str, str] = {}
        self.actuator: tuple[str, str] = ("", "")
        for name in scene.moving_links:
            self._add_link_body(name)
        for loop in scene.machine.loops:
            self._add_loop(loop)
        self._add_actuator()

    # -- bodies -------------------------------------------------------------------------------

    def _add_link_body(self, name: str) -> None:
        data = self.scene.links[name].mass_data
        if data is None:
            raise SceneError(
                f"links.{name}: joint forces need this link's mass: give mass, inertia and center_of_mass, "
                "or a sketch with thickness and a material with a density"
            )
        link_motion = self.motion.links[name]
        position, _, acceleration = link_motion.point(data.center_of_mass)
        self._body(name, Body(name, data.mass, data.inertia, position, acceleration, link_motion.alpha))

    def _body(self, name: str, body: Body) -> int:
        self.index[name] = len(self.bodies)
        self.bodies.append(body)
        return self.index[name]

    # -- joints -------------------------------------------------------------------------------

    def _pin(self, name: str, body: tuple[str, int], other: tuple[str, int] | None, position) -> None:
        """Pin ``name``: force on ``body`` (link, joint) from ``other`` (None: the ground)."""
        other_index = GROUND if other is None else self.index[other[0]]
        self.pins.append(Pin(name, self.index[body[0]], other_index, position))
        contacts = [_Contact(body[0], body[1], 1.0)]
        if other is not None and other[0] in self.scene.links:
            contacts.append(_Contact(other[0], other[1], -1.0))
        self.contacts[name] = contacts

    def _add_loop(self, loop) -> None:
        joints = self.motion.loops[loop.name].joints
        loop_motion = self.motion.loops[loop.name]
        crank, coupler = loop.crank, loop.coupler
        key = f"{loop.name}."
        names: dict[str, str] = {}
        rigid = loop.driven_by is not None and loop.driven_by.rigid
        if not rigid:
            self._pin(key + "O2", (crank.link, crank.joints[0]), None, joints["O2"].position)
        names["F12"] = self._pivot_pin_name(loop) if rigid else key + "O2"
        self._pin(key + "A", (crank.link, crank.joints[1]), (coupler.link, coupler.joints[0]), joints["A"].position)
        names["F32"] = key + "A"
        if loop.kind == "four-bar":
            output = loop.output
            self._pin(key + "B", (coupler.link, coupler.joints[1]), (output.link, output.joints[1]), joints["B"].position)
            self._pin(key + "O4", (output.link, output.joints[0]), None, joints["O4"].position)
            names["F43"], names["F14"] = key + "B", key + "O4"
        else:
            slider = loop.slider.link if loop.slider is not None else None
            if slider is None:
                slider = key + "slider"
                b = joints["B"]
                self._body(slider, Body(slider, 0.0, 0.0, b.position, b.acceleration, np.zeros(self.n)))
            slider_joint = loop.slider.joints[0] if loop.slider is not None else 0
            self._pin(key + "B", (coupler.link, coupler.joints[1]), (slider, slider_joint), joints["B"].position)
            u = np.array([np.cos(loop_motion.theta4[0]), np.sin(loop_motion.theta4[0])])
            friction = self.scene.loads.friction.get(loop.name, 0.0)
            self.slides.append(Slide(key + "slide", self.index[slider], u, joints["B"].position,
                                     loop_motion.slider_velocity, friction))
            self.contacts[key + "slide"] = [_Contact(slider, slider_joint, 1.0)] if slider in self.scene.links else []
            names["F43"], names["F14"] = key + "B", key + "slide"
        self.names[loop.name] = names
        self._add_drive(loop)

    def _pivot_pin_name(self, loop) -> str:
        """The pin at the pivot of the link that rigidly drives ``loop``'s crank."""
        drive = loop.driven_by
        driver = self.scene.machine.loop(drive.loop)
        if drive.role == "crank":
            return self._pivot_pin_name(driver) if driver.driven_by is not None and driver.driven_by.rigid else f"{driver.name}.O2"
        return f"{driver.name}.O4"

    def _add_drive(self, loop) -> None:
        """The coupling torque of a loop driven through a coupling (none for a rigid drive)."""
        drive = loop.driven_by
        if drive is None or drive.rigid:
            return
        source = getattr(self.scene.machine.loop(drive.loop), drive.role)
        name = f"T{drive.loop}"
        self.actuators.append(Actuator(name, self.index[loop.crank.link], self.index[source.link]))
        self.couple_at[name] = [
            _Contact(loop.crank.link, loop.crank.joints[0], 1.0), _Contact(source.link, source.joints[0], -1.0),
        ]
        self.drives[loop.name] = name

    def _add_actuator(self) -> None:
        """The unknown driving torque (a crank or output, at its pivot) or force (a slider, along its
        line) on the scene's actuator link."""
        name = self.scene.actuator
        for loop in self.scene.machine.loops:
            if loop.crank.link == name or (loop.output is not None and loop.output.link == name):
                role = loop.crank if loop.crank.link == name else loop.output
                label = "T12" if role is loop.crank else "T14"
                self.actuators.append(Actuator(label, self.index[name]))
                self.couple_at[label] = [_Contact(name, role.joints[0], 1.0)]
                self.actuator = (loop.name, label)
                return
            if loop.slider is not None and loop.slider.link == name:
                slide = next(s for s in self.slides if s.name == f"{loop.name}.slide")
                self.force_actuators.append(ForceActuator("P14", self.index[name], slide.direction, slide.position))
                self.contacts["P14"] = [_Contact(name, loop.slider.joints[0], 1.0)]
                self.actuator = (loop.name, "P14")
                return
        raise SceneError(f"motion.actuator: link {name!r} is not a crank, output or slider of any mechanism")

    # -- loads --------------------------------------------------------------------------------

    def assembly(self) -> Assembly:
        couples = tuple(
            AppliedCouple(self.index[c.link], np.full(self.n, c.value)) for c in self.scene.loads.couples
        )
        forces = tuple(
            AppliedForce(
                self.index[f.link], self.motion.links[f.link].point(f.at)[0], np.broadcast_to(f.force, (self.n, 2)),
            )
            for f in self.scene.loads.forces
        )
        return Assembly(
            tuple(self.bodies), tuple(self.pins), tuple(self.actuators), tuple(self.slides),
            forces, couples, np.asarray(self.scene.loads.gravity, float), tuple(self.force_actuators),
        )

    # -- results ------------------------------------------------------------------------------

    def mechanisms(self, solution: ForceSolution) -> dict[str, MechanismForces]:
        found = {**solution.pin_forces, **solution.slide_forces}
        result = {}
        for loop in self.scene.machine.loops:
            forces = {label: found[pin] for label, pin in self.names[loop.name].items()}
            torque_name, torque, push = None, None, None
            if self.actuator[0] == loop.name:
                if self.actuator[1] == "P14":
                    push = solution.actuator_forces["P14"]
                else:
                    torque_name, torque = self.actuator[1], solution.torques[self.actuator[1]]
            elif loop.name in self.drives:
                torque_name = self.drives[loop.name]
                torque = solution.torques[torque_name]
            result[loop.name] = MechanismForces(forces, torque_name, torque, push)
        return result

    def link_loads(self, solution: ForceSolution) -> dict[str, LinkLoadCase]:
        """The loads on every moving link of the scene, in its member frame."""
        n = self.n
        loads = {}
        found = {**solution.pin_forces, **solution.slide_forces}
        for actuator in self.force_actuators:
            found[actuator.name] = solution.actuator_forces[actuator.name][:, None] * np.asarray(actuator.direction, float)
        couples = {**solution.torques, **solution.slide_couples}
        couple_at = dict(self.couple_at)
        for slide in self.slides:
            couple_at[slide.name] = self.contacts[slide.name]
        gravity = np.broadcast_to(np.asarray(self.scene.loads.gravity, float), (n, 2))
        for name in self.scene.moving_links:
            link = self.scene.links[name]
            link_motion: LinkMotion = self.motion.links[name]
            to_member = _rotation_into(link_motion.angle)
            pin_forces = np.zeros((n, len(link.joints), 2))
            joint_couples = np.zeros((n, len(link.joints)))
            for pin_name, contacts in self.contacts.items():
                for c in contacts:
                    if c.link == name:
                        pin_forces[:, c.joint] += c.sign * found[pin_name]
            for torque_name, contacts in couple_at.items():
                for c in contacts:
                    if c.link == name:
                        joint_couples[:, c.joint] += c.sign * couples[torque_name]
            for c in self.scene.loads.couples:
                if c.link == name:
                    joint_couples[:, c.at_joint] += c.value
            point_forces = tuple(
                PointForce(np.asarray(f.at, float), to_member(np.broadcast_to(f.force, (n, 2))))
                for f in self.scene.loads.forces if f.link == name
            )
            loads[name] = LinkLoadCase(
                frame_joints=link_motion.frame_joints,
                pin_forces=to_member(pin_forces),
                joint_couples=joint_couples,
                omega=np.asarray(link_motion.omega, float),
                alpha=np.asarray(link_motion.alpha, float),
                origin_acceleration=to_member(link_motion.origin_acceleration),
                gravity=to_member(gravity),
                point_forces=point_forces,
            )
        return loads


def _rotation_into(angle: NDArray[np.float64]):
    """A function taking ground-frame vectors (P, ..., 2) into member axes at angles (P,)."""
    c, s = np.cos(angle), np.sin(angle)

    def to_member(v):
        v = np.asarray(v, float)
        shape = (len(c),) + (1,) * (v.ndim - 2)
        cc, ss = c.reshape(shape), s.reshape(shape)
        return np.stack([cc * v[..., 0] + ss * v[..., 1], -ss * v[..., 0] + cc * v[..., 1]], axis=-1)

    return to_member
