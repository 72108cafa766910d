"""Bends sharper than beam theory: where a member's centreline turns faster than its sections allow.

A curved member's sections take Winkler-Bach where the centreline's radius is under ten section
depths (``linkstress.geometry.curved_beam``). Where it is under one depth (a tight bend) or has a
corner (a dog-leg: the turn happens over no length at all) no beam theory holds: the stress at the
inner fillet is a stress concentration, as at a pin hole. Such stretches are found on the traced
centreline by how far it turns over a short window, ``BEND_WINDOW`` depths long: a circle of
radius R turns window / R there, a corner its whole angle. The stations within a section depth of
them are nominal (``linkstress.geometry.members``), as at junctions.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

SHARP_RADIUS = 1.0
"""Section depths: a centreline turning faster than once per this many depths (a radius under it) is
a bend sharper than the curved-beam range."""

BEND_WINDOW = 0.25
"""Section depths over which the centreline's turn is measured: short enough to see a bend of one
depth's radius as such (a longer window would average it with the straight on either side), long
enough to span a few of the traced centreline's points (a tenth of a width apart)."""


def sharp_arcs(path: ArrayLike, arc: ArrayLike, depth: float, clear: tuple[float, float]) -> NDArray[np.float64]:
    """Arc lengths [m] along the centreline ``path`` (K, 2) [m] (its points at arc lengths ``arc``
    (K,)) where it turns by more than ``BEND_WINDOW / SHARP_RADIUS`` rad over ``BEND_WINDOW`` x
    ``depth`` [m] of its length: its vertices there, and those of a corner. Only the stretch ``clear``
    = (s_lo, s_hi) [m] counts (clear of the joints' lugs, where the centreline runs straight into a
    pin's boss by construction)."""
    path, arc = np.asarray(path, float), np.asarray(arc, float)
    if len(path) < 3:
        return np.zeros(0)
    step = np.diff(path, axis=0)
    heading = np.unwrap(np.arctan2(step[:, 1], step[:, 0]))
    middle = (arc[1:] + arc[:-1]) / 2
    window = BEND_WINDOW * depth
    s = arc[(arc >= clear[0]) & (arc <= clear[1])]
    turn = np.interp(s + window / 2, middle, heading) - np.interp(s - window / 2, middle, heading)
    return s[np.abs(turn) > window / (SHARP_RADIUS * depth)]


def near_bends(stations: ArrayLike, depths: ArrayLike, sharp: ArrayLike) -> NDArray[np.bool_]:
    """(S,): the ``stations`` [m] (arc lengths) within their section's depth (``depths`` (S,) [m]) of
    a sharp arc length (``sharp_arcs``) along the centreline."""
    s, depth, sharp = np.asarray(stations, float), np.asarray(depths, float), np.asarray(sharp, float)
    if not len(sharp):
        return np.zeros(len(s), dtype=bool)
    return (np.abs(s[:, None] - sharp[None, :]) < depth[:, None]).any(axis=1)
