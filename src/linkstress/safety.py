"""Safety factors against yield: a link's yield strength over the stress it reaches.

Where a link's material gives ``yield_strength`` [Pa], ``analyze`` reports, per position, the yield
strength over the link's largest section von Mises (beam theory; nominal within a section depth of
a pin hole) and, where the link has pin-hole estimates, over the largest Kt x nominal estimate (an
estimate, labelled as one, like the stress it divides). Only estimates whose Kt is inside the
tables at that position count: a position where every hole's geometry is outside them has no
pin-hole factor. A position where the stress is zero, or without a pin-hole factor, has no finite
factor: the reports leave it empty (JSON null), never print infinity or NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.dynamics.section_stress import SectionStresses


@dataclass(frozen=True)
class SafetyFactors:
    """One link's factors over P positions: ``sections`` (P,), yield strength over the largest
    section von Mises; ``pin_holes`` (P,) over the largest pin-hole estimate inside the Kt tables, None
    where the link has none at any position (no pin hole, or every hole outside the tables at every
    position); inf where the stress is zero, nan at a position where every hole is outside the tables
    (``has_pin_hole_factor`` says which)."""

    yield_strength: float
    sections: NDArray[np.float64]
    pin_holes: NDArray[np.float64] | None

    @property
    def has_pin_hole_factor(self) -> NDArray[np.bool_] | None:
        """(P,) True where some hole's estimate is inside the Kt tables; None without estimates."""
        return None if self.pin_holes is None else ~np.isnan(self.pin_holes)

    def lowest(self, positions) -> tuple[float, float | None]:
        """The lowest factors over ``positions`` (a mask or indices): against the sections, and
        against the pin holes (None where no estimate inside the tables there); inf where no stress."""
        pin_holes = None
        if self.pin_holes is not None:
            values = self.pin_holes[positions]
            values = values[~np.isnan(values)]
            pin_holes = float(values.min()) if values.size else None
        return float(self.sections[positions].min()), pin_holes


def yield_factor(yield_strength: float, stress: NDArray[np.float64]) -> NDArray[np.float64]:
    """``yield_strength`` [Pa] over ``stress`` [Pa], inf where the stress is zero."""
    stress = np.asarray(stress, float)
    with np.errstate(divide="ignore"):
        return np.where(stress > 0, yield_strength / stress, np.inf)


def safety_factors(stress: SectionStresses, yield_strength: float) -> SafetyFactors:
    """The factors of a link whose stresses are ``stress`` and whose material yields at
    ``yield_strength`` [Pa]."""
    return SafetyFactors(yield_strength, yield_factor(yield_strength, stress.max_von_mises),
                         pin_hole_factor(stress.pin_holes, yield_strength))


def pin_hole_factor(holes, yield_strength: float) -> NDArray[np.float64] | None:
    """``yield_strength`` [Pa] over the largest estimate inside the Kt tables of ``holes``
    (``PinHoleEstimate``) per position: nan where none is inside there, None where none ever is."""
    holes = [hole for hole in holes if not hole.outside.all()]
    if not holes:
        return None
    trusted = np.array([np.where(hole.outside, -1.0, hole.estimate) for hole in holes]).max(axis=0)
    return np.where(trusted < 0, np.nan, yield_factor(yield_strength, np.maximum(trusted, 0.0)))


def link_safety_factors(result: AnalysisResult) -> dict[str, SafetyFactors]:
    """The factors of every link with section stresses and a material that gives a yield strength."""
    factors = {}
    for name, stress in result.stresses.items():
        material = result.scene.links[name].material
        if material is not None and material.yield_strength is not None:
            factors[name] = safety_factors(stress, material.yield_strength)
    return factors


def finite_or_none(values: NDArray[np.float64]) -> list[float | None]:
    """JSON-ready values: None where a factor is infinite (no stress) or nan (no estimate)."""
    return [v if np.isfinite(v) else None for v in values.tolist()]
