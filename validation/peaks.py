"""FEA peak stresses of a link over a whole sweep, by superposition of its unit load cases.

    cases = unit_load_cases(link, loads, peak_mesh(link, loads.frame_joints))
    peaks = sweep_peaks(cases, loads, positions)

Each position's recovered nodal stress is the unit cases' stresses weighted by that position's
loads (``UnitLoadCases.weights``): one matrix product per block of positions. From it, per
position, the largest von Mises over the nodes and the node where it is; per node, over the sweep,
the largest von Mises and the largest and smallest signed equivalent stress (von Mises with the
sign of the principal stress of larger magnitude, ``linkstress.fatigue``) that a fatigue check
cycles. Memory holds a block of positions and a few values per node, never nodes x positions.

The mesh is validate's finest of its default refinement study (``peak_mesh``). Whether the peak has
settled on it is checked at the sweep's worst position (``coarser_peak``): the direct FEA on the
mesh one refinement coarser, whose peak must lie within PEAK_CONVERGED_CHANGE of this one.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import PEAK_MESH_LEVELS
from linkstress.loads import LinkLoadCase
from linkstress.geometry.members import Member
from linkstress.geometry.profile import LinkProfile
from linkstress.stress_state import larger_principal_sign, von_mises
from linkstress.validation.stations import choose_stations, default_mesh, member_stations
from linkstress.validation.fea.convergence import PEAK_CONVERGED_CHANGE, REFINEMENT_RATIO
from linkstress.validation.fea.cache import DiskCache, cache_key
from linkstress.validation.fea.link import link_region, reaction_ratio, region_length, solve_link
from linkstress.validation.fea.mesh import MeshSettings, mesh_key_parts
from linkstress.validation.fea.unit_loads import UnitLoadCases
from linkstress.validation.peak_results import PeakCheck, SweepPeaks

BLOCK_VALUES = 2_000_000
"""Stress values (nodes x 3 x positions) superposed at once: 16 MB, whatever the mesh or sweep."""


def superposed_stress(cases: UnitLoadCases, weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """Recovered nodal stress (P, nodes, 3) [Pa] of the unit cases combined with ``weights`` (U, P)."""
    weights = np.asarray(weights, float).reshape(cases.count, -1)
    # Made position-major, so that the von Mises and principal stresses that follow read it in order.
    return (weights.T @ cases.stress.T).reshape(weights.shape[1], -1, 3)


@dataclass
class PeakReduction:
    """What a sweep keeps of its nodal stress, filled a block of positions at a time (``add``): per
    position the largest von Mises [Pa], its node and the reaction ratio [-]; per node the largest
    von Mises and the largest and smallest signed equivalent stress [Pa] (von Mises with the sign of
    the principal stress of larger magnitude, ``linkstress.fatigue``) that a fatigue check cycles."""

    peak: NDArray[np.float64]
    peak_node: NDArray[np.intp]
    ratio: NDArray[np.float64]
    envelope: NDArray[np.float64]
    largest: NDArray[np.float64]
    smallest: NDArray[np.float64]

    @classmethod
    def of(cls, positions: int, nodes: int) -> "PeakReduction":
        return cls(np.zeros(positions), np.zeros(positions, dtype=np.intp), np.zeros(positions), np.zeros(nodes),
                   np.full(nodes, -np.inf), np.full(nodes, np.inf))

    @staticmethod
    def blocks(positions: int, nodes: int) -> list[slice]:
        """The blocks of positions whose stress (positions x nodes x 3) fits BLOCK_VALUES."""
        size = max(1, BLOCK_VALUES // (3 * nodes))
        return [slice(first, first + size) for first in range(0, positions, size)]

    def add(self, part: slice, stress: NDArray[np.float64], ratio: NDArray[np.float64]) -> None:
        """The nodal ``stress`` (C, nodes, 3) [Pa] and reaction ``ratio`` (C,) of the positions ``part``."""
        vm = von_mises(stress)
        node = vm.argmax(axis=1)
        self.peak[part], self.peak_node[part] = vm[np.arange(len(node)), node], node
        signed = larger_principal_sign(stress) * vm  # fatigue's signed_von_mises, its von Mises reused
        np.maximum(self.envelope, vm.max(axis=0), out=self.envelope)
        np.maximum(self.largest, signed.max(axis=0), out=self.largest)
        np.minimum(self.smallest, signed.min(axis=0), out=self.smallest)
        self.ratio[part] = ratio

    @property
    def worst(self) -> int:
        """The index of the largest peak (0 without positions)."""
        return int(np.argmax(self.peak)) if len(self.peak) else 0

    def peaks(self, cases, positions: NDArray[np.intp], worst_stress: NDArray[np.float64], seconds: float) -> SweepPeaks:
        """The ``SweepPeaks`` of ``cases`` at ``positions``, the field at the worst one ``worst_stress``."""
        return SweepPeaks(cases, positions, self.peak, self.peak_node, self.envelope, self.largest, self.smallest,
                          self.ratio, self.worst, worst_stress, seconds)


def sweep_peaks(cases: UnitLoadCases, loads: LinkLoadCase, positions: NDArray[np.intp] | None = None) -> SweepPeaks:
    """Superpose ``cases`` over ``positions`` of ``loads`` (all by default), a block at a time."""
    start = time.perf_counter()
    chosen = np.arange(loads.n_positions) if positions is None else np.asarray(positions, dtype=np.intp)
    n_nodes = cases.stress.shape[0] // 3
    kept = PeakReduction.of(len(chosen), n_nodes)
    length = region_length(cases.model)
    for part in PeakReduction.blocks(len(chosen), n_nodes):
        weights = cases.weights(loads.at(chosen[part]))
        ratio = reaction_ratio(weights.T @ cases.reactions, np.abs(weights).T @ cases.applied, length)
        kept.add(part, superposed_stress(cases, weights), ratio)
    worst = kept.worst
    worst_stress = (
        superposed_stress(cases, cases.weights(loads.at(chosen[worst:worst + 1])))[0]
        if len(chosen) else np.zeros((n_nodes, 3))
    )
    return kept.peaks(cases, chosen, worst_stress, time.perf_counter() - start)


def peak_mesh(
    link: LinkProfile,
    frame_joints: tuple[int, int],
    members: Sequence[Member] = (),
    size: float | None = None,
    order: int = 2,
    levels: int = PEAK_MESH_LEVELS,
) -> MeshSettings:
    """Validate's default mesh of the link, refined to the finest of a ``levels`` study, without
    the comparison cuts (a peak is at a hole's rim or a fillet, not on a cut); sized at the stations
    of the frame's member among ``members`` (else of ``frame_member``)."""
    frame = next((m for m in members if m.joints == tuple(frame_joints)), None)
    stations = (member_stations(frame) if frame is not None else choose_stations(link, frame_joints)).x
    base = replace(default_mesh(link, frame_joints, stations, size, members), order=order)
    return replace(base.refined(REFINEMENT_RATIO ** (levels - 1)), stations=(), cuts=())


def coarser_peak(peaks: SweepPeaks, loads: LinkLoadCase, mesh: MeshSettings, cache: DiskCache | None = None,
                 link: LinkProfile | None = None) -> PeakCheck:
    """The peak's changes over the last two refinements at the sweep's worst position: the direct
    FEA on ``mesh`` (the peak mesh) made REFINEMENT_RATIO and REFINEMENT_RATIO^2 coarser (each
    from and into ``cache`` when given: ``direct_peak``); ``link`` that of the unit cases unless given."""
    worst = loads.at(peaks.positions[peaks.worst : peaks.worst + 1])
    link = link or peaks.cases.link
    coarser, coarsest = (direct_peak(link, worst, mesh.refined(REFINEMENT_RATIO ** -k), cache) for k in (1, 2))
    return PeakCheck(float(peaks.peak[peaks.worst]), coarser, coarsest, PEAK_CONVERGED_CHANGE)


DIRECT_PEAK = "direct-peak"
"""The cache's kind for the peak von Mises of a direct FEA at one position."""


def direct_peak(link: LinkProfile, loads: LinkLoadCase, mesh: MeshSettings, cache: DiskCache | None = None) -> float:
    """[Pa]: the largest recovered von Mises of the direct FEA of ``link`` under ``loads`` (one
    position) on ``mesh``. With ``cache``: its mesh is cached, and the peak itself under a key of
    the mesh's, the material's and these exact loads' (it is reused only for the same loads: the
    same scene run again, or one whose changes leave this link's worst position alone)."""
    if cache is None:
        return float(solve_link(link, loads, mesh).von_mises_peak[0])
    material = link.material
    key = cache_key(DIRECT_PEAK, {
        "mesh": mesh_key_parts(*link_region(link, loads, mesh)),
        "youngs_modulus": material.youngs_modulus, "poisson_ratio": material.poisson_ratio,
        "density": link.density, "thickness": link.thickness, "frame_joints": list(loads.frame_joints),
        "pin_forces": loads.pin_forces, "joint_couples": loads.joint_couples, "omega": loads.omega,
        "alpha": loads.alpha, "origin_acceleration": loads.origin_acceleration, "gravity": loads.gravity,
        "point_forces": [{"at": np.asarray(p.at, float), "force": np.asarray(p.force, float)} for p in loads.point_forces],
        "contacts": [c.record() for c in loads.contacts],
    })
    stored = cache.load(DIRECT_PEAK, key)
    if stored is not None:
        return float(stored["peak"][0])
    peak = float(solve_link(link, loads, mesh, cache).von_mises_peak[0])
    cache.store(DIRECT_PEAK, key, {"peak": np.array([peak])})
    return peak


def field_error(superposed: NDArray[np.float64], direct: NDArray[np.float64]) -> NDArray[np.float64]:
    """(P,) [-]: rms over the nodes of the von Mises difference of two nodal stress fields (P, nodes,
    3), relative to the rms of the direct one's von Mises."""
    vs, vd = von_mises(superposed), von_mises(direct)
    rms = np.sqrt((vd**2).mean(axis=1))
    diff = np.sqrt(((vs - vd) ** 2).mean(axis=1))
    return np.divide(diff, rms, out=np.zeros_like(diff), where=rms > 0)
