"""The link profile: outline with holes, joints, thickness and material, and what follows from them.

Everything is in SI units and in the sketch frame unless a member frame is named: a member frame
(i, j) has its origin at joint i and +x toward joint j.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray
from shapely import affinity
from shapely.geometry import LinearRing, Point, Polygon
from shapely.validation import explain_validity

from linkstress.geometry.boundary import Boundary, oriented_rings, rounding_slack
from linkstress.geometry.bounds import BoundingFunctions, bounding_functions
from linkstress.errors import GeometryError
from linkstress.geometry.frames import MemberFrame
from linkstress.geometry.mass_properties import AreaProperties, area_properties, edge_area_properties
from linkstress.materials import Material
from linkstress.geometry.sections import SectionTable, section_table

HOLE_CENTRE_TOLERANCE = 1e-2
"""A joint in a hole must lie within this fraction of the hole's equivalent radius of its centroid."""


@dataclass(frozen=True)
class LinkProfile:
    """A plate link: ``outline`` [m] (shapely Polygon with holes), ``joints`` (n, 2) [m], ``thickness`` [m].

    Joints must lie in material or at the centre of a hole (a pin hole). ``material`` may be None
    for geometry-only work; mass properties then raise an error that says so.
    """

    outline: Polygon
    joints: NDArray[np.float64]
    thickness: float
    material: Material | None = None
    name: str = "link"
    joint_holes: tuple[int | None, ...] = field(init=False)

    def __post_init__(self) -> None:
        joints = np.array(self.joints, dtype=float, ndmin=2)
        if joints.size == 0:
            joints = joints.reshape(0, 2)
        if joints.ndim != 2 or joints.shape[1] != 2 or not np.isfinite(joints).all():
            raise GeometryError(f"link {self.name!r}: joints must be finite (x, y) pairs in metres")
        joints.setflags(write=False)
        object.__setattr__(self, "joints", joints)
        if not (math.isfinite(self.thickness) and self.thickness > 0):
            raise GeometryError(f"link {self.name!r}: thickness must be > 0 m, got {self.thickness!r}")
        _check_outline(self.name, self.outline)
        holes = tuple(_joint_hole(self.name, self.outline, k, p) for k, p in enumerate(joints))
        object.__setattr__(self, "joint_holes", holes)

    # -- mass properties ---------------------------------------------------------------------

    @cached_property
    def area_properties(self) -> AreaProperties:
        """Area [m^2], centroid [m] and centroidal second moments [m^4] per unit thickness, sketch frame."""
        return area_properties(self.outline)

    @property
    def area(self) -> float:
        return self.area_properties.area

    @property
    def centroid(self) -> NDArray[np.float64]:
        return np.array(self.area_properties.centroid)

    @property
    def polar_moment_area(self) -> float:
        """Polar second moment of area about the centroid [m^4]."""
        return self.area_properties.polar

    @property
    def density(self) -> float:
        if self.material is None:
            raise GeometryError(
                f"link {self.name!r} has no material: give it one with a density to get its mass"
            )
        return self.material.density

    @property
    def mass(self) -> float:
        """Mass [kg] = density x thickness x area."""
        return self.density * self.thickness * self.area

    @property
    def center_of_mass(self) -> NDArray[np.float64]:
        """Centre of mass [m], sketch frame (the centroid: the plate is uniform)."""
        return self.centroid

    @property
    def mass_moment_of_inertia(self) -> float:
        """Mass moment of inertia about the centre of mass, axis normal to the plane [kg m^2]."""
        return self.density * self.thickness * self.polar_moment_area

    @cached_property
    def holes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Centroids (H, 2) [m] (sketch frame) and areas (H,) [m^2] of the holes, in outline order."""
        rings = self._rings[1:]
        if not rings:
            return np.zeros((0, 2)), np.zeros(0)
        # A hole's ring runs clockwise; reversed, it bounds the hole itself.
        holes = [edge_area_properties(Boundary.from_rings([r[::-1]]), r[0]) for r in rings]
        return np.array([h.centroid for h in holes]), np.array([h.area for h in holes])

    @cached_property
    def hole_sizes(self) -> NDArray[np.float64]:
        """(H, 2) [m]: each hole's length and width, the sides of the narrowest rectangle about it
        (a round hole's diameter twice, a slot's length and width), in outline order."""
        sizes = []
        for ring in self.outline.interiors:
            corners = np.asarray(Polygon(ring).minimum_rotated_rectangle.exterior.coords)[:3]
            sizes.append(sorted(np.hypot(*np.diff(corners, axis=0).T), reverse=True))
        return np.array(sizes, float).reshape(-1, 2)

    # -- member frames -------------------------------------------------------------------------

    def frame(self, i: int = 0, j: int = 1) -> MemberFrame:
        """Member frame with origin at joint ``i`` and +x toward joint ``j``."""
        n = len(self.joints)
        for k in (i, j):
            if not -n <= k < n:
                raise GeometryError(f"link {self.name!r} has {n} joints, no joint {k}")
        return MemberFrame.through(self.joints[i], self.joints[j])

    @cached_property
    def _rings(self) -> list[NDArray[np.float64]]:
        return oriented_rings(self.outline)

    def local_outline(self, i: int = 0, j: int = 1) -> Polygon:
        """The outline [m] in member frame (i, j)."""
        f = self.frame(i, j)
        moved = affinity.translate(self.outline, -f.origin[0], -f.origin[1])
        return affinity.rotate(moved, -f.angle, origin=(0.0, 0.0), use_radians=True)

    def boundary(self, i: int = 0, j: int = 1) -> Boundary:
        """The outline's edges in member frame (i, j), computed once per frame (what every section,
        bound and region moment of that frame walks)."""
        cache = self.__dict__.setdefault("_boundaries", {})
        key = (i % len(self.joints), j % len(self.joints))
        if key not in cache:
            frame = self.frame(i, j)
            rings = [frame.to_local(r) for r in self._rings]
            cache[key] = Boundary.from_rings(rings, rounding_slack(rings))
        return cache[key]

    def bounds(self, i: int = 0, j: int = 1) -> BoundingFunctions:
        """U(x), L(x) [m] in member frame (i, j), over the outline's full x extent."""
        return bounding_functions(self.boundary(i, j))

    def sections(self, stations: ArrayLike, i: int = 0, j: int = 1) -> SectionTable:
        """Section table at ``stations`` [m] along member frame (i, j): one call for all stations."""
        return section_table(self.boundary(i, j), stations, self.thickness)

    def x_extent(self, i: int = 0, j: int = 1) -> tuple[float, float]:
        """Smallest and largest x [m] of the outline in member frame (i, j)."""
        edges = self.boundary(i, j)
        return edges.x_min, edges.x_max


def _check_outline(name: str, outline: Polygon) -> None:
    if not isinstance(outline, Polygon) or outline.is_empty:
        raise GeometryError(f"link {name!r}: the outline must be a non-empty shapely Polygon")
    coords = np.concatenate([np.asarray(r.coords) for r in [outline.exterior, *outline.interiors]])
    if not np.isfinite(coords).all():
        raise GeometryError(f"link {name!r}: the outline has non-finite coordinates")
    shell = Polygon(outline.exterior)
    if not shell.is_valid:
        raise GeometryError(
            f"link {name!r}: the outline is not a simple closed curve "
            f"({explain_validity(shell)}); redraw it without self-intersections"
        )
    if not shell.area > 0:
        raise GeometryError(f"link {name!r}: the outline encloses no area")
    for k, ring in enumerate(outline.interiors):
        hole = Polygon(ring)
        if not hole.is_valid or not hole.area > 0:
            raise GeometryError(f"link {name!r}: hole {k} is not a simple closed curve ({explain_validity(hole)})")
        if not shell.contains(hole):
            where = _first_point(shell.exterior.intersection(LinearRing(ring)), ring)
            raise GeometryError(
                f"link {name!r}: hole {k} crosses or touches the outline near ({where[0]:.6g}, {where[1]:.6g}) m; "
                "a hole must lie strictly inside the outline"
            )
    if not outline.is_valid:
        raise GeometryError(
            f"link {name!r}: holes overlap or touch each other ({explain_validity(outline)})"
        )


def _first_point(geometry, fallback: LinearRing) -> tuple[float, float]:
    if geometry.is_empty:
        return fallback.coords[0]
    return geometry.representative_point().coords[0]


def _joint_hole(name: str, outline: Polygon, k: int, p: NDArray[np.float64]) -> int | None:
    """The hole whose centre joint ``k`` sits at, None for a joint in material; else an error."""
    point = Point(p)
    if outline.covers(point):
        return None
    for h, ring in enumerate(outline.interiors):
        hole = Polygon(ring)
        if hole.contains(point):
            radius = math.sqrt(hole.area / math.pi)
            if point.distance(hole.centroid) <= HOLE_CENTRE_TOLERANCE * radius:
                return h
            c = hole.centroid
            raise GeometryError(
                f"link {name!r}: joint {k} at ({p[0]:.6g}, {p[1]:.6g}) m is inside hole {h} but not at its "
                f"centre ({c.x:.6g}, {c.y:.6g}) m; put the joint at the pin's centre"
            )
    raise GeometryError(
        f"link {name!r}: joint {k} at ({p[0]:.6g}, {p[1]:.6g}) m is outside the link's material; "
        "a joint must lie in material or at the centre of a pin hole"
    )
