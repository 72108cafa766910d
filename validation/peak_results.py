"""The results of a link's FEA peaks over a sweep, as plain data: what ``validation.peaks`` computes
and ``validation.peaks_scene`` keeps in the disk cache. Importing this loads no FEA library, so that
a run whose peaks are all in the cache never loads gmsh or scikit-fem.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class SweepPeaks:
    """One link's superposed FEA over the positions ``positions`` (Pe,) (indices into the sweep).

    ``peak`` (Pe,) [Pa]: the largest recovered von Mises over the nodes, at node ``peak_node`` (Pe,);
    ``envelope`` (nodes,) [Pa]: each node's largest von Mises over the positions; ``largest`` and
    ``smallest`` (nodes,) [Pa]: each node's extremes of the signed equivalent stress;
    ``reaction_ratio`` (Pe,) [-]: the superposed support reactions (exact, the direct FEA's) over
    the unit cases' gross loads weighted by |weight| (at least the combined load's gross load, so
    the ratio is at most the direct FEA's; ~0 for loads in equilibrium); ``worst`` the index into
    ``positions`` of the largest peak and ``worst_stress`` (nodes, 3) [Pa] the field there;
    ``seconds`` of the superposition. ``cases``: the unit load cases (``fea.unit_loads.UnitLoadCases``)
    or, read from the cache, their ``StoredCases``.
    """

    cases: Any
    positions: NDArray[np.intp]
    peak: NDArray[np.float64]
    peak_node: NDArray[np.intp]
    envelope: NDArray[np.float64]
    largest: NDArray[np.float64]
    smallest: NDArray[np.float64]
    reaction_ratio: NDArray[np.float64]
    worst: int
    worst_stress: NDArray[np.float64]
    seconds: float

    @property
    def peak_at(self) -> NDArray[np.float64]:
        """Where (Pe, 2) [m, member frame] each position's peak is."""
        return self.cases.nodes[self.peak_node]


@dataclass(frozen=True)
class PeakCheck:
    """The peak at the sweep's worst position on three meshes, each REFINEMENT_RATIO finer than the
    last: ``coarsest`` and ``coarser`` [Pa] by direct FEA, ``finer`` [Pa] the superposed peak on the
    peak mesh. As validate judges its peak: both changes within ``limit`` (PEAK_CONVERGED_CHANGE) of
    the finer value (a singular corner can move little over one refinement and much over the one
    before)."""

    finer: float
    coarser: float
    coarsest: float
    limit: float

    @property
    def change(self) -> float:
        """[-]: the change over the last refinement, relative to the finer peak."""
        return abs(self.finer - self.coarser) / self.finer if self.finer > 0 else 0.0

    @property
    def previous_change(self) -> float:
        """[-]: the change over the refinement before, relative to the coarser peak."""
        return abs(self.coarser - self.coarsest) / self.coarser if self.coarser > 0 else 0.0

    @property
    def converged(self) -> bool:
        return self.change <= self.limit and self.previous_change <= self.limit


@dataclass(frozen=True)
class StoredCases:
    """What the reports read of a link's unit load cases, as the cache keeps them: the recovery
    ``nodes`` (nodes, 2) [m, member frame], the elements' node indices ``element_dofs`` (per element
    column), the model's ``dofs``, the number of unit cases ``count``, the bearing ``directions``
    (K,) [rad], the ``frame_joints`` and ``seconds`` (read from the cache: no mesh, no solve)."""

    nodes: NDArray[np.float64]
    element_dofs: NDArray[np.intp]
    dofs: int
    count: int
    directions: NDArray[np.float64]
    frame_joints: tuple[int, int]
    seconds: dict[str, float]


@dataclass(frozen=True)
class MeshSizes:
    """The peak mesh's element ``size`` and ``hole_size`` [m] and element ``order``, as the records
    report them (``fea.mesh.MeshSettings`` has these too)."""

    size: float
    hole_size: float
    order: int
