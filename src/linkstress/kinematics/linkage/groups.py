"""Where the joint graph is split into groups: the input, then Assur groups solvable in order.

Remove the ground and the input; what remains splits into groups of zero degrees of freedom, each
solvable once the links it attaches to are known (Uicker, Pennock & Shigley, Theory of Machines and
Mechanisms, sec. 2.6; the reference's "Order"). A slider's block is no member of a group: it rides
on its slider, placed by the point (its pin) and the guide's angle once both are known.

Counting equations over the group's links S with the known links K: a pin with m_S of its joints
in S and m_K in K gives 2 m_S equations if m_K > 0, else 2 (m_S - 1); a slider whose point and
guide are in S or K (one in S) gives 1, and the input's stroke 1 more. The smallest S whose
equations equal its 3 |S| unknowns is the next group: one link held by a pin and a slider (RRP:
its point on a known line; RPR: a known point on its line), two links and three pins (RRR), four
links and six pins (a triad: a ternary link held by three binary links), or another group of at most
``MAX_GROUP`` links, solved by Newton. A set of links with more equations than unknowns locks.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import TYPE_CHECKING

from linkstress.kinematics.errors import LinkageError

if TYPE_CHECKING:
    from linkstress.kinematics.linkage.graph import Joint, LinkageGraph

MAX_GROUP = 4
"""Links solved together at most: dyads (and their slider forms) and triads."""
CLOSED_FORMS = ("crank", "RRR", "RRP", "RPR")


@dataclass(frozen=True)
class Group:
    """Links solved together. ``pairs``: (joint of a group link, joint it coincides with) for every
    pin equation (2 each); ``slides``: indices of the sliders whose point-on-line equation (1 each)
    the group holds; ``stroke``: the input slider's index when the group holds its stroke equation.
    ``riders``: the blocks placed once this group is known. ``kind`` says how it is solved:
    "crank" (the input link), "RRR", "RRP", "RPR" in closed form, "triad" or "group" by Newton."""

    links: tuple[str, ...]
    kind: str
    pairs: tuple[tuple["Joint", "Joint"], ...]
    slides: tuple[int, ...] = ()
    stroke: int | None = None
    riders: tuple[str, ...] = ()

    @property
    def label(self) -> str:
        """"RRR dyad (rod, rocker)": what messages call the group."""
        names = ", ".join(self.links)
        kinds = {"crank": "input", "RRR": "RRR dyad", "RRP": "RRP dyad", "RPR": "RPR dyad", "triad": "triad"}
        return f"{kinds.get(self.kind, 'group')} ({names})"

    @property
    def closed_form(self) -> bool:
        return self.kind in CLOSED_FORMS


def decompose(graph: LinkageGraph) -> tuple[Group, ...]:
    """The groups of ``graph`` in solving order, the input first; a ``LinkageError`` naming the
    links that float or lock when no order exists."""
    groups, stuck = _decompose(graph)
    if stuck:
        raise LinkageError(f"{graph.key}: {stuck}")
    return groups


def mobility_problem(graph: LinkageGraph) -> str:
    """Why ``graph`` cannot be solved group by group ("" when it can)."""
    return _decompose(graph)[1]


def _decompose(graph: LinkageGraph) -> tuple[tuple[Group, ...], str]:
    blocks = graph.blocks
    known = {graph.ground}
    groups: list[Group] = []
    first = _input_group(graph)
    if first is not None:
        groups.append(first)
        known.add(first.links[0])
    groups = _with_riders(graph, groups, known)
    unknown = [name for name in graph.links if name not in known and name not in blocks]
    while unknown:
        found = None
        for size in range(1, min(MAX_GROUP, len(unknown)) + 1):
            for members in combinations(unknown, size):
                pairs, slides, stroke = equations(graph, set(members), known)
                count = 2 * len(pairs) + len(slides) + (stroke is not None)
                if count > 3 * size:
                    return tuple(groups), (
                        f"links {', '.join(members)} lock: their pins and sliders set {count} conditions on their "
                        f"{3 * size} coordinates (a structure, or a redundant link): remove a link or a joint"
                    )
                if count == 3 * size:
                    found = Group(members, _kind(graph, members, pairs, slides, stroke), pairs, slides, stroke)
                    break
            if found:
                break
        if found is None:
            return tuple(groups), (
                f"links {', '.join(unknown)} float: no group of up to {MAX_GROUP} of them is held by the links before "
                "it (a missing pin or slider, or more than one input)"
            )
        groups.append(found)
        known |= set(found.links)
        groups = _with_riders(graph, groups, known)
        unknown = [name for name in unknown if name not in known]
    loose = [name for name in blocks if name not in known]
    if loose:
        return tuple(groups), f"blocks {', '.join(loose)} float"
    return tuple(groups), ""


def _input_group(graph: LinkageGraph) -> Group | None:
    if graph.input.is_stroke:
        return None
    link = graph.input.link
    pivot = next((pin for pin in graph.all_pins if any(j.link == link and j.index == graph.input.pivot for j in pin)), ())
    ground = [j for j in pivot if j.link == graph.ground]
    if not ground:
        raise LinkageError(
            f"{graph.key}.input.pivot: joint {link}:{graph.input.pivot} is not pinned to the ground {graph.ground!r}; "
            "the input turns about a pivot on the ground: add a pin [\"GROUND:i\", \"LINK:pivot\"]"
        )
    crank = next(j for j in pivot if j.link == link)
    return Group((link,), "crank", ((crank, ground[0]),))


def equations(graph: LinkageGraph, members: set[str], known: set[str]):
    """The pin pairs, slider indices and stroke (index or None) that hold links ``members`` given
    the ``known`` links (``Group``'s fields)."""
    pairs = []
    for pin in graph.all_pins:
        inside = [j for j in pin if j.link in members]
        if not inside:
            continue
        outside = [j for j in pin if j.link in known]
        anchor = outside[0] if outside else inside[0]
        pairs += [(j, anchor) for j in inside if j != anchor]
    reach = members | known
    slides = tuple(
        k for k, s in enumerate(graph.sliders)
        if s.point.link in reach and s.on in reach and (s.point.link in members or s.on in members)
    )
    stroke = graph.input.slider if graph.input.is_stroke and graph.input.slider in slides else None
    return tuple(pairs), slides, stroke


def _kind(graph: LinkageGraph, members, pairs, slides, stroke) -> str:
    if stroke is None and len(members) == 2 and len(pairs) == 3 and not slides:
        return "RRR"
    if stroke is None and len(members) == 1 and len(pairs) == 1 and len(slides) == 1:
        return "RRP" if graph.sliders[slides[0]].point.link in members else "RPR"
    if len(members) == 4 and len(pairs) == 6 and not slides:
        return "triad"
    return "group"


def _with_riders(graph: LinkageGraph, groups: list[Group], known: set[str]) -> list[Group]:
    """``groups`` with the blocks that ``known`` now places added to the last group's riders."""
    riders = []
    for block, k in graph.blocks.items():
        slider = graph.sliders[k]
        if block not in known and slider.point.link in known and slider.on in known:
            riders.append(block)
            known.add(block)
    if not riders:
        return groups
    if not groups:
        raise LinkageError(f"{graph.key}.sliders: blocks {', '.join(riders)} ride on the ground alone; a block moves with a link")
    last = groups[-1]
    return groups[:-1] + [Group(last.links, last.kind, last.pairs, last.slides, last.stroke, last.riders + tuple(riders))]
