"""Writing output files whole or not at all: a temporary file beside each target, then renames.

Output paths are checked before any work (``check_outputs``); a write that still fails (disk full,
file-size limit, read-only folder) is an ``InputError`` naming the file, and leaves no file behind.
An output is bytes, or a function that writes into a binary stream (``json_stream``, ``npz_stream``),
so that a long sweep's records and arrays are encoded as they come and never all held at once.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import InputError

Content = bytes | Callable[[BinaryIO], None]
"""What an output file holds: its bytes, or a function that writes them into a stream."""
WRITE_BUFFER = 1 << 20
"""Bytes gathered before each write of a streamed file."""


def check_folder(path: Path | None, option: str) -> None:
    """Refuse an output ``path`` whose folder does not exist, before any work is done."""
    if path is not None and not path.resolve().parent.is_dir():
        raise InputError(f"{option}: folder {str(path.parent)!r} does not exist; create it or choose another")


def check_outputs(options: Mapping[str, Path | None], inputs: Iterable[Path] = ()) -> None:
    """Refuse, before any work, output files (``options``: flag -> path or None) that are folders, lie in
    no folder, name the same file twice, or would overwrite one of ``inputs`` (the scene, its sketches)."""
    given = {option: path for option, path in options.items() if path is not None}
    seen: dict[Path, str] = {}
    for option, path in given.items():
        check_folder(path, option)
        if path.is_dir():
            raise InputError(f"{option}: {str(path)!r} is a folder; give a file name, e.g. {str(path / 'out')!r}")
        if path.resolve() in seen:
            raise InputError(f"{seen[path.resolve()]} and {option} name the same file {str(path)!r}; give each output its own file")
        seen[path.resolve()] = option
    for source in inputs:
        for option, path in given.items():
            if _same_file(path, source):
                raise InputError(
                    f"{option}: {str(path)!r} is an input ({str(source)!r}); writing would overwrite it: choose another name"
                )


def _same_file(a: Path, b: Path) -> bool:
    if a.exists() and b.exists():
        return os.path.samefile(a, b)  # also sees hard and symbolic links
    return a.resolve() == b.resolve()


def json_bytes(data: object, option: str) -> bytes:
    """JSON text of ``data``; NaN and infinity are refused (they are never valid output)."""
    import json  # here and below: json and tempfile load only for a run that writes files

    try:
        return (json.dumps(data, indent=1, allow_nan=False) + "\n").encode("utf-8")
    except ValueError:
        raise _non_finite(option) from None


def json_stream(
    key: str, items: Iterable[object], option: str, after: Callable[[], Mapping[str, object]] | None = None
) -> Callable[[BinaryIO], None]:
    """The writer of ``json_bytes({key: list(items), **after()}, option)``, byte for byte, each item
    encoded and written as it comes. The items are at depth 2 of that indentation: each item's lines
    two spaces in. ``after`` gives the keys that follow the list, once it is written."""

    def write(stream: BinaryIO) -> None:
        import json

        stream.write(f"{{\n {json.dumps(key)}: [".encode())
        separator = "\n  "
        for item in items:
            try:
                text = json.dumps(item, indent=1, allow_nan=False).replace("\n", "\n  ")
            except ValueError:
                raise _non_finite(option) from None
            stream.write(f"{separator}{text}".encode())
            separator = ",\n  "
        stream.write(b"]" if separator == "\n  " else b"\n ]")
        for name, value in (after() if after is not None else {}).items():
            try:
                text = json.dumps(value, indent=1, allow_nan=False).replace("\n", "\n ")
            except ValueError:
                raise _non_finite(option) from None
            stream.write(f",\n {json.dumps(name)}: {text}".encode())
        stream.write(b"\n}\n")

    return write


@dataclass(frozen=True)
class RowBlocks:
    """An array of ``rows`` rows made a block of rows at a time: ``make(block)`` gives the rows of
    the slice ``block``, every block the same dtype and the same shape after the first axis."""

    rows: int
    make: Callable[[slice], NDArray]


def npz_stream(
    arrays: Mapping[str, NDArray | RowBlocks], blocks: Sequence[slice], option: str
) -> Callable[[BinaryIO], None]:
    """The writer of a NumPy .npz file (what ``np.savez`` writes: a zip of one .npy file per name,
    stored uncompressed; ``np.load`` reads it without pickles) holding ``arrays``: each whole array as
    it is, each ``RowBlocks`` made and written by ``blocks`` (consecutive slices covering its rows),
    so that only one block of one array is held at a time. A non-finite float is refused
    (``InputError`` naming ``option``), as in the JSON."""

    covered = [(block.start, block.stop) for block in blocks]
    if [stop for _, stop in covered[:-1]] != [start for start, _ in covered[1:]] or covered[0][0] != 0:
        raise ValueError(f"blocks {blocks} are not consecutive from row 0")
    for name, array in arrays.items():
        if isinstance(array, RowBlocks) and array.rows != covered[-1][1]:
            raise ValueError(f"{name}: {array.rows} rows, the blocks cover {covered[-1][1]}")

    def write(stream: BinaryIO) -> None:
        import zipfile

        with zipfile.ZipFile(stream, "w", zipfile.ZIP_STORED, allowZip64=True) as archive:
            for name, array in arrays.items():
                with archive.open(f"{name}.npy", "w", force_zip64=True) as member:
                    if isinstance(array, RowBlocks):
                        _write_row_blocks(member, array, blocks, option)
                    else:
                        _refuse_non_finite(array, option)
                        np.lib.format.write_array(member, np.asarray(array), allow_pickle=False)

    return write


def _write_row_blocks(member: BinaryIO, array: RowBlocks, blocks: Sequence[slice], option: str) -> None:
    """The .npy file of ``array``: its header from the first block's dtype and row shape, then the
    blocks' bytes in order (C order, rows first)."""
    first = None
    for block in blocks:
        rows = np.ascontiguousarray(array.make(block))
        if first is None:
            first = rows
            header = {"descr": np.lib.format.dtype_to_descr(rows.dtype), "fortran_order": False,
                      "shape": (array.rows, *rows.shape[1:])}
            np.lib.format.write_array_header_1_0(member, header)
        elif rows.dtype != first.dtype or rows.shape[1:] != first.shape[1:]:
            raise ValueError(f"block {block} is {rows.dtype} {rows.shape[1:]}, the first {first.dtype} {first.shape[1:]}")
        _refuse_non_finite(rows, option)
        member.write(rows.data.cast("B"))


def _refuse_non_finite(array: NDArray, option: str) -> None:
    if np.asarray(array).dtype.kind in "fc" and not np.isfinite(array).all():
        raise _non_finite(option)


def _non_finite(option: str) -> InputError:
    return InputError(f"{option}: the results hold a non-finite number (nan or inf); nothing written")


def write_all(outputs: Sequence[tuple[Path, Content]]) -> None:
    """Write every (path, content) whole, or none of them: each to a temporary file beside it, then the renames."""
    staged: list[tuple[str, Path]] = []
    try:
        for path, content in outputs:
            staged.append((_staged(path, content), path))
        for temporary, path in staged:
            try:
                os.replace(temporary, path)
            except OSError as error:
                raise _write_error(path, error) from None
    except BaseException:
        for temporary, _ in staged:
            Path(temporary).unlink(missing_ok=True)
        raise


def _staged(path: Path, content: Content) -> str:
    """``content`` in a temporary file in ``path``'s folder, with the permissions of an ordinary new file."""
    import tempfile

    try:
        handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.resolve().parent)
    except OSError as error:
        raise _write_error(path, error) from None
    try:
        with os.fdopen(handle, "wb", buffering=WRITE_BUFFER) as stream:
            if callable(content):
                content(stream)
            else:
                stream.write(content)
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp's files are private; outputs are not
    except BaseException as error:
        os.unlink(temporary)
        if isinstance(error, OSError):
            raise _write_error(path, error) from None
        raise
    return temporary


def _write_error(path: Path, error: OSError) -> InputError:
    return InputError(
        f"cannot write {str(path)!r}: {error.strerror or error}; nothing written: free space in its folder "
        "or choose another"
    )


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically."""
    write_all([(path, data)])


def write_text(path: Path, text: str) -> None:
    write_bytes(path, text.encode("utf-8"))


def write_json(path: Path, data: object) -> None:
    """JSON with NaN and infinity refused (they are never valid output)."""
    write_bytes(path, json_bytes(data, str(path)))


def write_json_stream(path: Path, key: str, items: Iterable[object]) -> None:
    """``write_json(path, {key: list(items)})`` byte for byte, written as the items come."""
    write_all([(path, json_stream(key, items, str(path)))])
