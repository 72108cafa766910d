"""Inventor iLogic CSV sketches: the original program's format and linkstress-sketch v1.

**Old format** (the original KSAM rule): the first line is ignored; ``New <entity>`` starts a run
of ``x, y`` rows (a polyline); ``Point`` is followed by one ``x, y`` row, a joint. It carries no
units: Inventor's API reports sketch geometry in centimetres, so that is assumed unless the caller
says otherwise. Its rule samples circles from 0 to 2 pi in steps of 0.01 rad (stopping short of
2 pi) and arcs without their first point, so its default gap tolerance is 1e-2 of the drawing size
(pairs of ends still join only with their nearest partner). A ``New Circle`` run is recognised as a
circle (least-squares fit) so its centre can serve as a joint.

**linkstress-sketch v1** (written by ``cad_scripts/ExportSketchToLinkstress.iLogicVb``): a first
line ``# linkstress-sketch v1 units=cm``, ``#`` comments, and one exact primitive per line, angles
in radians, counter-clockwise positive::

    line, x0, y0, x1, y1
    arc, cx, cy, r, start, sweep
    circle, cx, cy, r
    ellipse, cx, cy, major_x, major_y, ratio, start, sweep   (parametric angles, as in DXF)
    spline, x0, y0, x1, y1, ...                              (points sampled along the spline)
    point, x, y                                              (a joint)

Both accept CRLF, a UTF-8 BOM, blank lines, and ``;`` as separator with decimal commas (then for
the whole file). Anything else is refused with its line number.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from linkstress.errors import SketchError
from linkstress.importers.primitives import CurveSet, Origin, Polyline, RawSketch
from linkstress.importers.units import choose_unit, unit_named

OLD_GAP_TOLERANCE = 1e-2
V1_GAP_TOLERANCE = 1e-4
INVENTOR_UNITS = "cm"
CIRCLE_FIT = 1e-6
"""A sampled circle is taken as one when every sample is within this fraction of r of the fitted circle."""

_NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?")
_HEADER = re.compile(r"#\s*linkstress-sketch\s+v(\d+)(.*)$", re.IGNORECASE)
_NEW = re.compile(r"new(?:$|[\s_\-]+(.*))", re.IGNORECASE)
_POINT = re.compile(r"point(?:$|[\s_\-].*)", re.IGNORECASE)
_V1_FIELDS = {"line": 4, "arc": 5, "circle": 3, "ellipse": 7, "point": 2}


def read_csv(path: Path, data: bytes, units: str | None, override_units: bool = True) -> RawSketch:
    """The curves and points of an iLogic CSV sketch (either format) in ``units`` if given, else its
    own; ``override_units`` False refuses ``units`` that disagree with the header's instead."""
    lines = _decode(data).replace("\r\n", "\n").replace("\r", "\n").split("\n")
    separator = ";" if any(";" in line for line in lines[1:]) else ","
    header = _HEADER.match(lines[0].strip())
    if header:
        return _read_v1(lines, header, separator, units, override_units)
    return _read_old(lines, separator, units)


def _decode(data: bytes) -> str:
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise SketchError("the CSV is UTF-16 text: save it as UTF-8 (or ANSI) text")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        line = data[:error.start].count(b"\n") + 1
        raise SketchError(
            f"line {line}: not UTF-8 text (byte 0x{data[error.start]:02x}): not a DXF or linkstress CSV "
            "sketch, or one saved in another encoding; save the sketch as UTF-8 text"
        ) from None


class _Rows:
    """Splits and parses the data lines of one file."""

    def __init__(self, separator: str) -> None:
        self.separator = separator

    def fields(self, text: str) -> list[str]:
        fields = [f.strip() for f in text.split(self.separator)]
        return fields[:-1] if len(fields) > 1 and fields[-1] == "" else fields

    def number(self, text: str, line: int) -> float:
        candidate = text.replace(",", ".") if self.separator == ";" else text
        if not _NUMBER.fullmatch(candidate):
            raise SketchError(f"line {line}: {text!r} is not a number")
        value = float(candidate)
        if not math.isfinite(value):
            raise SketchError(f"line {line}: {text!r} is too large a number")
        return value

    def numbers(self, fields: list[str], count: int | None, line: int, what: str) -> list[float]:
        if count is not None and len(fields) != count:
            hint = ""
            if self.separator == "," and len(fields) == 2 * count:
                hint = "; if the numbers use decimal commas, separate fields with ';'"
            raise SketchError(
                f"line {line}: expected {what} ({count} number{'s' * (count > 1)}), got "
                f"{self.separator.join(fields)!r}{hint}"
            )
        return [self.number(f, line) for f in fields]


# -- the original program's format ---------------------------------------------------------------


def _read_old(lines: list[str], separator: str, units: str | None) -> RawSketch:
    _check_old_format(lines)
    rows = _Rows(separator)
    runs: list[tuple[str, int, list[list[float]]]] = []
    joints: list[list[float]] = []
    joint_lines: list[int] = []
    k = 1
    while k < len(lines):
        text, line = lines[k].strip(), k + 1
        k += 1
        if not text:
            continue
        fields = rows.fields(text)
        new = _NEW.fullmatch(fields[0])
        if new:
            _no_extra(fields, line)
            runs.append(((new[1] or "curve").strip(), line, []))
        elif _POINT.fullmatch(fields[0]):
            _no_extra(fields, line)
            while k < len(lines) and not lines[k].strip():
                k += 1
            if k == len(lines):
                raise SketchError(f"line {line}: 'Point' must be followed by its x, y line")
            joints.append(rows.numbers(rows.fields(lines[k].strip()), 2, k + 1, "the point's x, y"))
            joint_lines.append(k + 1)
            k += 1
        else:
            xy = rows.numbers(fields, 2, line, "x, y")
            if not runs:
                raise SketchError(f"line {line}: coordinates before the first 'New <entity>' line")
            runs[-1][2].append(xy)
    curves = CurveSet()
    for kind, line, points in runs:
        if len(points) < 2:
            raise SketchError(f"line {line}: 'New {kind}' has {len(points)} x, y line(s); a curve needs two or more")
        xy = np.array(points)
        circle = _fit_circle(xy) if "circle" in kind.lower() else None
        curves.add_polyline(Polyline(xy, np.zeros(len(xy)), False, circle), (f"New {kind}", None, None, line, None))
    if joints:
        curves.add_points(joints, [("Point", None, None, n, None) for n in joint_lines])
    assumed = (unit_named(INVENTOR_UNITS, "units"),
               "assumed: the old iLogic CSV carries no units and Inventor's API reports centimetres; "
               "pass --units to say otherwise")
    unit, source = choose_unit(None, "the old iLogic CSV", units, default=assumed)
    return RawSketch(curves, unit, source, "iLogic CSV (original format)", {}, (), OLD_GAP_TOLERANCE)


def _check_old_format(lines: list[str]) -> None:
    """Refuse a file that is not an old iLogic CSV (its first data line starts a curve or is a Point)
    without quoting it: it may be any file, which a message must not echo."""
    first = next((k for k in range(1, len(lines)) if lines[k].strip()), None)
    if first is None:
        return
    head = lines[first].strip().split(";")[0].split(",")[0].strip()
    if not (_NEW.fullmatch(head) or _POINT.fullmatch(head)):
        raise SketchError(
            f"line {first + 1}: not a DXF or linkstress CSV sketch (an iLogic CSV's data starts with a "
            "'New <entity>' line, a linkstress-sketch CSV with '# linkstress-sketch v1'); give a sketch "
            "exported from CAD"
        )


def _no_extra(fields: list[str], line: int) -> None:
    if len(fields) > 1:
        raise SketchError(f"line {line}: {fields[0]!r} stands alone on its line, found {fields[1:]!r} after it")


def _fit_circle(xy: np.ndarray) -> tuple[float, float, float] | None:
    """Centre and radius of the circle through the samples (Kasa's algebraic least squares), or
    None if they do not lie on one within ``CIRCLE_FIT`` x r."""
    if len(xy) < 3:
        return None
    mean = xy.mean(axis=0)
    x, y = (xy - mean).T
    a = np.column_stack([x, y, np.ones_like(x)])
    (d, e, f), *_ = np.linalg.lstsq(a, -(x * x + y * y), rcond=None)
    cx, cy = -d / 2, -e / 2
    r2 = cx * cx + cy * cy - f
    if not r2 > 0:
        return None
    r = math.sqrt(r2)
    if np.abs(np.hypot(x - cx, y - cy) - r).max() > CIRCLE_FIT * r:
        return None
    return float(cx + mean[0]), float(cy + mean[1]), r


# -- linkstress-sketch v1 ---------------------------------------------------------------------------


def _read_v1(lines: list[str], header: re.Match, separator: str, units: str | None, override_units: bool) -> RawSketch:
    if header[1] != "1":
        raise SketchError(f"line 1: linkstress-sketch v{header[1]} is not a version this linkstress reads (v1)")
    declared = None
    for option in header[2].split():
        key, _, value = option.partition("=")
        if key.lower() != "units" or not value:
            raise SketchError(f"line 1: unknown header option {option!r}; the header is '# linkstress-sketch v1 units=mm'")
        unit = unit_named(value, "line 1: units")
        if declared is not None and unit.name != declared.name:
            raise SketchError(
                f"line 1: the header gives two units, {declared.name} and {unit.name}; keep the one the "
                "numbers are in"
            )
        declared = unit
    rows = _Rows(separator)
    curves = CurveSet()
    found: dict[str, list] = {kind: [] for kind in _V1_FIELDS}
    where: dict[str, list[Origin]] = {kind: [] for kind in _V1_FIELDS}
    for k in range(1, len(lines)):
        text, line = lines[k].strip(), k + 1
        if not text or text.startswith("#"):
            continue
        fields = rows.fields(text)
        kind = fields[0].lower()
        if kind == "spline":
            values = rows.numbers(fields[1:], None, line, "spline points")
            if len(values) < 4 or len(values) % 2:
                raise SketchError(f"line {line}: a spline needs x, y pairs of two or more points, got {len(values)} numbers")
            xy = np.array(values).reshape(-1, 2)
            curves.add_polyline(Polyline(xy, np.zeros(len(xy)), False), ("spline", None, None, line, None))
            continue
        if kind not in _V1_FIELDS:
            raise SketchError(
                f"line {line}: unknown record {fields[0]!r}; expected line, arc, circle, ellipse, spline or point"
            )
        values = rows.numbers(fields[1:], _V1_FIELDS[kind], line, _what(kind))
        _check_v1(kind, values, line)
        found[kind].append(values)
        where[kind].append((kind, None, None, line, None))
    _add_v1(curves, found, where)
    unit, source = choose_unit(declared, "the header's units=", units, default=None, override=override_units)
    return RawSketch(curves, unit, source, "linkstress-sketch v1 CSV", {}, (), V1_GAP_TOLERANCE)


def _what(kind: str) -> str:
    return {
        "line": "x0, y0, x1, y1", "arc": "cx, cy, r, start, sweep", "circle": "cx, cy, r",
        "ellipse": "cx, cy, major_x, major_y, ratio, start, sweep", "point": "x, y",
    }[kind]


def _check_v1(kind: str, values: list[float], line: int) -> None:
    if kind in ("arc", "circle") and not values[2] > 0:
        raise SketchError(f"line {line}: the radius must be > 0, got {values[2]!r}")
    if kind == "ellipse":
        if not math.hypot(values[2], values[3]) > 0:
            raise SketchError(f"line {line}: the major axis (major_x, major_y) must not be zero")
        if not 0 < values[4] <= 1:
            raise SketchError(f"line {line}: the ratio minor/major must be in (0, 1], got {values[4]!r}")
    if kind in ("arc", "ellipse") and not 0 < abs(values[-1]) <= 2 * math.pi * (1 + 1e-12):
        raise SketchError(f"line {line}: the sweep must be non-zero and at most 2 pi in size, got {values[-1]!r}")


def _add_v1(curves: CurveSet, found: dict[str, list], where: dict[str, list[Origin]]) -> None:
    if found["line"]:
        curves.add_lines(np.array(found["line"]), where["line"])
    if found["arc"]:
        a = np.array(found["arc"])
        curves.add_arcs(a[:, :2], a[:, 2], a[:, 3], a[:, 4], where["arc"])
    if found["circle"]:
        c = np.array(found["circle"])
        curves.add_arcs(c[:, :2], c[:, 2], np.zeros(len(c)), np.full(len(c), 2 * math.pi), where["circle"])
    if found["ellipse"]:
        e = np.array(found["ellipse"])
        major = e[:, 2:4]
        minor = e[:, 4:5] * np.column_stack([-major[:, 1], major[:, 0]])
        curves.add_conics(e[:, :2], major, minor, e[:, 5], e[:, 6], where["ellipse"])
    if found["point"]:
        curves.add_points(np.array(found["point"]), where["point"])

