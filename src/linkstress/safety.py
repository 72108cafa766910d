"""Safety factors against yield: a link's yield strength over the stress it reaches.

Where a link's material gives ``yield_strength`` [Pa], ``analyze`` reports, per position, the yield
strength over the link's largest section von Mises (beam theory; nominal within a section depth of
a pin hole) and, where the link has pin-hole estimates, over the largest Kt x nominal estimate (an
estimate, labelled as one, like the stress it divides). A position where the stress is zero has no
finite factor: the reports leave it empty (JSON null), never print infinity.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.dynamics.section_stress import SectionStresses, StressSummary


@dataclass(frozen=True)
class SafetyFactors:
    """One link's factors over P positions: ``sections`` (P,), yield strength over the largest
    section von Mises; ``pin_holes`` (P,) over the largest pin-hole estimate, None where the link has
    none (no pin hole, or every hole beyond the Kt table); inf where the stress is zero."""

    yield_strength: float
    sections: NDArray[np.float64]
    pin_holes: NDArray[np.float64] | None

    def lowest(self, positions) -> tuple[float, float | None]:
        """The lowest factors over ``positions`` (a mask or indices): against the sections, and
        against the pin holes (None where the link has no estimate); inf where no stress there."""
        pin_holes = None if self.pin_holes is None else float(self.pin_holes[positions].min())
        return float(self.sections[positions].min()), pin_holes


def yield_factor(yield_strength: float, stress: NDArray[np.float64]) -> NDArray[np.float64]:
    """``yield_strength`` [Pa] over ``stress`` [Pa], inf where the stress is zero."""
    stress = np.asarray(stress, float)
    with np.errstate(divide="ignore"):
        return np.where(stress > 0, yield_strength / stress, np.inf)


def safety_factors(stress: SectionStresses | StressSummary, yield_strength: float) -> SafetyFactors:
    """The factors of a link whose stresses are ``stress`` and whose material yields at
    ``yield_strength`` [Pa]."""
    estimates = [hole.estimate for hole in stress.pin_holes if hole.estimate is not None]
    pin_holes = yield_factor(yield_strength, np.max(estimates, axis=0)) if estimates else None
    return SafetyFactors(yield_strength, yield_factor(yield_strength, stress.max_von_mises), pin_holes)


def link_safety_factors(result: AnalysisResult) -> dict[str, SafetyFactors]:
    """The factors of every link with section stresses and a material that gives a yield strength."""
    factors = {}
    for name, stress in result.stresses.items():
        material = result.scene.links[name].material
        if material is not None and material.yield_strength is not None:
            factors[name] = safety_factors(stress, material.yield_strength)
    return factors


def finite_or_none(values: NDArray[np.float64]) -> list[float | None]:
    """JSON-ready values: None where a factor is infinite."""
    return [v if np.isfinite(v) else None for v in values.tolist()]
