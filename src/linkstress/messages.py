"""Pieces of messages, kept short: a message that lists 185 problems or quotes a 100,000-character
argument stays one short line.

``capped(["'a'", "'b'", ...])`` is "'a', 'b', 'c', 'd', 'e' (first 5 of 150)" (the full lists belong
in the JSON, where a command has one); ``quoted(text)`` is ``repr(text)``, its middle cut when long.
"""

from __future__ import annotations

from collections.abc import Iterable

MAX_LISTED = 5
"""Items a message spells out at most."""
MAX_QUOTED = 120
"""Characters of a user's text a message quotes at most."""


def capped(items: Iterable[object], limit: int = MAX_LISTED, separator: str = ", ") -> str:
    """The first ``limit`` of ``items`` (as ``str`` gives them) joined by ``separator``, and
    "(first LIMIT of N)" when there are more."""
    items = [str(item) for item in items]
    if len(items) <= limit:
        return separator.join(items)
    return f"{separator.join(items[:limit])} (first {limit} of {len(items)})"


def quoted(text: str, limit: int = MAX_QUOTED) -> str:
    """``repr(text)`` (control characters escaped: one line), its middle cut to "..." when ``text``
    is longer than ``limit``: the start and the end say which it was."""
    if len(text) > limit:
        end = max(limit // 3, 1)
        text = text[: limit - end - 3] + "..." + text[-end:]
    return repr(text)
