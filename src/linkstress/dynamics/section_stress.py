"""Beam-section stresses along a link: normal, Jourawski shear and von Mises at every fibre.

At station x with N, V, M (see ``internal_forces``) and the section's A, I, y_na and first moment
Q(y) (``linkstress.sections``), at fibre y of the plate of thickness t:

    sigma = N / A + M (y - y_na) / I,   tau = V Q(y) / (I t),   sigma_vM = sqrt(sigma^2 + 3 tau^2).

Fibres: FIBRES_PER_CHORD evenly spaced points of every material chord (ends included) and the
neutral axis. Near a pin hole beam theory does not hold: stations closer to a hole than one local
section depth are flagged, and their values are nominal.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.internal_forces import InternalForces, internal_forces
from linkstress.loads import LinkLoadCase
from linkstress.profile import LinkProfile
from linkstress.region_moments import region_moments
from linkstress.sections import SectionTable

FIBRES_PER_CHORD = 9
POSITION_CHUNK = 512
"""Positions evaluated together: bounds memory at (chunk x stations x fibres) floats."""


@dataclass(frozen=True)
class SectionStresses:
    """Stresses along one link over P positions and S stations, member frame.

    ``forces``: N, V, M. ``von_mises`` (P, S) [Pa]: the largest von Mises over the section's fibres,
    reached at ``fibre_y`` (P, S) [m]; ``sigma``/``tau`` (P, S) [Pa] at that fibre. ``near_hole`` (S,):
    station within one section depth of a hole (nominal values only). ``max_von_mises`` (P,) and
    ``max_at`` (P, 2) [m]: the largest over all stations; ``max_away_from_holes`` likewise over
    stations not near a hole (0 where every station is near one).
    """

    sections: SectionTable
    forces: InternalForces
    von_mises: NDArray[np.float64]
    fibre_y: NDArray[np.float64]
    sigma: NDArray[np.float64]
    tau: NDArray[np.float64]
    near_hole: NDArray[np.bool_]

    @property
    def x(self) -> NDArray[np.float64]:
        return self.sections.x

    @property
    def max_von_mises(self) -> NDArray[np.float64]:
        return self.von_mises.max(axis=1)

    @property
    def max_at(self) -> NDArray[np.float64]:
        k = self.von_mises.argmax(axis=1)
        rows = np.arange(len(k))
        return np.column_stack([self.x[k], self.fibre_y[rows, k]])

    @property
    def max_away_from_holes(self) -> NDArray[np.float64]:
        away = self.von_mises[:, ~self.near_hole]
        return away.max(axis=1) if away.shape[1] else np.zeros(len(self.von_mises))


def default_stations(link: LinkProfile, frame_joints: tuple[int, int], count: int) -> NDArray[np.float64]:
    """``count`` stations [m] at the centres of equal cells over the link's extent (never on an end,
    where a rounded link's section shrinks to a point)."""
    lo, hi = link.x_extent(*frame_joints)
    return lo + (hi - lo) * (np.arange(count) + 0.5) / count


def fibres(sections: SectionTable) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Fibre heights (S, F) [m] and which of them are material (S, F)."""
    s = np.linspace(0.0, 1.0, FIBRES_PER_CHORD)
    lower, upper = sections.lower[:, :, None], sections.upper[:, :, None]
    y = (lower + (upper - lower) * s).reshape(len(sections.x), -1)
    chord = np.repeat(np.arange(sections.lower.shape[1]), FIBRES_PER_CHORD)
    valid = chord[None, :] < sections.n_chords[:, None]
    y = np.column_stack([y, sections.neutral_axis])
    inside = ((sections.lower <= sections.neutral_axis[:, None]) & (sections.neutral_axis[:, None] <= sections.upper)
              & (np.arange(sections.lower.shape[1])[None, :] < sections.n_chords[:, None])).any(axis=1)
    return y, np.column_stack([valid, inside])


def near_holes(link: LinkProfile, frame_joints: tuple[int, int], sections: SectionTable) -> NDArray[np.bool_]:
    """Stations closer (along x) to a hole's extent than the local section depth."""
    outline = link.local_outline(*frame_joints)
    flags = np.zeros(len(sections.x), bool)
    height = sections.top - sections.bottom
    for ring in outline.interiors:
        xs = np.asarray(ring.coords)[:, 0]
        gap = np.maximum(xs.min() - sections.x, sections.x - xs.max())
        flags |= gap < height
    return flags


def section_stresses(
    link: LinkProfile,
    loads: LinkLoadCase,
    stations: NDArray[np.float64],
) -> SectionStresses:
    """Stresses at ``stations`` [m] (member frame of ``loads.frame_joints``) for every position."""
    frame_joints = loads.frame_joints
    table = link.sections(stations, *frame_joints)
    moments = region_moments(link.local_outline(*frame_joints), table.x)
    forces = internal_forces(link, loads, table, moments)
    y, valid = fibres(table)
    has_area = table.area > 0
    area = np.where(has_area, table.area, 1.0)
    inertia = np.where(table.second_moment > 0, table.second_moment, 1.0)
    lever = (y - table.neutral_axis[:, None]) / inertia[:, None]
    shear_flow = table.first_moment(y) / (inertia[:, None] * table.thickness)
    valid = valid & has_area[:, None] & (table.second_moment > 0)[:, None]
    n_pos = len(loads.omega)
    vm = np.zeros((n_pos, len(table.x)))
    fibre_y, sigma_at, tau_at = np.zeros_like(vm), np.zeros_like(vm), np.zeros_like(vm)
    rows = np.arange(len(table.x))
    for start in range(0, n_pos, POSITION_CHUNK):
        p = slice(start, start + POSITION_CHUNK)
        sigma = (forces.normal[p] / area)[..., None] + forces.moment[p][..., None] * lever
        tau = forces.shear[p][..., None] * shear_flow
        vm2 = np.where(valid, sigma * sigma + 3 * tau * tau, -1.0)
        k = vm2.argmax(axis=2)
        pick = (np.arange(k.shape[0])[:, None], rows[None, :], k)
        vm[p] = np.sqrt(np.maximum(vm2[pick], 0.0))
        fibre_y[p] = y[rows[None, :], k]
        sigma_at[p], tau_at[p] = sigma[pick], tau[pick]
    return SectionStresses(table, forces, vm, fibre_y, sigma_at, tau_at, near_holes(link, frame_joints, table))
