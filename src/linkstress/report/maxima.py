"""Where each figure of a stress or safety table comes from: its input angle and its location.

A sweep's tables give one number per link for each figure (the largest section von Mises, the
largest away from holes, the largest pin-hole estimate, the lowest safety factors), and each can
come from a different position of the sweep and a different place on the link. ``link_figures``
names, for every figure, the position it was taken at (index and input angle [deg]) and where on
the link it is: a point in the ground frame at that position [m], and for a pin-hole value the joint
whose hole it is. Only feasible positions count.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.report.cells import mpa, point, significant
from linkstress.safety import SafetyFactors


@dataclass(frozen=True)
class SweepFigure:
    """One table figure of a link: ``what`` it is, its ``value`` (a stress [Pa] or a factor [-]),
    the sweep position ``position`` it comes from at input ``input_angle_deg`` [deg], the point
    ``at`` [m] (ground frame, at that position) where it is reached, and the ``joint`` of the pin
    hole for a pin-hole value (else None)."""

    what: str
    value: float
    position: int
    input_angle_deg: float
    at: NDArray[np.float64]
    joint: int | None = None
    factor: bool = False
    """A safety factor [-] (else a stress [Pa])."""

    def describe(self, joint_labels: tuple[str, ...] | None = None) -> str:
        """One line: the value (a stress in MPa, a factor, 3 significant digits), its input angle and
        its location with its frame; a pin hole named by ``joint_labels`` (per joint) when given."""
        if not np.isfinite(self.value):
            value = "- (no stress)"
        else:
            value = significant(self.value) if self.factor else f"{mpa(self.value)} MPa"
        joint = None if self.joint is None else (f"joint {self.joint}" if joint_labels is None else joint_labels[self.joint])
        hole = "" if joint is None else f"the pin hole at {joint}, centre "
        return (
            f"{self.what} {value} at input {self.input_angle_deg:.6g} deg, {hole}at "
            f"{point(self.at)} m, ground frame"
        )


@dataclass(frozen=True)
class LinkFigures:
    """The figures of one link over the feasible positions: ``max_von_mises``, ``away_from_holes``
    (None where every station is near a hole), ``pin_hole`` (None without an estimate) and, with a
    yield strength, ``section_factor`` and ``pin_hole_factor``."""

    max_von_mises: SweepFigure
    away_from_holes: SweepFigure | None
    pin_hole: SweepFigure | None
    section_factor: SweepFigure | None = None
    pin_hole_factor: SweepFigure | None = None
    members: tuple[SweepFigure, ...] = ()
    """Each member's largest von Mises, for a link of more than one member."""


def to_ground(result: AnalysisResult, name: str, k: int, local: NDArray[np.float64]) -> NDArray[np.float64]:
    """The point ``local`` [m] of link ``name``'s member frame in the ground frame at position ``k`` [m]."""
    motion = result.kinematics.links[name]
    c, s = np.cos(motion.angle[k]), np.sin(motion.angle[k])
    return motion.origin[k] + np.array([c * local[0] - s * local[1], s * local[0] + c * local[1]])


def worst_position(values: NDArray[np.float64], ok: NDArray[np.bool_]) -> int:
    """The feasible position (index into the sweep) where ``values`` (P,) is largest."""
    return int(np.flatnonzero(ok)[np.argmax(values[ok])])


def link_figures(result: AnalysisResult, name: str, factors: SafetyFactors | None = None) -> LinkFigures | None:
    """Every table figure of link ``name`` with where it comes from; None without a feasible position."""
    ok = result.feasible
    if not ok.any():
        return None
    angles = result.scene.motion.angle_deg
    stress = result.stresses[name]
    k = worst_position(stress.max_von_mises, ok)
    peak = SweepFigure("max von Mises", float(stress.max_von_mises[k]), k, float(angles[k]), result.max_location(name)[k])
    away = _away_from_holes(result, name, ok)
    pin_hole = _pin_hole(result, name, ok)
    members = _members(result, name, ok)
    if factors is None:
        return LinkFigures(peak, away, pin_hole, members=members)
    section_factor = None
    if factors.sections is not None:
        section_factor = SweepFigure("yield safety factor", float(factors.sections[k]), k, peak.input_angle_deg, peak.at,
                                     factor=True)
    pin_factor = None
    if pin_hole is not None and factors.pin_holes is not None:
        j = pin_hole.position
        pin_factor = SweepFigure(
            "yield safety factor at pin holes (estimate)", float(factors.pin_holes[j]), j, pin_hole.input_angle_deg,
            pin_hole.at, pin_hole.joint, factor=True,
        )
    return LinkFigures(peak, away, pin_hole, section_factor, pin_factor, members)


def _members(result: AnalysisResult, name: str, ok: NDArray[np.bool_]) -> tuple[SweepFigure, ...]:
    """Each member's largest von Mises over the sweep, where a link has more than one member."""
    members = result.stresses[name].members
    if len(members) < 2:
        return ()
    angles = result.scene.motion.angle_deg
    figures = []
    for index, member in enumerate(members):
        k = worst_position(member.max_von_mises, ok)
        what = f"member {list(member.joints)} ({member.theory} beam) max von Mises"
        at = result.max_location(name, index)[k]
        figures.append(SweepFigure(what, float(member.max_von_mises[k]), k, float(angles[k]), at))
    return tuple(figures)


def _away_from_holes(result: AnalysisResult, name: str, ok: NDArray[np.bool_]) -> SweepFigure | None:
    stress = result.stresses[name]
    values = stress.max_away_from_holes
    if values is None:
        return None
    k = worst_position(values, ok)
    member = max(
        (m for m in stress.members if m.max_away_from_holes is not None), key=lambda m: m.max_away_from_holes[k],
    )
    away = np.flatnonzero(~member.near_hole)
    arrays = member.at(slice(k, k + 1))  # that one position's arrays along the member
    s = int(away[np.argmax(arrays.von_mises[0, away])])
    at = to_ground(result, name, k, arrays.cuts.points(arrays.fibre_y[0])[s])
    return SweepFigure("max von Mises away from holes", float(values[k]), k, float(result.scene.motion.angle_deg[k]), at)


def _pin_hole(result: AnalysisResult, name: str, ok: NDArray[np.bool_]) -> SweepFigure | None:
    """The largest pin-hole estimate inside the Kt tables over the holes and positions, at its hole's
    centre; None where no hole's estimate is inside them at a feasible position."""
    holes = [hole for hole in result.stresses[name].pin_holes if not hole.outside[ok].all()]
    if not holes:
        return None
    estimates = np.stack([np.where(hole.outside, -1.0, hole.estimate) for hole in holes])
    k = worst_position(estimates.max(axis=0), ok)
    hole = holes[int(np.argmax(estimates[:, k]))]
    profile = result.scene.links[name].profile
    frame_joints = result.forces.link_loads[name].frame_joints
    centre = profile.frame(*frame_joints).to_local(profile.joints)[hole.joint]
    at = to_ground(result, name, k, centre)
    return SweepFigure(
        "pin hole estimate", float(hole.estimate[k]), k, float(result.scene.motion.angle_deg[k]), at, hole.joint,
    )
