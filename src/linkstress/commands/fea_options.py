"""The FEA's settings that commands share: ``--cache DIR`` and ``--no-cache``, where the FEA keeps
the work it can reuse between runs (each link's meshes, unit-load solutions and peak check;
docs/fea.md, "The cache"), and the ``LINKSTRESS_SOLVER`` variable, checked before any work."""

from __future__ import annotations

import argparse
import os

CACHE_HELP = (
    "keep the FEA's meshes and unit-load solutions in DIR and reuse them in later runs (default: the "
    "LINKSTRESS_CACHE variable, else the user's cache folder; at most LINKSTRESS_CACHE_SIZE bytes, 2e9 by default, "
    "the least recently used going first)"
)


def add_cache_options(parser: argparse.ArgumentParser) -> None:
    """Add ``--cache DIR`` and ``--no-cache`` (one or the other) to ``parser``."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--cache", metavar="DIR", help=CACHE_HELP)
    group.add_argument("--no-cache", action="store_true", help="compute every FEA mesh and solution afresh, and keep none")


def fea_choices(args: argparse.Namespace):
    """The ``CacheSettings`` of ``args`` (None with ``--no-cache``), once ``LINKSTRESS_SOLVER`` is
    known good; an InputError naming the option or variable for a folder that cannot be made, a
    size or a solver that is not one (a command that reports a link's FEA failure as a failed check
    would otherwise report bad input so)."""
    from linkstress.validation.fea.cache import cache_settings  # the FEA side: only when FEA runs

    if os.environ.get("LINKSTRESS_SOLVER", "").strip():
        # Checking the variable loads the solvers (SciPy, scikit-fem): only when it is set.
        from linkstress.validation.fea.plane_stress import spd_solver

        spd_solver()
    return cache_settings(args.cache, args.no_cache)
