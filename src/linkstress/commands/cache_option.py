"""``--cache DIR`` and ``--no-cache``: where the FEA keeps the work it can reuse between runs (each
link's meshes, unit-load solutions and peak check; docs/fea.md, "The cache")."""

from __future__ import annotations

import argparse

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


def cache_choice(args: argparse.Namespace):
    """The ``CacheSettings`` of ``args`` (None with ``--no-cache``); an InputError naming the option
    or variable for a folder that cannot be made or a size that is not one."""
    from linkstress.validation.fea.cache import cache_settings  # numpy's FEA side: only when FEA runs

    return cache_settings(args.cache, args.no_cache)
