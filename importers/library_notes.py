"""What libraries say while a sketch is read (ezdxf's log, Python warnings such as numpy's
RuntimeWarnings) is kept off the terminal: it joins the sketch's fixes, or the one error message."""

from __future__ import annotations

import logging
import warnings
from contextlib import contextmanager

MAX_NOTES = 5
"""How many distinct library warnings a sketch's fixes list; the rest are counted."""


def with_notes(fixes: tuple[str, ...], notes: list[str]) -> tuple[str, ...]:
    """``fixes`` and the library ``notes`` that do not repeat one of them, each listed once."""
    added = _summary([note for note in notes if not _repeats(note, fixes)])
    return tuple(dict.fromkeys(fixes + added))


def _repeats(note: str, fixes: tuple[str, ...]) -> bool:
    """True when an ezdxf log line says what recover mode's auditor already listed among ``fixes``."""
    return note.startswith("ezdxf: ") and any(fix.endswith(note.removeprefix("ezdxf: ")) for fix in fixes)


class _Collect(logging.Handler):
    def __init__(self, notes: list[str]) -> None:
        super().__init__(logging.WARNING)
        self.notes = notes

    def emit(self, record: logging.LogRecord) -> None:
        self.notes.append(f"ezdxf: {record.getMessage()}")


@contextmanager
def library_notes(notes: list[str]):
    """ezdxf's log warnings (e.g. what recover mode repaired) and Python warnings (numpy's
    RuntimeWarnings) raised while reading go into ``notes``, not onto the terminal."""
    logger = logging.getLogger("ezdxf")
    handler, propagate = _Collect(notes), logger.propagate
    logger.addHandler(handler)
    logger.propagate = False
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            yield
    finally:
        logger.removeHandler(handler)
        logger.propagate = propagate
        notes.extend(f"{w.category.__name__}: {w.message}" for w in caught)


def one_line(said: object) -> str:
    """What a library said (an exception, a log line), as one printable line: libraries quote the
    file's own bytes, newlines and NULs included."""
    return " ".join("".join(ch if ch.isprintable() else " " for ch in str(said)).split())


def _distinct(notes: list[str]) -> list[str]:
    return list(dict.fromkeys(one_line(note) for note in notes))


def _summary(notes: list[str]) -> tuple[str, ...]:
    """The distinct ``notes``, one line each: the first ``MAX_NOTES`` and a count of the rest."""
    distinct = _distinct(notes)
    shown = tuple(f"library warning: {note}" for note in distinct[:MAX_NOTES])
    more = len(distinct) - MAX_NOTES
    return shown + ((f"library warning: {more} more not listed",) if more > 0 else ())


def noted(notes: list[str]) -> str:
    """The first library warning, as a note to an error message."""
    distinct = _distinct(notes)
    if not distinct:
        return ""
    more = f"; and {len(distinct) - 1} more" if len(distinct) > 1 else ""
    return f" (note: library warning: {distinct[0]}{more})"
