"""Invariants of a plane stress state (sigma_xx, sigma_yy, tau_xy), for arrays of points.

The FEA recovers these components at its nodes, and fatigue cycles a signed equivalent of them:
both take von Mises from here.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def von_mises(stress: NDArray[np.float64]) -> NDArray[np.float64]:
    """Plane-stress von Mises [Pa] of stresses (..., 3) = (sigma_xx, sigma_yy, tau_xy) [Pa]."""
    sxx, syy, txy = stress[..., 0], stress[..., 1], stress[..., 2]
    return np.sqrt(np.maximum(sxx * sxx - sxx * syy + syy * syy + 3 * txy * txy, 0.0))


def larger_principal_sign(stress: NDArray[np.float64]) -> NDArray[np.float64]:
    """+1 or -1 (...): the sign of the principal stress of larger magnitude of stresses (..., 3).

    The principal stresses are c +- r with c = (sigma_xx + sigma_yy) / 2, so the one of larger
    magnitude has the sign of the trace; a zero trace counts as tension."""
    return np.where(stress[..., 0] + stress[..., 1] >= 0.0, 1.0, -1.0)
