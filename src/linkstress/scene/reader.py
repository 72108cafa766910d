"""Read a scene file (TOML) into a checked ``Scene``.

Top-level keys: ``title`` and ``notes`` (optional strings shown at the top of every report: what
the case is and what a reader must know to judge it), ``units`` (optional: the length unit of
unitless sketches, e.g. "mm"; the importers check the name; bare joints and every key ending ``_m``
are always metres), ``[materials.NAME]``,
``[links.NAME]``, ``[mechanisms.NAME]``, ``[motion]``, ``[loads]``, ``[analysis]``. Every error
names the file, the key's dotted path and what to do.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from types import MappingProxyType

from linkstress.errors import InputError, SceneError
from linkstress.inputs import SCENE_BYTES, read_bounded
from linkstress.scene.keys import Table
from linkstress.scene.links import mass_data, read_links, read_materials
from linkstress.scene.loads import read_analysis, read_loads
from linkstress.scene.mechanisms import read_machine
from linkstress.scene.model import Scene, SceneLink
from linkstress.scene.motion import read_actuator, read_motion
from linkstress.scene.plausibility import plausibility_warnings

TOP_KEYS = ("title", "notes", "units", "materials", "links", "mechanisms", "motion", "loads", "analysis")


def load_scene(path: str | Path) -> Scene:
    """The scene in file ``path``; a ``SceneError`` naming the key for anything wrong in it."""
    path = Path(path)
    return scene_from_text(_text(path), path)


def scene_from_text(text: str, path: Path) -> Scene:
    """The scene that ``text`` would be as file ``path`` (sketches are read relative to its folder):
    what a writer of scenes checks before writing."""
    data = _parsed(path, text)
    try:
        return _scene(Table(data, "", path.name), path)
    except SceneError:
        raise
    except InputError as error:
        raise SceneError(f"{path.name}: {error}") from None


def _frame_angle(machine, name: str) -> float:
    """A linkage's one-joint link's member-frame angle as drawn [rad] (its slider's line); 0 otherwise."""
    angles = getattr(machine, "drawn_angles", None)
    if angles is None or machine.link_frames[name][0] != machine.link_frames[name][1]:
        return 0.0
    return angles[name]


def _text(path: Path) -> str:
    """The scene file's text (a regular file of at most ``SCENE_BYTES``); a byte-order mark, as some
    Windows editors write, is dropped."""
    if path.is_dir():
        raise SceneError(f"scene file {str(path)!r} is a folder; give the .toml file inside it")
    try:
        # utf-8-sig: a byte-order mark is accepted (the CSV reader does the same)
        text = read_bounded(path, SCENE_BYTES, "scene file").decode("utf-8-sig")
    except FileNotFoundError:
        raise SceneError(f"scene file {str(path)!r} not found") from None
    except UnicodeDecodeError as error:
        raise SceneError(
            f"{path.name}: not UTF-8 text (byte {error.start}); save the scene file as UTF-8"
        ) from None
    except OSError as error:
        raise SceneError(f"{path.name}: cannot read the scene file ({error.strerror or error})") from None
    if not text.strip():
        raise SceneError(f"{path.name}: the scene file is empty; see the README's scene schema")
    return text


def _parsed(path: Path, text: str) -> dict:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise SceneError(f"{path.name}: not valid TOML: {error}") from None
    except RecursionError:
        # tomllib recurses once per nesting level of arrays and inline tables
        raise SceneError(
            f"{path.name}: arrays or inline tables nested too deep to read; a scene needs at most three levels"
        ) from None


def _scene(top: Table, path: Path) -> Scene:
    top.allow(TOP_KEYS)
    title = top.string("title", path.stem)
    notes = top.data.get("notes", [])
    if isinstance(notes, str):
        notes = [notes]
    if not isinstance(notes, list) or not all(isinstance(n, str) for n in notes):
        raise top.error("notes", "must be a string or a list of strings")
    units = top.string("units")
    materials = read_materials(top.table("materials"))
    sources, drawing_warnings = read_links(top.table("links", required=True), materials, units, path.parent)
    machine = read_machine(top.table("mechanisms", required=True), {name: s.joints for name, s in sources.items()})
    unused = [name for name in sources if name not in machine.link_frames]
    if unused:
        raise top.error(f"links.{unused[0]}", "no mechanism uses this link; name it in a [mechanisms] table or remove it")
    links = {
        name: SceneLink(
            name, s.joints, machine.link_frames[name], s.thickness, s.material, s.profile, mass_data(s),
            s.sketch, s.layer, s.members, _frame_angle(machine, name),
        )
        for name, s in sources.items()
    }
    motion_table = top.table("motion", required=True)
    motion = read_motion(motion_table, machine)
    actuator = read_actuator(motion_table, machine)
    loads = read_loads(top.table("loads"), machine, links)
    analysis = read_analysis(top.table("analysis"), links)
    return Scene(
        path, units, MappingProxyType(materials), MappingProxyType(links), machine, motion, actuator, loads,
        analysis, title, tuple(notes), drawing_warnings + plausibility_warnings(materials, links),
    )
