"""Checked reads from a parsed TOML table: every error names the key's dotted path and what to do."""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import SceneError

# The range of magnitudes accepted per unit: (smallest for a quantity that must be > 0, largest for any).
# Far wider than any machine, yet narrow enough that squares and products of them in the dynamics and
# stresses stay finite (1e300 m/s^2 of gravity reached the tables as inf and nan). A value outside is
# almost always a wrong unit or a typo.
RANGES: dict[str, tuple[float, float, str]] = {
    "m": (1e-6, 1e3, "a length"),
    "kg/m^3": (1e-2, 1e5, "a density"),
    "Pa": (1.0, 1e13, "a modulus or strength"),
    "kg": (1e-9, 1e9, "a mass"),
    "kg m^2": (0.0, 1e9, "a moment of inertia"),
    "deg": (0.0, 1e7, "an angle"),
    "s": (0.0, 1e9, "a time"),
    "rad/s": (0.0, 1e5, "an angular speed"),
    "rad/s^2": (0.0, 1e9, "an angular acceleration"),
    "m/s": (0.0, 1e5, "a speed"),
    "m/s^2": (0.0, 1e6, "an acceleration"),
    "N": (0.0, 1e12, "a force"),
    "N m": (0.0, 1e12, "a couple"),
}

SHOWN_KEY_PATH = 160
"""Longest dotted key path named in a message [characters]; a longer one keeps its start and end."""

MAX_STATIONS = 100_000
"""Section stations per link: far finer than any section changes (the default is 101)."""


def range_problem(value: float, unit: str, positive: bool = False) -> str | None:
    """Why ``value`` [``unit``] lies outside the range accepted for its quantity, or None."""
    if unit not in RANGES:
        return None
    smallest, largest, what = RANGES[unit]
    if abs(value) > largest:
        return f"must be at most {largest:g} {unit} in size ({what}; check the unit), got {value!r}"
    if positive and value < smallest:
        return f"must be at least {smallest:g} {unit} ({what}; check the unit), got {value!r}"
    return None


class Table:
    """A TOML table at dotted ``path`` in scene file ``source`` (its name, for messages)."""

    def __init__(self, data: object, path: str, source: str) -> None:
        if not isinstance(data, dict):
            raise SceneError(f"{source}: {path}: must be a table ([{path}] or {{ ... }}), got {shown_value(data)}")
        self.data, self.path, self.source = data, path, source

    def key_path(self, key: str) -> str:
        return f"{self.path}.{key}" if self.path else key

    def error(self, key: str | None, text: str) -> SceneError:
        where = self.key_path(key) if key is not None else self.path
        if len(where) > SHOWN_KEY_PATH:  # a table name of thousands of characters
            where = where[: SHOWN_KEY_PATH - 43] + "..." + where[-40:]
        return SceneError(f"{self.source}: {where}: {text}")

    def has(self, key: str) -> bool:
        return key in self.data

    def allow(self, keys: Iterable[str]) -> None:
        """Refuse keys outside ``keys``, listing the allowed ones."""
        allowed = list(keys)
        for key in self.data:
            if key not in allowed:
                raise self.error(key, f"unknown key; allowed keys are: {', '.join(allowed)}")

    def require(self, key: str, what: str) -> object:
        if key not in self.data:
            raise self.error(key, f"missing; give {what}")
        return self.data[key]

    def table(self, key: str, required: bool = False) -> Table | None:
        if key not in self.data:
            if required:
                raise self.error(key, f"missing table; add [{self.key_path(key)}]")
            return None
        return Table(self.data[key], self.key_path(key), self.source)

    def number(self, key: str, default: float | None = None, *, minimum: float | None = None,
               positive: bool = False, unit: str = "") -> float | None:
        """A finite number (int or float), optionally > 0 or >= ``minimum``; ``default`` when absent."""
        if key not in self.data:
            return default
        return self.check_number(key, self.data[key], minimum=minimum, positive=positive, unit=unit)

    def check_number(self, key: str, value: object, *, minimum: float | None = None,
                     positive: bool = False, unit: str = "") -> float:
        suffix = f" {unit}" if unit else ""
        if type(value) not in (int, float) or not math.isfinite(value):
            raise self.error(key, f"must be a finite number{suffix}, got {shown_value(value)}")
        if positive and not value > 0:
            raise self.error(key, f"must be > 0{suffix}, got {value!r}")
        if minimum is not None and value < minimum:
            raise self.error(key, f"must be >= {minimum:g}{suffix}, got {value!r}")
        if (problem := range_problem(value, unit, positive)) is not None:
            raise self.error(key, problem)
        return float(value)

    def integer(self, key: str, default: int | None = None, *, minimum: int | None = None,
                maximum: int | None = None) -> int | None:
        if key not in self.data:
            return default
        value = self.data[key]
        if type(value) is not int:
            raise self.error(key, f"must be a whole number, got {shown_value(value)}")
        if minimum is not None and value < minimum:
            raise self.error(key, f"must be >= {minimum}, got {value!r}")
        if maximum is not None and value > maximum:
            raise self.error(key, f"must be <= {maximum}, got {value!r}")
        return value

    def string(self, key: str, default: str | None = None, choices: Iterable[str] | None = None) -> str | None:
        if key not in self.data:
            return default
        value = self.data[key]
        if not isinstance(value, str) or not value:
            raise self.error(key, f"must be a non-empty string, got {shown_value(value)}")
        if choices is not None and value not in (options := list(choices)):
            raise self.error(key, f"must be one of {', '.join(repr(c) for c in options)}, got {value!r}")
        return value

    def boolean(self, key: str, default: bool) -> bool:
        if key not in self.data:
            return default
        value = self.data[key]
        if not isinstance(value, bool):
            raise self.error(key, f"must be true or false, got {shown_value(value)}")
        return value

    def numbers(self, key: str, unit: str = "") -> NDArray[np.float64]:
        """A non-empty flat list of finite numbers."""
        value = self.data[key]
        if not isinstance(value, list) or not value:
            raise self.error(key, f"must be a non-empty list of numbers{' ' + unit if unit else ''}, got {shown_value(value)}")
        return np.array([self.check_number(f"{key}[{k}]", v, unit=unit) for k, v in enumerate(value)])

    def point(self, key: str, unit: str) -> NDArray[np.float64]:
        """An (x, y) pair of finite numbers."""
        value = self.data[key]
        if not isinstance(value, list) or len(value) != 2:
            raise self.error(key, f"must be a pair [x, y] {unit}, got {shown_value(value)}")
        return np.array([self.check_number(f"{key}[{k}]", v, unit=unit) for k, v in enumerate(value)])

    def points(self, key: str, unit: str) -> NDArray[np.float64]:
        """A non-empty list of (x, y) pairs."""
        value = self.data[key]
        if not isinstance(value, list) or not value:
            raise self.error(key, f"must be a list of [x, y] pairs {unit}, got {shown_value(value)}")
        rows = []
        for k, row in enumerate(value):
            if not isinstance(row, list) or len(row) != 2:
                raise self.error(f"{key}[{k}]", f"must be a pair [x, y] {unit}, got {shown_value(row)}")
            rows.append([self.check_number(f"{key}[{k}]", v, unit=unit) for v in row])
        return np.array(rows, float)


def shown_value(value: object) -> str:
    """A short rendering of a TOML value for messages."""
    if isinstance(value, dict):
        return "a table"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
