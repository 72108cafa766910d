"""The mechanism of a drawing of links in place, each on its own layer, and its scene.

A drawing that is exactly four-bar loops and slider-cranks, chained as ``assembly`` chains them,
is written in their form (``type = "four-bar"``, ``"slider-crank"``); any other one-DOF
mechanism of pins and sliders as one ``type = "linkage"`` (``linkage_assembly``), unless the
drawing has problems (a part left out may be a link of it). The scene
written is read back and solved at the drawn input: every drawn joint must come back
(``assembly.check_pose``).
"""

from __future__ import annotations

from pathlib import Path

from linkstress.errors import SketchError
from linkstress.importers.assembly import Assembly, NotLoops, check_pose, find_assembly
from linkstress.importers.linkage_assembly import LinkageAssembly, find_linkage
from linkstress.importers.linkage_writer import linkage_text
from linkstress.importers.pins import shared_joints
from linkstress.importers.problems import listed
from linkstress.importers.scene_writer import scene_text
from linkstress.importers.sketch import Sketch
from linkstress.scene.reader import scene_from_text


def find_mechanism(sketch: Sketch) -> Assembly | LinkageAssembly:
    """The loops of ``sketch`` when it is exactly loops linkstress chains, else its linkage; a
    SketchError saying why it is neither (links that share no joint: why it is no loops alone)."""
    try:
        return find_assembly(sketch)
    except NotLoops as loops:
        joints = shared_joints(sketch.links, sketch.gap_tolerance_m)
        if not any(len({name for name, _ in joint.ends}) > 1 for joint in joints):
            raise
        if sketch.problems:
            # A linkage may hold any of the links: what a problem left out may be one of them.
            raise SketchError(
                f"{loops}; nor is it read as a linkage of pins and sliders while the drawing has problems, which "
                f"leave parts out that may be links of it: {listed(sketch.problems)}; fix them, or leave their layers "
                "out with --exclude-layers"
            ) from None
        try:
            return find_linkage(sketch)
        except SketchError as linkage:
            raise SketchError(f"{loops}; nor is it a one-DOF linkage of pins and sliders: {linkage}") from None


def mechanism_scene(sketch: Sketch, out: Path, sketch_path: str, units: str | None,
                    hole_layers: tuple[str, ...]) -> tuple[str, list[str]]:
    """The scene text of ``sketch``'s mechanism, checked by reading it back as file ``out`` and
    solving it at the drawn input, and lines saying what was found. ``sketch_path``: the sketch
    from the scene's folder; ``units`` and ``hole_layers`` as ``import`` was given them."""
    mechanism = find_mechanism(sketch)
    if isinstance(mechanism, LinkageAssembly):
        text = linkage_text(mechanism, sketch_path, sketch.path.name, units, hole_layers)
        solved = "the linkage solved at the drawn input"
    else:
        text = scene_text(mechanism, sketch_path, sketch.path.name, units, hole_layers)
        solved = "the loop solved at the drawn crank angle"
    check_pose(scene_from_text(text, out), sketch.gap_tolerance_m, solved)
    return text, mechanism.summary()
