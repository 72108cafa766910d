"""A sweep solved a block of positions at a time, the blocks spread over the machine's cores.

Every position of a closed-form loop is independent of the others, so a sweep splits into blocks
of consecutive positions that write disjoint rows of the results. A block's temporaries stay in the
cores' caches (a whole sweep's would stream through main memory, once per arithmetic step), and
numpy lets go of the interpreter lock inside its element loops, so blocks run side by side on
threads (``linkstress.threads.in_parallel``).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from linkstress.threads import in_parallel

BLOCK = 1 << 15
"""Positions per block: a dozen temporaries of 256 kB each, which stay in the caches."""


def solve_in_blocks(work: Callable[[slice], None], n: int) -> None:
    """``work(rows)`` for consecutive slices ``rows`` of ``range(n)``, ``BLOCK`` positions each
    (the last one shorter), on a thread per core when there are several. Not to be called from
    inside ``in_parallel``'s blocks."""
    in_parallel(work, [slice(start, min(start + BLOCK, n)) for start in range(0, n, BLOCK)])


def empty_arrays(n: int, vectors: int, pairs: int) -> tuple[list[NDArray[np.float64]], list[NDArray[np.float64]]]:
    """``vectors`` arrays (n,) and ``pairs`` arrays (n, 2), uninitialised, carved from one
    allocation: the kernel maps a sweep's fresh pages for it in one go (large pages where it can),
    which costs less than a separate mapping per array."""
    memory = np.empty((vectors + 2 * pairs) * n)
    ends = np.cumsum([0] + [n] * vectors + [2 * n] * pairs)
    arrays = [memory[lo:hi] for lo, hi in zip(ends[:-1], ends[1:])]
    return arrays[:vectors], [array.reshape(n, 2) for array in arrays[vectors:]]


def angle_of(y: NDArray[np.float64], x: NDArray[np.float64], out: NDArray[np.float64],
             scratch: NDArray[np.float64]) -> NDArray[np.float64]:
    """``out`` = arctan2(y, x) [rad] in [-pi, pi], as arctan(y / x) plus pi where x is negative
    (its sign bit set), pi taking the sign of y. Within an ulp of pi of ``np.arctan2``, except that
    the zero vector gives NaN; numpy calls the C library per element for both, and there atan2
    costs about twice atan. ``scratch`` (same length as ``out``) is overwritten."""
    # x = 0 gives y / x = +-inf, whose arctan is +-pi/2; 0 / 0 gives the NaN above
    with np.errstate(divide="ignore", invalid="ignore"):
        np.divide(y, x, out=out)
    np.arctan(out, out=out)
    np.copysign(math.pi, y, out=scratch)
    np.add(out, scratch, out=out, where=np.signbit(x))
    return out


def dot_into(x1: NDArray[np.float64], y1: NDArray[np.float64], x2: NDArray[np.float64], y2: NDArray[np.float64],
             out: NDArray[np.float64], scratch: NDArray[np.float64]) -> NDArray[np.float64]:
    """``out`` = x1 y1 + x2 y2 (the dot product of (x1, x2) and (y1, y2)); ``scratch`` is overwritten."""
    np.multiply(x1, y1, out=out)
    out += np.multiply(x2, y2, out=scratch)
    return out


def set_columns(pairs: NDArray[np.float64], x: NDArray[np.float64], y: NDArray[np.float64]) -> None:
    """Fill the (M, 2) array ``pairs`` with its columns ``x`` and ``y`` (M,)."""
    pairs[:, 0] = x
    pairs[:, 1] = y
