"""How the reports write numbers and tables: a few significant digits, stresses in MPa, round-off
noise as 0, text left and numbers right.

A sweep's arithmetic leaves values like -1.3e-14 where the exact answer is 0 (a cosine of 90 deg, a
force along a frame's axis). In a table whose largest value in that column is 100, such a value is
noise: ``NOISE`` of the column's scale or less is written 0. Every figure is rounded to its digits
once, here, so that a report's text and its JSON (which keeps the full value) agree to those digits.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

NOISE = 1e-9
"""Values this small against the largest of their column are round-off: shown as 0."""
STRESS_DIGITS = 3
FORCE_DIGITS = 4


def significant(value: float, digits: int = 3, zeros: bool = True) -> str:
    """``value`` to ``digits`` significant digits, in plain notation from 1e-4 to below 1e6 (no
    exponent for a stress of 1,230 MPa), else in scientific notation; "0" for zero. Without
    ``zeros``, trailing zeros after the point are dropped ("60" rather than "60.0000")."""
    if value == 0 or not math.isfinite(value):
        return "0" if value == 0 else str(value)
    exponent = math.floor(math.log10(abs(value)))
    rounded = round(value, digits - 1 - exponent)
    exponent = math.floor(math.log10(abs(rounded)))  # 9.996 rounds up to 10.0
    if -4 <= exponent < 6:
        decimals = max(digits - 1 - exponent, 0)
        text = f"{rounded:.{decimals}f}"
        return text if zeros or "." not in text else text.rstrip("0").rstrip(".")
    text = f"{rounded:.{digits - 1}e}"
    if zeros:
        return text
    mantissa, power = text.split("e")
    return (mantissa.rstrip("0").rstrip(".") if "." in mantissa else mantissa) + "e" + power


def mpa(stress_pa: float, digits: int = STRESS_DIGITS) -> str:
    """A stress [Pa] written in MPa to ``digits`` significant digits (without the unit)."""
    return significant(stress_pa / 1e6, digits)


def without_noise(values: np.ndarray, scale: float | None = None) -> np.ndarray:
    """``values`` with those within ``NOISE`` of ``scale`` (default: their largest magnitude) of 0 set to 0."""
    values = np.asarray(values, float)
    if scale is None:
        finite = np.abs(values[np.isfinite(values)])
        scale = float(finite.max()) if finite.size else 0.0
    return np.where(np.abs(values) <= NOISE * scale, 0.0, values) + 0.0


def point(xy, digits: int = 4) -> str:
    """"(x, y)" to ``digits`` significant digits, a coordinate that is round-off against the other
    (a pin at y = 1.4e-17 on the x axis) written 0."""
    x, y = without_noise(np.asarray(xy, float)[:2])
    return f"({x:.{digits}g}, {y:.{digits}g})"


def column_cells(rows: Sequence[Sequence[object]], digits: Sequence[int | None]) -> list[list[object]]:
    """``rows`` with each float column ``k`` written to ``digits[k]`` significant digits (None: kept
    as given; trailing zeros dropped) after its round-off noise is set to 0 against the column's
    largest magnitude."""
    columns = list(zip(*rows)) if rows else []
    out = [list(row) for row in rows]
    for k, column in enumerate(columns):
        if digits[k] is None:
            continue
        numbers = [v for v in column if isinstance(v, float) and math.isfinite(v)]
        scale = max((abs(v) for v in numbers), default=0.0)
        for r, value in enumerate(column):
            if isinstance(value, float):
                out[r][k] = significant(float(without_noise(np.array([value]), scale)[0]), digits[k], zeros=False)
    return out


def text_table(headers: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """A terminal table: each column as wide as its widest cell, text left-aligned and numbers (cells
    that read as one) right-aligned."""
    cells = [[str(v) for v in row] for row in rows]
    widths = [max([len(h), *(len(r[k]) for r in cells)]) for k, h in enumerate(headers)]
    numeric = [all(_reads_as_number(r[k]) for r in cells) and bool(cells) for k in range(len(headers))]

    def line(values: Sequence[str]) -> str:
        return "  ".join(v.rjust(w) if n else v.ljust(w) for v, w, n in zip(values, widths, numeric)).rstrip()

    return "\n".join([line(headers), line(["-" * w for w in widths]), *(line(r) for r in cells)])


def _reads_as_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return text in ("-", "")
    return True
