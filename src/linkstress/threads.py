"""Running numpy work on every core.

numpy lets go of the interpreter lock inside its element loops, so blocks of a sweep that write
disjoint rows run side by side on threads (``in_parallel``). BLAS has threads of its own: beside
ours they compete for the same cores, and after each product they keep spinning on them for a
while, which slows the single-threaded element loops that follow. The products in an analysis are
small (a few load coefficients by a few hundred stations), so ``blas_alone`` keeps BLAS to one
thread while an analysis runs.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from functools import lru_cache
from typing import TYPE_CHECKING, TypeVar

import numpy as np
from threadpoolctl import ThreadpoolController

from linkstress.errors import InputError

if TYPE_CHECKING:
    from concurrent.futures import ThreadPoolExecutor

Block = TypeVar("Block")

POOL_PREFIX = "linkstress-pool"
"""Name prefix of the pool's threads, so that a block can tell it runs on one."""


def in_parallel(work: Callable[[Block], None], blocks: Sequence[Block], threads: bool = True) -> None:
    """``work(block)`` for every block, on a thread per core where ``threads`` and there is more
    than one block (small work runs faster on the calling thread alone). The blocks' writes must
    not overlap; an exception in any block is raised here. Called from inside a block, it runs its
    blocks on that block's thread: waiting for the pool there could wait for threads its caller holds."""
    if not threads or len(blocks) <= 1 or cores() == 1 or _in_pool():
        for block in blocks:
            work(block)
        return
    list(_pool().map(work, blocks))


def _in_pool() -> bool:
    return threading.current_thread().name.startswith(POOL_PREFIX)


def even_blocks(count: int, pieces: int) -> list[slice]:
    """``range(count)`` as ``pieces`` consecutive slices of near-equal length."""
    edges = np.linspace(0, count, pieces + 1).round().astype(int)
    return [slice(lo, hi) for lo, hi in zip(edges[:-1], edges[1:])]


def blas_alone() -> AbstractContextManager:
    """A context in which BLAS runs on the calling thread only."""
    return _controller().limit(limits=1, user_api="blas")


def cores() -> int:
    """The cores this process may run on, or fewer where ``LINKSTRESS_THREADS`` asks for fewer (a Dask
    worker beside others on one machine runs on one: a thread per core in every worker would put
    workers x cores threads on the machine's cores)."""
    available = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    limit = thread_limit()
    return available if limit is None else min(available, limit)


THREADS_VARIABLE = "LINKSTRESS_THREADS"


def thread_limit() -> int | None:
    """The environment's ``LINKSTRESS_THREADS`` (a whole number >= 1), None when unset; an
    ``InputError`` naming the variable when it is set to anything else."""
    text = os.environ.get(THREADS_VARIABLE, "").strip()
    if not text:
        return None
    if not text.isdigit() or int(text) < 1:
        raise InputError(f"{THREADS_VARIABLE}={text[:40]!r}: must be a whole number of threads, 1 or more (or unset)")
    return int(text)


@lru_cache(maxsize=1)
def _pool() -> ThreadPoolExecutor:
    # kept for the process: starting threads for every call costs about a millisecond each; imported
    # here, as a run of a single block (one position) needs no pool and concurrent.futures costs ~5 ms
    from concurrent.futures import ThreadPoolExecutor

    return ThreadPoolExecutor(cores(), thread_name_prefix=POOL_PREFIX)


if hasattr(os, "register_at_fork"):
    # a forked child (a process pool's worker) has none of the parent's threads: it makes its own
    # pool, where the parent's would take work and never run it
    os.register_at_fork(after_in_child=_pool.cache_clear)


@lru_cache(maxsize=1)
def _controller() -> ThreadpoolController:
    # made once: finding the loaded BLAS libraries takes milliseconds
    return ThreadpoolController()
