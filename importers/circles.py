"""Which closed loops of a sketch are circles, and by which rule (drawing units).

A circular hole is a pin hole: its centre can be a joint (``sketch.HOLE_RULE``) and its diameter is
reported. CAD writes circles in several ways, each recognised by its own rule:

- ``"circle"``: one CIRCLE (or a closed bulge polyline of one circle, a CSV circle);
- ``"arcs of one circle"``: ARCs or bulges that all lie on one circle, chained into a loop;
- ``"ellipse with equal axes"``: a full ELLIPSE whose axes differ by at most ``EQUAL_AXES`` of the
  major one (a circle scaled by rounding, e.g. through a block);
- ``"regular n-gon"``: a loop of straight pieces with at least ``MIN_POLYGON_SIDES`` corners, all on
  one circle and evenly spread in angle (OpenSCAD and STL-derived drawings write circles so);
- ``"closed spline on a circle"``: a closed SPLINE whose flattened points lie on one circle.

"On one circle" is a least-squares circle with every point within ``CIRCLE_FIT`` x its radius; the
polygon's corners step around the centre by 2 pi / n, each within the angle that same tolerance
allows a corner on either side (2 ``CIRCLE_FIT`` rad). A 12-gon's own sagitta is 0.034 r, so
``CIRCLE_FIT`` = 1e-3 r separates polygons that are circles from polygons that are outlines, and
still accepts coordinates written to six significant digits.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from linkstress.importers.contours import Loop
    from linkstress.importers.flatten import Pieces

CIRCLE_FIT = 1e-3
"""Largest distance of a point from the fitted circle, as a fraction of its radius."""
EQUAL_AXES = 1e-6
"""An ellipse is a circle when its axes differ by at most this fraction of the major one."""
MIN_POLYGON_SIDES = 12
"""A regular polygon with fewer corners is a polygon (a hexagonal socket), not a circle."""

# What a flattened piece is, as far as circles go (``Pieces.shape``).
STRAIGHT = "straight"
ARC = "arc"
CIRCLE = "circle"
ELLIPSE = "ellipse with equal axes"
SPLINE = "closed spline on a circle"
CURVE = "curve"

ARCS = "arcs of one circle"

Circle = tuple[float, float, float]


def circle_of(xy: NDArray[np.float64], shapes: list[str], circle: Circle | None) -> tuple[Circle | None, str | None]:
    """The circle (cx, cy, r) of a closed loop and its rule name, or (None, None).

    ``xy``: the loop's vertices (first not repeated); ``shapes``: the shape of each piece it is made
    of (``Pieces.shape``); ``circle``: the circle all its pieces lie on when they do (chaining's rule
    on ``Pieces.circle``, which carries circles, arcs, equal-axis ellipses and circular splines)."""
    if circle is not None:
        if len(shapes) == 1 and shapes[0] in (CIRCLE, ELLIPSE, SPLINE):
            return circle, shapes[0]
        return circle, ARCS
    if all(shape == STRAIGHT for shape in shapes):
        found = regular_polygon(xy)
        if found is not None:
            return found, f"regular {len(xy)}-gon"
    return None, None


def with_circle(loop: "Loop", pieces: "Pieces") -> "Loop":
    """``loop`` with its circle and rule (:func:`circle_of`) filled in."""
    circle, rule = circle_of(loop.xy, [pieces.shape[k] for k in loop.pieces], loop.circle)
    return replace(loop, circle=circle, circle_rule=rule)


def fit_circle(xy: NDArray[np.float64]) -> tuple[Circle, float]:
    """The least-squares circle (cx, cy, r) through points ``xy`` (m, 2), and the largest distance of a
    point from it. Algebraic fit (Kasa) about the points' mean, which keeps it well conditioned far
    from the origin."""
    mean = xy.mean(axis=0)
    p = xy - mean
    a = np.column_stack([p, np.ones(len(p))])
    (u, v, w), *_ = np.linalg.lstsq(a, (p * p).sum(axis=1), rcond=None)
    centre = np.array([u / 2, v / 2])
    r = math.sqrt(max(w + centre @ centre, 0.0))
    deviation = float(np.abs(np.hypot(*(p - centre).T) - r).max())
    return (float(centre[0] + mean[0]), float(centre[1] + mean[1]), r), deviation


def on_circle(xy: NDArray[np.float64]) -> Circle | None:
    """The circle through the closed ring ``xy`` when all its points lie on one (within ``CIRCLE_FIT``)
    and it goes once around the centre, never turning back; else None."""
    if len(xy) < 3:
        return None
    circle, deviation = fit_circle(xy)
    if not (circle[2] > 0 and deviation <= CIRCLE_FIT * circle[2]):
        return None
    steps = _angle_steps(xy, circle)
    once = abs(abs(steps.sum()) - 2 * math.pi) <= 1e-6 and (np.all(steps > 0) or np.all(steps < 0))
    return circle if once else None


def regular_polygon(xy: NDArray[np.float64]) -> Circle | None:
    """The circle of a regular polygon ``xy`` (its corners, first not repeated) with at least
    ``MIN_POLYGON_SIDES`` corners, all on the circle and evenly spread in angle; else None."""
    n = len(xy)
    if n < MIN_POLYGON_SIDES:
        return None
    circle = on_circle(xy)
    if circle is None:
        return None
    steps = np.abs(_angle_steps(xy, circle))
    return circle if np.abs(steps - 2 * math.pi / n).max() <= 2 * CIRCLE_FIT else None


def _angle_steps(xy: NDArray[np.float64], circle: Circle) -> NDArray[np.float64]:
    """Signed angle [rad] from each point of the ring to the next, seen from the circle's centre."""
    angle = np.arctan2(xy[:, 1] - circle[1], xy[:, 0] - circle[0])
    return np.mod(np.roll(angle, -1) - angle + math.pi, 2 * math.pi) - math.pi
