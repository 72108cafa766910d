"""Reading a user's input file: a regular file only, and never more of it than a stated size.

A path may name something that is not a file: a FIFO (a read waits for a writer forever), a device
(``/dev/zero`` never ends: read whole, it grows until memory runs out), a socket or a folder. Each
is refused by what it is before a byte is read. A regular file is read up to its limit and refused,
with its size, past it. A missing or unreadable path raises the ``OSError`` as it comes, for the
caller to word ("scene file ... not found").
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from linkstress.errors import InputError
from linkstress.messages import quoted

MiB = 2**20
SCENE_BYTES = 16 * MiB
"""Largest scene file read [bytes]. A scene is a few kB; 16 MiB is a list of about 1.7 million
input angles, which tomllib parses in about 3 s (a range or an expression gives any sweep)."""
SKETCH_BYTES = 256 * MiB
"""Largest DXF or CSV sketch read [bytes]: about a million LINEs, or the 5,000,000 vertices a sketch
may flatten to as polylines; a sheet of a hundred parts is a few MB."""

KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


class InputFileError(InputError):
    """An input path that is not a regular file, or a file larger than its limit."""


def kind_of(mode: int) -> str | None:
    """What a ``st_mode`` names when it is not a regular file ("a FIFO (named pipe)"), else None."""
    if stat.S_ISREG(mode):
        return None
    return next((name for test, name in KINDS if test(mode)), "not a regular file")


def check_regular(path: str | Path, what: str) -> None:
    """Refuse ``path`` (following links) unless it is a regular file; ``what`` names it ("sketch")."""
    _refuse_kind(path, os.stat(path).st_mode, what)


def read_bounded(path: str | Path, limit: int, what: str) -> bytes:
    """The bytes of the regular file ``path``, at most ``limit`` of them; an ``InputFileError``
    naming ``what`` ("scene file") for anything else: a FIFO, a device, a socket or a folder
    (before it is opened), or a file over ``limit`` bytes (with its size)."""
    check_regular(path, what)
    # O_NONBLOCK: should the path become a FIFO after the check above, opening it still returns.
    handle = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    with os.fdopen(handle, "rb") as stream:
        status = os.fstat(stream.fileno())
        _refuse_kind(path, status.st_mode, what)
        if status.st_size > limit:
            raise _too_large(path, status.st_size, limit, what)
        data = stream.read(limit + 1)
    if len(data) > limit:  # it grew while being read
        raise _too_large(path, len(data), limit, what, "at least ")
    return data


def _refuse_kind(path: str | Path, mode: int, what: str) -> None:
    kind = kind_of(mode)
    if kind is not None:
        raise InputFileError(
            f"the {what} {quoted(str(path))} is {kind}, not a file: give the path of a {what} saved as a file"
        )


def _too_large(path: str | Path, size: int, limit: int, what: str, bound: str = "") -> InputFileError:
    return InputFileError(
        f"the {what} {quoted(str(path))} is {bound}{size:,} bytes ({size / MiB:.1f} MiB), more than the {limit // MiB} MiB "
        f"a {what} may be"
    )
