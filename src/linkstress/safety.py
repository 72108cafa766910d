"""Safety factors against yield: a link's yield strength over the stress it reaches.

Where a link's material gives ``yield_strength`` [Pa], ``analyze`` reports, per position, the yield
strength over the link's largest section von Mises (beam theory; nominal within a section depth of
a pin hole) and, where the link has pin-hole estimates, over the largest Kt x nominal estimate (an
estimate, labelled as one, like the stress it divides). Only estimates whose Kt is inside the
tables at that position count: a position where every hole's geometry is outside them has no
pin-hole factor. A position where the stress is zero, or without a pin-hole factor, has no finite
factor: the reports leave it empty (JSON null), never print infinity.

Every member of a link counts, a curved one with its curved-beam (Winkler-Bach) stresses on the cuts
square to its centreline (``linkstress.geometry.members``), so a curved link has its section factor too.
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
    section von Mises of any member; ``pin_holes`` (P,) over the
    largest pin-hole estimate inside the Kt tables, None where the link has none at any position (no
    pin hole, or every hole outside the tables at every position); ``pin_hole_inside`` (P,) where
    some hole's estimate is inside the tables (elsewhere ``pin_holes`` is inf: no factor); inf where
    the stress is zero."""

    yield_strength: float
    sections: NDArray[np.float64]
    pin_holes: NDArray[np.float64] | None
    pin_hole_inside: NDArray[np.bool_] | None = None

    def lowest(self, positions) -> tuple[float, float | None]:
        """The lowest factors over ``positions`` (a mask or indices): against the sections, and against the pin holes (None where no estimate is inside the tables
        there); inf where no stress there."""
        sections = float(self.sections[positions].min())
        pin_holes = None
        if self.pin_holes is not None:
            inside = self.pin_holes[positions][self.pin_hole_inside[positions]]
            pin_holes = float(inside.min()) if inside.size else None
        return sections, pin_holes


def yield_factor(yield_strength: float, stress: NDArray[np.float64]) -> NDArray[np.float64]:
    """``yield_strength`` [Pa] over ``stress`` [Pa], inf where the stress is zero."""
    stress = np.asarray(stress, float)
    with np.errstate(divide="ignore"):
        return np.where(stress > 0, yield_strength / stress, np.inf)


def safety_factors(stress: SectionStresses | StressSummary, yield_strength: float) -> SafetyFactors:
    """The factors of a link whose stresses are ``stress`` and whose material yields at
    ``yield_strength`` [Pa]."""
    pin_holes, inside = pin_hole_factor(stress.pin_holes, yield_strength)
    return SafetyFactors(yield_strength, yield_factor(yield_strength, stress.max_von_mises), pin_holes, inside)


def pin_hole_factor(holes, yield_strength: float) -> tuple[NDArray[np.float64] | None, NDArray[np.bool_] | None]:
    """``yield_strength`` [Pa] over the largest estimate inside the Kt tables of ``holes``
    (``PinHoleEstimate``) per position, inf where none is inside there, and where some is; (None,
    None) where none ever is."""
    holes = [hole for hole in holes if not hole.outside.all()]
    if not holes:
        return None, None
    trusted = np.array([np.where(hole.outside, -1.0, hole.estimate) for hole in holes]).max(axis=0)
    inside = trusted >= 0
    return np.where(inside, yield_factor(yield_strength, np.maximum(trusted, 0.0)), np.inf), inside


def link_safety_factors(result: AnalysisResult) -> dict[str, SafetyFactors]:
    """The factors of every link with section stresses and a material that gives a yield strength."""
    factors = {}
    for name, stress in result.stresses.items():
        material = result.scene.links[name].material
        if material is not None and material.yield_strength is not None:
            factors[name] = safety_factors(stress, material.yield_strength)
    return factors


def finite_or_none(values: NDArray[np.float64]) -> list[float | None]:
    """JSON-ready values: None where a factor is infinite (no stress, or no estimate there)."""
    return [v if np.isfinite(v) else None for v in values.tolist()]


def uncovered_pin_holes(stress: SectionStresses | StressSummary, feasible: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """(joint, positions) of each loaded pin hole whose estimate is outside the Kt tables at some
    ``feasible`` position: there no yield safety factor covers the hole (beam theory is silent at a
    hole, and no estimate stands in for it)."""
    counts = [(hole.joint, int((hole.outside & (hole.nominal > 0))[feasible].sum())) for hole in stress.pin_holes]
    return [(joint, count) for joint, count in counts if count]
