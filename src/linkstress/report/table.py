"""``analyze --table OUT``: an analysis's per-position numbers as named NumPy arrays in one .npz file.

``np.load(OUT)`` gives one array per quantity, named by the path of its key in ``analyze --json``'s
position records (docs/design.md, "The table"): ``links/crank/max_von_mises_pa`` holds
``positions[k]["links"]["crank"]["max_von_mises_pa"]`` at row k. Per-position arrays have the
sweep's positions as their first axis ((P,), or (P, 2) for a point or a force, (P, J, 2) for a
linkage link's joints); what every position shares (a member's joints, a pin hole's diameter, a
force's name) is stored once, without that axis. Each part of a name is a JSON key as it is, with
``%``, ``/`` and control characters percent-encoded (``urllib.parse.unquote`` undoes it), or a list
index (``members/0``).

Where the JSON writes no number the table holds 0, and a mask says where: ``feasible`` for every
link, mechanism and transmission value (an infeasible position has none), ``kt_outside_table`` for
a pin hole's ``estimate_pa`` and ``kt_at_position``; a safety factor is 0 where the JSON has null
(no stress there: no factor; a real factor is never 0). A text per position ``K`` (``reason``,
``warnings``, a pin hole's ``end_shape`` and ``kt_outside_reason``) is ``K_code`` (P,), indexing
``K_texts``; "" stands for the JSON's null or an absent ``warnings`` (one position's warnings are
joined by newlines). Never a NaN: a non-finite number at a feasible position is refused, as in the
JSON. The arrays along the links (``--stations``) are the JSON's only.

The arrays come from the JSON's own columns (``report.records.link_value_columns`` and
``mechanism_columns``) and are written a block of positions at a time (``output.npz_stream``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import BinaryIO

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.errors import InputError
from linkstress.output import RowBlocks, npz_stream
from linkstress.report.records import SHARED, Coded, Nullable, link_value_columns, mechanism_columns
from linkstress.threads import even_blocks

TABLE_BLOCK = 1 << 16
"""Positions written together: a block of one array is at most a few MB."""
SUFFIX = ".npz"


def check_table_name(path: Path | None, option: str = "--table") -> None:
    """Refuse, before any work, a table file not named ``*.npz`` (the suffix names the format)."""
    if path is not None and path.suffix.lower() != SUFFIX:
        raise InputError(
            f"{option}: {str(path)!r} does not end in {SUFFIX}; the table is a NumPy .npz file: give a name like "
            f"{str(path.with_suffix(SUFFIX))!r}"
        )


def table_stream(result: AnalysisResult, option: str = "--table") -> Callable[[BinaryIO], None]:
    """The writer of ``result``'s table (see the module's docstring) into a binary stream."""
    count = len(result.scene.motion.angle_deg)
    blocks = even_blocks(count, -(-count // TABLE_BLOCK))
    return npz_stream(table_arrays(result), blocks, option)


def table_arrays(result: AnalysisResult) -> dict[str, NDArray | RowBlocks]:
    """Every array of ``result``'s table by name: whole arrays for what positions share and for the
    texts, ``RowBlocks`` for the per-position values."""
    count = len(result.scene.motion.angle_deg)
    every = np.ones(count, bool)
    feasible = np.asarray(result.feasible, bool)
    input_key = "input_stroke_m" if result.scene.motion.is_stroke else "input_angle_deg"
    arrays: dict[str, NDArray | RowBlocks] = {}
    for key, value in _flat((input_key,), result.scene.motion.angle_deg, every, count):
        arrays[key] = value
    arrays["feasible"] = feasible
    arrays.update(_flat(("reason",), text_codes(result.reasons), every, count))
    arrays.update(_flat(("warnings",), warning_codes(result.kinematics.crossings, count), every, count))
    transmission = {name: np.degrees(loop.transmission_angle) for name, loop in result.kinematics.loops.items()}
    described = {
        "links": link_value_columns(result),
        "transmission_angle_deg": transmission,
        "mechanisms": mechanism_columns(result),
    }
    arrays.update(_flat((), described, feasible, count))
    return arrays


def text_codes(texts: Sequence[str]) -> Coded:
    """``texts`` (one per position) as codes into their distinct values, "" first."""
    index = {text: k for k, text in enumerate(dict.fromkeys(("", *texts)))}
    codes = np.fromiter(map(index.__getitem__, texts), np.int32, count=len(texts))
    return Coded(codes, tuple(index))


def warning_codes(crossings: Sequence[tuple[int, str]], count: int) -> Coded:
    """Each of ``count`` positions' warnings (``crossings``: (row, message), a few in a sweep), joined
    by newlines, as codes into their distinct texts, "" (none) first."""
    joined: dict[int, str] = {}
    for row, message in crossings:
        joined[row] = f"{joined[row]}\n{message}" if row in joined else message
    index = {text: k for k, text in enumerate(dict.fromkeys(("", *joined.values())))}
    codes = np.zeros(count, np.int32)
    codes[list(joined)] = [index[text] for text in joined.values()]
    return Coded(codes, tuple(index))


def key_part(text: str) -> str:
    """One part of an array's name: ``text`` with ``%``, ``/`` and control characters percent-encoded."""
    return "".join(
        "".join(f"%{b:02X}" for b in ch.encode("utf-8")) if ch in "%/" or not ch.isprintable() else ch
        for ch in text
    )


def _flat(path: tuple[str, ...], value: object, keep: NDArray[np.bool_], count: int) -> Iterator[tuple[str, NDArray | RowBlocks]]:
    """The arrays of ``value`` at ``path``: per-position columns (zero where not ``keep``), nested
    dicts and lists of dicts by their keys and indices, and what positions share as it is (None or
    an empty list: nothing)."""
    name = "/".join(key_part(part) for part in path)
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _flat((*path, str(key)), item, keep, count)
    elif isinstance(value, list) and (not value or isinstance(value[0], dict)):  # records (none: no arrays)
        for k, item in enumerate(value):
            yield from _flat((*path, str(k)), item, keep, count)
    elif isinstance(value, Nullable):
        yield name, _rows(lambda block: value.values[block], keep & ~value.null, count)
    elif isinstance(value, Coded):
        # Only the texts some kept row uses (and the first, which the rows left out index): a pin hole
        # has dozens of possible reasons and a sweep meets a few.
        used = np.bincount(value.codes[keep], minlength=len(value.texts)) > 0
        used[0] = True
        renumber = (np.cumsum(used) - 1).astype(value.codes.dtype)
        texts = ["" if text is None else text for text, use in zip(value.texts, used) if use]
        yield f"{name}_code", _rows(lambda block: renumber[value.codes[block]], keep, count)
        yield f"{name}_texts", np.array(texts, dtype=str)
    elif isinstance(value, np.ndarray) and path[-1] not in SHARED:
        yield name, _rows(lambda block: value[block], keep, count)
    elif callable(value):
        yield name, _rows(value, keep, count)
    elif value is not None:
        yield name, np.asarray(value)


def _rows(make: Callable[[slice], NDArray], keep: NDArray[np.bool_], count: int) -> RowBlocks:
    """``make``'s rows, 0 where not ``keep`` (whatever they hold there, nan included)."""

    def block(rows: slice) -> NDArray:
        values, kept = np.asarray(make(rows)), keep[rows]
        if kept.all():  # most blocks of most sweeps: no copy
            return values
        return np.where(kept.reshape(-1, *(1,) * (values.ndim - 1)), values, np.zeros((), values.dtype))

    return RowBlocks(count, block)
