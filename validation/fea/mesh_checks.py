"""Can a region be meshed at the requested sizes? Thin parts and narrow ligaments, found before gmsh runs.

A plate part needs at least ``MIN_ELEMENTS_ACROSS`` quadratic elements across its width to carry
bending; with fewer, gmsh still meshes it but the stresses there mean little. Two checks:

- every ligament between a hole and the outline or another hole is at least that many
  ``hole_size`` elements wide (the mesh is at hole size there);
- the region opened by a disc of that many ``size`` elements (eroded then dilated) keeps one piece:
  a neck narrower than that disc would be cut off by the opening.
"""

from __future__ import annotations

from shapely.geometry import MultiPolygon, Polygon
from shapely.ops import nearest_points
from shapely.validation import explain_validity

from linkstress.validation.fea.errors import FEAError

MIN_ELEMENTS_ACROSS = 2


def check_meshable(region: Polygon, settings, name: str) -> None:
    """Raise FEAError naming ``name`` and the place when ``region`` is too thin for ``settings``' sizes.

    An invalid polygon (self-intersecting, holes crossing) is refused first: gmsh may never return
    on one.
    """
    if not isinstance(region, Polygon) or region.is_empty or not region.is_valid:
        reason = explain_validity(region) if isinstance(region, Polygon) else type(region).__name__
        raise FEAError(f"{name}: the region to mesh is not a valid polygon ({reason})")
    need = MIN_ELEMENTS_ACROSS * settings.hole_size
    rings = [("the outline", region.exterior)] + [(f"hole {k}", r) for k, r in enumerate(region.interiors)]
    for k, ring in enumerate(region.interiors):
        for other, other_ring in rings:
            if other == f"hole {k}" or (other.startswith("hole") and int(other.split()[1]) < k):
                continue
            width = ring.distance(other_ring)
            if width < need:
                a, _ = nearest_points(ring, other_ring)
                raise FEAError(
                    f"{name}: the material between hole {k} and {other} is {width * 1e3:.3g} mm wide near "
                    f"({a.x:.6g}, {a.y:.6g}) m, less than {MIN_ELEMENTS_ACROSS} elements of "
                    f"hole_size = {settings.hole_size * 1e3:.3g} mm; use a smaller hole_size"
                )
    shell = Polygon(region.exterior)
    radius = MIN_ELEMENTS_ACROSS * settings.size / 2 * (1 - 1e-3)
    opened = shell.buffer(-radius).buffer(radius)
    if opened.is_empty or isinstance(opened, MultiPolygon):
        lost = shell.difference(opened)
        parts = list(lost.geoms) if hasattr(lost, "geoms") else [lost]
        where = max(parts, key=lambda p: p.area).representative_point()
        raise FEAError(
            f"{name}: a part of the outline near ({where.x:.6g}, {where.y:.6g}) m is narrower than "
            f"{MIN_ELEMENTS_ACROSS} elements of size = {settings.size * 1e3:.3g} mm; use a smaller size"
        )
