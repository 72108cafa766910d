"""Links without CAD: the straight bars and round-ended links that tests and textbook scenes need.

Both are drawn in their member frame: first joint at the origin, second at (spacing, 0). Round parts
are flattened with a chord (sagitta) tolerance, by default ``RELATIVE_SAGITTA`` x the link's length.
"""

from __future__ import annotations

import math

import numpy as np
from shapely.geometry import Polygon

from linkstress.geometry.curves import arc_points, circle_points
from linkstress.errors import GeometryError
from linkstress.materials import Material
from linkstress.geometry.profile import LinkProfile

RELATIVE_SAGITTA = 1e-6


def straight_bar(
    spacing: float,
    height: float,
    overhang: float,
    thickness: float,
    material: Material | None = None,
    hole_diameter: float | None = None,
    name: str = "bar",
    sagitta: float | None = None,
) -> LinkProfile:
    """A rectangular bar with joints ``spacing`` [m] apart at mid-height, ``overhang`` [m] from each end.

    With ``hole_diameter`` [m] each joint is the centre of a pin hole; without, the joints sit in
    solid material (the seed program's model of the same bar).
    """
    _require_positive(name, spacing=spacing, height=height, thickness=thickness)
    if overhang < 0:
        raise GeometryError(f"link {name!r}: overhang must be >= 0 m, got {overhang!r}")
    length = spacing + 2 * overhang
    shell = [(-overhang, -height / 2), (spacing + overhang, -height / 2),
             (spacing + overhang, height / 2), (-overhang, height / 2)]
    joints = [(0.0, 0.0), (spacing, 0.0)]
    tol = sagitta if sagitta is not None else RELATIVE_SAGITTA * length
    holes = _pin_holes(name, joints, hole_diameter, tol)
    return LinkProfile(Polygon(shell, holes), np.array(joints), thickness, material, name)


def stadium(
    spacing: float,
    width: float,
    thickness: float,
    material: Material | None = None,
    hole_diameter: float | None = None,
    name: str = "stadium",
    sagitta: float | None = None,
) -> LinkProfile:
    """A link with straight sides ``width`` [m] apart and semicircular ends centred on its two joints."""
    _require_positive(name, spacing=spacing, width=width, thickness=thickness)
    r = width / 2
    tol = sagitta if sagitta is not None else RELATIVE_SAGITTA * (spacing + width)
    right = arc_points((spacing, 0.0), r, -math.pi / 2, math.pi / 2, tol)
    left = arc_points((0.0, 0.0), r, math.pi / 2, 3 * math.pi / 2, tol)
    joints = [(0.0, 0.0), (spacing, 0.0)]
    holes = _pin_holes(name, joints, hole_diameter, tol)
    return LinkProfile(Polygon(np.vstack([right, left]), holes), np.array(joints), thickness, material, name)


def _pin_holes(name: str, joints, diameter: float | None, sagitta: float) -> list:
    if diameter is None:
        return []
    _require_positive(name, hole_diameter=diameter)
    # Clockwise rings: shapely accepts either sense, clockwise is the convention for holes.
    return [circle_points(j, diameter / 2, sagitta)[::-1] for j in joints]


def _require_positive(name: str, **values: float) -> None:
    for key, value in values.items():
        if not (math.isfinite(value) and value > 0):
            raise GeometryError(f"link {name!r}: {key} must be > 0 m, got {value!r}")
