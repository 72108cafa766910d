"""The [materials.NAME] and [links.NAME] tables: materials, and links from sketches or bare joints.

A link is either a sketch (``sketch = "file.dxf"``, optional ``layer`` and ``units``; read by
``linkstress.importers.read_sketch``) with a ``thickness`` and usually a ``material``, or bare
``joints = [[x, y], ...]`` in metres. Sketch paths are relative to the scene file's folder; a
sketch's unit is its own (DXF $INSUNITS) unless unitless, then the link's ``units``, else the
scene's top-level ``units`` (a unit name the importers know: "mm", "cm", "m", "in", "ft", ...).
Explicit ``mass`` [kg], ``inertia`` [kg m^2, about the centre of mass]
and ``center_of_mass`` [m, member frame] come together and take precedence over a profile's.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import GeometryError, InputError
from linkstress.inputs import check_regular
from linkstress.messages import capped
from linkstress.materials import Material, fatigue_data_problem
from linkstress.geometry.members import check_members
from linkstress.geometry.profile import LinkProfile
from linkstress.scene.keys import Table
from linkstress.scene.model import MassData
from linkstress.scene.plausibility import RULES, value_warning

MATERIAL_KEYS = (
    "density", "youngs_modulus", "poisson_ratio", "yield_strength",
    "endurance_limit", "ultimate_strength", "surface_factor", "size_factor",
)
FATIGUE_KEYS = ("endurance_limit", "ultimate_strength", "surface_factor", "size_factor")
LINK_KEYS = (
    "sketch", "layer", "units", "joints", "thickness", "material", "mass", "inertia", "center_of_mass", "members",
    "hole_layers",
)
MASS_KEYS = ("mass", "inertia", "center_of_mass")


@dataclass(frozen=True)
class LinkSource:
    """A link as read, before the machine fixes its member frame. ``center_of_mass`` is explicit."""

    name: str
    joints: NDArray[np.float64]
    thickness: float | None
    material: Material | None
    profile: LinkProfile | None
    mass: float | None
    inertia: float | None
    center_of_mass: NDArray[np.float64] | None
    sketch: Path | None
    layer: str | None
    members: tuple[tuple[int, int], ...] | None = None


def read_materials(table: Table | None) -> dict[str, Material]:
    """Each [materials.NAME]: density [kg/m^3] required; youngs_modulus [Pa], poisson_ratio [-],
    yield_strength [Pa] optional; for fatigue, endurance_limit and ultimate_strength [Pa] together,
    with optional Marin surface_factor and size_factor [-] in (0, 1.5] (default 1)."""
    materials: dict[str, Material] = {}
    if table is None:
        return materials
    for name in table.data:
        entry = table.table(name)
        entry.allow(MATERIAL_KEYS)
        entry.require("density", "the density in kg/m^3, e.g. density = 7850.0")
        density = entry.number("density", positive=True, unit="kg/m^3")
        youngs = entry.number("youngs_modulus", positive=True, unit="Pa")
        poisson = entry.number("poisson_ratio")
        if poisson is not None and not -1.0 < poisson < 0.5:
            raise entry.error("poisson_ratio", f"must lie in (-1, 0.5), got {poisson!r}")
        strength = entry.number("yield_strength", positive=True, unit="Pa")
        endurance = entry.number("endurance_limit", positive=True, unit="Pa")
        ultimate = entry.number("ultimate_strength", positive=True, unit="Pa")
        surface = entry.number("surface_factor", 1.0, positive=True)
        size = entry.number("size_factor", 1.0, positive=True)
        given = [k for k in FATIGUE_KEYS if entry.has(k)]
        if given and (endurance is None or ultimate is None):
            missing = [k for k in ("endurance_limit", "ultimate_strength") if not entry.has(k)]
            raise entry.error(
                given[0], f"fatigue needs endurance_limit and ultimate_strength together [Pa]; missing: {', '.join(missing)}"
            )
        if (problem := fatigue_data_problem(endurance, ultimate, strength, surface, size)) is not None:
            key, text = problem
            strengths = {"yield_strength": strength, "endurance_limit": endurance, "ultimate_strength": ultimate}
            slips = [w for k, v in strengths.items() if (w := value_warning(entry.key_path(k), RULES[k], v))]
            # 58 (ksi meant) as ultimate_strength puts a real endurance limit above it: say which is the slip
            raise entry.error(key, f"{text}; {slips[0]}" if slips else text)
        materials[name] = Material(name, density, youngs, poisson, strength, endurance, ultimate, surface, size)
    return materials


UNIT_FIX = 'save the sketch in {unit}, or for a unitless one set units = "{unit}"'
"""What a scene's reader does about a drawing in the wrong unit: a scene's ``units`` cannot
override the unit a sketch's header declares."""


def read_links(table: Table, materials: dict[str, Material], units: str | None,
               folder: Path) -> tuple[dict[str, LinkSource], tuple[str, ...]]:
    """Every [links.NAME], checked, and the sketches' unit warnings (``importers.unit_warnings``:
    pin holes or links of a size no mechanism has, over the links the scene takes from each);
    sketches are read once per (file, units, hole layers)."""
    sketches: dict[tuple[Path, str | None, tuple[str, ...]], object] = {}
    links: dict[str, LinkSource] = {}
    for name in table.data:
        links[name] = _read_link(table.table(name), name, materials, units, folder, sketches)
    if not links:
        raise table.error(None, "no links; add [links.NAME] tables with joints or a sketch")
    return links, _unit_warnings(links, sketches)


def _unit_warnings(links: dict[str, LinkSource], sketches) -> tuple[str, ...]:
    if not sketches:
        return ()  # bare joints: the sketch readers stay unloaded
    from linkstress.importers import unit_warnings

    found: list[str] = []
    for (path, _, _), sketch in sketches.items():
        layers = [source.layer for source in links.values() if source.sketch is not None and source.sketch.resolve() == path]
        found += [f"{path.name}: {w}" for w in unit_warnings(sketch, [sketch.link(layer) for layer in layers], UNIT_FIX)]
    return tuple(found)


def _read_link(entry: Table, name: str, materials, units, folder: Path, sketches) -> LinkSource:
    entry.allow(LINK_KEYS)
    thickness = entry.number("thickness", positive=True, unit="m")
    material = None
    if entry.has("material"):
        material_name = entry.string("material")
        if material_name not in materials:
            known = capped(sorted(materials)) or "none defined"
            raise entry.error(
                "material", f"no material named {material_name!r}; materials are: {known} (add [materials.{material_name}])"
            )
        material = materials[material_name]
    given = [k for k in MASS_KEYS if entry.has(k)]
    if given and len(given) < 3:
        missing = [k for k in MASS_KEYS if k not in given]
        raise entry.error(given[0], f"give mass, inertia and center_of_mass together; missing: {', '.join(missing)}")
    mass = entry.number("mass", positive=True, unit="kg")
    inertia = entry.number("inertia", minimum=0.0, unit="kg m^2")
    center = entry.point("center_of_mass", "m") if entry.has("center_of_mass") else None

    if entry.has("sketch") == entry.has("joints"):
        raise entry.error(None, "give either sketch = \"file.dxf\" or joints = [[x, y], ...] (metres), not both or neither")
    if entry.has("joints"):
        for key in ("layer", "units", "members", "hole_layers"):
            if entry.has(key):
                raise entry.error(key, "only for a sketch link; bare joints are in metres")
        joints = entry.points("joints", "m")
        return LinkSource(name, joints, thickness, material, None, mass, inertia, center, None, None)

    if thickness is None:
        raise entry.error("thickness", "missing; a sketch link needs its plate thickness in metres")
    sketch_units = entry.string("units") or units
    layer = entry.string("layer")
    path = folder / entry.string("sketch")
    profile = _load_profile(entry, name, path, layer, sketch_units, thickness, material, sketches, _hole_layers(entry))
    return LinkSource(
        name, np.asarray(profile.joints, float), thickness, material, profile, mass, inertia, center, path, layer,
        _read_members(entry, profile),
    )


def _read_members(entry: Table, profile: LinkProfile) -> tuple[tuple[int, int], ...] | None:
    """``members = [[i, j], ...]``: the link's arms as joint pairs that join every joint (a tree)."""
    if not entry.has("members"):
        return None
    value = entry.require("members", "a list of joint pairs")
    pairs = value if isinstance(value, list) else None
    if not pairs or not all(
        isinstance(p, list) and len(p) == 2 and all(isinstance(k, int) and not isinstance(k, bool) for k in p) for p in pairs
    ):
        raise entry.error("members", "must be a list of joint pairs [[i, j], ...] (joint indices, integers)")
    try:
        return check_members(profile, pairs)
    except GeometryError as error:
        raise entry.error("members", str(error)) from None


def _hole_layers(entry: Table) -> tuple[str, ...]:
    """``hole_layers = ["holes"]``: layers of the sketch whose outlines are holes of the links they lie in."""
    if not entry.has("hole_layers"):
        return ()
    value = entry.require("hole_layers", "a list of layer names")
    if not (isinstance(value, list) and value and all(isinstance(v, str) and v for v in value)):
        raise entry.error("hole_layers", 'must be a list of layer names, e.g. hole_layers = ["holes"]')
    return tuple(value)


def _load_profile(entry: Table, name, path: Path, layer, units, thickness, material, sketches,
                  hole_layers: tuple[str, ...] = ()) -> LinkProfile:
    from linkstress.importers import read_sketch  # ezdxf and shapely's importers: only for a scene with sketches

    try:
        found = path.exists()
        if found:
            check_regular(path, "sketch")  # a FIFO would wait for a writer, /dev/zero never end
    except OSError as error:  # e.g. a name longer than the file system allows
        raise entry.error("sketch", f"cannot use this path ({error.strerror or error}); give a sketch file's path") from None
    except InputError as error:
        raise entry.error("sketch", str(error)) from None
    if not found:
        raise entry.error("sketch", f"file {_short(str(path))!r} not found (paths are relative to the scene file's folder)")
    try:
        key = (path.resolve(), units, hole_layers)
        if key not in sketches:
            sketches[key] = read_sketch(path, units=units, override_units=False, hole_layers=hole_layers)
        return sketches[key].link(layer).profile(thickness, material, name)
    except InputError as error:
        raise entry.error("sketch", str(error)) from None


def _short(text: str) -> str:
    return text if len(text) <= 200 else text[:100] + "..." + text[-40:]


def mass_data(source: LinkSource) -> MassData | None:
    if source.mass is None:
        return None
    return MassData(source.mass, source.inertia, source.center_of_mass)
