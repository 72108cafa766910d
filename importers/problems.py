"""What is wrong with part of a sketch: a curve, a chain or a loop left out, and why.

A sketch keeps every clean outline; each problem disqualifies only the curves or loops it names
(and a link whose hole it names). Positions are in drawing units.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from linkstress.messages import MAX_LISTED

OPEN_CHAIN = "open_chain"
BRANCH = "branch"
SELF_CROSSING = "self_crossing"
CROSSING = "crossing"
SHARED_CUT = "shared_cut"
CUT_BY_CHAIN = "cut_by_open_chain"
WITH_ANOTHER = "left_out_with_another"
POINT_OFF_CENTRE = "point_off_hole_centre"
POINT_IN_OTHER_HOLE = "point_in_hole_not_round"
HOLE_ON_OWN_LAYER = "hole_on_own_layer"
HOLE_CROSSING_EDGE = "hole_crossing_link_edge"
HOLE_IN_NO_LINK = "hole_in_no_link"
OTHER = "other"

KINDS = {
    OPEN_CHAIN: ("open chain", "open chains"),
    BRANCH: ("place where three or more curve ends meet", "places where three or more curve ends meet"),
    SELF_CROSSING: ("outline crossing itself", "outlines crossing themselves"),
    CROSSING: ("pair of outlines crossing or touching", "pairs of outlines crossing or touching"),
    SHARED_CUT: ("pair of outlines sharing a cut", "pairs of outlines sharing a cut"),
    CUT_BY_CHAIN: ("outline cut into by an open chain", "outlines cut into by open chains"),
    WITH_ANOTHER: ("outline left out with another's problem", "outlines left out with another's problem"),
    POINT_OFF_CENTRE: ("POINT in a hole off its centre", "POINTs in holes off their centres"),
    POINT_IN_OTHER_HOLE: ("POINT in a hole that is not round", "POINTs in holes that are not round"),
    HOLE_ON_OWN_LAYER: ("likely hole or slot drawn on its own layer", "likely holes or slots drawn on their own layer"),
    HOLE_CROSSING_EDGE: ("hole crossing its link's edge", "holes crossing their link's edge"),
    HOLE_IN_NO_LINK: ("outline of a hole layer in no link", "outlines of a hole layer in no link"),
    OTHER: ("other problem", "other problems"),
}
"""Each kind of problem (``SketchProblem.kind``, the JSON's ``kind``): how one and how several are named."""


@dataclass(frozen=True)
class SketchProblem:
    """One thing left out of a sketch.

    ``layer``: the layer of the curves named (None for a CSV, or curves on several layers);
    ``at``: (x, y) where it is, in drawing units ``unit``; ``entities``: the curves or POINTs named
    (``describe(origin)``), each once, in order; ``problem``: what went wrong, a sentence naming position and entities;
    ``fix``: what to do; ``kind``: which of ``KINDS`` it is (problems are grouped by it).
    """

    layer: str | None
    at: tuple[float, float]
    unit: str
    entities: tuple[str, ...]
    problem: str
    fix: str
    kind: str = OTHER

    def __post_init__(self) -> None:
        # A chain of 93 lines through one corner names each once, in order (replace() comes here too).
        object.__setattr__(self, "entities", tuple(dict.fromkeys(self.entities)))

    @property
    def text(self) -> str:
        """The problem and its fix on one line."""
        return f"{self.problem}; {self.fix}"

    def json(self) -> dict:
        """``{"kind", "layer", "at", "entities", "problem", "fix"}``, ``at`` in drawing units."""
        return {"kind": self.kind, "layer": self.layer, "at": list(self.at), "entities": list(self.entities),
                "problem": self.problem, "fix": self.fix}


def counted(n: int, kind: str) -> str:
    """``183 open chains (...)``: a count and the kind's name, one or many."""
    one, many = KINDS.get(kind, KINDS[OTHER])
    return f"{n} {one if n == 1 else many}"


def by_kind(problems: Sequence[SketchProblem]) -> dict[str, list[SketchProblem]]:
    """The problems grouped by kind, the largest group first (then in the order first met)."""
    groups: dict[str, list[SketchProblem]] = {}
    for problem in problems:
        groups.setdefault(problem.kind, []).append(problem)
    return dict(sorted(groups.items(), key=lambda item: -len(item[1])))


def listed(problems: Sequence[SketchProblem]) -> str:
    """The problems in one line: the only one's text, or how many of each kind and the first of each
    kind numbered (of the first MAX_LISTED kinds: 183 tick marks must not hide the crossing that
    refused the part), "and N more (every one in import --json)"."""
    if len(problems) == 1:
        return problems[0].text
    groups = by_kind(problems)
    kinds = ", ".join(counted(len(group), kind) for kind, group in groups.items())
    firsts = [group[0] for group in groups.values()][:MAX_LISTED]
    shown = "; ".join(f"({k + 1}) {p.text}" for k, p in enumerate(firsts))
    more = (f"; and {len(problems) - len(firsts)} more (every one in linkstress import --json)"
            if len(problems) > len(firsts) else "")
    return f"{len(problems)} problems ({kinds}): {shown}{more}"


PAGE_FRAME = "page_frame"
SMALL_OUTLINE = "small_outline"
IN_A_HOLE = "in_a_hole"
ANNOTATION_LAYER = "annotation_layer"

SKIPPED_KINDS = {
    PAGE_FRAME: ("page frame", "page frames"),
    SMALL_OUTLINE: ("outline too small to be a part, without joints (a text glyph, a drill mark)",
                    "outlines too small to be parts, without joints (text glyphs, drill marks)"),
    IN_A_HOLE: ("outline without joints inside another link's hole (a pin, a mark)",
                "outlines without joints inside other links' holes (pins, marks)"),
    ANNOTATION_LAYER: ("layer named for annotation", "layers named for annotation"),
}
"""Each kind of :class:`Skipped` (its ``kind``, the JSON's): how one and how several are named."""


@dataclass(frozen=True)
class Skipped:
    """What a sheet draws that is not a part: read, then skipped rather than imported as a link.

    ``kind``: one of ``SKIPPED_KINDS``; ``layer``: its layer; ``at``: (x, y) in drawing units ``unit``;
    ``entities``: the curves it is made of (a frame's with the marks that touch it; a layer's first
    few); ``count``: how many outlines (a frame, a layer: one) it stands for; ``note``: what it was
    taken for, and what to do if it is a part.
    """

    kind: str
    layer: str | None
    at: tuple[float, float]
    unit: str
    entities: tuple[str, ...]
    note: str
    count: int = 1

    def json(self) -> dict:
        """``{"kind", "layer", "at", "entities", "count", "note"}``, ``at`` in drawing units."""
        return {"kind": self.kind, "layer": self.layer, "at": list(self.at), "entities": list(self.entities),
                "count": self.count, "note": self.note}


def skipped_counted(n: int, kind: str) -> str:
    """``146 outlines too small to be parts ...``: a count and the skipped kind's name, one or many."""
    one, many = SKIPPED_KINDS[kind]
    return f"{n} {one if n == 1 else many}"
