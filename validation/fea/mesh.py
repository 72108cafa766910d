"""Triangle meshes of a plate region through the gmsh Python API: quadratic (P2, curved edges on the
exact curves, the default) or linear (P1, straight edges between vertices on the exact curves).

The region is a shapely Polygon with holes (a link's outline in its member frame). Its rings are
read back into circles, arcs, splines and lines first (:mod:`linkstress.validation.fea.ring_curves`),
so that the drawing's flattening does not refine the mesh. Each cut becomes a line fragmented into
the plate, so that element edges run along it and section resultants can be integrated over the
cut exactly: a station x is the vertical line x = const across the whole region, a cut segment
runs between its two ends on the outline (a member's section at any angle, stopping short of
material the infinite line would cross), and the pieces of either inside material are the cut.
The element size is ``hole_size`` at the holes, ``station_size`` along the cuts and at the
refinement points, growing linearly (by ``grading`` per unit distance) to ``size`` elsewhere. The same region and settings always give the same mesh.

gmsh physical groups: "material" (2D), "outline", "hole k" and "cut k" (1D); the mesh carries the
facets of each group.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, replace

import gmsh
import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import LinearRing, LineString, Point, Polygon
from skfem import MeshTri1, MeshTri2

from linkstress.validation.fea.cache import DiskCache, cache_key
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.mesh_checks import check_meshable
from linkstress.validation.fea.ring_curves import Arc, Circle, Line, Spline, ring_curves

TRIANGLE3, TRIANGLE6 = 2, 9
LINE2, LINE3 = 1, 8
ORDERS = (1, 2)
"""Element orders: 1 linear triangles (3 nodes), 2 quadratic isoparametric triangles (6 nodes)."""
CUT_END_TOLERANCE = 1e-3
"""How far inside material (a fraction of the segment's length) a cut segment's end may be and
still count as on the outline: the drawing's flattened outline and the exact curves gmsh meshes
differ by the flattening tolerance."""
CUT_MARGIN = 0.02
"""Each cut segment is extended past its ends by this fraction of its length (less where other
material is that close) so that it crosses the outline's exact curves and fragmenting is robust."""


@dataclass(frozen=True)
class MeshSettings:
    """Element sizes [m] and the cuts to mesh (member frame): comparison ``stations`` x [m], each
    the vertical line x = const across the region, and ``cuts``, segments ((x0, y0), (x1, y1)) [m]
    from outline to outline (ends on the outline or just outside it; holes they cross stay holes).

    ``hole_size`` defaults to size / 4 and ``station_size`` to size / 2; ``grading`` [-] is how fast
    the size grows with the distance from a hole, cut or refinement point. ``order``: 2 quadratic
    triangles (default), 1 linear triangles.
    """

    size: float
    hole_size: float | None = None
    stations: tuple[float, ...] = ()
    station_size: float | None = None
    grading: float = 0.3
    order: int = 2
    cuts: tuple[tuple[tuple[float, float], tuple[float, float]], ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "stations", tuple(float(s) for s in np.atleast_1d(self.stations)))
        if self.hole_size is None:
            object.__setattr__(self, "hole_size", self.size / 4)
        if self.station_size is None:
            object.__setattr__(self, "station_size", self.size / 2)
        for key in ("size", "hole_size", "station_size", "grading"):
            value = getattr(self, key)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise FEAError(f"mesh settings: {key} must be a finite number > 0, got {value!r}")
        if self.order not in ORDERS:
            raise FEAError(f"mesh settings: order must be 1 (linear) or 2 (quadratic triangles), got {self.order!r}")
        if not np.isfinite(self.stations).all():
            raise FEAError(f"mesh settings: stations must be finite, got {self.stations!r}")
        try:
            segments = np.asarray(self.cuts, float).reshape(-1, 2, 2)
        except (TypeError, ValueError):
            raise FEAError(f"mesh settings: cuts must be segments ((x0, y0), (x1, y1)) [m], got {self.cuts!r}") from None
        if not np.isfinite(segments).all() or (np.hypot(*(segments[:, 1] - segments[:, 0]).T) == 0).any():
            raise FEAError(f"mesh settings: cuts must be finite segments of non-zero length, got {self.cuts!r}")
        object.__setattr__(self, "cuts", tuple(tuple(map(tuple, c)) for c in segments.tolist()))

    @property
    def finest(self) -> float:
        return min(self.size, self.hole_size, self.station_size)

    def refined(self, ratio: float) -> MeshSettings:
        """The same settings with every element size divided by ``ratio``."""
        return replace(
            self,
            size=self.size / ratio,
            hole_size=self.hole_size / ratio,
            station_size=self.station_size / ratio,
        )


@dataclass(frozen=True)
class PlaneMesh:
    """A triangle mesh (quadratic isoparametric or linear, ``settings.order``) and the facets of its
    boundary parts and cuts.

    ``holes[k]``: boundary facets of the region's k-th hole (shapely interior order); ``outline``:
    facets of the outer boundary; ``cuts``: interior facets of each cut, the stations' first
    (``cuts[s]`` on x = ``stations[s]``), then the segments' (``cuts[S + k]`` on ``segments[k]``).
    """

    mesh: MeshTri1 | MeshTri2
    outline: NDArray[np.intp]
    holes: tuple[NDArray[np.intp], ...]
    cuts: tuple[NDArray[np.intp], ...]
    stations: NDArray[np.float64]
    settings: MeshSettings
    seconds: float

    @property
    def segments(self) -> NDArray[np.float64]:
        """The cut segments (C, 2, 2) [m] as asked (``settings.cuts``): ends (x, y) of each."""
        return np.asarray(self.settings.cuts, float).reshape(-1, 2, 2)

    @property
    def segment_cuts(self) -> tuple[NDArray[np.intp], ...]:
        """Interior facets of each cut segment (C,), in ``segments`` order."""
        return self.cuts[len(self.stations):]

    @property
    def n_elements(self) -> int:
        return int(self.mesh.t.shape[1])

    @property
    def order(self) -> int:
        return self.settings.order

    def arrays(self) -> dict[str, NDArray]:
        """The mesh as plain arrays (``from_arrays`` makes it again, the same to the bit)."""
        return {
            "mesh_doflocs": self.mesh.doflocs,
            "mesh_t": self.mesh.t,
            "mesh_outline": self.outline,
            "mesh_holes": np.concatenate([np.zeros(0, dtype=np.intp), *self.holes]),
            "mesh_hole_sizes": np.array([len(h) for h in self.holes], dtype=np.intp),
            "mesh_cuts": np.concatenate([np.zeros(0, dtype=np.intp), *self.cuts]),
            "mesh_cut_sizes": np.array([len(c) for c in self.cuts], dtype=np.intp),
            "mesh_stations": self.stations,
        }

    @classmethod
    def from_arrays(cls, arrays: dict[str, NDArray], settings: MeshSettings, seconds: float = 0.0) -> PlaneMesh:
        """The mesh that ``arrays`` (from ``arrays()``) hold, made with ``settings``."""
        kind = MeshTri2 if settings.order == 2 else MeshTri1
        return cls(
            mesh=kind(arrays["mesh_doflocs"], arrays["mesh_t"]),
            outline=arrays["mesh_outline"],
            holes=_split(arrays["mesh_holes"], arrays["mesh_hole_sizes"]),
            cuts=_split(arrays["mesh_cuts"], arrays["mesh_cut_sizes"]),
            stations=arrays["mesh_stations"],
            settings=settings,
            seconds=seconds,
        )


def _split(values: NDArray[np.intp], sizes: NDArray[np.intp]) -> tuple[NDArray[np.intp], ...]:
    """``values`` cut into consecutive pieces of ``sizes`` (none for no sizes)."""
    return tuple(np.split(values, np.cumsum(sizes)[:-1])) if len(sizes) else ()


MESH = "mesh"
"""The cache's kind for a meshed region (``cached_mesh_region``)."""


def mesh_key_parts(region: Polygon, settings: MeshSettings, points: NDArray[np.float64]) -> dict:
    """Everything a mesh depends on, for a cache key: the region's rings exactly, the settings and
    the refinement points."""
    return {
        "exterior": np.asarray(region.exterior.coords, float),
        "interiors": [np.asarray(ring.coords, float) for ring in region.interiors],
        "settings": {
            "size": settings.size, "hole_size": settings.hole_size, "stations": list(settings.stations),
            "station_size": settings.station_size, "grading": settings.grading, "order": settings.order,
            "cuts": [list(map(list, cut)) for cut in settings.cuts],
        },
        "points": np.asarray(points, float).reshape(-1, 2),
    }


def cached_mesh_region(
    region: Polygon,
    settings: MeshSettings,
    points: Sequence[Sequence[float]] = (),
    name: str = "region",
    cache: DiskCache | None = None,
) -> PlaneMesh:
    """``mesh_region``, from and into ``cache`` when given (gmsh gives the same mesh for the same
    input, so a stored one is what meshing again would give)."""
    if cache is None:
        return mesh_region(region, settings, points, name)
    start = time.perf_counter()
    key = cache_key(MESH, mesh_key_parts(region, settings, np.asarray(points, float)))
    stored = cache.load(MESH, key)
    if stored is not None:
        return PlaneMesh.from_arrays(stored, settings, time.perf_counter() - start)
    plane = mesh_region(region, settings, points, name)
    cache.store(MESH, key, plane.arrays())
    return plane


def mesh_region(
    region: Polygon,
    settings: MeshSettings,
    points: Sequence[Sequence[float]] = (),
    name: str = "region",
) -> PlaneMesh:
    """Mesh ``region`` [m] with triangles of ``settings.order``; refine to ``station_size`` at ``points`` (Q, 2) too.

    Raises FEAError naming ``name`` when a part is too thin for the sizes, a station does not cut
    the region's interior, a cut segment misses the material or ends inside it, or gmsh fails.
    """
    start = time.perf_counter()
    check_meshable(region, settings, name)
    stations = np.asarray(settings.stations, float)
    minx, _, maxx, _ = region.bounds
    margin = 1e-6 * (maxx - minx)
    outside = (stations <= minx + margin) | (stations >= maxx - margin)
    if outside.any():
        raise FEAError(
            f"{name}: station x = {stations[outside][0]:.6g} m is not inside the region's extent "
            f"({minx:.6g}, {maxx:.6g}) m; stations must cut through material"
        )
    if len(np.unique(stations)) != len(stations):
        raise FEAError(f"{name}: the mesh stations repeat a value: {settings.stations!r}")
    segments = np.asarray(settings.cuts, float).reshape(-1, 2, 2)
    _check_segments(region, segments, name)
    lines = np.concatenate([_station_lines(region, stations), _extended(region, segments)])
    with _gmsh_model(name):
        try:
            groups = _build_geometry(region, lines, settings, np.asarray(points, float).reshape(-1, 2))
            gmsh.model.mesh.generate(2)
            if settings.order == 2:
                gmsh.model.mesh.setOrder(2)
            mesh, facet_of = _read_mesh(settings.order)
            facets = {key: facet_of(_group_edges(tags)) for key, tags in groups.items()}
        except FEAError:
            raise
        except Exception as error:
            raise FEAError(
                f"{name}: gmsh could not mesh it ({error}); check the outline or change the sizes"
            ) from error
    return PlaneMesh(
        mesh=mesh,
        outline=facets["outline"],
        holes=tuple(facets[f"hole {k}"] for k in range(len(region.interiors))),
        cuts=tuple(facets[f"cut {k}"] for k in range(len(lines))),
        stations=stations,
        settings=settings,
        seconds=time.perf_counter() - start,
    )


def _station_lines(region: Polygon, stations: NDArray[np.float64]) -> NDArray[np.float64]:
    """The vertical lines (S, 2, 2) [m] x = ``stations``, from below the region to above it."""
    _, miny, _, maxy = region.bounds
    pad = 0.01 * (maxy - miny)
    x = np.repeat(stations[:, None], 2, axis=1)
    y = np.broadcast_to([miny - pad, maxy + pad], x.shape)
    return np.stack([x, y], axis=-1)


def _check_segments(region: Polygon, segments: NDArray[np.float64], name: str) -> None:
    """FEAError naming the cut when a segment (C, 2, 2) misses the material of ``region`` or ends
    more than CUT_END_TOLERANCE of its length inside it."""
    lines = shapely.linestrings(segments)
    length = shapely.length(lines)
    crossed = shapely.length(shapely.intersection(region, lines))
    ends = segments.reshape(-1, 2)
    depth = np.where(shapely.contains_xy(region, ends[:, 0], ends[:, 1]),
                     shapely.distance(region.boundary, shapely.points(ends)), 0.0).reshape(-1, 2)
    tolerance = CUT_END_TOLERANCE * length
    for k in np.flatnonzero((crossed <= tolerance) | (depth > tolerance[:, None]).any(axis=1)):
        (x0, y0), (x1, y1) = segments[k]
        label = f"{name}: cut {k} from ({x0:.6g}, {y0:.6g}) to ({x1:.6g}, {y1:.6g}) m"
        if crossed[k] <= tolerance[k]:
            raise FEAError(f"{label} misses the material; a cut must cross the region from outline to outline")
        x, y = segments[k, int(np.argmax(depth[k]))]
        raise FEAError(
            f"{label} ends inside the material at ({x:.6g}, {y:.6g}) m, {depth[k].max():.3g} m from the "
            "outline; a cut's ends must lie on the outline (or just outside it)"
        )


def _extended(region: Polygon, segments: NDArray[np.float64]) -> NDArray[np.float64]:
    """The segments (C, 2, 2) extended past each end by CUT_MARGIN of their length, or by half the
    gap to other material where that is nearer (the other arm of an L), so that no extension
    reaches material the cut does not cross."""
    extended = segments.copy()
    for k, segment in enumerate(segments):
        along = segment[1] - segment[0]
        length = float(np.hypot(*along))
        tolerance = CUT_END_TOLERANCE * length
        for end, sign in ((0, -1.0), (1, 1.0)):
            tip = segment[end]
            reach = sign * CUT_MARGIN * along
            hit = shapely.get_parts(region.intersection(LineString([tip, tip + reach])))
            gaps = [g for g in shapely.distance(hit, Point(tip)) if g > tolerance]
            extended[k, end] = tip + reach * min(1.0, 0.5 * min(gaps, default=np.inf) / (CUT_MARGIN * length))
    return extended


@contextmanager
def _gmsh_model(name: str) -> Iterator[None]:
    """A fresh gmsh model, silent and single-threaded; gmsh is left as it was found."""
    owner = not gmsh.isInitialized()
    if owner:
        gmsh.initialize(interruptible=False)
    gmsh.model.add(f"linkstress {name}")
    try:
        for option, value in (
            ("General.Terminal", 0),
            ("General.NumThreads", 1),
            ("Mesh.Algorithm", 6),
            ("Mesh.MeshSizeExtendFromBoundary", 0),
            ("Mesh.MeshSizeFromPoints", 0),
            ("Mesh.MeshSizeFromCurvature", 0),
        ):
            gmsh.option.setNumber(option, value)
        yield
    finally:
        gmsh.model.remove()
        if owner:
            gmsh.finalize()


def _build_geometry(region, lines, settings, points) -> dict[str, list[int]]:
    """The plate, its cut ``lines`` (K, 2, 2) and size fields in gmsh; returns the curve tags of
    each 1D group. The pieces of a line inside the material are its cut."""
    occ = gmsh.model.occ
    rings = [region.exterior, *region.interiors]
    loops = [occ.addCurveLoop(_ring_curves(ring, settings.finest)) for ring in rings]
    surface = occ.addPlaneSurface(loops)
    cut_lines = [occ.addLine(occ.addPoint(*a, 0.0), occ.addPoint(*b, 0.0)) for a, b in lines]
    cut_pieces: list[list[int]] = [[] for _ in lines]
    if cut_lines:
        _, pieces = occ.fragment([(2, surface)], [(1, c) for c in cut_lines])
        dangling = []
        for k, dimtags in enumerate(pieces[1:]):
            for _, tag in dimtags:
                inside = region.contains(Point(occ.getCenterOfMass(1, tag)[:2]))
                (cut_pieces[k] if inside else dangling).append(tag)
        occ.remove([(1, t) for t in dangling], recursive=True)
    occ.synchronize()
    _embed_loose([t for piece in cut_pieces for t in piece])
    cut_tags = {t for piece in cut_pieces for t in piece}
    boundary = [t for _, t in gmsh.model.getEntities(1) if t not in cut_tags]
    nearest = [_nearest_ring(_curve_midpoint(t), rings) for t in boundary]
    groups = {"outline": [t for t, r in zip(boundary, nearest) if r == 0]}
    groups |= {
        f"hole {k}": [t for t, r in zip(boundary, nearest) if r == k + 1] for k in range(len(rings) - 1)
    }
    groups |= {f"cut {k}": piece for k, piece in enumerate(cut_pieces)}
    gmsh.model.addPhysicalGroup(2, [t for _, t in gmsh.model.getEntities(2)], name="material")
    for key, tags in groups.items():
        gmsh.model.addPhysicalGroup(1, tags, name=key)
    hole_curves = [t for key, tags in groups.items() if key.startswith("hole") for t in tags]
    _size_fields(settings, hole_curves, sorted(cut_tags), points)
    return groups


def _embed_loose(curves: list[int]) -> None:
    """Embed in the surface that holds it each of ``curves`` that the fragment split off at the
    outline but left out of the surface's boundary: OCC does so on some outlines (an L whose ring
    runs clockwise, with holes), and the mesh would ignore the cut."""
    surfaces = [t for _, t in gmsh.model.getEntities(2)]
    bound = {t for s in surfaces for _, t in gmsh.model.getBoundary([(2, s)], combined=False, oriented=False)}
    for curve in curves:
        if curve in bound:
            continue
        x, y = _curve_midpoint(curve)
        holder = [s for s in surfaces if gmsh.model.isInside(2, s, [x, y, 0.0])]
        if not holder:
            # isInside misses some points of a surface with holes (a cut beyond a slot's end): the
            # surface nearest the midpoint holds it.
            holder = [min(surfaces, key=lambda s: _distance(gmsh.model.getClosestPoint(2, s, [x, y, 0.0])[0], x, y))]
        gmsh.model.mesh.embed(1, [curve], 2, holder[0])


def _distance(point, x: float, y: float) -> float:
    return float(np.hypot(point[0] - x, point[1] - y))


def _ring_curves(ring: LinearRing, short: float) -> list[int]:
    """gmsh OCC curves of one ring, in order."""
    occ = gmsh.model.occ
    pieces = ring_curves(np.asarray(ring.coords), short)
    if isinstance(pieces, Circle):
        return [occ.addCircle(pieces.centre[0], pieces.centre[1], 0.0, pieces.radius)]
    first = occ.addPoint(*_ends(pieces[0])[0], 0.0)
    curves, start = [], first
    for k, piece in enumerate(pieces):
        end = first if k == len(pieces) - 1 else occ.addPoint(*_ends(piece)[1], 0.0)
        if isinstance(piece, Line):
            curves.append(occ.addLine(start, end))
        elif isinstance(piece, Arc):
            curves.append(occ.addCircleArc(start, occ.addPoint(*piece.centre, 0.0), end))
        else:
            inner = [occ.addPoint(x, y, 0.0) for x, y in piece.points[1:-1]]
            curves.append(occ.addSpline([start, *inner, end]))
        start = end
    return curves


def _ends(piece) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    if isinstance(piece, Spline):
        return piece.points[0], piece.points[-1]
    return piece.start, piece.end


def _size_fields(settings: MeshSettings, holes: list[int], cuts: list[int], points) -> None:
    """Size = min over (holes, cuts, points) of fine size + grading x distance, capped at ``size``."""
    field = gmsh.model.mesh.field
    thresholds = []
    sources = [("CurvesList", holes, settings.hole_size), ("CurvesList", cuts, settings.station_size)]
    if len(points):
        point_tags = [gmsh.model.occ.addPoint(x, y, 0.0) for x, y in points]
        gmsh.model.occ.synchronize()
        sources.append(("PointsList", point_tags, settings.station_size))
    for key, tags, fine in sources:
        if not tags:
            continue
        distance = field.add("Distance")
        field.setNumbers(distance, key, tags)
        field.setNumber(distance, "Sampling", _sampling(tags, fine) if key == "CurvesList" else 1)
        threshold = field.add("Threshold")
        field.setNumber(threshold, "InField", distance)
        field.setNumber(threshold, "SizeMin", fine)
        field.setNumber(threshold, "SizeMax", settings.size)
        field.setNumber(threshold, "DistMin", 0.0)
        field.setNumber(threshold, "DistMax", max(settings.size - fine, 0.0) / settings.grading + 1e-12)
        thresholds.append(threshold)
    gmsh.option.setNumber("Mesh.MeshSizeMax", settings.size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", settings.finest / 2)
    if thresholds:
        smallest = field.add("Min")
        field.setNumbers(smallest, "FieldsList", thresholds)
        field.setAsBackgroundMesh(smallest)


def _sampling(curves: list[int], size: float) -> int:
    """Distance-field samples per curve: four per element along the longest curve."""
    longest = max(gmsh.model.occ.getMass(1, t) for t in curves)
    return int(min(max(4 * longest / size, 20), 100_000))


def _curve_midpoint(tag: int) -> tuple[float, float]:
    lo, hi = gmsh.model.getParametrizationBounds(1, tag)
    x, y, _ = gmsh.model.getValue(1, tag, [(lo[0] + hi[0]) / 2])
    return x, y


def _nearest_ring(xy: tuple[float, float], rings) -> int:
    point = Point(xy)
    return int(np.argmin([ring.distance(point) for ring in rings]))


def _group_edges(curve_tags: list[int]) -> NDArray[np.int64]:
    """gmsh node tags (E, 2) of the end vertices of the line elements on ``curve_tags``."""
    edges = [np.zeros((0, 2), dtype=np.int64)]
    for tag in curve_tags:
        types, _, nodes = gmsh.model.mesh.getElements(1, tag)
        for etype, enodes in zip(types, nodes):
            if etype in (LINE2, LINE3):
                width = 2 if etype == LINE2 else 3
                edges.append(np.asarray(enodes, dtype=np.int64).reshape(-1, width)[:, :2])
    return np.concatenate(edges)


def _read_mesh(order: int):
    """The MeshTri2 (order 2) or MeshTri1 (order 1) of the generated mesh and a map from gmsh
    vertex-tag pairs to its facet indices."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = np.asarray(coords).reshape(-1, 3)[:, :2]
    where = np.empty(int(np.max(tags)) + 1, dtype=np.int64)
    where[np.asarray(tags, dtype=np.int64)] = np.arange(len(tags))
    expected, width = (TRIANGLE6, 6) if order == 2 else (TRIANGLE3, 3)
    triangles = []
    for _, tag in gmsh.model.getEntities(2):
        types, _, nodes = gmsh.model.mesh.getElements(2, tag)
        for etype, enodes in zip(types, nodes):
            if etype != expected:
                raise FEAError(f"gmsh made elements of type {etype}, expected {width}-node triangles")
            triangles.append(np.asarray(enodes, dtype=np.int64).reshape(-1, width))
    t = np.concatenate(triangles)
    vertex_tags = np.unique(t[:, :3])
    middle_tags = np.setdiff1d(np.unique(t[:, 3:]), vertex_tags)
    listed = np.concatenate([vertex_tags, middle_tags])
    number = np.empty(int(np.max(tags)) + 1, dtype=np.int64)
    number[listed] = np.arange(len(listed))
    t = number[t]
    doflocs = xy[where[listed]]
    a, b, c = (doflocs[t[:, k]] for k in range(3))
    clockwise = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) < 0
    t[clockwise] = t[clockwise][:, [0, 2, 1, 5, 4, 3][:width]]
    mesh = (MeshTri2 if order == 2 else MeshTri1)(doflocs.T.copy(), t.T.copy())
    n_vertices = len(vertex_tags)
    keys = np.sort(mesh.facets, axis=0)
    key = keys[0].astype(np.int64) * n_vertices + keys[1]
    sorter = np.argsort(key)

    def facet_of(edges: NDArray[np.int64]) -> NDArray[np.intp]:
        ends = np.sort(number[edges], axis=1)
        wanted = ends[:, 0] * n_vertices + ends[:, 1]
        pos = sorter[np.searchsorted(key, wanted, sorter=sorter)]
        if not np.array_equal(key[pos], wanted):
            raise FEAError("a boundary edge of the gmsh mesh is not an element edge")
        return np.sort(pos)

    return mesh, facet_of
