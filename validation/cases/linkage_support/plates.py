"""Plates drawn in place for the linkage cases' sketches (a mechanism drawn assembled, every link on
its own layer), with ezdxf: rounded plates around pins (bars, bosses, ternary plates), straight
capsules and rectangles (a cylinder's barrel and rod, a ram, a collar block), slots and pin holes.

Outlines are LINE and ARC entities that the importer chains; a pin hole is a CIRCLE with a POINT at
its centre; a joint in material (a foot, a line's far end) is a POINT alone. Coordinates are in the
drawing's units. ``drawing.py`` beside this file makes and saves the drawing and draws bent links.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

Point = Sequence[float]


def rounded_plate(msp, layer: str, circles: Sequence[tuple[Point, float]]) -> None:
    """The outline of the convex hull of ``circles`` ((centre, radius), two or more): a bar with
    round ends (two circles; different radii make a boss), a ternary plate with rounded corners
    (three). Every circle must touch the hull: the centres are taken counter-clockwise about
    their mean, and each tangent runs on the outer side between neighbours."""
    centres = np.array([c for c, _ in circles], float)
    radii = np.array([r for _, r in circles], float)
    mean = centres.mean(axis=0)
    order = np.argsort(np.arctan2(*(centres - mean).T[::-1]))
    centres, radii = centres[order], radii[order]
    n = len(centres)
    normals = [_outer_normal(centres[k], radii[k], centres[(k + 1) % n], radii[(k + 1) % n]) for k in range(n)]
    attrs = {"layer": layer}
    for k in range(n):
        m = (k + 1) % n
        msp.add_line(_pt(centres[k] + radii[k] * normals[k]), _pt(centres[m] + radii[m] * normals[k]), dxfattribs=attrs)
        # About circle m the outline turns counter-clockwise from the tangent that arrives to the one that leaves.
        msp.add_arc(_pt(centres[m]), radii[m], _deg(normals[k]), _deg(normals[m]), dxfattribs=attrs)


def capsule(msp, layer: str, start: Point, end: Point, width: float, round_start: bool, round_end: bool) -> None:
    """A straight bar of ``width`` from ``start`` to ``end``, each end a half circle about its point
    (``round_*``) or square through it."""
    a, b = np.asarray(start, float), np.asarray(end, float)
    u = (b - a) / math.hypot(*(b - a))
    n = np.array([-u[1], u[0]]) * width / 2
    attrs = {"layer": layer}
    msp.add_line(_pt(a - n), _pt(b - n), dxfattribs=attrs)
    msp.add_line(_pt(b + n), _pt(a + n), dxfattribs=attrs)
    for centre, side, rounded in ((b, -n, round_end), (a, n, round_start)):
        if rounded:
            msp.add_arc(_pt(centre), width / 2, _deg(side), _deg(-side), dxfattribs=attrs)
        else:
            msp.add_line(_pt(centre + side), _pt(centre - side), dxfattribs=attrs)


def rectangle(msp, layer: str, centre: Point, direction: Point, length: float, width: float) -> None:
    """A rectangle of ``length`` along ``direction`` and ``width`` across it, about ``centre``."""
    c, d = np.asarray(centre, float), np.asarray(direction, float)
    u = d / math.hypot(*d) * length / 2
    n = np.array([-u[1], u[0]]) / length * width
    corners = [c - u - n, c + u - n, c + u + n, c - u + n]
    for k in range(4):
        msp.add_line(_pt(corners[k]), _pt(corners[(k + 1) % 4]), dxfattribs={"layer": layer})


def slot(msp, layer: str, start: Point, end: Point, width: float) -> None:
    """A slot (a hole) of ``width`` with round ends about ``start`` and ``end``."""
    capsule(msp, layer, start, end, width, round_start=True, round_end=True)


def pin_holes(msp, layer: str, centres: Sequence[Point], diameter: float) -> None:
    """A pin hole of ``diameter`` with a POINT at its centre at each of ``centres``."""
    for centre in centres:
        msp.add_circle(_pt(centre), diameter / 2, dxfattribs={"layer": layer})
    joints(msp, layer, centres)


def joints(msp, layer: str, centres: Sequence[Point]) -> None:
    """A POINT at each of ``centres``: a joint in the material (no hole)."""
    for centre in centres:
        msp.add_point(_pt(centre), dxfattribs={"layer": layer})


def _outer_normal(c1: np.ndarray, r1: float, c2: np.ndarray, r2: float) -> np.ndarray:
    """The unit normal n of the tangent from circle 1 to circle 2 on the right of c1 -> c2 (the
    outside, going counter-clockwise): n . (c2 - c1) = r1 - r2."""
    d = c2 - c1
    length = math.hypot(*d)
    if length <= abs(r1 - r2):
        raise ValueError(f"circle at {c1.tolist()} and circle at {c2.tolist()}: one holds the other, no outer tangent")
    u = d / length
    along = (r1 - r2) / length
    return along * u + math.sqrt(1 - along**2) * np.array([u[1], -u[0]])


def _deg(v) -> float:
    return math.degrees(math.atan2(v[1], v[0]))


def _pt(v) -> tuple[float, float]:
    return float(v[0]), float(v[1])
