"""Exact area properties of polygons with holes, by Green's theorem.

Each integral over the region becomes a sum over its boundary edges (exterior counter-clockwise,
holes clockwise), so the result is exact for the polygon up to rounding. Coordinates are shifted to
a reference point inside the bounding box first, so that large sketch offsets do not cancel digits.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from shapely.geometry import Polygon

from linkstress.geometry.boundary import Boundary, oriented_rings


@dataclass(frozen=True)
class AreaProperties:
    """Area properties of a plane region, per unit thickness.

    area [m^2]; centroid [m] in the polygon's frame; second moments [m^4] about the centroid with
    axes parallel to the polygon's frame: ``i_xx = int (y - yc)^2 dA``, ``i_yy = int (x - xc)^2 dA``,
    ``i_xy = int (x - xc)(y - yc) dA``; ``polar = i_xx + i_yy``.
    """

    area: float
    centroid: tuple[float, float]
    i_xx: float
    i_yy: float
    i_xy: float

    @property
    def polar(self) -> float:
        return self.i_xx + self.i_yy


def area_properties(polygon: Polygon) -> AreaProperties:
    """Area, centroid and centroidal second moments of ``polygon`` (Green's theorem, exact)."""
    minx, miny, maxx, maxy = polygon.bounds
    return edge_area_properties(Boundary.from_rings(oriented_rings(polygon)), ((minx + maxx) / 2, (miny + maxy) / 2))


def edge_area_properties(edges: Boundary, ref: tuple[float, float]) -> AreaProperties:
    """``area_properties`` of the region bounded by ``edges`` (material on their left), with the sums
    taken about ``ref`` [m], a point near the region, so that far-off regions keep their digits."""
    ref = np.asarray(ref, float)
    x0, y0 = (edges.starts - ref).T
    x1, y1 = (edges.ends - ref).T
    cross = x0 * y1 - x1 * y0
    area = cross.sum() / 2
    cx = ((x0 + x1) * cross).sum() / (6 * area)
    cy = ((y0 + y1) * cross).sum() / (6 * area)
    ixx_ref = ((y0 * y0 + y0 * y1 + y1 * y1) * cross).sum() / 12
    iyy_ref = ((x0 * x0 + x0 * x1 + x1 * x1) * cross).sum() / 12
    ixy_ref = ((x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) * cross).sum() / 24
    return AreaProperties(
        area=float(area),
        centroid=(float(cx + ref[0]), float(cy + ref[1])),
        i_xx=float(ixx_ref - area * cy * cy),
        i_yy=float(iyy_ref - area * cx * cx),
        i_xy=float(ixy_ref - area * cx * cy),
    )
