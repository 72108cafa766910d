"""Is an imported drawing in the unit it says? Sizes no mechanism has, and the unit that would fit.

A drawing read in the wrong unit imports without complaint: a sheet whose header says inches but is
drawn in millimetres becomes a 12 m Strandbeest with 81 mm pins. Pin holes under ``MIN_PIN_HOLE_M``
or links over ``MAX_LINK_M`` are implausible; the warning then names the unit (of ``CANDIDATES``)
that would make every pin hole and link ordinary (``ORDINARY_PIN_HOLE_M``, ``ORDINARY_LINK_M``),
nearest in scale to the unit read. A warning, never a refusal: a large or a fine mechanism exists.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import shapely

from linkstress.importers.sketch import ImportedLink, Sketch
from linkstress.importers.units import INSUNITS, TYPOGRAPHIC, unit_named, unit_of

MIN_PIN_HOLE_M = 0.5e-3
"""A round hole smaller than this [m] is no pin hole of a mechanism one analyses for stress."""
MAX_LINK_M = 5.0
"""A link longer than this [m] is outside what linkstress is used for (and a unit slip, most likely)."""
ORDINARY_PIN_HOLE_M = (1e-3, 0.1)
"""Pin hole diameters [m] of ordinary mechanisms, a unit must give to be suggested."""
ORDINARY_LINK_M = (5e-3, 2.0)
"""Link lengths [m] of ordinary mechanisms, a unit must give to be suggested."""
CANDIDATES = ("mm", "cm", "m", "in", "ft")
"""The units a drawing may have been drawn in."""


def unit_warnings(sketch: Sketch, links: Iterable[ImportedLink] | None = None,
                  fix: str = "give --units {unit}") -> tuple[str, ...]:
    """One line when the pin holes (round holes) of ``links`` (default: all the sketch's) are under
    ``MIN_PIN_HOLE_M`` or a link is longer than ``MAX_LINK_M``, naming the unit that would make them
    ordinary in ``fix`` (its ``{unit}``: e.g. ``give --units mm``); else nothing."""
    links = list(sketch.links if links is None else links)
    holes = [d for link in links for d in link.hole_diameters_m if d is not None]
    lengths = [_length(link) for link in links]
    if not lengths or not ((holes and min(holes) < MIN_PIN_HOLE_M) or max(lengths) > MAX_LINK_M):
        return ()
    seen, read = _sizes(lengths, holes, 1.0), _read_as(sketch)
    fitting = _fitting(sketch.units, lengths, holes)
    if not fitting:
        return (f"{seen}: no mechanism is that size, while {read}; check the drawing's units",)
    unit, scale = fitting[0]
    return (f"{seen}: the drawing looks drawn in {_word(unit)} while {read}; {fix.format(unit=unit)} (then "
            f"{_sizes(lengths, holes, scale)})",)


def _length(link: ImportedLink) -> float:
    """The link's length [m]: the longer side of its outline's smallest enclosing rectangle."""
    rectangle = shapely.oriented_envelope(link.outline)
    x, y = rectangle.exterior.coords.xy if rectangle.geom_type == "Polygon" else ([0.0], [0.0])
    sides = [math.hypot(x[k + 1] - x[k], y[k + 1] - y[k]) for k in range(len(x) - 1)]
    return max(sides, default=rectangle.length)


def _fitting(read: str, lengths: list[float], holes: list[float]):
    """(unit, scale) of the candidate units that make every length and hole ordinary, nearest first;
    ``scale`` multiplies the sizes read."""
    per_metre = unit_of(read).per_metre
    found = []
    for name in CANDIDATES:
        scale = per_metre / unit_named(name, "units").per_metre
        if name == read or not _ordinary(lengths, ORDINARY_LINK_M, scale) or not _ordinary(holes, ORDINARY_PIN_HOLE_M, scale):
            continue
        found.append((abs(math.log(scale)), name, scale))
    return [(name, scale) for _, name, scale in sorted(found)]


def _ordinary(sizes: list[float], bounds: tuple[float, float], scale: float) -> bool:
    return all(bounds[0] <= size * scale <= bounds[1] for size in sizes)


def _sizes(lengths: list[float], holes: list[float], scale: float) -> str:
    """``links up to 12.2 m long and pin holes of 81.3 mm`` (or from 3 to 8 mm), sizes times ``scale``."""
    text = f"links up to {_metres(max(lengths) * scale)} long"
    if holes:
        low, high = min(holes) * scale, max(holes) * scale
        across = _metres(low) if math.isclose(low, high, rel_tol=1e-3) else f"{_metres(low)} to {_metres(high)}"
        text += f" and pin holes of {across}"
    return text


def _metres(value: float) -> str:
    return f"{value:.3g} m" if value >= 1.0 else f"{value * 1e3:.3g} mm"


def _word(unit: str) -> str:
    """``millimeters``, ``inches``, ``points``: the unit's name."""
    for symbol, name, _ in INSUNITS.values():
        if symbol == unit:
            return name.lower()
    return TYPOGRAPHIC[unit][0] if unit in TYPOGRAPHIC else unit


def _read_as(sketch: Sketch) -> str:
    """Where the unit read came from, as the second half of a sentence."""
    source = sketch.units_source
    if source == "$INSUNITS":
        return f"its header ($INSUNITS) says {_word(sketch.units)}"
    if source.startswith("--units"):
        return f"--units gave {_word(sketch.units)}"
    return f"it is read in {_word(sketch.units)} ({source})"
