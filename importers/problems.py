"""What is wrong with part of a sketch: a curve, a chain or a loop left out, and why.

A sketch keeps every clean outline; each problem disqualifies only the curves or loops it names
(and a link whose hole it names). Positions are in drawing units.
"""

from __future__ import annotations

from dataclasses import dataclass

MAX_LISTED = 5
"""Problems spelt out in a one-line message; the rest are counted ("and N more")."""


@dataclass(frozen=True)
class SketchProblem:
    """One thing left out of a sketch.

    ``layer``: the layer of the curves named (None for a CSV, or curves on several layers);
    ``at``: (x, y) where it is, in drawing units ``unit``; ``entities``: the curves or POINTs named
    (``describe(origin)``), each once, in order; ``problem``: what went wrong, a sentence naming position and entities;
    ``fix``: what to do.
    """

    layer: str | None
    at: tuple[float, float]
    unit: str
    entities: tuple[str, ...]
    problem: str
    fix: str

    def __post_init__(self) -> None:
        # A chain of 93 lines through one corner names each once, in order (replace() comes here too).
        object.__setattr__(self, "entities", tuple(dict.fromkeys(self.entities)))

    @property
    def text(self) -> str:
        """The problem and its fix on one line."""
        return f"{self.problem}; {self.fix}"

    def json(self) -> dict:
        """``{"layer", "at", "entities", "problem", "fix"}``, ``at`` in drawing units."""
        return {"layer": self.layer, "at": list(self.at), "entities": list(self.entities),
                "problem": self.problem, "fix": self.fix}


def listed(problems: tuple[SketchProblem, ...] | list[SketchProblem]) -> str:
    """The problems in one line: the only one's text, or the first few numbered and "and N more"."""
    if len(problems) == 1:
        return problems[0].text
    shown = "; ".join(f"({k + 1}) {p.text}" for k, p in enumerate(problems[:MAX_LISTED]))
    more = f"; and {len(problems) - MAX_LISTED} more" if len(problems) > MAX_LISTED else ""
    return f"{len(problems)} problems: {shown}{more}"
