"""What a scene asks for, and computing it: kinematics, joint forces, section stresses.

Without an [analysis] table a scene gets everything its data allows (docs/design.md, "Scene file"):
kinematics always, forces when every moving link has mass data, section stresses for the moving
links that have a profile and a material. With the table, exactly what it names, and a named stage
whose data is missing is an error that says which keys would supply it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.linkage_forces import moving_contacts
from linkstress.dynamics.machine_forces import MachineForces, machine_forces
from linkstress.dynamics.section_stress import StressSummary, links_section_stresses
from linkstress.errors import SceneError
from linkstress.kinematics import MachineMotion, solve_machine
from linkstress.geometry.members import Member, link_members
from linkstress.loads import hole_at
from linkstress.model_choice import DEFAULT_ACCURACY, FEA_PEAKS, NO_FEA, ModelChoice, choose_models
from linkstress.scene import Scene
from linkstress.threads import blas_alone

DEFAULT_STATIONS = 101
"""Section stations per link when the scene does not say (see docs/benchmarks.md, the speed/error table)."""
PEAK_MESH_LEVELS = 3
"""The FEA peaks' mesh is the finest of validate's default refinement study of this many levels."""


@dataclass(frozen=True)
class Plan:
    """The stages to run: ``forces``; section stresses for ``stresses`` (link names) at ``stations``
    per link, with the body-load term near holes too when ``body_load_near_holes``; FEA for
    ``validate``; FEA peaks over the sweep, by superposition of unit loads, and fatigue for ``peaks``
    (judged by ``fatigue_criterion``); ``notes`` say why a stage or link is left out, and
    ``unstressed`` (link, why) names each moving link with a drawn profile that gets no section
    stresses (a slider's block, one without a material, one left out by [analysis]), for the
    verdict to show as not analysed. Each stressed
    link's stress model is chosen for the governing stress within ``accuracy``
    (``linkstress.model_choice``); ``analyze`` runs the FEA peaks of the links chosen for them
    unless ``beam_only``, and of every stressed link when ``peaks`` names them (``with_peaks``)."""

    forces: bool
    stresses: tuple[str, ...]
    stations: int
    validate: tuple[str, ...]
    notes: tuple[str, ...]
    body_load_near_holes: bool = False
    peaks: tuple[str, ...] = ()
    fatigue_criterion: str = "goodman"
    accuracy: float = DEFAULT_ACCURACY
    beam_only: bool = False
    unstressed: tuple[tuple[str, str], ...] = ()
    guides: tuple[str, ...] = ()
    """Links a slider's block slides along: their sections take the moving contact, and their FEA
    bears the block on the walls of the closed slot it runs in (none where it runs elsewhere)."""

    def with_peaks(self) -> Plan:
        """The same plan with FEA peaks for every stressed link."""
        return replace(self, peaks=self.stresses)

    def fea_links(self, models: dict[str, ModelChoice]) -> tuple[str, ...]:
        """The links whose FEA peaks ``analyze`` computes: none when ``beam_only``, ``peaks`` when
        asked for, else those whose chosen model (``models``) is "fea-peaks"."""
        if self.beam_only:
            return ()
        unable = {name for name, m in models.items() if NO_FEA in m.reason}
        if self.peaks:
            return tuple(name for name in self.peaks if name not in unable)
        return tuple(name for name in self.stresses
                     if name in models and models[name].model == FEA_PEAKS and name not in unable)

    def describe(self) -> str:
        lines = ["plan:", "  kinematics: every position"]
        lines.append(f"  joint forces: {'yes' if self.forces else 'no'}")
        lines.append(
            f"  section stresses: {', '.join(self.stresses) if self.stresses else 'none'}"
            + (f" ({self.stations} stations each)" if self.stresses else "")
            + (", body-load term near holes too" if self.stresses and self.body_load_near_holes else "")
        )
        lines.append(f"  FEA check: {', '.join(self.validate) if self.validate else 'none'}")
        if self.stresses and not self.peaks:
            lines.append(
                "  FEA peaks: none (--beam-only)" if self.beam_only else
                f"  FEA peaks over the sweep: the links whose governing stress beam theory and the Kt tables cannot "
                f"answer within {100 * self.accuracy:g} % (the model of each is chosen after the section stresses)"
            )
        if self.peaks:
            lines.append(
                f"  FEA peaks over the sweep (superposed unit loads) and fatigue ({self.fatigue_criterion}): "
                + ", ".join(self.peaks)
            )
        lines += [f"  note: {note}" for note in self.notes]
        return "\n".join(lines)


def plan_for(scene: Scene) -> Plan:
    """The plan of ``scene``: its [analysis] table, or everything its data allows."""
    moving = scene.moving_links
    without_mass = [n for n in moving if scene.links[n].mass_data is None]
    profiled = [n for n in moving if scene.links[n].profile is not None and scene.links[n].material is not None]
    # A slider block's frame is its one joint: no member between two joints to section.
    sliders = [n for n in profiled if len(set(scene.links[n].frame_joints)) == 1]
    # A linkage's guide carries its slider's contact at a point that moves along it.
    guides = [n for n in profiled if scene.linkage is not None and n in moving_contacts(scene.linkage)]
    stressable = [n for n in profiled if n not in sliders]
    asked = scene.analysis
    notes = []
    if asked is None:
        forces = not without_mass
        if without_mass:
            notes.append(f"no joint forces: {', '.join(without_mass)} lack mass data (mass, inertia, center_of_mass)")
        stresses = tuple(stressable) if forces else ()
        validate = stresses
        stations = DEFAULT_STATIONS
    else:
        wants_stresses = asked.stresses or bool(asked.validate)
        forces = asked.forces or wants_stresses
        if forces and without_mass:
            raise SceneError(
                f"analysis: forces need the mass of every moving link; links.{without_mass[0]} has none: give "
                "mass, inertia and center_of_mass, or a sketch with thickness and material"
            )
        stresses = tuple(stressable) if asked.stresses else tuple(asked.validate)
        validate = tuple(asked.validate)
        for name in validate:
            if name in sliders:
                raise SceneError(
                    f"analysis.validate: link {name!r} is a slider, with one joint: there is no member between two "
                    "joints to compare along; leave it out"
                )
            if name not in stressable:
                raise SceneError(f"analysis.validate: link {name!r} needs a sketch, a thickness and a material")
        stations = asked.stations or DEFAULT_STATIONS
    unstressed = []
    for name in moving:
        drawn = scene.links[name].profile is not None
        if name in sliders:
            why = "a slider, with one joint, has no member between two to section"
        elif name not in stressable:
            why = "it has no material" if drawn else "it has no sketch profile with a material"
        elif name not in stresses:
            why = "left out by [analysis] (stresses = false)" if forces else "no joint forces to stress it with"
        else:
            continue
        if (asked is None or asked.stresses) and name not in stressable:
            notes.append(f"no section stresses for {name}: {why}")
        if drawn:
            unstressed.append((name, why))
    body_load_near_holes = asked is not None and asked.body_load_near_holes
    peaks = stresses if asked is not None and asked.peaks else ()
    criterion = asked.fatigue_criterion if asked is not None else "goodman"
    accuracy = asked.accuracy if asked is not None and asked.accuracy is not None else DEFAULT_ACCURACY
    return Plan(forces, stresses, stations, validate, tuple(notes), body_load_near_holes, peaks, criterion, accuracy,
                unstressed=tuple(unstressed), guides=tuple(guides))


@dataclass(frozen=True)
class AnalysisResult:
    """Everything computed for a scene over its P positions; ``feasible`` (P,) where every stage
    that ran could compute, ``reasons`` why not elsewhere; ``seconds`` per stage.
    ``stresses`` keep per-position reductions, per member; ``stresses[name].members[k].at(positions)``
    recomputes the arrays along a member. ``peaks``: per link of ``plan.peaks``, its FEA peaks over
    the sweep and fatigue (``linkstress.validation.peaks_scene.LinkPeaks``). ``models``: per
    stressed link, its stress model and why (``linkstress.model_choice``)."""

    scene: Scene
    plan: Plan
    kinematics: MachineMotion
    forces: MachineForces | None
    stresses: dict[str, StressSummary]
    seconds: dict[str, float] = field(default_factory=dict)
    peaks: dict[str, object] = field(default_factory=dict)
    models: dict[str, ModelChoice] = field(default_factory=dict)

    def curved(self, name: str) -> bool:
        """Whether link ``name`` has a curved member: one sectioned normal to its curved centreline
        (``linkstress.geometry.members``)."""
        stress = self.stresses.get(name)
        return stress is not None and any(m.member.curved for m in stress.members)

    @property
    def feasible(self) -> NDArray[np.bool_]:
        return self.kinematics.feasible if self.forces is None else self.forces.feasible

    @property
    def reasons(self) -> tuple[str, ...]:
        return self.kinematics.reasons if self.forces is None else self.forces.reasons

    def max_location(self, name: str, member: int | None = None) -> NDArray[np.float64]:
        """Where each position's largest section von Mises of link ``name`` (of its ``member``-th
        member, if given) is, ground frame (P, 2) [m]."""
        stress = self.stresses[name]
        return self.to_ground(name, stress.max_at if member is None else stress.members[member].max_at)

    def to_ground(self, name: str, local: NDArray[np.float64], positions: NDArray[np.intp] | None = None) -> NDArray[np.float64]:
        """Points (P, 2) [m] fixed in link ``name``'s member frame, one per position (of ``positions``,
        indices into the sweep, if given), in the ground frame."""
        motion = self.kinematics.links[name]
        angle, origin = motion.angle, motion.origin
        if positions is not None:
            angle, origin = angle[positions], origin[positions]
        c, s = np.cos(angle), np.sin(angle)
        return origin + np.column_stack([c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]])


def run_analysis(scene: Scene, plan: Plan | None = None, peaks: bool = True) -> AnalysisResult:
    """Run ``plan`` (default: the scene's) on ``scene`` (BLAS on one thread: ``linkstress.threads``):
    kinematics, forces, section stresses, each stressed link's model, and the FEA peaks of
    ``plan.peaks`` here unless ``peaks`` is False (the caller computes them: ``analyze`` does, for
    the links the plan and the models name, here or on a cluster)."""
    with blas_alone():
        return _run(scene, plan or plan_for(scene), peaks)


def _run(scene: Scene, plan: Plan, fea: bool) -> AnalysisResult:
    seconds = {}
    start = time.perf_counter()
    kinematics = solve_machine(scene.machine, scene.motion)
    seconds["kinematics"] = time.perf_counter() - start
    forces = None
    stresses: dict[str, StressSummary] = {}
    if plan.forces:
        start = time.perf_counter()
        forces = machine_forces(scene, kinematics)
        seconds["forces"] = time.perf_counter() - start
        start = time.perf_counter()
        jobs = []
        for name in plan.stresses:
            profile, loads = scene.links[name].profile, forces.link_loads[name]
            members = scene_link_members(scene, name, loads.frame_joints)
            jobs.append((profile, loads, members, plan.stations))
        stresses = dict(zip(plan.stresses, links_section_stresses(jobs, plan.body_load_near_holes)))
        seconds["stresses"] = time.perf_counter() - start
    result = AnalysisResult(scene, plan, kinematics, forces, stresses, seconds)
    result = replace(result, models=models_of(result))
    if fea and plan.peaks and forces is not None and not plan.beam_only:
        # The FEA stack (gmsh, scikit-fem) loads only when peaks are asked for.
        from linkstress.validation.peaks_scene import scene_peaks

        start = time.perf_counter()
        peaks = scene_peaks(scene, plan, forces)
        result = replace(result, peaks=peaks, seconds={**seconds, "peaks": time.perf_counter() - start})
    return result


ASKED = "FEA peaks asked for every stressed link (--peaks or [analysis] peaks = true)"


def models_of(result: AnalysisResult) -> dict[str, ModelChoice]:
    """Each stressed link's model for the plan's accuracy; "fea-peaks" for the links whose peaks the
    plan asks for, its reason saying so and what the choice alone would have been."""
    start = time.perf_counter()
    models = choose_models(result, result.plan.accuracy)
    result.seconds["model choice"] = time.perf_counter() - start
    for name in result.plan.peaks if not result.plan.beam_only else ():
        chosen = models[name]
        if chosen.model != FEA_PEAKS:
            models[name] = replace(chosen, model=FEA_PEAKS, reason=f"{ASKED}; by itself {chosen.model}: {chosen.reason}")
        else:
            models[name] = replace(chosen, reason=f"{ASKED}; by itself too: {chosen.reason}")
    return models


def used_joints(scene: Scene, name: str) -> tuple[int, ...]:
    """The joints of link ``name`` that ``scene`` uses, in order: those its mechanisms pin (the axis
    joints of every role the link plays; a linkage's pins, sliders and input), those its couples act at, those whose pin hole holds one of
    its point forces, and those its named members join. Its other joints (the centre of a lightening
    hole, taken as a joint by the sketch) end no member: their holes are plain holes."""
    link = scene.links[name]
    used = scene.machine.used_joints(name)
    used |= {c.at_joint for c in scene.loads.couples if c.link == name}
    used |= {k for pair in link.members or () for k in pair}
    profile = link.profile
    if profile is not None:
        i, j = link.frame_joints
        at = np.array([f.at for f in scene.loads.forces if f.link == name], float).reshape(-1, 2)
        # a point force's ``at`` is in the link's member frame (a slider's: its sketch moved to its joint)
        drawn = profile.frame(i, j).to_global(at) if i != j else at + profile.joints[i]
        holes = {hole_at(profile.outline, point) for point in drawn}
        used |= {k for k, hole in enumerate(profile.joint_holes) if hole is not None and hole in holes}
    return tuple(sorted(used))


def scene_link_members(scene: Scene, name: str, frame_joints: tuple[int, int]) -> tuple[Member, ...]:
    """Link ``name``'s members in the load frame of ``frame_joints``: those its scene names, else the
    tree over the joints the scene uses (``used_joints``), the same for the beam, validate and the
    FEA peaks."""
    link = scene.links[name]
    return link_members(link.profile, frame_joints, link.members, used_joints(scene, name))
