"""Safety factors against yield: a link's yield strength over the stress it reaches.

Where a link's material gives ``yield_strength`` [Pa], ``analyze`` reports, per position, the yield
strength over the link's largest section von Mises (beam theory; nominal within a section depth of
a pin hole) and, where the link has pin-hole estimates, over the largest Kt x nominal estimate (an
estimate, labelled as one, like the stress it divides). A position where the stress is zero has no
finite factor: the reports leave it empty (JSON null), never print infinity.

A curved link (``linkstress.curvature``) gets no section factor: its straight-beam von Mises falls
10-20 % short of the FEA, and a factor from it would be unconservative. The reports say why
(``CURVED_NOTE``) and point to ``linkstress validate``. The pin-hole estimate's factor stays: Kt x
the net-section stress of the pin force is the lug's own value at the hole, not a section across
the curved bar.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.dynamics.section_stress import SectionStresses


CURVED_NOTE = "not given: curved link (straight-beam value), see validate"
"""Said in place of the section factor of a curved link."""


@dataclass(frozen=True)
class SafetyFactors:
    """One link's factors over P positions: ``sections`` (P,), yield strength over the largest
    section von Mises, None where withheld (``withheld`` says why); ``pin_holes`` (P,) over the
    largest pin-hole estimate, None where the link has none (no pin hole, or every hole beyond the
    Kt table); inf where the stress is zero."""

    yield_strength: float
    sections: NDArray[np.float64] | None
    pin_holes: NDArray[np.float64] | None
    withheld: str | None = None

    def lowest(self, positions) -> tuple[float | None, float | None]:
        """The lowest factors over ``positions`` (a mask or indices): against the sections (None
        where withheld), and against the pin holes (None where the link has no estimate); inf where
        no stress there."""
        sections = None if self.sections is None else float(self.sections[positions].min())
        pin_holes = None if self.pin_holes is None else float(self.pin_holes[positions].min())
        return sections, pin_holes


def yield_factor(yield_strength: float, stress: NDArray[np.float64]) -> NDArray[np.float64]:
    """``yield_strength`` [Pa] over ``stress`` [Pa], inf where the stress is zero."""
    stress = np.asarray(stress, float)
    with np.errstate(divide="ignore"):
        return np.where(stress > 0, yield_strength / stress, np.inf)


def safety_factors(stress: SectionStresses, yield_strength: float, curved: bool = False) -> SafetyFactors:
    """The factors of a link whose stresses are ``stress`` and whose material yields at
    ``yield_strength`` [Pa]; a ``curved`` link's section factor is withheld."""
    estimates = [hole.estimate for hole in stress.pin_holes if hole.estimate is not None]
    pin_holes = yield_factor(yield_strength, np.max(estimates, axis=0)) if estimates else None
    if curved:
        return SafetyFactors(yield_strength, None, pin_holes, CURVED_NOTE)
    return SafetyFactors(yield_strength, yield_factor(yield_strength, stress.max_von_mises), pin_holes)


def link_safety_factors(result: AnalysisResult) -> dict[str, SafetyFactors]:
    """The factors of every link with section stresses and a material that gives a yield strength."""
    factors = {}
    for name, stress in result.stresses.items():
        material = result.scene.links[name].material
        if material is not None and material.yield_strength is not None:
            factors[name] = safety_factors(stress, material.yield_strength, result.curved(name))
    return factors


def finite_or_none(values: NDArray[np.float64]) -> list[float | None]:
    """JSON-ready values: None where a factor is infinite."""
    return [v if np.isfinite(v) else None for v in values.tolist()]
