"""Writing output files whole or not at all: a temporary file beside the target, then a rename."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

from linkstress.errors import InputError


def check_folder(path: Path | None, option: str) -> None:
    """Refuse an output ``path`` whose folder does not exist, before any work is done."""
    if path is not None and not path.resolve().parent.is_dir():
        raise InputError(f"{option}: folder {str(path.parent)!r} does not exist; create it or choose another")


def write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically."""
    folder = path.resolve().parent
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp's files are private; outputs are not
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: Path, text: str) -> None:
    write_bytes(path, text.encode("utf-8"))


def write_json(path: Path, data: object) -> None:
    """JSON with NaN and infinity refused (they are never valid output)."""
    write_text(path, json.dumps(data, indent=1, allow_nan=False) + "\n")
