"""Isotropic linear-elastic materials."""

from __future__ import annotations

import math
from dataclasses import dataclass

from linkstress.errors import GeometryError


@dataclass(frozen=True)
class Material:
    """An isotropic material.

    density [kg/m^3]; youngs_modulus [Pa] and poisson_ratio [-] are needed only by the FEA;
    yield_strength [Pa] is optional and only used to report safety factors.
    """

    name: str
    density: float
    youngs_modulus: float | None = None
    poisson_ratio: float | None = None
    yield_strength: float | None = None

    def __post_init__(self) -> None:
        _require_positive(self.name, "density", self.density)
        if self.youngs_modulus is not None:
            _require_positive(self.name, "youngs_modulus", self.youngs_modulus)
        if self.poisson_ratio is not None and not -1.0 < self.poisson_ratio < 0.5:
            raise GeometryError(
                f"material {self.name!r}: poisson_ratio = {self.poisson_ratio} is outside (-1, 0.5)"
            )
        if self.yield_strength is not None:
            _require_positive(self.name, "yield_strength", self.yield_strength)


def _require_positive(name: str, key: str, value: float) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise GeometryError(f"material {name!r}: {key} must be a finite number > 0, got {value!r}")


STRUCTURAL_STEEL = Material("structural steel", 7850.0, 200e9, 0.3, 250e6)
