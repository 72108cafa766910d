"""Fatigue safety factors (infinite life) from the range of one signed equivalent stress per point.

Over a cycle each point's stress swings between a largest and a smallest value of one signed
equivalent stress (``signed_von_mises``); their half range and mid value are the alternating and
mean stresses sigma_a and sigma_m. The fatigue criteria of Shigley (Budynas & Nisbett, Shigley's
Mechanical Engineering Design, 10th ed., ch. 6, fatigue failure criteria for fluctuating stress)
turn them into a factor of safety n against the Marin-corrected endurance limit S_e, the ultimate
strength S_ut and, for ASME-elliptic, the yield strength S_y:

    Goodman        sigma_a / S_e + sigma_m / S_ut = 1 / n
    Gerber         n sigma_a / S_e + (n sigma_m / S_ut)^2 = 1
    ASME-elliptic  (n sigma_a / S_e)^2 + (n sigma_m / S_y)^2 = 1

Each is written as n = S_e / sigma_ar, sigma_ar the fully reversed stress that the criterion deems
as damaging as (sigma_a, sigma_m): fully reversed (sigma_m = 0) every criterion then gives S_e /
sigma_a to the last digit, and nothing that cycles (sigma_ar = 0) gives inf, never a division by
zero. A compressive mean (sigma_m < 0) is taken not to shorten fatigue life (Shigley ch. 6: on the
compressive side the failure line is sigma_a = S_e), so every criterion gives S_e / sigma_a there.
Pure numpy, vectorised over any array shape.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from linkstress.stress_state import larger_principal_sign, von_mises

CRITERIA = ("goodman", "gerber", "asme-elliptic")
"""The fatigue criteria, the first the one reported as ``fatigue_safety_factor``."""


def signed_von_mises(stress: ArrayLike) -> NDArray[np.float64]:
    """Plane-stress von Mises [Pa] with the sign of the principal stress of larger magnitude.

    ``stress`` (..., 3): (sigma_xx, sigma_yy, tau_xy) [Pa], any frame (both the magnitude and the
    sign are invariant). The principal stresses are c +- r with c = (sigma_xx + sigma_yy) / 2, so the
    one of larger magnitude has the sign of the trace; a zero trace counts as tension.

    Why this equivalent: on a uniaxial point it is the stress itself, so Goodman on a bar is the
    textbook one; a pure-shear point (trace 0) counts as tension, which is conservative under the
    criteria since a tensile mean is penalised and a compressive one is not. A point whose principal
    directions turn during the cycle (a non-proportional multiaxial history) is beyond it: it sees
    only the size of the stress and the sign of its larger principal.
    """
    stress = np.asarray(stress, float)
    if stress.shape[-1:] != (3,):
        raise ValueError(f"stress must have shape (..., 3) = (sigma_xx, sigma_yy, tau_xy), got {stress.shape}")
    return larger_principal_sign(stress) * von_mises(stress)


def alternating_and_mean(largest: ArrayLike, smallest: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(sigma_a, sigma_m) = ((largest - smallest) / 2, (largest + smallest) / 2) [Pa] of a stress that
    swings between ``smallest`` and ``largest`` [Pa] (same shapes)."""
    largest, smallest = np.asarray(largest, float), np.asarray(smallest, float)
    if np.any(largest < smallest):
        raise ValueError("largest must be >= smallest at every point")
    return 0.5 * (largest - smallest), 0.5 * (largest + smallest)


@dataclass(frozen=True)
class FatigueStrength:
    """A material's fatigue data [Pa]: ``endurance_limit`` S_e' of the rotating-beam test specimen,
    ``ultimate_strength`` S_ut, ``yield_strength`` S_y (None: no ASME-elliptic), and the Marin surface
    and size factors k_a, k_b [-]. The other Marin factors are 1: the load factor because a von Mises
    equivalent is compared with the bending (rotating-beam) limit (Shigley ch. 6, combinations of
    loading modes); temperature, reliability and the rest belong in ``endurance_limit`` as given."""

    endurance_limit: float
    ultimate_strength: float
    yield_strength: float | None = None
    surface_factor: float = 1.0
    size_factor: float = 1.0

    @property
    def corrected_endurance_limit(self) -> float:
        """S_e = k_a k_b S_e' [Pa] (Marin)."""
        return self.surface_factor * self.size_factor * self.endurance_limit


def criteria_available(strength: FatigueStrength) -> tuple[str, ...]:
    """The criteria ``strength`` supports: ASME-elliptic only with a yield strength."""
    return tuple(c for c in CRITERIA if c != "asme-elliptic" or strength.yield_strength is not None)


def safety_factor(criterion: str, sigma_a: ArrayLike, sigma_m: ArrayLike, strength: FatigueStrength) -> NDArray[np.float64]:
    """Fatigue factor of safety n [-] of ``criterion`` at alternating ``sigma_a`` >= 0 and mean
    ``sigma_m`` [Pa] (broadcast together); inf where nothing cycles, never nan.

    Gerber's textbook closed form, n = (1/2) (S_ut / sigma_m)^2 (sigma_a / S_e) [-1 + sqrt(1 + (2
    sigma_m S_e / (S_ut sigma_a))^2)], loses digits as sigma_m -> 0 and divides by zero at either
    limit; the same root of n^2 (sigma_m / S_ut)^2 + n sigma_a / S_e - 1 = 0 is taken here as
    2 / (b + sqrt(b^2 + 4 a)), a = (sigma_m / S_ut)^2, b = sigma_a / S_e, which has neither problem
    (times S_e / S_e: n = 2 S_e / (sigma_a + hypot(sigma_a, 2 sigma_m S_e / S_ut))).
    ASME-elliptic needs ``strength.yield_strength`` (ValueError without it).
    """
    if criterion not in CRITERIA:
        raise ValueError(f"criterion must be one of {', '.join(CRITERIA)}, got {criterion!r}")
    if criterion not in criteria_available(strength):
        raise ValueError(f"{criterion} needs a yield strength")
    sigma_a, sigma_m = np.broadcast_arrays(np.asarray(sigma_a, float), np.asarray(sigma_m, float))
    if np.any(sigma_a < 0.0):
        raise ValueError("sigma_a is half a range and must be >= 0")
    s_e = strength.corrected_endurance_limit
    # A compressive mean is taken not to reduce the fatigue strength: only a tensile mean counts.
    tensile_mean = np.maximum(sigma_m, 0.0)
    if criterion == "goodman":
        reversed_stress = sigma_a + tensile_mean * (s_e / strength.ultimate_strength)
        scale = s_e
    elif criterion == "gerber":
        reversed_stress = sigma_a + np.hypot(sigma_a, 2.0 * tensile_mean * (s_e / strength.ultimate_strength))
        scale = 2.0 * s_e
    else:
        reversed_stress = np.hypot(sigma_a, tensile_mean * (s_e / strength.yield_strength))
        scale = s_e
    return np.divide(scale, reversed_stress, out=np.full(reversed_stress.shape, np.inf), where=reversed_stress > 0.0)


@dataclass(frozen=True)
class NodeFatigue:
    """Fatigue over the N nodes of a mesh: ``factors`` per available criterion (N,) [-]; the
    ``critical_node`` (smallest factor of ``criterion``, the lowest index of a tie), its
    ``sigma_a`` and ``sigma_m`` [Pa] and ``critical_factors``, every available criterion's factor
    there."""

    criterion: str
    factors: dict[str, NDArray[np.float64]]
    critical_node: int
    sigma_a: float
    sigma_m: float
    critical_factors: dict[str, float]

    @property
    def factor(self) -> float:
        """The factor of ``criterion`` at the critical node."""
        return self.critical_factors[self.criterion]


def node_fatigue(largest: ArrayLike, smallest: ArrayLike, strength: FatigueStrength,
                 criterion: str = "goodman") -> NodeFatigue:
    """Fatigue of the nodes whose signed equivalent stress swings between ``smallest`` and
    ``largest`` (N,) [Pa] over a cycle."""
    available = criteria_available(strength)
    if criterion not in available:
        raise ValueError(f"criterion must be one of {', '.join(available)} for this material, got {criterion!r}")
    sigma_a, sigma_m = alternating_and_mean(largest, smallest)
    if sigma_a.ndim != 1 or sigma_a.size == 0:
        raise ValueError(f"largest and smallest must be non-empty (N,) arrays, got shape {sigma_a.shape}")
    factors = {c: safety_factor(c, sigma_a, sigma_m, strength) for c in available}
    node = int(np.argmin(factors[criterion]))
    return NodeFatigue(
        criterion, factors, node, float(sigma_a[node]), float(sigma_m[node]),
        {c: float(f[node]) for c, f in factors.items()},
    )
