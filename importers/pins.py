"""Pins of a mechanism drawn assembled: where links' pin centres coincide, and who uses each.

A pin (``Joint``) is a place where the pin centres of links drawn in place (a POINT, or a circular
hole's centre: ``ImportedLink.joints``) coincide within the sketch's gap tolerance, across layers.
Everything here is in metres, sketch frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.importers.chaining import close_pairs
from linkstress.importers.neighbours import components
from linkstress.importers.sketch import ImportedLink

ANGLE_DIGITS = 9
"""Decimals of the angles [deg] written for a drawing (the crank's, a slider line's): a 1e-9 deg turn
moves a 1 km crank's pin by 2e-8 m."""
BARE_GROUND = "ground"
"""The name of the ground link when it is not drawn (then no layer is named ground)."""


@dataclass(frozen=True)
class Joint:
    """A pin: ``at`` (2,) [m] the mean of its drawn centres; ``ends`` (link name, joint index) per link."""

    at: NDArray[np.float64]
    ends: tuple[tuple[str, int], ...]

    def index(self, link: str) -> int:
        """The joint's index among ``link``'s joints (sorted by x, then y)."""
        return next(k for name, k in self.ends if name == link)


def shared_joints(links: tuple[ImportedLink, ...], tolerance: float) -> list[Joint]:
    """Every link's joints gathered into pins: centres closer than ``tolerance`` [m] (directly or through
    others) are one pin. Sorted by x, then y."""
    ends = [(link.name, k) for link in links for k in range(len(link.joints))]
    if not ends:
        return []
    points = np.vstack([link.joints for link in links if len(link.joints)])
    pairs = close_pairs(points, tolerance, "joints")
    _, pin = components(len(points), pairs)
    found = [
        Joint(points[pin == k].mean(axis=0), tuple(ends[i] for i in np.flatnonzero(pin == k)))
        for k in range(pin.max() + 1)
    ]
    return sorted(found, key=lambda j: (j.at[0], j.at[1]))


def pins_of(joints: list[Joint]) -> dict[str, list[int]]:
    """Each link's pins, as indices into ``joints``."""
    at: dict[str, list[int]] = {}
    for index, joint in enumerate(joints):
        for name, _ in joint.ends:
            at.setdefault(name, []).append(index)
    return at


def users(joint: Joint) -> list[str]:
    """The links pinned at ``joint``, one entry per end."""
    return [name for name, _ in joint.ends]


def others(joint: Joint, *excluded: str) -> list[str]:
    """The links pinned at ``joint`` but ``excluded``, each once."""
    return [name for name in dict.fromkeys(users(joint)) if name not in excluded]


def pin_distance(joints: list[Joint], i: int, j: int) -> float:
    """[m] between pins ``i`` and ``j``."""
    return float(math.hypot(*(joints[j].at - joints[i].at)))
