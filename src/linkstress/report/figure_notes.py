"""What matplotlib says while a figure is drawn is kept off the terminal, and kept as a note.

A layer or link named in a script its font lacks (CJK, Devanagari) makes matplotlib warn once per
character, "Glyph 26354 (\\N{CJK UNIFIED IDEOGRAPH-66F2}) missing from font(s) DejaVu Sans.", with
the path of the source line that drew it; a font family it cannot find is logged ("findfont: ...").
Every figure writer draws inside ``figure_warnings``: those become notes, one line each ("the
figure's font lacks 4 characters: 曲柄连杆 (drawn as empty boxes)"), for a report to show or to drop.
This module imports no matplotlib: the importers' picture uses it too.
"""

from __future__ import annotations

import logging
import re
import warnings
from collections.abc import Iterator
from contextlib import contextmanager

from linkstress.messages import capped

MAX_NOTES = 5
"""Distinct notes listed at most; the rest are counted."""
MAX_CHARACTERS = 20
"""Missing characters spelt out at most; the rest are counted."""
NOTE_LENGTH = 200
"""Characters of a warning kept in its note."""
GLYPH = re.compile(r"Glyph (\d+) .*missing from (?:current )?font")


class _Collect(logging.Handler):
    def __init__(self, messages: list[str]) -> None:
        super().__init__(logging.WARNING)
        self.messages = messages

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


_OPEN: list[list[str]] = []
"""The notes of the ``figure_warnings`` blocks open now, innermost last."""


@contextmanager
def figure_warnings(notes: list[str] | None = None) -> Iterator[list[str]]:
    """Python warnings and matplotlib's log warnings raised inside the block go to the list it yields
    (``notes``, when given; else the enclosing block's, so that a drawing step inside a figure writer
    keeps its notes) as ``figure_notes`` words them, never to the terminal."""
    found = notes if notes is not None else _OPEN[-1] if _OPEN else []
    _OPEN.append(found)
    messages: list[str] = []
    logger = logging.getLogger("matplotlib")
    handler, propagate = _Collect(messages), logger.propagate
    logger.addHandler(handler)
    logger.propagate = False
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            yield found
    finally:
        _OPEN.pop()
        logger.removeHandler(handler)
        logger.propagate = propagate
        messages += [f"{w.category.__name__}: {w.message}" for w in caught]
        found.extend(note for note in figure_notes(messages) if note not in found)


def figure_notes(messages: list[str]) -> list[str]:
    """The distinct ``messages`` as notes: the characters every "Glyph ... missing" names, in one
    line; the others each in a line of their own, at most MAX_NOTES of them and a count of the rest."""
    missing: list[str] = []
    others: list[str] = []
    for message in messages:
        glyph = GLYPH.search(message)
        if glyph is not None:
            missing.append(chr(int(glyph.group(1))))
        else:
            others.append(" ".join(message.split())[:NOTE_LENGTH])
    notes = []
    missing = list(dict.fromkeys(missing))
    if missing:
        shown = capped(missing, MAX_CHARACTERS, separator="")
        notes.append(f"the figure's font lacks {len(missing)} character(s): {shown} (drawn as empty boxes)")
    others = list(dict.fromkeys(others))
    notes += [f"library warning: {note}" for note in others[:MAX_NOTES]]
    if len(others) > MAX_NOTES:
        notes.append(f"library warning: {len(others) - MAX_NOTES} more not listed")
    return notes
