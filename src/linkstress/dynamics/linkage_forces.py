"""Where slide forces are assembled: one Newton-Euler system per position from a linkage's joint graph.

Every moving link of a ``type = "linkage"`` mechanism is a body (its block too); a slider without a
block gets a massless one. A pin joining k links gives k - 1 unknown forces, each on one link from
the same other link (the ground's, when the ground is in the pin): the pin itself is massless. A
slider is a slide between its block and its guide (the ground or a moving link): a normal force
and a couple, the guide taking the opposite, with Coulomb friction from the relative sliding
velocity where ``[loads.friction]`` gives it. The input is an unknown torque on the crank at its
pivot (reacting on the ground), or an unknown force along the input slider's line on its block
(reacting on the guide). Solved by ``newton_euler.solve_forces``.

What reaches each link goes into its ``LinkLoadCase`` (member frame): the pins' forces at its
joints, the input torque at the crank's pivot, a slide's couple on its block at the block's joint 0.
A guide's slide reaction acts where the block is, which moves along the guide: it is given to the
guide as a ``SlidingContact`` (the block's push and couple at the point, anchored at the line's
joint i), which the section forces take exactly (``linkstress.dynamics.section_stress``). An
actuator's thrust reaches its guide at that joint i, the actuator's base (a cylinder's end cap).

The power balance (``power_balance``) checks the solution without a second solver: the input's
power equals the rate of kinetic energy less the power of the applied loads and of friction.
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
from linkstress.kinematics.linkage.graph import Joint, LinkageGraph
from linkstress.kinematics.results import MachineMotion
from linkstress.loads import LinkLoadCase, PointForce, SlidingContact

FloatArray = NDArray[np.float64]
SINGULAR_REASON = "toggle: the joint forces are unbounded (singular Newton-Euler system)"


@dataclass(frozen=True)
class SliderForces:
    """Slider ``point`` on link ``on`` over P positions: ``stroke`` [m] along its line from its
    joint i; the guide's ``normal`` push on the block along the line's left normal k x u [N], its
    ``couple`` on the block [N m], the ``friction`` along u [N], and the ``pin_force`` (P, 2) [N] the
    pin at the point puts on the block."""

    point: str
    on: str
    stroke: FloatArray
    normal: FloatArray
    couple: FloatArray
    friction: FloatArray
    pin_force: FloatArray


@dataclass(frozen=True)
class LinkageForces:
    """Per pin (``graph.all_pins``' order): its joints, position (P, 2) [m] and the force (P, 2) [N]
    it puts on each joint's link; per slider its ``SliderForces``."""

    pins: tuple[tuple[str, ...], ...]
    positions: tuple[FloatArray, ...]
    forces: tuple[dict[str, FloatArray], ...]
    sliders: tuple[SliderForces, ...]


class LinkageAssembly:
    """A linkage scene and its kinematics as Newton-Euler bodies, pins, slides and actuators."""

    def __init__(self, scene, motion: MachineMotion) -> None:
        self.scene, self.motion = scene, motion
        self.graph: LinkageGraph = scene.linkage
        self.n = len(motion.input_angle)
        self.bodies: list[Body] = []
        self.index: dict[str, int] = {self.graph.ground: GROUND}
        for name in scene.moving_links:
            self._link_body(name)
        self.virtual = {}
        for k, slider in enumerate(self.graph.sliders):
            if slider.block is None:
                self.virtual[k] = self._virtual_block(k)
        self.pin_joints = self._pin_joints()
        self.pins = self._pins()
        self.slides = [self._slide(k) for k in range(len(self.graph.sliders))]
        self.actuators, self.force_actuators = self._input()

    # -- bodies -------------------------------------------------------------------------------

    def _link_body(self, name: str) -> None:
        data = self.scene.links[name].mass_data
        if data is None:
            raise SceneError(
                f"links.{name}: joint forces need this link's mass: give mass, inertia and center_of_mass, "
                "or a sketch with thickness and a material with a density"
            )
        link_motion = self.motion.links[name]
        position, _, acceleration = link_motion.point(data.center_of_mass)
        self.index[name] = len(self.bodies)
        self.bodies.append(Body(name, data.mass, data.inertia, position, acceleration, link_motion.alpha))

    def _virtual_block(self, k: int) -> str:
        """A massless block for slider k, at its point, turning with its guide."""
        slider = self.graph.sliders[k]
        name = f"{self.graph.name}.sliders[{k}]"
        point = self.motion.linkage.joints[str(slider.point)]
        self.index[name] = len(self.bodies)
        self.bodies.append(Body(name, 0.0, 0.0, point.position, point.acceleration, self.motion.links[slider.on].alpha))
        return name

    # -- joints -------------------------------------------------------------------------------

    def _pin_joints(self) -> list[tuple[Joint, ...]]:
        """``all_pins`` with each massless block's joint at its slider's point."""
        pins = [list(pin) for pin in self.graph.all_pins]
        for k, name in self.virtual.items():
            point = self.graph.sliders[k].point
            holder = next((pin for pin in pins if point in pin), None)
            if holder is None:
                pins.append([point, Joint(name, 0)])
            else:
                holder.append(Joint(name, 0))
        return [tuple(pin) for pin in pins]

    def _pins(self) -> list[tuple[Joint, Joint, Pin]]:
        """(joint, reference joint, Pin: force on the joint's link from the reference's) for every
        joint of every pin but its reference (the ground's joint, else the first)."""
        out = []
        for p, pin in enumerate(self.pin_joints):
            reference = next((j for j in pin if j.link == self.graph.ground), pin[0])
            position = self.motion.linkage.joints[str(pin[0])].position
            for joint in pin:
                if joint != reference:
                    pin_object = Pin(f"{p}|{joint}", self.index[joint.link], self.index[reference.link], position)
                    out.append((joint, reference, pin_object))
        return out

    def _slide(self, k: int) -> Slide:
        slider = self.graph.sliders[k]
        block = slider.block or self.virtual[k]
        u = self.direction(k)
        point = self.motion.linkage.joints[str(slider.point)].position
        velocity = self.motion.linkage.strokes[k][1]
        friction = self.scene.loads.friction.get(f"{self.graph.name}.sliders[{k}]", 0.0)
        return Slide(f"sliders[{k}]", self.index[block], u, point, velocity, friction, self.index[slider.on])

    def direction(self, k: int) -> FloatArray:
        """Slider k's line direction u (P, 2), unit, from its joint i toward j."""
        slider = self.graph.sliders[k]
        local = self.graph.local[slider.on]
        i, j = slider.line
        d = local[j] - local[i]
        d = d / np.hypot(*d)
        angle = self.motion.links[slider.on].angle
        c, s = np.cos(angle), np.sin(angle)
        return np.column_stack([c * d[0] - s * d[1], s * d[0] + c * d[1]])

    def _input(self):
        graph = self.graph
        if not graph.input.is_stroke:
            return [Actuator("input", self.index[graph.input.link])], []
        k = graph.input.slider
        slider = graph.sliders[k]
        block = slider.block or self.virtual[k]
        push = ForceActuator("input", self.index[block], self.direction(k), self.slides[k].position, self.index[slider.on])
        return [], [push]

    def assembly(self) -> Assembly:
        loads = self.scene.loads
        couples = tuple(AppliedCouple(self.index[c.link], np.full(self.n, c.value)) for c in loads.couples)
        forces = tuple(
            AppliedForce(self.index[f.link], self.motion.links[f.link].point(f.at)[0], np.broadcast_to(f.force, (self.n, 2)))
            for f in loads.forces
        )
        return Assembly(
            tuple(self.bodies), tuple(p for _, _, p in self.pins), tuple(self.actuators), tuple(self.slides),
            forces, couples, np.asarray(loads.gravity, float), tuple(self.force_actuators),
        )

    # -- results ------------------------------------------------------------------------------

    def pin_results(self, solution: ForceSolution) -> tuple[dict[str, FloatArray], ...]:
        """Per pin (``graph.all_pins``, then the pins of massless blocks at points no pin holds):
        the force (P, 2) [N] it puts on each joint's link, massless blocks' joints included."""
        results = []
        for p, pin in enumerate(self.pin_joints):
            forces = {str(j): np.zeros((self.n, 2)) for j in pin}
            for joint, reference, pin_object in self.pins:
                if pin_object.name.split("|")[0] != str(p):
                    continue
                force = solution.pin_forces[pin_object.name]
                forces[str(joint)] += force
                forces[str(reference)] -= force
            results.append(forces)
        return tuple(results)

    def slider_results(self, solution: ForceSolution, pins: tuple[dict[str, FloatArray], ...]) -> tuple[SliderForces, ...]:
        out = []
        for k, slider in enumerate(self.graph.sliders):
            slide = self.slides[k]
            u = self.direction(k)
            total = solution.slide_forces[slide.name]
            normal = total[:, 1] * u[:, 0] - total[:, 0] * u[:, 1]
            friction = total[:, 0] * u[:, 0] + total[:, 1] * u[:, 1] if slide.friction else np.zeros(self.n)
            key = f"{slider.block or self.virtual[k]}:0"
            pin = next(f for f in pins if key in f)[key]
            out.append(SliderForces(str(slider.point), slider.on, self.motion.linkage.strokes[k][0], normal,
                                    solution.slide_couples[slide.name], friction, pin))
        return tuple(out)

    def block_length(self, k: int) -> float:
        """[m]: slider ``k``'s block's drawn length along its line, over which it bears on its guide
        (0 for a block drawn without a profile, or none)."""
        slider = self.graph.sliders[k]
        block = self.scene.links.get(slider.block) if slider.block else None
        if block is None or block.profile is None:
            return 0.0
        guide = self.scene.links[slider.on]
        line = np.asarray(guide.joints[slider.line[1]], float) - np.asarray(guide.joints[slider.line[0]], float)
        outline = np.asarray(block.profile.outline.exterior.coords)
        return float(np.ptp(outline @ (line / np.hypot(*line))))

    def input_power_rate(self, solution: ForceSolution) -> tuple[FloatArray | None, FloatArray | None]:
        """The driving torque (P,) [N m] or force (P,) [N]."""
        if self.actuators:
            return solution.torques["input"], None
        return None, solution.actuator_forces["input"]

    def link_loads(self, solution: ForceSolution, pins) -> dict[str, LinkLoadCase]:
        """The loads on every moving link of the scene, in its member frame."""
        n = self.n
        loads = {}
        gravity = np.broadcast_to(np.asarray(self.scene.loads.gravity, float), (n, 2))
        torque, push = self.input_power_rate(solution)
        for name in self.scene.moving_links:
            link = self.scene.links[name]
            link_motion = self.motion.links[name]
            to_member = _rotation_into(link_motion.angle)
            count = len(link.joints)
            pin_forces = np.zeros((n, count, 2))
            couples = np.zeros((n, count))
            contacts = []
            for forces in pins:
                for joint, force in forces.items():
                    link_name, index = joint.rsplit(":", 1)
                    if link_name == name:
                        pin_forces[:, int(index)] += force
            for k, slider in enumerate(self.graph.sliders):
                slide = self.slides[k]
                total = solution.slide_forces[slide.name]
                couple = solution.slide_couples[slide.name]
                u = self.direction(k)
                thrust = push[:, None] * u if push is not None and self.graph.input.slider == k else None
                if slider.block == name:
                    pin_forces[:, 0] += total if thrust is None else total + thrust
                    couples[:, 0] += couple
                if slider.on == name:
                    i = slider.line[0]
                    anchor = np.asarray(self.graph.local[name][i], float)
                    arm = slide.position - link_motion.point(anchor)[0]
                    contacts.append(SlidingContact(anchor + to_member(arm), to_member(-total), -np.asarray(couple, float), i,
                                                   self.block_length(k)))
                    if thrust is not None:
                        # An actuator's thrust reaches its guide (a cylinder's barrel, a screw's housing) at the
                        # line's joint i, its base: the oil on the end cap, the screw on its thrust bearing.
                        contacts.append(SlidingContact(np.tile(anchor, (n, 1)), to_member(-thrust), np.zeros(n), i))
            if torque is not None and name == self.graph.input.link:
                couples[:, self.graph.input.pivot] += torque
            for c in self.scene.loads.couples:
                if c.link == name:
                    couples[:, c.at_joint] += c.value
            point_forces = tuple(
                PointForce(np.asarray(f.at, float), to_member(np.broadcast_to(f.force, (n, 2))))
                for f in self.scene.loads.forces if f.link == name
            )
            loads[name] = LinkLoadCase(
                frame_joints=link_motion.frame_joints,
                pin_forces=to_member(pin_forces),
                joint_couples=couples,
                omega=np.asarray(link_motion.omega, float),
                alpha=np.asarray(link_motion.alpha, float),
                origin_acceleration=to_member(link_motion.origin_acceleration),
                gravity=to_member(gravity),
                point_forces=point_forces,
                contacts=tuple(contacts),
            )
        return loads


def moving_contacts(graph: LinkageGraph) -> tuple[str, ...]:
    """The moving links a slider's block slides along (guides): their contact moves along them, so
    their section stresses take it as a ``SlidingContact`` and the FEA, whose unit loads stand at
    fixed points, cannot take them."""
    return tuple(dict.fromkeys(s.on for s in graph.sliders if s.on != graph.ground))


def _rotation_into(angle: FloatArray):
    """A function taking ground-frame vectors (P, ..., 2) into member axes at angles (P,)."""
    c, s = np.cos(angle), np.sin(angle)

    def to_member(v):
        v = np.asarray(v, float)
        shape = (len(c),) + (1,) * (v.ndim - 2)
        cc, ss = c.reshape(shape), s.reshape(shape)
        return np.stack([cc * v[..., 0] + ss * v[..., 1], -ss * v[..., 0] + cc * v[..., 1]], axis=-1)

    return to_member


def linkage_forces(scene, motion: MachineMotion):
    """Newton-Euler forces of ``scene``'s linkage over the sweep ``motion``: a ``MachineForces``
    with one mechanism (its pins, sliders and driving torque or force)."""
    from linkstress.dynamics.machine_forces import MachineForces, MechanismForces

    builder = LinkageAssembly(scene, motion)
    solution = solve_forces(builder.assembly(), motion.feasible)
    feasible = motion.feasible & solution.solved
    reasons = list(motion.reasons)
    for k in np.flatnonzero(~feasible).tolist():
        reasons[k] = reasons[k] or SINGULAR_REASON
    pins = builder.pin_results(solution)
    sliders = builder.slider_results(solution, pins)
    loads = builder.link_loads(solution, pins)
    graph = builder.graph
    pins = tuple({j: f for j, f in forces.items() if j.rsplit(":", 1)[0] in graph.links}
                 for forces in pins[:len(graph.all_pins)])
    labelled = {}
    for pin, forces in zip(graph.all_pins, pins):
        label = graph.pin_label(pin)
        if len(pin) == 2:
            labelled[label] = forces[str(pin[1])]
        else:
            labelled.update({f"{label} on {j}": forces[str(j)] for j in pin[1:]})
    for k, s in enumerate(sliders):
        labelled[f"slider {s.point} on {s.on}"] = solution.slide_forces[builder.slides[k].name]
    torque, push = builder.input_power_rate(solution)
    detail = LinkageForces(
        tuple(tuple(str(j) for j in pin) for pin in graph.all_pins), motion.linkage.pin_positions, pins, sliders,
    )
    name = f"T {graph.input.link}" if torque is not None else None
    mechanism = MechanismForces(labelled, name, torque, push, linkage=detail, force_name="P input")
    return MachineForces(feasible, tuple(reasons), {graph.name: mechanism}, loads, solution)


def power_balance(scene, motion: MachineMotion, forces) -> tuple[FloatArray, FloatArray]:
    """(input power, d/dt KE - power of the applied loads - power of friction) (P,) [W]: equal
    where the forces are right (any mechanism, no second solver). KE = sum 1/2 m v_G^2 + 1/2 I_G
    omega^2, so d/dt KE = sum m v_G . a_G + I_G omega alpha; the applied loads are gravity on every
    centre of mass, the point forces and couples; friction dissipates f v_rel at each slider."""
    graph = scene.linkage
    mechanism = forces.mechanisms[graph.name]
    if mechanism.driving_torque is not None:
        power_in = mechanism.driving_torque * motion.links[graph.input.link].omega
    else:
        power_in = mechanism.driving_force * motion.linkage.strokes[graph.input.slider][1]
    gravity = np.asarray(scene.loads.gravity, float)
    rate, applied = np.zeros(len(power_in)), np.zeros(len(power_in))
    for name in scene.moving_links:
        data = scene.links[name].mass_data
        link = motion.links[name]
        _, v, a = link.point(data.center_of_mass)
        rate += data.mass * (v[:, 0] * a[:, 0] + v[:, 1] * a[:, 1]) + data.inertia * link.omega * link.alpha
        applied += data.mass * (v @ gravity)
    for f in scene.loads.forces:
        _, v, _ = motion.links[f.link].point(f.at)
        applied += v @ np.asarray(f.force, float)
    for c in scene.loads.couples:
        applied += c.value * motion.links[c.link].omega
    for k, s in enumerate(mechanism.linkage.sliders):
        applied += s.friction * motion.linkage.strokes[k][1]
    return power_in, rate - applied
