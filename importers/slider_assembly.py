"""Slider-cranks drawn assembled: a crank pivoted on the ground, a rod pinned to it, and a slider.

A drawing has no mark for a prismatic joint, so a link whose one joint is the rod's far pin is
taken for the slider. It slides along the longer side of its outline's smallest enclosing
rectangle, through its pin, in the direction from the crank's pivot toward it; a block about as
long as it is wide (less than SLIDER_ELONGATION) gives no direction and is refused. Everything here
is in metres, sketch frame = ground frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.errors import SketchError
from linkstress.importers.pins import ANGLE_DIGITS, Joint, others, pin_distance, pins_of
from linkstress.importers.sketch import ImportedLink
from linkstress.kinematics.machine import Drive, Loop, Role

SLIDER_ELONGATION = 1.2
"""A slider block's outline must be at least this much longer than wide (its smallest enclosing
rectangle) for its longer side to give the line it slides on."""


@dataclass(frozen=True)
class SliderChain:
    """A slider-crank through the ground: crank ``p`` pivoted at joint ``jp``, rod ``k`` pinned to
    ``p`` at ``kp`` and to the slider ``s`` (a link whose one joint it is) at ``kb``."""

    p: str
    jp: int
    kp: int
    k: str
    kb: int
    s: str


def slider_chains(joints: list[Joint], ground: str, links: dict[str, ImportedLink]) -> list[SliderChain]:
    """Every crank -> rod -> slider chain from a pivot of ``ground`` to a link with one joint."""
    at = pins_of(joints)
    return [
        SliderChain(p, jp, kp, k, kb, s)
        for jp in at.get(ground, [])
        for p in others(joints[jp], ground)
        for kp in at[p] if kp != jp
        for k in others(joints[kp], ground, p)
        for kb in at[k] if kb not in (jp, kp)
        for s in others(joints[kb], ground, p, k) if len(links[s].joints) == 1
    ]



def driven_sliders(grounded: dict[tuple[str, int], Drive], chains: list[SliderChain],
                   covered: set[str]) -> list[tuple[SliderChain, Drive]]:
    """Slider-cranks whose crank is one of the ``grounded`` links (a placed loop's crank or output,
    by its link and pivot) with a rod and a slider not ``covered`` yet: each driven rigidly by that
    link, in the order found."""
    found, placed = [], set(covered)
    for chain in chains:
        drive = grounded.get((chain.p, chain.jp))
        if drive is not None and chain.k not in placed and chain.s not in placed:
            found.append((chain, drive))
            placed |= {chain.k, chain.s}
    return found


def pivot_ground(chain: SliderChain, joints: list[Joint], links: dict[str, ImportedLink], ground: str,
                  bare: list[int] | None) -> Role:
    """The ground role of a slider-crank from its crank's pivot to another ground joint (its slider
    line is written apart, so any other one serves)."""
    if bare is not None:
        pivot = bare.index(chain.jp)
        return Role(ground, (pivot, 1 if pivot == 0 else 0))
    pivot = joints[chain.jp].index(ground)
    others = [k for k in range(len(links[ground].joints)) if k != pivot]
    if not others:
        raise SketchError(
            f"the ground {ground!r} has one joint, the crank's pivot; a slider-crank's ground needs a second one "
            "(a POINT or hole anywhere on it), or leave its layer out with --exclude-layers"
        )
    return Role(ground, (pivot, others[0]))


def slider_loop(name: str, chain: SliderChain, joints: list[Joint], links: dict[str, ImportedLink], ground: Role,
                 drive: Drive | None = None) -> Loop:
    """``chain`` as a slider-crank loop on the ``ground`` role, its slider line along the slider
    block's longer side through its pin, pointing from the crank's pivot toward it, on the branch
    the drawing shows."""
    o2, a, b = (joints[j] for j in (chain.jp, chain.kp, chain.kb))
    u = slider_direction(links[chain.s], b.at - o2.at)
    ahead = float((b.at - a.at) @ u)
    if abs(ahead) <= 1e-9 * pin_distance(joints, chain.kp, chain.kb):
        raise SketchError(
            f"mechanism {name}: the drawing is at a toggle (rod {chain.k!r} square to the slider line at B "
            f"({b.at[0]:.6g}, {b.at[1]:.6g}) m), where neither branch is drawn; draw the mechanism at another crank angle"
        )
    # Rounded as the crank angle is, and the offset to 1e-12 m: a line drawn through the pivot reads 0.0.
    slider_angle = math.radians(round(math.degrees(math.atan2(u[1], u[0])), ANGLE_DIGITS))
    return Loop(
        name=name,
        kind="slider-crank",
        crank=Role(chain.p, (o2.index(chain.p), a.index(chain.p))),
        coupler=Role(chain.k, (a.index(chain.k), b.index(chain.k))),
        slider=Role(chain.s, (b.index(chain.s), b.index(chain.s))),
        ground=ground,
        branch="open" if ahead > 0 else "crossed",
        offset=round(float((b.at - o2.at) @ np.array([-u[1], u[0]])), 12),
        slider_angle=slider_angle,
        driven_by=drive,
    )


def slider_direction(slider: ImportedLink, ahead: NDArray[np.float64]) -> NDArray[np.float64]:
    """The unit direction of the longer side of ``slider``'s smallest enclosing rectangle, pointing
    along ``ahead`` (from the crank's pivot to the slider's pin) where the two are not square."""
    corners = np.asarray(slider.outline.minimum_rotated_rectangle.exterior.coords)[:3]
    sides = np.diff(corners, axis=0)
    lengths = np.hypot(*sides.T)
    if lengths.max() < SLIDER_ELONGATION * lengths.min():
        raise SketchError(
            f"link {slider.name!r} is taken for a slider (a link with one pin, at the rod's end), but its outline is "
            f"about as long as it is wide ({lengths.max():.3g} x {lengths.min():.3g} m): the line it slides on is "
            f"taken along its longer side, which must be at least {SLIDER_ELONGATION:g} x the shorter; draw the block "
            "longer along its line, or write the scene by hand (docs/scenes.md)"
        )
    u = sides[int(np.argmax(lengths))] / lengths.max()
    return -u if float(u @ ahead) < 0 else u
