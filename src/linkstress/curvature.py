"""Is a link curved? Straight-beam sections across a curved bar fall short of its stress.

A section table cuts a link square to its member axis (the line through two joints). On a curved
bar (a banana or arc coupler) those cuts meet the bar at an angle and sigma = N/A + M y/I misses the
curvature's shift of the neutral axis (Winkler-Bach): on the shipped banana coupler and curved rod
the straight-beam maximum is 10-18 % below the FEA. The sign of a curved bar is its neutral axis
(the centroid of each cut) bending away from a straight line. Measured as the spread of the neutral
axis about its least-squares line, over the cuts that are one solid chord a section depth from every
hole and between the outermost holes: a hole moves the centroid of a straight bar too, the tip
of a lug beyond its pin is no part of the bar, and a straight taper tilts the neutral axis
without bending it. A link is curved when that spread exceeds ``CURVED`` of its smallest depth there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.section_stress import near_holes
from linkstress.profile import LinkProfile
from linkstress.sections import SectionTable

CURVED = 0.1
"""A link whose neutral axis wanders more than this fraction of its depth off a straight line."""
STATIONS = 201
"""Cuts between the joints for the decision: the same for every scene, whatever its analysis stations."""


@dataclass(frozen=True)
class Curvature:
    """How far a link's neutral axis wanders off a straight line, ``wander`` [m], and the smallest
    section depth [m] where it was measured (member frame)."""

    wander: float
    depth: float

    @property
    def depths(self) -> float:
        """The wander in section depths [-]."""
        return self.wander / self.depth

    @property
    def curved(self) -> bool:
        return self.depths > CURVED


def neutral_axis_wander(table: SectionTable, near_hole: NDArray[np.bool_]) -> tuple[float, float] | None:
    """The spread [m] of the neutral axis about its least-squares line and the smallest section depth
    [m], over the single-chord stations not ``near_hole`` and between the outermost near-hole ones
    (beyond a pin is the end of its lug, whose rounded tip says nothing of the bar's axis); None
    with fewer than three such stations (two always lie on a line)."""
    plain = (table.n_chords == 1) & ~near_hole
    if near_hole.any():
        holes = np.flatnonzero(near_hole)
        plain[: holes[0]] = plain[holes[-1] + 1 :] = False
    if plain.sum() < 3:
        return None
    x, y = table.x[plain], table.neutral_axis[plain]
    line = np.polyval(np.polyfit(x, y, 1), x)
    return float(np.ptp(y - line)), float((table.top - table.bottom)[plain].min())


def is_curved(table: SectionTable, near_hole: NDArray[np.bool_]) -> bool:
    """A link whose neutral axis wanders more than CURVED section depths: straight sections fall short."""
    wander = neutral_axis_wander(table, near_hole)
    return wander is not None and wander[0] > CURVED * wander[1]


def link_curvature(link: LinkProfile, frame_joints: tuple[int, int]) -> Curvature | None:
    """The curvature of ``link`` along the member axis of ``frame_joints``, from ``STATIONS`` cuts
    between those joints (beyond a joint is its lug, whose rounded or hooked end says nothing of the
    bar's axis); None where fewer than three cuts are clear of holes (the link is all near-hole
    region, where every section value is nominal anyway)."""
    span = float(np.linalg.norm(np.subtract(*link.joints[list(frame_joints)])))
    table = link.sections(span * (np.arange(STATIONS) + 0.5) / STATIONS, *frame_joints)
    wander = neutral_axis_wander(table, near_holes(link, frame_joints, table))
    return None if wander is None else Curvature(*wander)
