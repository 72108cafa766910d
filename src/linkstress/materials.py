"""Isotropic linear-elastic materials, with optional strengths for yield and fatigue safety factors."""

from __future__ import annotations

import math
from dataclasses import dataclass

from linkstress.errors import GeometryError
from linkstress.fatigue import FatigueStrength

MARIN_FACTOR_MAX = 1.5
"""Largest Marin surface or size factor accepted [-]. Shigley's k_a and k_b pass 1 only a little (a
ground surface of a soft steel, a bar of a few millimetres: about 1.1); a factor past 1.5 is a
mistake (a percentage, a reciprocal)."""


@dataclass(frozen=True)
class Material:
    """An isotropic material.

    density [kg/m^3]; youngs_modulus [Pa] and poisson_ratio [-] are needed only by the FEA;
    yield_strength [Pa] is optional and only used to report safety factors. Fatigue takes
    endurance_limit [Pa] (S_e', rotating-beam specimen) and ultimate_strength [Pa] together, with the
    Marin surface_factor and size_factor [-] (k_a, k_b) that correct the endurance limit.
    """

    name: str
    density: float
    youngs_modulus: float | None = None
    poisson_ratio: float | None = None
    yield_strength: float | None = None
    endurance_limit: float | None = None
    ultimate_strength: float | None = None
    surface_factor: float = 1.0
    size_factor: float = 1.0

    def __post_init__(self) -> None:
        _require_positive(self.name, "density", self.density)
        if self.youngs_modulus is not None:
            _require_positive(self.name, "youngs_modulus", self.youngs_modulus)
        if self.poisson_ratio is not None and not -1.0 < self.poisson_ratio < 0.5:
            raise GeometryError(
                f"material {self.name!r}: poisson_ratio = {self.poisson_ratio} is outside (-1, 0.5)"
            )
        for key in ("yield_strength", "endurance_limit", "ultimate_strength"):
            if getattr(self, key) is not None:
                _require_positive(self.name, key, getattr(self, key))
        _require_positive(self.name, "surface_factor", self.surface_factor)
        _require_positive(self.name, "size_factor", self.size_factor)
        problem = fatigue_data_problem(
            self.endurance_limit, self.ultimate_strength, self.yield_strength, self.surface_factor, self.size_factor
        )
        if problem is not None:
            raise GeometryError(f"material {self.name!r}: {problem[0]} {problem[1]}")

    @property
    def fatigue_strength(self) -> FatigueStrength | None:
        """The fatigue data, None unless both endurance_limit and ultimate_strength are given."""
        if self.endurance_limit is None or self.ultimate_strength is None:
            return None
        return FatigueStrength(
            self.endurance_limit, self.ultimate_strength, self.yield_strength, self.surface_factor, self.size_factor
        )


def fatigue_data_problem(endurance_limit: float | None, ultimate_strength: float | None,
                         yield_strength: float | None, surface_factor: float,
                         size_factor: float) -> tuple[str, str] | None:
    """The first key whose (positive) value the fatigue data cannot take and why, or None: a Marin
    factor above ``MARIN_FACTOR_MAX``, an endurance limit not below the ultimate strength, a yield
    strength above it."""
    for key, factor in (("surface_factor", surface_factor), ("size_factor", size_factor)):
        if factor > MARIN_FACTOR_MAX:
            return key, f"must lie in (0, {MARIN_FACTOR_MAX:g}] (a Marin factor), got {factor!r}"
    if ultimate_strength is None:
        return None
    if endurance_limit is not None and not endurance_limit < ultimate_strength:
        return "endurance_limit", f"must be below ultimate_strength ({ultimate_strength!r} Pa), got {endurance_limit!r}"
    if yield_strength is not None and yield_strength > ultimate_strength:
        return "yield_strength", f"must not exceed ultimate_strength ({ultimate_strength!r} Pa), got {yield_strength!r}"
    return None


def _require_positive(name: str, key: str, value: float) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise GeometryError(f"material {name!r}: {key} must be a finite number > 0, got {value!r}")


STRUCTURAL_STEEL = Material("structural steel", 7850.0, 200e9, 0.3, 250e6)
