"""Regression cases: each folder holds a scene, its sketches and a stored reference with tolerances.

``reference.json``::

    {"tolerances": {"kinematics": 1e-9, "forces": 1e-7, "stresses": 1e-6, "fea": 0.02,
                    "fea_error_pct": 0.25},
     "limits": {"resultant_error_pct": 0.5, "nominal_error_pct": 3.0},
     "validation_settings": {"positions": 4, "mesh_levels": 1},
     "analysis": [... the analyze JSON's positions ...],
     "validation": {"links": {NAME: {... the validate JSON's errors and maxima ...}}}}

A value passes when it is within its group's relative tolerance of the stored one, the scale being
the largest stored magnitude of that quantity over the positions and, for a vector or a list of
points, over its components (so a value near zero, such as the y of a ram's acceleration along a
level guide, is judged against the size of the quantity, not against itself). Beam-against-FEA errors must not grow by
more than ``fea_error_pct`` percentage points, and must stay under the case's ``limits``.

``--update`` stores this run's values but keeps each stored number the run reproduces to rounding
(``rewritten``), so that the reference's diff after an intended change shows what changed.
"""

from __future__ import annotations

import json
import os
import tempfile
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from linkstress.analysis import plan_for, run_analysis
from linkstress.errors import InputError
from linkstress.report.records import position_records
from linkstress.scene import load_scene
from linkstress.validation.fea.cache import CacheSettings

SCENE_FILE = "scene.toml"
REFERENCE_FILE = "reference.json"
DEFAULT_TOLERANCES = {"kinematics": 1e-9, "forces": 1e-7, "stresses": 1e-6, "fea": 0.02, "fea_error_pct": 0.25}
DEFAULT_VALIDATION = {"positions": 4, "mesh_levels": 1}
GROUPS = {
    "angle_deg": "kinematics", "omega_rad_s": "kinematics", "alpha_rad_s2": "kinematics", "acc_G_m_s2": "kinematics",
    "forces_n": "forces", "driving_torque_nm": "forces", "driving_force_n": "forces",
    "max_von_mises_pa": "stresses", "max_at_m": "stresses", "max_von_mises_away_from_holes_pa": "stresses",
}
ERRORS = ("resultant_error_pct", "nominal_error_pct", "peak_error_pct")
FEA_VALUES = {"beam_max_von_mises_pa": "stresses", "fea_max_von_mises_pa": "fea"}
EQUILIBRIUM_LIMIT = 1e-9
ROUNDING = 1e-10
"""Relative difference (against the quantity's scale, as in the checks) within which ``--update``
keeps a stored number: ten times under the tightest tolerance, far above the 1e-13 by which the
shipped cases' FEA figures vary between runs."""


@dataclass(frozen=True)
class Check:
    """One compared quantity: ``worst`` deviation against ``allowed`` (same units), and whether it passed."""

    case: str
    what: str
    worst: float
    allowed: float
    detail: str = ""
    room: float | None = None
    """The width of the allowed band (the tolerance on a stored value); default ``allowed``."""

    @property
    def passed(self) -> bool:
        return self.worst <= self.allowed

    @property
    def closeness(self) -> float:
        """How far into its allowed band the value is: 0 at the stored value (or zero), 1 at the edge."""
        room = self.allowed if self.room is None else self.room
        if room <= 0:
            return 0.0 if self.worst <= self.allowed else float("inf")
        return (self.worst - (self.allowed - room)) / room


@dataclass
class CaseResult:
    name: str
    checks: list[Check] = field(default_factory=list)
    error: str = ""

    @property
    def passed(self) -> bool:
        return not self.error and all(c.passed for c in self.checks)


def find_cases(folder: Path) -> list[Path]:
    """Every sub-folder of ``folder`` (or ``folder`` itself) that holds a scene file."""
    if not folder.is_dir():
        raise InputError(f"cases folder {str(folder)!r} does not exist")
    if (folder / SCENE_FILE).is_file():
        return [folder]
    cases = sorted(p.parent for p in folder.glob(f"*/{SCENE_FILE}"))
    if not cases:
        raise InputError(f"{str(folder)!r} holds no case: each case is a folder with a {SCENE_FILE}")
    return cases


def read_reference(case: Path) -> dict:
    """The case's stored reference (empty when it has none); an ``InputError`` naming the case and
    file when it is not a JSON object."""
    path = case / REFERENCE_FILE
    if not path.is_file():
        return {}
    where = f"case {case.name}: {REFERENCE_FILE}"
    try:
        stored = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise InputError(f"{where}: not valid JSON ({error}); restore it from version control, or delete it and run regress --update") from None
    if not isinstance(stored, dict):
        raise InputError(f"{where}: must be a JSON object {{...}}, got {type(stored).__name__}; restore it, or delete it and run regress --update")
    return stored


def check_case(case: Path) -> None:
    """Read ``case``'s scene (its keys and sketches) before any case runs: an ``InputError``
    naming the case when it cannot be read (a sketch path that leads nowhere is bad input, not a
    regression)."""
    try:
        load_scene(case / SCENE_FILE)
    except InputError as error:
        raise InputError(f"case {case.name}: {error}") from None


def current_values(case: Path, settings: dict, cache: CacheSettings | None = None) -> dict:
    """Analysis records and, where the scene has profiled links, the beam-against-FEA errors (the
    FEA's meshes from and into the disk cache of ``cache`` when given)."""
    scene = load_scene(case / SCENE_FILE)
    plan = plan_for(scene)
    values = {"analysis": position_records(run_analysis(scene, plan))}
    if plan.validate:
        from linkstress.validation.report import validation_json
        from linkstress.validation.validate_scene import validate_scene

        result = validate_scene(scene, plan, settings["positions"], settings["mesh_levels"], cache=cache)
        links = validation_json(result)["links"]
        keep = ERRORS + tuple(FEA_VALUES) + ("error",)
        values["validation"] = {"links": {n: {k: v for k, v in r.items() if k in keep} for n, r in links.items()}}
    return values


def run_case(case: Path, update: bool = False, cache: CacheSettings | None = None) -> CaseResult:
    """Re-run ``case`` and compare it with its reference (or, with ``update``, rewrite the reference),
    with the disk ``cache`` of the FEA's meshes when given."""
    result = CaseResult(case.name)
    reference_path = case / REFERENCE_FILE
    stored = read_reference(case)
    settings = {**DEFAULT_VALIDATION, **stored.get("validation_settings", {})}
    try:
        values = current_values(case, settings, cache)
    except InputError as error:
        result.error = str(error)
        return result
    if update:
        stored = {
            "tolerances": {**DEFAULT_TOLERANCES, **stored.get("tolerances", {})},
            "limits": stored.get("limits", {}),
            "validation_settings": settings,
            **rewritten(stored, values),
        }
        from linkstress.output import write_json

        write_json(reference_path, stored)
        return result
    if not stored:
        result.error = f"no {REFERENCE_FILE}: run linkstress regress --update to record one"
        return result
    tolerances = {**DEFAULT_TOLERANCES, **stored.get("tolerances", {})}
    result.checks += compare_analysis(case.name, stored.get("analysis", []), values["analysis"], tolerances)
    result.checks += compare_validation(
        case.name, stored.get("validation", {}).get("links", {}), values.get("validation", {}).get("links", {}),
        tolerances, stored.get("limits", {}),
    )
    return result


@dataclass(frozen=True)
class PackedCase:
    """A case carried by content, for a worker that cannot see this machine's files: ``files`` maps
    each path (relative to the folder that holds them all, '/'-separated) to its bytes, ``folder``
    is the case folder's path there and ``name`` its name."""

    name: str
    folder: str
    files: dict[str, bytes]


def packed_case(case: Path) -> PackedCase:
    """``case``'s scene file, reference and every sketch its scene names (``[links.NAME] sketch``,
    relative to the scene's folder, inside it or not), by content. A scene that is not valid TOML
    travels alone: the worker reports it as the case's error, as a local run would."""
    scene = case / SCENE_FILE
    paths = [scene, *([case / REFERENCE_FILE] if (case / REFERENCE_FILE).is_file() else [])]
    try:
        links = tomllib.loads(scene.read_text(encoding="utf-8-sig")).get("links", {})
    except (UnicodeDecodeError, tomllib.TOMLDecodeError):
        links = {}
    sketches = {entry.get("sketch") for entry in links.values() if isinstance(entry, dict)} if isinstance(links, dict) else set()
    paths += sorted(case / s for s in sketches if isinstance(s, str) and (case / s).is_file())
    # Lexical, as the scene reader joins the scene's folder and a sketch's relative path; the root is
    # one level above the files' common folder, so that the case folder keeps its name (the case's).
    absolute = [Path(os.path.abspath(p)) for p in paths]
    root = Path(os.path.commonpath([p.parent for p in absolute])).parent
    return PackedCase(
        case.name,
        Path(os.path.abspath(case)).relative_to(root).as_posix(),
        {p.relative_to(root).as_posix(): p.read_bytes() for p in absolute},
    )


def run_packed_case(packed: PackedCase, update: bool = False, cache: CacheSettings | None = None) -> tuple[CaseResult, bytes | None]:
    """``run_case`` on a case carried by content, unpacked in a temporary folder that is removed
    after; with ``update`` the rewritten reference's bytes too (None when the case could not run),
    for the caller to write where the case lives."""
    with tempfile.TemporaryDirectory(prefix="linkstress-case-") as folder:
        for relative, data in packed.files.items():
            path = Path(folder, relative)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        case = Path(folder, packed.folder)
        result = run_case(case, update, cache)
        reference = (case / REFERENCE_FILE).read_bytes() if update and not result.error else None
    return result, reference


def rewritten(stored: dict, values: dict) -> dict:
    """``values`` (this run's) to store, with every stored number that this run reproduces to
    ``ROUNDING`` kept in its place (and an equilibrium mismatch kept while both are under
    ``EQUILIBRIUM_LIMIT``: they are rounding too)."""
    analysis = values["analysis"]
    before = stored.get("analysis", [])
    if len(before) == len(analysis):
        leaves: dict[tuple, list[tuple[float, float]]] = {}
        for s, c in zip(before, analysis):
            _collect((), s, c, leaves)
        scales = _scales(leaves)
        analysis = [_kept(s, c, (), scales) for s, c in zip(before, analysis)]
    result = {"analysis": analysis}
    if "validation" in values:
        links = stored.get("validation", {}).get("links", {})
        result["validation"] = {"links": {
            name: _kept(links.get(name), record, (), {}) for name, record in values["validation"]["links"].items()
        }}
    return result


def _kept(stored, current, path: tuple, scales: dict):
    """``current`` with the numbers of ``stored`` (same structure) that it reproduces; ``scales``:
    the largest stored size of each quantity over the positions, by path (default: the number's own)."""
    if isinstance(current, dict) and isinstance(stored, dict):
        return {key: _kept(stored.get(key), value, path + (key,), scales) for key, value in current.items()}
    if isinstance(current, list) and isinstance(stored, list) and len(current) == len(stored):
        return [_kept(s, c, path + (k,), scales) for k, (s, c) in enumerate(zip(stored, current))]
    if not (_is_number(stored) and _is_number(current)):
        return current
    if path and path[-1] == "equilibrium_mismatch":
        return stored if max(abs(stored), abs(current)) <= EQUILIBRIUM_LIMIT else current
    return stored if abs(current - stored) <= ROUNDING * _scale(path, stored, scales) else current


def _scale(path: tuple, stored: float, scales: dict) -> float:
    """The size against which a number's rounding is judged: its quantity's largest over the
    positions, else its own; a beam-against-FEA error in percent against 100 %, since its rounding
    is that of the two stresses whose difference it is (a 0.25 % error carries their 1e-13 x 400)."""
    if any(isinstance(part, str) and part.endswith("_pct") for part in path):
        return max(100.0, abs(stored))
    return scales.get(path, abs(stored))


def _scales(leaves: dict[tuple, list[tuple[float, float]]]) -> dict[tuple, float]:
    """The largest stored magnitude of each number's quantity over the positions, by path: the
    components of a vector (and the points of a list) share one size, that of the whole."""
    sizes: dict[tuple, float] = {}
    for path, pairs in leaves.items():
        key = _quantity(path)
        sizes[key] = max(sizes.get(key, 0.0), max(abs(s) for s, _ in pairs))
    return {path: sizes[_quantity(path)] for path in leaves}


def _quantity(path: tuple) -> tuple:
    """``path`` without its trailing list indices: the quantity a component belongs to."""
    end = len(path)
    while end and isinstance(path[end - 1], int):
        end -= 1
    return path[:end]


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def compare_analysis(case: str, stored: list, current: list, tolerances: dict) -> list[Check]:
    if len(stored) != len(current):
        return [Check(case, "positions", abs(len(current) - len(stored)), 0, "the sweep changed length")]
    flips = sum(s["feasible"] != c["feasible"] for s, c in zip(stored, current))
    checks = [Check(case, "feasibility", flips, 0, "positions whose feasibility changed")]
    leaves: dict[tuple, list[tuple[float, float]]] = {}
    for s, c in zip(stored, current):
        if s["feasible"] and c["feasible"]:
            _collect(("links",), s.get("links", {}), c.get("links", {}), leaves)
            _collect(("mechanisms",), s.get("mechanisms", {}), c.get("mechanisms", {}), leaves)
    worst: dict[str, tuple[float, str]] = {}
    scales = _scales(leaves)
    for path, pairs in leaves.items():
        group = next((GROUPS[p] for p in path if p in GROUPS), None)
        if path[-1] == "equilibrium_mismatch":
            value = max(abs(c) for _, c in pairs)
            checks.append(Check(case, f"equilibrium {'.'.join(map(str, path[1:-1]))}", value, EQUILIBRIUM_LIMIT))
            continue
        if group is None:
            continue
        scale = max(scales[path], 1e-300)
        deviation = max(abs(c - s) for s, c in pairs) / scale
        if deviation >= worst.get(group, (-1.0, ""))[0]:
            worst[group] = (deviation, ".".join(map(str, path)))
    for group, (deviation, where) in worst.items():
        checks.append(Check(case, group, deviation, tolerances[group], f"relative, worst at {where}"))
    return checks


def _collect(path: tuple, stored, current, leaves: dict) -> None:
    """Pair the numbers of ``stored`` and ``current`` by key path; a missing key is a deviation."""
    if isinstance(stored, dict):
        for key, value in stored.items():
            _collect(path + (key,), value, current.get(key) if isinstance(current, dict) else None, leaves)
    elif isinstance(stored, list):
        current = current if isinstance(current, list) and len(current) == len(stored) else [None] * len(stored)
        for k, (s, c) in enumerate(zip(stored, current)):
            _collect(path + (k,), s, c, leaves)
    elif isinstance(stored, (int, float)) and not isinstance(stored, bool):
        value = current if isinstance(current, (int, float)) and not isinstance(current, bool) else np.inf
        leaves.setdefault(path, []).append((float(stored), float(value)))


def compare_validation(case: str, stored: dict, current: dict, tolerances: dict, limits: dict) -> list[Check]:
    checks = []
    for name, reference in stored.items():
        now = current.get(name, {"error": "link not validated any more"})
        if "error" in now or "error" in reference:
            same = now.get("error") == reference.get("error")
            checks.append(Check(case, f"{name} FEA", 0 if same else 1, 0, now.get("error", "") or "now runs"))
            continue
        for key in ERRORS:
            if reference.get(key) is None:
                continue
            value = now.get(key)
            value = np.inf if value is None else value
            checks.append(Check(case, f"{name} {key}", value, reference[key] + tolerances["fea_error_pct"],
                                "percent: stored value + tolerance", tolerances["fea_error_pct"]))
            if key in limits:
                checks.append(Check(case, f"{name} {key} limit", value, limits[key], "percent: the case's limit"))
        for key, group in FEA_VALUES.items():
            deviation = abs(now[key] - reference[key]) / max(abs(reference[key]), 1e-300)
            checks.append(Check(case, f"{name} {key}", deviation, tolerances[group], "relative"))
    return checks
