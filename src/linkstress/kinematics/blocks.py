"""A sweep solved a block of positions at a time, the blocks spread over the machine's cores.

Every position of a closed-form loop is independent of the others, so a sweep splits into blocks
of consecutive positions that write disjoint rows of the results. A block's temporaries stay in the
cores' caches (a whole sweep's would stream through main memory, once per arithmetic step), and
numpy lets go of the interpreter lock inside its element loops, so blocks run side by side on
threads (``linkstress.threads.in_parallel``).
"""

from __future__ import annotations

from collections.abc import Callable

from linkstress.threads import in_parallel

BLOCK = 1 << 14
"""Positions per block: about 20 temporaries of 128 kB each, which stay in the caches."""


def solve_in_blocks(work: Callable[[slice], None], n: int) -> None:
    """``work(rows)`` for consecutive slices ``rows`` of ``range(n)``, ``BLOCK`` positions each
    (the last one shorter), on a thread per core when there are several. Not to be called from
    inside ``in_parallel``'s blocks."""
    in_parallel(work, [slice(start, min(start + BLOCK, n)) for start in range(0, n, BLOCK)])
