"""FEA peak stresses of a link over a sweep by a direct solve per position, for loads that unit
cases cannot superpose: a slider's block that slides along the link (a guide, the slotted lever
of a quick-return) bears on its slot where the block is, a place that moves with the position.

    peaks = direct_sweep_peaks(link, loads, positions, peak_mesh(link, loads.frame_joints))

The stiffness is factorised once; each block of positions is a block of right-hand sides (the
loads of ``fea.loads.link_loads``, the block's push on the slot included), solved, recovered and
reduced as ``peaks.sweep_peaks`` reduces the superposed field (``peaks.PeakReduction``). Memory
holds a block of positions, never nodes x positions.
"""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import NDArray

from linkstress.geometry.profile import LinkProfile
from linkstress.loads import LinkLoadCase
from linkstress.validation.fea.cache import DiskCache
from linkstress.validation.fea.link import applied_load, link_model, reaction_ratio, region_length, support_reactions
from linkstress.validation.fea.loads import link_loads
from linkstress.validation.fea.mesh import MeshSettings
from linkstress.validation.fea.plane_stress import factorise, minimal_support
from linkstress.validation.fea.recovery import stress_recovery
from linkstress.validation.peak_results import StoredCases, SweepPeaks
from linkstress.validation.peaks import PeakReduction


def direct_sweep_peaks(
    link: LinkProfile, loads: LinkLoadCase, positions: NDArray[np.intp], mesh: MeshSettings,
    cache: DiskCache | None = None,
) -> SweepPeaks:
    """The peaks of ``link`` at ``positions`` (indices into ``loads``) by a direct solve of each on
    ``mesh`` (from and into ``cache`` when given); its ``cases`` a ``StoredCases`` with no unit case
    (``count`` 0): every position is solved."""
    start = time.perf_counter()
    chosen = np.asarray(positions, dtype=np.intp)
    model = link_model(link, loads.at(chosen), mesh, cache)
    meshed = time.perf_counter()
    fixed, _ = minimal_support(model)
    stiffness = factorise(model, fixed)
    recovery = stress_recovery(model)
    n_nodes = model.scalar.N
    kept = PeakReduction.of(len(chosen), n_nodes)
    length = region_length(model)
    worst_stress, worst_value = np.zeros((n_nodes, 3)), -np.inf
    for part in PeakReduction.blocks(len(chosen), n_nodes):
        forces = link_loads(model, link, loads.at(chosen[part]), patch_radius=mesh.station_size)
        displacement, support = stiffness.solve(forces)
        stress = recovery.nodal_stress(displacement)  # (C, nodes, 3)
        kept.add(part, stress, reaction_ratio(support_reactions(model, fixed, support), applied_load(model, forces), length))
        k = int(np.argmax(kept.peak[part]))
        if kept.peak[part][k] > worst_value:
            worst_value, worst_stress = kept.peak[part][k], stress[k]
    cases = StoredCases(model.scalar.doflocs.T, model.scalar.element_dofs, model.n_dofs, 0, np.zeros(0),
                        tuple(loads.frame_joints), {"mesh": meshed - start, "solve": time.perf_counter() - meshed})
    return kept.peaks(cases, chosen, worst_stress, 0.0)
