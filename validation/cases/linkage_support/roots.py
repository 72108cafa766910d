"""One scalar unknown along a path, for a group with no closed form (a triad): the rest of the
group follows from dyad formulas once the unknown is known, and a residual r(x, phi) closes it.

The root is followed by continuation: Brent's bracketing method (scipy's ``brentq``) at every
step of a fine table of inputs, each bracketed next to the previous root, from a start the drawing
gives; then, for any inputs, bisection in a narrow bracket about the table's interpolated root,
vectorised over the inputs, down to the last bits. A bracket without a sign change (the group
cannot close, or the table jumped to another assembly) is an error, never a silent switch.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from linkage_support.geometry import AssemblyError

FloatArray = NDArray[np.float64]
Residual = Callable[[FloatArray, FloatArray], FloatArray]


def root_table(residual: Residual, path: FloatArray, start: float, half_width: float) -> FloatArray:
    """The root phi at each input of ``path`` (a fine, ordered table, path[0] the drawn input),
    continued from ``start`` (a guess at path[0]) with brackets of +-``half_width``."""
    roots = np.empty(len(path))
    guess = start
    for k, x in enumerate(path):
        def f(phi: float, x: float = x) -> float:
            return float(residual(np.array([x]), np.array([phi]))[0])

        lower, upper = guess - half_width, guess + half_width
        if not f(lower) * f(upper) < 0:
            raise AssemblyError(f"no root within {half_width} of {guess} at input {x}: the group does not close there")
        roots[k] = brentq(f, lower, upper, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        guess = roots[k] + (roots[k] - roots[k - 1] if k else 0.0)
    return roots


def continued_root(residual: Residual, x: FloatArray, table_x: FloatArray, table_root: FloatArray,
                   half_width: float, period: float | None = None) -> FloatArray:
    """The root at inputs ``x`` (any shape), by bisection within +-``half_width`` of the table's
    linear interpolation (``period``: the table covers one period of a periodic input)."""
    x = np.asarray(x, float)
    wrapped = table_x[0] + np.mod(x - table_x[0], period) if period else x
    centre = np.interp(wrapped, table_x, table_root)
    lower, upper = centre - half_width, centre + half_width
    f_lower = residual(x, lower)
    if not np.all(f_lower * residual(x, upper) < 0):
        raise AssemblyError(f"no sign change within {half_width} of the continued root at some inputs")
    for _ in range(80):
        middle = 0.5 * (lower + upper)
        f_middle = residual(x, middle)
        same = f_middle * f_lower > 0
        lower, f_lower = np.where(same, middle, lower), np.where(same, f_middle, f_lower)
        upper = np.where(same, upper, middle)
    return 0.5 * (lower + upper)
