"""Unit load cases of one link: the recovered stress of each elementary load, one factorisation.

Linear elasticity makes the stress of any combination of loads the same combination of their
stresses (one stiffness, one set of supports; docs/design.md, "FEA peaks over a sweep"). A link's load
case over a sweep is a combination, position by position, of:

- each loaded pin's cosine bearing pressure (``link_loads.bearing_loads``) for a unit force in each
  of K directions, every ``DIRECTION_STEP_DEG``: the pressure is not linear in the force's
  direction (it acts on the half of the hole the force faces), so a pin force between two basis
  directions takes those two, with the non-negative weights that reproduce the force exactly;
- a unit couple through each pin that carries one (tangential traction on its hole);
- each point force: in material its two unit components (a patch load, linear); in a hole, the
  pin's K bearing directions and a unit couple about the hole's centre for its offset;
- the d'Alembert body load rho (g - a_O - alpha k x r + omega^2 r), member frame: a uniform load per
  unit of (g - a_O)_x and (g - a_O)_y, rho (y, -x) per unit alpha and rho (x, y) per unit omega^2.

Every unit load has exactly the resultant its weight stands for, so a combination of a load case
in equilibrium is in equilibrium and its superposed field is the direct FEA of that combination:
only the bearing pressure's shape between basis directions differs from the direct solution's
(measured by ``linkstress bench`` and the tests).

Only the loads a sweep has are modelled: a pin that never carries force, a joint without a couple,
get no unit cases, and a pin gets the bearing directions its forces fall between, not all K (a
two-force bar's pins take a few either side of its axis). The disk cache keeps a link's solutions
under a key without the directions (``unit_cases_key``), with the directions each pin has: a later
run whose forces fall between those reads them, one that needs others solves the union and keeps it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.loads import LinkLoadCase
from linkstress.geometry.profile import LinkProfile
from linkstress.validation.fea.cache import DiskCache, cache_key
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.link import applied_load, link_model, link_region, support_reactions
from linkstress.validation.fea.loads import (
    bearing_loads,
    body_loads,
    patch_loads,
    point_force_hole,
    shaft_couple_loads,
)
from linkstress.validation.fea.mesh import MeshSettings, PlaneMesh, mesh_key_parts
from linkstress.validation.fea.plane_stress import PlaneStressModel, factorise, minimal_support, plane_stress_model
from linkstress.validation.fea.recovery import stress_recovery

DIRECTION_STEP_DEG = 10.0
"""Spacing of a pin's bearing directions (36 per pin). A force halfway between two of them is
carried by two cosine pressures 5 deg either side, whose shape differs from the direct one near the
edges of the loaded half; measured by ``linkstress bench`` (superposed against direct peaks)."""
BODY_TERMS = ("(g - a_O)_x", "(g - a_O)_y", "alpha", "omega^2")
UNIT_LOADS = "unit-loads"
"""The cache's kind for a link's unit-load solutions: its mesh and the recovered stress of every unit case."""


@dataclass(frozen=True)
class Bearing:
    """A pin's bearing cases, in the columns from ``first``, one per basis direction of ``indices``
    (into the K directions, ascending): on hole ``hole`` (the outline's interior index) about
    ``centre`` (2,) [m, member frame]."""

    first: int
    hole: int
    centre: NDArray[np.float64]
    indices: NDArray[np.intp]

    def weights(self, forces: NDArray[np.float64], directions: NDArray[np.float64], name: str) -> NDArray[np.float64]:
        """(len(indices), P): the weights of its cases for ``forces`` (P, 2) [N]; FEAError naming
        link ``name`` when a force falls between directions it has no case for."""
        w = bearing_weights(forces, directions)
        missing = np.setdiff1d(np.flatnonzero((w != 0).any(axis=0)), self.indices)
        if len(missing):
            raise FEAError(
                f"link {name!r}: a pin force along {np.rad2deg(directions[missing[0]]):g} deg, a bearing direction its "
                "unit load cases were not made for"
            )
        return w[:, self.indices].T


def used_directions(forces: NDArray[np.float64], directions: NDArray[np.float64]) -> NDArray[np.intp]:
    """The indices (ascending) of the basis ``directions`` that ``forces`` (P, 2) [N] fall between."""
    return np.flatnonzero((bearing_weights(forces, directions) != 0).any(axis=0))


@dataclass(frozen=True)
class UnitLoadCases:
    """The unit load cases of ``link`` meshed in ``model`` (member frame of ``frame_joints``).

    ``stress`` (nodes x 3, U) [Pa per unit weight]: the recovered nodal sigma_xx, sigma_yy, tau_xy of
    unit case u in column u, node-major (rows 3 i, 3 i + 1, 3 i + 2 are node i's components);
    ``reactions`` (U, 3): each unit case's support force x, y [N] and moment about the origin [N m];
    ``applied`` (U,) [N]: its gross nodal load (sum of |nodal force|); ``labels`` (U,) name each
    case; ``directions`` (K,) [rad] the bearing directions. ``seconds``: mesh, solve (factorise,
    the unit solves and the stress recovery), and cache (reading them) when ``cached``: read from
    the disk cache, not solved.
    """

    link: LinkProfile
    frame_joints: tuple[int, int]
    model: PlaneStressModel
    stress: NDArray[np.float64]
    reactions: NDArray[np.float64]
    applied: NDArray[np.float64]
    labels: tuple[str, ...]
    directions: NDArray[np.float64]
    pins: tuple[tuple[int, Bearing], ...]
    couples: tuple[tuple[int, int], ...]
    point_forces: tuple[tuple[int, Bearing | None, int], ...]
    body: int
    seconds: dict[str, float]
    cached: bool = False

    @property
    def count(self) -> int:
        return self.stress.shape[1]

    @property
    def nodes(self) -> NDArray[np.float64]:
        """Positions (nodes, 2) [m, member frame] of the nodes the stresses are recovered at."""
        return self.model.scalar.doflocs.T

    @property
    def dofs(self) -> int:
        return self.model.n_dofs

    @property
    def element_dofs(self) -> NDArray[np.intp]:
        """(nodes per element, elements): the nodes of each element, for drawing the field."""
        return self.model.scalar.element_dofs

    def weights(self, loads: LinkLoadCase) -> NDArray[np.float64]:
        """(U, P): the weight of each unit case at each position of ``loads`` (the same link, the
        same load terms: a term the unit cases lack must be zero in ``loads``, else FEAError)."""
        check_same_terms(self, loads)
        w = np.zeros((self.count, loads.n_positions))
        name = self.link.name
        for joint, bearing in self.pins:
            w[bearing.first:bearing.first + len(bearing.indices)] = bearing.weights(
                loads.pin_forces[:, joint], self.directions, name)
        for joint, column in self.couples:
            w[column] = loads.joint_couples[:, joint]
        for index, bearing, column in self.point_forces:
            point = loads.point_forces[index]
            force = np.asarray(point.force, float)
            if bearing is None:
                w[column:column + 2] = force.T
                continue
            w[bearing.first:bearing.first + len(bearing.indices)] = bearing.weights(force, self.directions, name)
            offset = np.asarray(point.at, float) - bearing.centre
            w[column] = offset[0] * force[:, 1] - offset[1] * force[:, 0]
        free = loads.gravity - loads.origin_acceleration
        w[self.body:self.body + 4] = [free[:, 0], free[:, 1], loads.alpha, loads.omega**2]
        return w


def bearing_weights(forces: NDArray[np.float64], directions: NDArray[np.float64]) -> NDArray[np.float64]:
    """(P, K): weights on K evenly spaced unit ``directions`` [rad] that sum to each force (P, 2) [N]
    exactly, non-zero only on the two directions either side of it (both >= 0)."""
    forces = np.asarray(forces, float).reshape(-1, 2)
    k = len(directions)
    step = 2 * np.pi / k
    angle = np.mod(np.arctan2(forces[:, 1], forces[:, 0]) - directions[0], 2 * np.pi)
    below = np.minimum(np.floor(angle / step).astype(np.intp), k - 1)
    offset = angle - below * step
    magnitude = np.hypot(forces[:, 0], forces[:, 1])
    # F = a d_k + b d_k+1 with d the unit vectors: Cramer's rule on the 2x2 system.
    a = magnitude * np.sin(step - offset) / np.sin(step)
    b = magnitude * np.sin(offset) / np.sin(step)
    w = np.zeros((len(forces), k))
    rows = np.arange(len(forces))
    w[rows, below] = a
    w[rows, (below + 1) % k] = b
    return w


@dataclass(frozen=True)
class UnitCaseGroup:
    """Consecutive unit cases of one kind: ``bearing`` (one per direction of ``indices``, on ``hole``
    about ``centre``), ``couple`` (a unit couple on ``hole`` about ``centre``), ``patch`` (unit x and
    y point forces at ``centre``, in material) or ``body`` (the four body-load terms); their ``labels``."""

    kind: str
    hole: int | None
    centre: tuple[float, float] | None
    labels: tuple[str, ...]
    indices: tuple[int, ...] = ()

    def key(self) -> dict:
        """What determines the group's solutions but its bearing directions (which the cache entry
        holds: a pin's entry serves every subset of the directions it has)."""
        cases = "directions" if self.kind == "bearing" else len(self.labels)
        return {"kind": self.kind, "hole": self.hole, "centre": self.centre, "cases": cases}


@dataclass(frozen=True)
class UnitCaseLayout:
    """Which unit cases a link's load case needs, in column order, found from the link and the loads
    alone (no mesh): ``groups``, and where the weights go (``UnitLoadCases``' pins, couples,
    point_forces and body)."""

    directions: NDArray[np.float64]
    groups: tuple[UnitCaseGroup, ...]
    pins: tuple[tuple[int, Bearing], ...]
    couples: tuple[tuple[int, int], ...]
    point_forces: tuple[tuple[int, Bearing | None, int], ...]
    body: int

    @property
    def labels(self) -> tuple[str, ...]:
        return tuple(label for group in self.groups for label in group.labels)


def unit_case_layout(link: LinkProfile, loads: LinkLoadCase, step_deg: float = DIRECTION_STEP_DEG,
                     wider: dict[int, NDArray[np.intp]] | None = None) -> UnitCaseLayout:
    """The unit cases of the load terms ``loads`` has over its sweep (see the module's docstring):
    each pin's bearing directions those its forces fall between, and those of ``wider`` (per
    bearing group, in order: the directions a cache entry has).

    Raises FEAError naming the link for a loaded joint without a hole.
    """
    joints = link.frame(*loads.frame_joints).to_local(link.joints)
    directions = np.deg2rad(np.arange(0.0, 360.0, step_deg))
    groups: list[UnitCaseGroup] = []

    def add(kind: str, hole: int | None, centre, labels: list[str], indices=()) -> int:
        first = sum(len(g.labels) for g in groups)
        point = None if centre is None else (float(centre[0]), float(centre[1]))
        groups.append(UnitCaseGroup(kind, hole, point, tuple(labels), tuple(int(k) for k in indices)))
        return first

    def bearing(label: str, hole: int, centre: NDArray[np.float64], forces: NDArray[np.float64]) -> Bearing:
        indices = used_directions(forces, directions)
        extra = (wider or {}).get(sum(g.kind == "bearing" for g in groups))
        if extra is not None:
            indices = np.union1d(indices, extra)
        names = [f"{label}: unit bearing force at {np.rad2deg(directions[k]):g} deg" for k in indices]
        return Bearing(add("bearing", hole, centre, names, indices), hole, np.asarray(centre, float), indices)

    pins, couples = [], []
    for j, hole in enumerate(link.joint_holes):
        pin, couple = loads.pin_forces[:, j], loads.joint_couples[:, j]
        loaded, turned = bool(np.any(pin != 0)), bool(np.any(couple != 0))
        if (loaded or turned) and hole is None:
            raise FEAError(
                f"link {link.name!r}: joint {j} carries a pin force or couple but has no hole; the FEA applies "
                "joint loads on a pin hole: draw the hole (a circle centred on the joint)"
            )
        if loaded:
            pins.append((j, bearing(f"pin {j}", hole, joints[j], pin)))
        if turned:
            couples.append((j, add("couple", hole, joints[j], [f"pin {j}: unit couple"])))
    points = []
    for index, point in enumerate(loads.point_forces):
        pin = point_force_hole(link, loads.frame_joints, point.at)
        label = f"point force {index} at {np.round(np.asarray(point.at, float), 6).tolist()} m"
        if pin is None:
            points.append((index, None, add("patch", None, point.at, [f"{label}: unit x", f"{label}: unit y"])))
            continue
        hole, centre = pin
        cases = bearing(label, hole, centre, np.asarray(point.force, float))
        points.append((index, cases, add("couple", hole, centre, [f"{label}: unit couple"])))
    body = add("body", None, None, [f"body: unit {t}" for t in BODY_TERMS])
    return UnitCaseLayout(directions, tuple(groups), tuple(pins), tuple(couples), tuple(points), body)


def unit_load_cases(
    link: LinkProfile,
    loads: LinkLoadCase,
    mesh: MeshSettings,
    step_deg: float = DIRECTION_STEP_DEG,
    cache: DiskCache | None = None,
) -> UnitLoadCases:
    """Mesh ``link`` (member frame of ``loads.frame_joints``), factorise once and solve the unit
    cases of the load terms ``loads`` has over its sweep (see the module's docstring); from and
    into ``cache`` when given (its key: ``unit_cases_key``).

    Raises FEAError naming the link for a loaded joint without a hole, a mesh or solver failure.
    """
    start = time.perf_counter()
    region = link_region(link, loads, mesh)
    layout = unit_case_layout(link, loads, step_deg)
    key = None
    if cache is not None:
        key = unit_cases_key(link, loads.frame_joints, region, layout)
        stored = cache.load(UNIT_LOADS, key)
        if stored is not None:
            held = stored_directions(stored)
            wider = unit_case_layout(link, loads, step_deg, held)
            if all(np.array_equal(g.indices, w.indices) for g, w in zip(wider.groups, _held_layout(wider, held))):
                return _from_entry(link, loads, mesh, wider, stored, time.perf_counter() - start)
            # The entry lacks directions this sweep needs: solve those it has and these, and keep them all.
            layout = wider
    model = link_model(link, loads, mesh, cache)
    meshed = time.perf_counter()
    forces = np.hstack([group_loads(model, group, layout.directions, link.density, loads.frame_joints, mesh)
                        for group in layout.groups])
    fixed, _ = minimal_support(model)
    try:
        displacement, support = factorise(model, fixed).solve(forces)
    except FEAError as error:
        raise FEAError(f"link {link.name!r}: {error}") from None
    nodal = stress_recovery(model).nodal_stress(displacement)  # (U, nodes, 3)
    stress = np.ascontiguousarray(nodal.reshape(len(layout.labels), -1).T)
    cases = UnitLoadCases(
        link=link,
        frame_joints=tuple(loads.frame_joints),
        model=model,
        stress=stress,
        reactions=support_reactions(model, fixed, support),
        applied=applied_load(model, forces),
        labels=layout.labels,
        directions=layout.directions,
        pins=layout.pins,
        couples=layout.couples,
        point_forces=layout.point_forces,
        body=layout.body,
        seconds={"mesh": meshed - start, "solve": time.perf_counter() - meshed},
    )
    if cache is not None:
        directions = {f"bearing {k}": np.asarray(g.indices, np.intp)
                      for k, g in enumerate(g for g in layout.groups if g.kind == "bearing")}
        cache.store(UNIT_LOADS, key, {**model.plane.arrays(), "stress": cases.stress, "reactions": cases.reactions,
                                       "applied": cases.applied, **directions})
    return cases


def stored_directions(stored: dict[str, NDArray]) -> dict[int, NDArray[np.intp]]:
    """Per bearing group (in order), the directions a cache entry holds solutions for."""
    return {int(key.split()[1]): np.asarray(value, np.intp) for key, value in stored.items() if key.startswith("bearing ")}


def _held_layout(layout: UnitCaseLayout, held: dict[int, NDArray[np.intp]]) -> list[UnitCaseGroup]:
    """``layout``'s groups with each bearing group's directions those the entry ``held`` has."""
    out, k = [], 0
    for group in layout.groups:
        if group.kind == "bearing":
            out.append(UnitCaseGroup(group.kind, group.hole, group.centre, group.labels,
                                     tuple(int(i) for i in held.get(k, ()))))
            k += 1
        else:
            out.append(group)
    return out


def unit_cases_key(link: LinkProfile, frame_joints: tuple[int, int], region: tuple, layout: UnitCaseLayout) -> str:
    """The cache key of a link's unit-load solutions: everything that determines them (its
    ``region`` from ``link_region``: the outline and holes exactly, the mesh settings, the
    refinement points; the elastic constants, density and thickness; each unit case's kind, hole and
    centre; the frame)."""
    material = link.material
    return cache_key(UNIT_LOADS, {
        "mesh": mesh_key_parts(*region),
        "youngs_modulus": material.youngs_modulus,
        "poisson_ratio": material.poisson_ratio,
        "density": link.density,
        "thickness": link.thickness,
        "frame_joints": list(frame_joints),
        "directions": layout.directions,
        "groups": [group.key() for group in layout.groups],
    })


def _from_entry(link, loads, mesh, layout, stored, seconds) -> UnitLoadCases:
    """The unit load cases from a cache entry: the model rebuilt on the stored mesh (no stiffness)."""
    material = link.material
    model = plane_stress_model(
        PlaneMesh.from_arrays(stored, mesh), material.youngs_modulus, material.poisson_ratio, link.thickness
    )
    return UnitLoadCases(
        link=link,
        frame_joints=tuple(loads.frame_joints),
        model=model,
        stress=stored["stress"],
        reactions=stored["reactions"],
        applied=stored["applied"],
        labels=layout.labels,
        directions=layout.directions,
        pins=layout.pins,
        couples=layout.couples,
        point_forces=layout.point_forces,
        body=layout.body,
        seconds={"mesh": 0.0, "solve": 0.0, "cache": seconds},
        cached=True,
    )


def group_loads(model: PlaneStressModel, group: UnitCaseGroup, directions: NDArray[np.float64], density: float,
                 frame_joints: tuple[int, int], mesh: MeshSettings) -> NDArray[np.float64]:
    """The nodal forces (dofs, cases) of one group of unit cases."""
    holes = model.plane.holes
    if group.kind == "bearing":
        chosen = directions[list(group.indices)]
        unit = np.column_stack([np.cos(chosen), np.sin(chosen)])
        return bearing_loads(model, holes[group.hole], np.asarray(group.centre), unit)
    if group.kind == "couple":
        return shaft_couple_loads(model, holes[group.hole], np.asarray(group.centre), np.ones(1))
    if group.kind == "patch":
        return patch_loads(model, np.asarray(group.centre), np.eye(2), mesh.station_size)
    return _unit_body_loads(model, frame_joints, density)


def _unit_body_loads(model: PlaneStressModel, frame_joints: tuple[int, int], density: float) -> NDArray[np.float64]:
    """The four body-load unit cases (dofs, 4): per unit (g - a_O)_x, (g - a_O)_y, alpha and omega^2."""
    basis = LinkLoadCase(
        frame_joints,
        pin_forces=np.zeros((4, 0, 2)),
        joint_couples=np.zeros((4, 0)),
        omega=np.array([0.0, 0.0, 0.0, 1.0]),
        alpha=np.array([0.0, 0.0, 1.0, 0.0]),
        origin_acceleration=np.zeros((4, 2)),
        gravity=np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0]]),
    )
    return body_loads(model, basis, density)


def check_same_terms(cases: UnitLoadCases, loads: LinkLoadCase) -> None:
    """FEAError when ``loads`` has a load the unit cases of ``cases`` were not made for."""
    name = cases.link.name
    if tuple(loads.frame_joints) != cases.frame_joints:
        raise FEAError(f"link {name!r}: load case in the frame of joints {loads.frame_joints}, unit cases in {cases.frame_joints}")
    pinned = {j for j, _ in cases.pins}
    turned = {j for j, _ in cases.couples}
    for j in range(loads.pin_forces.shape[1]):
        if j not in pinned and np.any(loads.pin_forces[:, j] != 0):
            raise FEAError(f"link {name!r}: joint {j} carries a pin force its unit load cases were not made for")
        if j not in turned and np.any(loads.joint_couples[:, j] != 0):
            raise FEAError(f"link {name!r}: joint {j} carries a couple its unit load cases were not made for")
    if loads.contacts:
        raise FEAError(f"link {name!r}: a slider's block slides along it, and unit load cases stand at fixed points "
                       "(its FEA peaks are solved position by position: validation.direct_peaks)")
    if len(loads.point_forces) != len(cases.point_forces):
        raise FEAError(
            f"link {name!r}: {len(loads.point_forces)} point forces, unit load cases made for {len(cases.point_forces)}"
        )
