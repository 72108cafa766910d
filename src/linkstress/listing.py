"""Lists in messages, capped: a message that lists 185 problems or 150 link names stays one short line.

``capped(["'a'", "'b'", ...])`` is "'a', 'b', 'c', 'd', 'e' (first 5 of 150)"; the full lists belong
in the JSON, where a command has one.
"""

from __future__ import annotations

from collections.abc import Iterable

MAX_LISTED = 5
"""Items a message spells out at most."""


def capped(items: Iterable[object], limit: int = MAX_LISTED, separator: str = ", ") -> str:
    """The first ``limit`` of ``items`` (as ``str`` gives them) joined by ``separator``, and
    "(first LIMIT of N)" when there are more."""
    items = [str(item) for item in items]
    if len(items) <= limit:
        return separator.join(items)
    return f"{separator.join(items[:limit])} (first {limit} of {len(items)})"
