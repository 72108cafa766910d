"""Values a scene may give but real links do not have: most likely a unit slip, warned of, never refused.

A scene is in SI units throughout. ``thickness = 6`` (meant mm) is a 6 m plate and gives a safety
factor of thousands; ``yield_strength = 250`` (meant MPa) is 250 Pa and gives 1e-5. Both are valid
numbers (the reader's ranges, ``linkstress.scene.keys.RANGES``, only keep the arithmetic finite), so
here each is held to the range that real link plates and engineering materials have (``RULES``, their
reasons in docs/scenes.md), and a value outside it gets one line saying which unit it looks like
written in: "links.crank.thickness = 6 m: did you mean 6 mm = 0.006?".

Two checks compare values with the link's own size (the largest distance between its joints, or its
outline's diagonal when drawn): a plate thicker than the link is long is a block, outside what plane
stress describes; and a radius of gyration sqrt(inertia / mass) over ``GYRATION_FACTOR`` times the
link's size (a body whose material lies within R of its centre of mass has one of at most R) is an
inertia in CAD's kg mm^2 or g mm^2.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from linkstress.materials import Material
from linkstress.scene.model import SceneLink


@dataclass(frozen=True)
class Rule:
    """The plausible range [``low``, ``high``] of a scene key in its SI ``unit``, named in messages by
    ``span`` (what has values in that range); ``slips``: the units a value may have been written in
    by mistake, (name, size in ``unit``), most likely first. Messages say "real {span}"."""

    unit: str
    low: float
    high: float
    span: str
    slips: tuple[tuple[str, float], ...]


PSI = 6894.757293168361
"""Pa per pound-force per square inch."""
INCH = 0.0254
"""m per inch."""
POUND = 0.45359237
"""kg per pound."""

THICKNESS = Rule("m", 1e-4, 0.3, "plates are 0.1 mm to 300 mm thick", (("mm", 1e-3), ("in", INCH)))
DENSITY = Rule(
    "kg/m^3", 100.0, 25_000.0, "solids are 100 to 25,000 kg/m^3, balsa wood to osmium",
    (("g/cm^3", 1e3), ("lb/in^3", POUND / INCH**3), ("N/m^3 (a weight per volume)", 1 / 9.80665)),
)
MODULUS = Rule(
    "Pa", 1e8, 1.2e12, "moduli are 0.1 GPa to 1,200 GPa, soft polymers to diamond",
    (("GPa", 1e9), ("MPa", 1e6), ("Msi", 1e6 * PSI), ("ksi", 1e3 * PSI), ("psi", PSI)),
)
STRENGTH = Rule(
    "Pa", 1e6, 5e9, "strengths are 1 MPa to 5 GPa, soft polymers to the strongest steels",
    (("MPa", 1e6), ("kPa", 1e3), ("ksi", 1e3 * PSI), ("psi", PSI)),
)
RULES: dict[str, Rule] = {
    "thickness": THICKNESS,
    "density": DENSITY,
    "youngs_modulus": MODULUS,
    "yield_strength": STRENGTH,
    "endurance_limit": STRENGTH,
    "ultimate_strength": STRENGTH,
}
"""Each checked key (a link's ``thickness``, a material's others) and its rule."""
MATERIAL_KEYS = ("density", "youngs_modulus", "yield_strength", "endurance_limit", "ultimate_strength")
MAX_SUGGESTIONS = 2
"""Units suggested at most per value (a metric one and an imperial one may both fit)."""
GYRATION_FACTOR = 100.0
"""A radius of gyration this many times the link's size is warned of: a flywheel on a short crank
reaches about 20, an inertia in kg mm^2 read as kg m^2 1000 times the true radius."""
INERTIA_SLIPS = (("kg mm^2", 1e-6), ("g mm^2", 1e-9))
"""The units CAD reports mass moments in (Inventor kg mm^2, SolidWorks g mm^2) [kg m^2 each]."""


def plausibility_warnings(materials: Mapping[str, Material], links: Mapping[str, SceneLink]) -> tuple[str, ...]:
    """One line for each value of the scene outside what real links and materials have: the
    materials' values, then each link's thickness and mass data, in the scene's order."""
    found = [
        warning
        for name, material in materials.items()
        for key in MATERIAL_KEYS
        if (warning := value_warning(f"materials.{name}.{key}", RULES[key], getattr(material, key))) is not None
    ]
    for name, link in links.items():
        found += [w for w in (_thickness_warning(link), _inertia_warning(link)) if w is not None]
    return tuple(found)


def value_warning(path: str, rule: Rule, value: float | None) -> str | None:
    """The warning for key ``path`` = ``value`` [rule.unit] outside ``rule``'s range, or None."""
    if value is None or rule.low <= value <= rule.high:
        return None
    given = f"{path} = {value:g} {rule.unit}"
    suggestions = _suggestions(value, rule.slips, lambda v: rule.low <= v <= rule.high)
    if suggestions:
        return f"{given}: did you mean {suggestions}? (real {rule.span})"
    return f"{given}: real {rule.span}; check the value and its unit"


def link_size(link: SceneLink) -> float:
    """The link's size [m]: the largest distance between two of its joints, or its outline's
    diagonal when it is drawn, whichever is larger (0 for a one-joint link without a sketch)."""
    joints = np.asarray(link.joints, float)
    span = float(np.max(np.hypot(*(joints[:, None, :] - joints[None, :, :]).transpose(2, 0, 1))))
    if link.profile is not None:
        x0, y0, x1, y1 = link.profile.outline.bounds
        span = max(span, math.hypot(x1 - x0, y1 - y0))
    return span


def _thickness_warning(link: SceneLink) -> str | None:
    if link.thickness is None:
        return None
    path = f"links.{link.name}.thickness"
    if (warning := value_warning(path, THICKNESS, link.thickness)) is not None:
        return warning
    size = link_size(link)
    if link.profile is None or link.thickness <= size:
        return None
    fits = lambda v: v <= size and THICKNESS.low <= v <= THICKNESS.high  # noqa: E731
    suggestions = _suggestions(link.thickness, THICKNESS.slips, fits)
    text = f"{path} = {link.thickness:g} m is more than the link's size, {_number(size)} m: a block, not a plate"
    return f"{text}; did you mean {suggestions}?" if suggestions else f"{text}; check the value and its unit"


def _inertia_warning(link: SceneLink) -> str | None:
    mass = link.explicit_mass
    size = link_size(link)
    if mass is None or size <= 0 or mass.inertia <= GYRATION_FACTOR**2 * size**2 * mass.mass:
        return None
    radius = math.sqrt(mass.inertia / mass.mass)
    listed = " or ".join(f"{unit} (= {_number(mass.inertia * factor)})" for unit, factor in INERTIA_SLIPS)
    return (
        f"links.{link.name}.inertia = {mass.inertia:g} kg m^2 with mass = {mass.mass:g} kg is a radius of gyration "
        f"of {_number(radius)} m, over {GYRATION_FACTOR:g} times the link's size {_number(size)} m: is it in {listed}?"
    )


def _suggestions(value: float, slips: tuple[tuple[str, float], ...], fits) -> str:
    """"6 mm = 0.006" for each unit of ``slips`` that makes ``value`` fit, at most MAX_SUGGESTIONS,
    joined by "or"; "" when none does."""
    found = [f"{value:g} {unit} = {_number(value * size)}" for unit, size in slips if fits(value * size)]
    return " or ".join(found[:MAX_SUGGESTIONS])


def _number(value: float) -> str:
    """``value`` as a reader would type it: plainly from 0.001 to 99,999 ("0.006", "7850"), else with
    an exponent that is a multiple of 3, as SI prefixes are ("250e6", "206.8e9")."""
    if value == 0 or 1e-3 <= abs(value) < 1e5:
        return f"{value:.4g}"
    exponent = 3 * math.floor(math.log10(abs(value)) / 3)
    mantissa = round(value / 10.0**exponent, 12)
    return f"{mantissa:.4g}e{exponent}"
