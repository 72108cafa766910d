"""Writing output files whole or not at all: a temporary file beside the target, then a rename."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import BinaryIO

from linkstress.errors import InputError


def check_folder(path: Path | None, option: str) -> None:
    """Refuse an output ``path`` whose folder does not exist, before any work is done."""
    if path is not None and not path.resolve().parent.is_dir():
        raise InputError(f"{option}: folder {str(path.parent)!r} does not exist; create it or choose another")


def write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically."""
    with replacing(path) as stream:
        stream.write(data)


@contextmanager
def replacing(path: Path) -> Iterator[BinaryIO]:
    """A binary stream to a temporary file beside ``path`` that replaces ``path`` when the block
    ends; if anything in the block fails, the temporary file is removed and ``path`` is untouched.
    The system's refusal to write (a full disk, no permission) is an ``InputError`` naming the file."""
    folder = path.resolve().parent
    try:
        handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as error:
        raise _unwritable(path, error) from error
    try:
        with os.fdopen(handle, "wb", buffering=WRITE_BUFFER) as stream:
            yield stream
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp's files are private; outputs are not
        os.replace(temporary, path)
    except OSError as error:
        os.unlink(temporary)
        raise _unwritable(path, error) from error
    except BaseException:
        os.unlink(temporary)
        raise


def _unwritable(path: Path, error: OSError) -> InputError:
    return InputError(
        f"could not write {str(path)!r}: {error.strerror or error}; no file was written: "
        "free space in its folder or choose another"
    )


WRITE_BUFFER = 1 << 20
"""Bytes gathered before each write of a streamed file."""


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: Path, text: str) -> None:
    write_bytes(path, text.encode("utf-8"))


def write_json(path: Path, data: object) -> None:
    """JSON with NaN and infinity refused (they are never valid output)."""
    write_text(path, json.dumps(data, indent=1, allow_nan=False) + "\n")


def write_json_stream(path: Path, key: str, items: Iterable[object]) -> None:
    """``write_json(path, {key: list(items)})`` byte for byte, each item encoded and written as it
    comes, so that the items are never all held at once; whole or not at all, like ``write_bytes``.
    The items are at depth 2 of ``write_json``'s indentation: each item's own lines, two spaces in."""
    with replacing(path) as stream:
        stream.write(f"{{\n {json.dumps(key)}: [".encode())
        separator = "\n  "
        for item in items:
            text = json.dumps(item, indent=1, allow_nan=False).replace("\n", "\n  ")
            stream.write(f"{separator}{text}".encode())
            separator = ",\n  "
        stream.write(b"]\n}\n" if separator == "\n  " else b"\n ]\n}\n")
