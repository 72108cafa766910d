"""A block's work: the closed-form groups placed in turn on one block of path positions.

Each step (a group with the blocks riding on it) hands its links on as soon as they are placed
(to the link motions, or to the store along the path), makes now the points of its links that
later steps read, and then forgets every point and track that no later step reads. A block's
working set is then the step at hand and a few points, and stays in a core's cache: numpy's
element loops run at about twice the rate they do over a block's every result.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.graph import Joint
from linkstress.kinematics.linkage.placing import Block, Closure, Rider


@dataclass(frozen=True)
class Step:
    """One group's placer (or None: only its riders) with its riders; ``group`` its index in
    solving order; ``links`` the links they place; ``make`` the joints of links placed so far that
    later steps read (made after this step); ``joints`` and ``tracks`` what later steps read."""

    placer: object | None
    riders: tuple[Rider, ...]
    group: int
    links: tuple[str, ...]
    make: tuple[Joint, ...]
    joints: tuple[Joint, ...]
    tracks: frozenset[str]


def plan(items: list[tuple[int, object | None, tuple[Rider, ...]]]) -> list[Step]:
    """The steps for ``items`` (group index, placer or None, riders), in order."""
    parts = [(g, placer, riders, (placer.links if placer else ()) + tuple(r.name for r in riders))
             for g, placer, riders in items]

    def reads(placer, riders):
        every = ([placer] if placer else []) + list(riders)
        return [j for p in every for j in p.reads], {name for p in every for name in p.guides}

    steps, placed = [], set()
    for k, (g, placer, riders, links) in enumerate(parts):
        placed |= set(links)
        later_joints, later_tracks = [], set()
        for _, p, r, _ in parts[k + 1:]:
            joints, tracks = reads(p, r)
            later_joints += joints
            later_tracks |= tracks
        make = tuple(dict.fromkeys(j for j in later_joints if j.link in placed))
        steps.append(Step(placer, tuple(riders), g, links, make, tuple(dict.fromkeys(later_joints)),
                          frozenset(later_tracks)))
    return steps


def run(block: Block, steps: list[Step], hand_on: Callable[[Block, tuple[str, ...]], None],
        record: Callable[[int, Closure], NDArray[np.bool_] | None]) -> NDArray[np.bool_] | None:
    """Every step on ``block``: each step's links handed on (``hand_on(block, links)``) and its
    closure recorded (``record(group, closure)``: where the group fails, or None). Where any group
    fails over the block (None: nowhere)."""
    bad = None
    for step in steps:
        closure = step.placer.place(block) if step.placer is not None else None
        for rider in step.riders:
            rider.place(block)
        if closure is not None:
            fails = record(step.group, closure)
            if fails is not None:
                bad = fails if bad is None else bad | fails
        hand_on(block, step.links)
        for joint in step.make:
            block.joint(joint)
        block.keep(step.joints, step.tracks)
    return bad
