"""Drawing units: names a user may type, DXF ``$INSUNITS`` codes, and their size in metres.

The codes, symbols, names and factors are ezdxf's (``ezdxf.units``), copied here so that reading a
plain DXF sketch needs no ezdxf (0.2 s to import; a test holds the copy equal to ezdxf's); this
module adds the names a user types on the command line or in a scene (``mm``, ``inch``,
``millimetres``...), and the typographic units of drawings exported from vector and board editors
(Inkscape, KiCad), which have no ``$INSUNITS`` code: the point (1/72 inch), the pixel (1/96 inch,
CSS) and the pica (1/6 inch).

The short symbols of astronomical units (``pc``, ``ly``, ``au``, ``gm``) are refused with what they
mean: ``pc`` typed for picas would read a drawing 1e17 times too large. Spelt out (``parsecs``) they
are taken as meant.
"""

from __future__ import annotations

from dataclasses import dataclass

from linkstress.errors import SketchError

INSUNITS = {
    1: ("in", "Inches", 39.37007874), 2: ("ft", "Feet", 3.280839895), 3: ("mi", "Miles", 0.00062137119),
    4: ("mm", "Millimeters", 1000.0), 5: ("cm", "Centimeters", 100.0), 6: ("m", "Meters", 1.0),
    7: ("km", "Kilometers", 0.001), 10: ("yd", "Yards", 1.093613298), 11: ("\u00c5", "Angstroms", 1e10),
    12: ("nm", "Nanometers", 1e9), 13: ("\u00b5m", "Microns", 1e6), 14: ("dm", "Decimeters", 10.0),
    15: ("dam", "Decameters", 0.1), 16: ("hm", "Hectometers", 0.01), 17: ("gm", "Gigameters", 1e-9),
    18: ("au", "AstronomicalUnits", 6.684587122268445e-12), 19: ("ly", "Lightyears", 1.0570824524312897e-16),
    20: ("pc", "Parsecs", 3.2362459546925564e-17),
}
"""$INSUNITS code: (symbol, name, how many make a metre), for the codes with a conversion to metres."""
UNCONVERTIBLE = {0: "Unitless", 8: "Microinches", 9: "Mils", 21: "USSurveyFeet", 22: "USSurveyInch",
                 23: "USSurveyYard", 24: "USSurveyMile"}
"""The names of the other codes, which have no conversion to metres; any code not listed is "unitless"."""

INCH_M = 0.0254
"""An inch in metres (exact, by definition)."""
TYPOGRAPHIC = {"pt": ("points", INCH_M / 72), "px": ("pixels", INCH_M / 96), "pica": ("picas", INCH_M / 6)}
"""Units without a ``$INSUNITS`` code: symbol: (name, metres each)."""
SPELL_OUT = {17: "a gigametre", 18: "an astronomical unit", 19: "a light year", 20: "a parsec"}
"""$INSUNITS codes whose short symbol is refused: what the symbol means; the spelt-out name is taken."""

_EXTRA_NAMES = {
    "um": 13, "micron": 13, "microns": 13,
    "inch": 1, "foot": 2, "meter": 6, "metre": 6, "metres": 6,
    "millimetre": 4, "millimetres": 4, "millimeter": 4,
    "centimetre": 5, "centimetres": 5, "centimeter": 5,
    "decimetre": 14, "decimetres": 14, "kilometre": 7, "kilometres": 7, "yard": 10,
}


@dataclass(frozen=True)
class DrawingUnit:
    """A length unit of a drawing: ``name`` (short symbol, e.g. ``mm``), its DXF ``$INSUNITS`` ``code``
    (None for a unit DXF has no code for: ``pt``, ``px``, ``pica``) and ``per_metre``, how many of it make
    a metre (ezdxf's factor): metres = value / per_metre. Two units are the same when their names are."""

    name: str
    code: int | None
    per_metre: float


_CODES = {code: symbol for code, (symbol, _, _) in INSUNITS.items()}
_UNITS: dict[str, DrawingUnit] = {
    **{symbol: DrawingUnit(symbol, code, float(factor)) for code, (symbol, _, factor) in INSUNITS.items()},
    **{symbol: DrawingUnit(symbol, None, 1.0 / metres) for symbol, (_, metres) in TYPOGRAPHIC.items()},
}
_NAMES: dict[str, str] = {
    **{symbol.lower(): symbol for symbol in _UNITS},
    **{name.lower(): _CODES[code] for code, (_, name, _) in INSUNITS.items()},
    **{name: _CODES[code] for name, code in _EXTRA_NAMES.items()},
    **{name: symbol for symbol, (name, _) in TYPOGRAPHIC.items()},
    **{name[:-1]: symbol for symbol, (name, _) in TYPOGRAPHIC.items()},
}
_SHORT = {_CODES[code].lower(): (meaning, code) for code, meaning in SPELL_OUT.items()}


def unit_named(name: str, where: str) -> DrawingUnit:
    """The unit a user named (``mm``, ``cm``, ``m``, ``in``, ``ft``, ``pt``, ``px``, ``inches``...); ``where``
    names the source. The short symbol of an astronomical unit (``pc``: a parsec, not a pica) is refused,
    asking for the name spelt out."""
    typed = str(name).strip().lower()
    if typed in _SHORT:
        meaning, code = _SHORT[typed]
        picas = "; for picas give --units pica" if typed == "pc" else ""
        raise SketchError(
            f"{where}: {name!r} is {meaning} ({1 / INSUNITS[code][2]:.2g} m){picas}; a drawing in "
            f"{INSUNITS[code][1].lower()} must say so in full (units {INSUNITS[code][1].lower()!r})"
        )
    symbol = _NAMES.get(typed)
    if symbol is None:
        known = ", ".join(sorted(s for s in _UNITS if s.isascii() and s.lower() not in _SHORT))
        raise SketchError(f"{where}: unknown length unit {name!r}; use one of {known}")
    return _UNITS[symbol]


def unit_of(symbol: str) -> DrawingUnit:
    """The unit whose short symbol is ``symbol`` (``DrawingUnit.name``, as a sketch reports its units)."""
    return _UNITS[symbol]


def unit_from_insunits(code: int) -> DrawingUnit | None:
    """The unit of a DXF ``$INSUNITS`` code; None for 0 (unitless) or a code ezdxf cannot convert."""
    if code in _CODES:
        return _UNITS[_CODES[code]]
    return None


def insunits_label(code: int) -> str:
    """ezdxf's name of a ``$INSUNITS`` code, e.g. ``Mils`` or ``Unitless``."""
    if code in INSUNITS:
        return INSUNITS[code][1]
    return UNCONVERTIBLE.get(code, "unitless")


def choose_unit(declared: DrawingUnit | None, declared_by: str, given: str | None,
                default: tuple[DrawingUnit, str] | None, unsaid: str | None = None,
                override: bool = True) -> tuple[DrawingUnit, str]:
    """The unit of a sketch file and where it came from: the caller's ``given`` name, else the file's
    own (``declared``, found in ``declared_by``), else ``default`` (unit, reason); ``unsaid`` says why
    the file declares none (default: ``declared_by`` is unitless).

    With ``override`` (``--units``) a given unit overrides a declared one (a drawing saved with the
    wrong $INSUNITS is common) and the source says so: "--units mm, overriding the file's $INSUNITS
    inches". Without (a scene's ``units``, meant for unitless sketches) a disagreement is an error:
    one of them is wrong.
    """
    chosen = unit_named(given, "units") if given is not None else None
    if chosen is not None and declared is not None and declared.name != chosen.name:
        if not override:
            raise SketchError(
                f"the file declares its units as {declared.name} ({declared_by}) but units {given!r} were "
                "given; drop the units or fix the drawing's units"
            )
        label = insunits_label(declared.code).lower() if declared.code is not None else declared.name
        return chosen, f"--units {chosen.name}, overriding the file's {declared_by.removeprefix('the ')} {label}"
    if declared is not None:
        return declared, declared_by
    if chosen is not None:
        return chosen, "given by the caller (--units or the scene's units)"
    if default is not None:
        return default
    why = unsaid or f"{declared_by} is unitless"
    raise SketchError(
        f"the file does not say its units ({why}): pass --units with the drawing's unit, e.g. --units mm "
        "(mm, cm, m, in, ft, pt or px), or set the scene's units"
    )
