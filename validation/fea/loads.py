"""Nodal force vectors of a link's loads: the kinetics' loads and nothing else, for all positions at once.

Member frame of the load case; P positions; every function returns forces (dofs, P) [N].

- Pin force F at a joint with a hole of centre c: a cosine bearing pressure on the loaded half of
  the hole, p(phi) = a cos(phi) + b sin(phi) for cos(phi) > 0, phi the angle from F to the radius
  r - c, pushing radially into the material. a ~ 2 |F| / (pi R t) and b ~ 0; both are solved from
  the discrete resultant (a 2x2 system per position), so that the nodal forces sum to F exactly
  whatever the mesh. Radial tractions have no moment about c.
- Couple C at a joint with a hole: a uniform traction tangent to the hole (a keyed shaft), scaled
  so that the nodal moment about c is C exactly. The discrete tangents integrate to zero round a
  closed hole, so the couple adds no net force.
- d'Alembert body force rho (g - a(r)) of the rigid-body motion: affine in r, so it is three
  integrals of the shape functions (of 1, x and y), combined per position.
- Point force F at p in material: a load density over the elements within a patch radius of p,
  affine and with zero first moment about p, so that its nodal resultant is F and its moment about
  the origin is p x F, exactly.
- Point force F at p in a hole (a pin's load given as a force, at a joint's hole or any other): the
  pin force F on that hole as above, bearing about the hole's centre c (its joint, if a joint sits
  in it), plus the couple (p - c) x F as tangential traction when p is off the centre, so that
  resultant and moment are those of F at p, exactly. (Spread over the elements next to an empty
  hole, such a force had no converging peak.)
- A slider block's push on the slot it runs in (``SlidingContact``), at the block's point a, along
  the line u (n = k x u): a pressure (c0 + c1 xi) along n on the slot's wall the push faces, over
  the block's length centred on a (xi along u from a; a block drawn without a link of its own,
  over the slot's width), and a uniform shear c2 along u there (the
  friction); c0, c1 and c2 are solved per position from the discrete integrals, so that the nodal
  forces sum to the push and their moment about a is the block's couple, exactly.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
import scipy.sparse as sp
from shapely.geometry import Polygon
from skfem import Basis

from linkstress.loads import LinkLoadCase, SlidingContact, contact_hole, hole_at
from linkstress.geometry.profile import LinkProfile
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.plane_stress import PlaneStressModel, quadrature_weights, vector_loads

FACET_POINTS = 5
"""Gauss points per hole edge (exact to degree 9): resolves the bearing pressure's kink at +-90
degrees from F as the mesh is refined."""


def edge_quadrature(
    model: PlaneStressModel, facets: NDArray[np.intp], centre: NDArray[np.float64]
) -> tuple[sp.csr_matrix, NDArray[np.float64], NDArray[np.float64]]:
    """Weights W (scalar dofs, Nq), points (2, Nq) [m] and unit tangents (2, Nq) along the edges
    ``facets``, the tangents turning counter-clockwise about ``centre``.

    On a P2 mesh each edge is the quadratic curve through its two vertices and its mid-edge node,
    parameterised by s in [0, 1] exactly as the isoparametric elements are, so the trace of the P2
    functions on it is the 1D quadratic Lagrange basis (P1: the straight edge and the linear basis).
    This avoids skfem's FacetBasis, whose inverse isoparametric mapping does not always converge on
    curved P2 meshes (scikit-fem issue #965).
    """
    s, w = np.polynomial.legendre.leggauss(FACET_POINTS)
    s, w = (s + 1) / 2, w / 2
    scalar = model.scalar
    vertices = scalar.nodal_dofs[0][model.plane.mesh.facets[:, facets]]
    if model.order == 2:
        shape = np.array([(1 - s) * (1 - 2 * s), s * (2 * s - 1), 4 * s * (1 - s)])  # vertex, vertex, middle
        slope = np.array([4 * s - 3, 4 * s - 1, 4 - 8 * s])
        dofs = np.vstack([vertices, scalar.facet_dofs[0][facets]])  # (3, F)
    else:
        shape, slope = np.array([1 - s, s]), np.array([-np.ones_like(s), np.ones_like(s)])
        dofs = vertices  # (2, F)
    xy = scalar.doflocs[:, dofs]  # (2, nodes per edge, F)
    points = np.einsum("cnf,nq->cfq", xy, shape)
    derivative = np.einsum("cnf,nq->cfq", xy, slope)
    length = np.hypot(*derivative)
    tangent = derivative / length
    arm = points - np.asarray(centre, float)[:, None, None]
    turn = np.sign(arm[0] * tangent[1] - arm[1] * tangent[0])
    tangent = tangent * np.where(turn == 0, 1.0, turn)
    values = shape[:, None, :] * (w * length)[None, :, :]  # (nodes per edge, F, Q)
    n_points = dofs.shape[1] * len(s)
    columns = np.broadcast_to(np.arange(n_points).reshape(dofs.shape[1], len(s)), values.shape)
    rows = np.broadcast_to(dofs[:, :, None], values.shape)
    weights = sp.csr_matrix((values.ravel(), (rows.ravel(), columns.ravel())), shape=(scalar.N, n_points))
    return weights, points.reshape(2, -1), tangent.reshape(2, -1)


def nodal_resultant(
    model: PlaneStressModel, forces: NDArray[np.float64], about: NDArray[np.float64] | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Net force (P, 2) [N] and moment (P,) [N m] of nodal ``forces`` (dofs, P).

    The moment is taken about ``about`` (2,) [m], the origin by default.
    """
    origin = np.zeros(2) if about is None else np.asarray(about, float)
    xy = model.scalar.doflocs - origin[:, None]
    fx, fy = forces[model.components[0]], forces[model.components[1]]
    force = np.column_stack([fx.sum(axis=0), fy.sum(axis=0)])
    return force, xy[0] @ fy - xy[1] @ fx


def bearing_loads(
    model: PlaneStressModel,
    facets: NDArray[np.intp],
    centre: NDArray[np.float64],
    forces: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Cosine bearing pressure of pin forces (P, 2) [N] on the hole ``facets`` around ``centre`` (2,) [m]."""
    weights, points, _ = edge_quadrature(model, facets, centre)
    radius = points - np.asarray(centre, float)[:, None]
    radial = radius / np.hypot(*radius)
    magnitude = np.hypot(forces[:, 0], forces[:, 1])
    direction = np.where(
        magnitude[:, None] > 0, forces / np.where(magnitude > 0, magnitude, 1.0)[:, None], [1.0, 0.0]
    )
    cos = direction @ radial
    sin = direction[:, :1] * radial[1] - direction[:, 1:] * radial[0]
    loaded = cos > 0
    shapes = [np.where(loaded, cos, 0.0), np.where(loaded, sin, 0.0)]
    ds = model.thickness * np.asarray(weights.sum(axis=0)).ravel()
    resultants = np.stack([(s * ds) @ radial.T for s in shapes], axis=-1)
    a, b = np.linalg.solve(resultants, forces[:, :, None])[:, :, 0].T
    pressure = a[:, None] * shapes[0] + b[:, None] * shapes[1]
    return vector_loads(model, weights, pressure[:, None, :] * radial[None, :, :])


def shaft_couple_loads(
    model: PlaneStressModel,
    facets: NDArray[np.intp],
    centre: NDArray[np.float64],
    couples: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Uniform tangential traction on the hole ``facets`` carrying couples (P,) [N m] about ``centre``."""
    weights, points, tangent = edge_quadrature(model, facets, centre)
    arm = points - np.asarray(centre, float)[:, None]
    ds = model.thickness * np.asarray(weights.sum(axis=0)).ravel()
    unit_moment = float(((arm[0] * tangent[1] - arm[1] * tangent[0]) * ds).sum())
    scale = np.asarray(couples, float) / unit_moment
    return vector_loads(model, weights, scale[:, None, None] * tangent[None, :, :])


def contact_loads(
    model: PlaneStressModel, facets: NDArray[np.intp], contact: SlidingContact, anchor: NDArray[np.float64],
    least: float,
) -> NDArray[np.float64]:
    """A slider block's push (``contact``, P positions) on the walls ``facets`` of the slot it runs
    in, its line through ``anchor`` (2,) [m] and the contact's points: over the block's length (at
    least ``least`` [m], the station size), on the wall the push faces (see the module's docstring)."""
    weights, points, _ = edge_quadrature(model, facets, np.asarray(anchor, float))
    at = np.asarray(contact.at, float)
    direction = at - anchor
    far = np.argmax(np.hypot(*direction.T))
    u = direction[far] / np.hypot(*direction[far]) if np.hypot(*direction[far]) > 0 else np.array([1.0, 0.0])
    n = np.array([-u[1], u[0]])
    force, couple = np.asarray(contact.force, float), np.asarray(contact.couple, float)
    offset = points[None, :, :] - at[:, :, None]  # (P, 2, Nq)
    xi, eta = np.einsum("d,pdq->pq", u, offset), np.einsum("d,pdq->pq", n, offset)
    side = np.where(force @ n >= 0, 1.0, -1.0)
    half = max(contact.length, least) / 2
    bearing = (np.abs(xi) <= half) & (eta * side[:, None] > 0)
    ds = model.thickness * np.asarray(weights.sum(axis=0)).ravel() * bearing  # (P, Nq)
    s0, s1, s2 = ds.sum(axis=1), (ds * xi).sum(axis=1), (ds * xi**2).sum(axis=1)
    if not (s0 > 0).all():
        raise FEAError("a slider's block bears on no wall of its slot at some position: refine the mesh")
    along = force @ u
    shear = along / s0
    # normal: side (c0 s0 + c1 s1) = F.n; moment about a: side (c0 s1 + c1 s2) - shear sum(ds eta) = C
    moment = couple + shear * (ds * eta).sum(axis=1)
    determinant = s0 * s2 - s1 * s1
    c0 = side * ((force @ n) * s2 - moment * s1) / determinant
    c1 = side * (moment * s0 - (force @ n) * s1) / determinant
    pressure = np.where(bearing, c0[:, None] + c1[:, None] * xi, 0.0)
    traction = (side[:, None] * pressure)[:, None, :] * n[None, :, None] + np.where(bearing, shear[:, None], 0.0)[:, None, :] * u[None, :, None]
    return vector_loads(model, weights, traction)


def body_loads(model: PlaneStressModel, loads: LinkLoadCase, density: float) -> NDArray[np.float64]:
    """d'Alembert body force (and gravity) of ``loads``' rigid-body motion for a material ``density`` [kg/m^3]."""
    weights, points = quadrature_weights(model.scalar)
    moments = [weights @ np.ones(points.shape[1]), weights @ points[0], weights @ points[1]]
    # The load density is affine in r: b(r) = b(0) + (b(e_x) - b(0)) x + (b(e_y) - b(0)) y.
    b = loads.body_force_density(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), density)
    coefficients = [b[:, 0], b[:, 1] - b[:, 0], b[:, 2] - b[:, 0]]
    forces = np.zeros((model.n_dofs, loads.n_positions))
    for c in range(2):
        forces[model.components[c]] = model.thickness * sum(
            np.outer(m, k[:, c]) for m, k in zip(moments, coefficients)
        )
    return forces


def patch_loads(
    model: PlaneStressModel, at: NDArray[np.float64], forces: NDArray[np.float64], radius: float
) -> NDArray[np.float64]:
    """Point forces (P, 2) [N] at ``at`` (2,) [m] spread over the elements within ``radius`` [m] of it."""
    mesh = model.plane.mesh
    at = np.asarray(at, float)
    centroids = mesh.p[:, mesh.t].mean(axis=1)
    patch = np.flatnonzero(np.hypot(*(centroids - at[:, None])) <= radius)
    if len(patch) < 2:
        patch = np.argsort(np.hypot(*(centroids - at[:, None])))[:3]
    basis = Basis(mesh, model.scalar.elem, elements=patch, intorder=4)
    weights, points = quadrature_weights(basis)
    d = points - at[:, None]
    da = np.asarray(weights.sum(axis=0)).ravel()
    rows = np.vstack([np.ones_like(d[0]), d])
    system = (rows * da) @ rows.T
    alpha, *beta = np.linalg.solve(system, [1.0, 0.0, 0.0])
    shape = (alpha + beta[0] * d[0] + beta[1] * d[1]) / model.thickness
    return vector_loads(model, weights, forces[:, :, None] * shape[None, None, :])


def link_loads(
    model: PlaneStressModel, link: LinkProfile, loads: LinkLoadCase, patch_radius: float
) -> NDArray[np.float64]:
    """All the loads of ``loads`` on ``link`` meshed in ``model`` (its member frame): forces (dofs, P) [N]."""
    check_load_case(link, loads)
    frame = link.frame(*loads.frame_joints)
    joints = frame.to_local(link.joints)
    forces = body_loads(model, loads, link.density)
    for j, hole in enumerate(link.joint_holes):
        pin, couple = loads.pin_forces[:, j], loads.joint_couples[:, j]
        if hole is None:
            if np.any(pin != 0) or np.any(couple != 0):
                raise FEAError(
                    f"link {link.name!r}: joint {j} carries a pin force of up to "
                    f"{np.hypot(*pin.T).max():.6g} N and a couple of up to {np.abs(couple).max():.6g} N m but "
                    "has no hole; the FEA applies joint loads on a pin hole: draw the hole (a circle centred "
                    "on the joint)"
                )
            continue
        facets = model.plane.holes[hole]
        forces += bearing_loads(model, facets, joints[j], pin)
        if np.any(couple != 0):
            forces += shaft_couple_loads(model, facets, joints[j], couple)
    outline = link.local_outline(*loads.frame_joints)
    for contact in loads.contacts:
        hole = contact_hole(outline, contact)
        # A block drawn without a link of its own bears over the slot's width at least.
        forces += contact_loads(model, model.plane.holes[hole], contact, frame.to_local(link.joints)[contact.anchor],
                                max(float(link.hole_sizes[hole, 1]), patch_radius))
    for point in loads.point_forces:
        force = np.asarray(point.force, float)
        pin = point_force_hole(link, loads.frame_joints, point.at)
        if pin is None:
            forces += patch_loads(model, point.at, force, patch_radius)
            continue
        hole, centre = pin
        facets = model.plane.holes[hole]
        forces += bearing_loads(model, facets, centre, force)
        offset = np.asarray(point.at, float) - centre
        couple = offset[0] * force[:, 1] - offset[1] * force[:, 0]
        if np.any(couple != 0):
            forces += shaft_couple_loads(model, facets, centre, couple)
    return forces


def point_force_hole(
    link: LinkProfile, frame_joints: tuple[int, int], at: NDArray[np.float64]
) -> tuple[int, NDArray[np.float64]] | None:
    """The hole (its index in the outline's interiors) holding a point force at ``at`` (2,) [m, member
    frame] and the centre (2,) [m] its pin bears about: the joint in that hole, else the hole's
    centroid; None for a point in material."""
    outline = link.local_outline(*frame_joints)
    hole = hole_at(outline, at)
    if hole is None:
        return None
    joints = [j for j, h in enumerate(link.joint_holes) if h == hole]
    if joints:
        return hole, link.frame(*frame_joints).to_local(link.joints[joints[0]])
    return hole, np.array(Polygon(outline.interiors[hole]).centroid.coords[0])


GUIDE_REFUSAL = ("a slider's block slides along it with its contact not inside a closed slot of the link at every "
                 "position: the FEA bears a block only on the walls of a closed slot it runs in; its stresses are its "
                 "beam sections")


def check_load_case(link: LinkProfile, loads: LinkLoadCase) -> None:
    """The load case's arrays fit the link (P positions, J joints) and are finite, and it has no
    sliding contact (the FEA applies loads at fixed points); else FEAError."""
    outline = link.local_outline(*loads.frame_joints)
    for contact in loads.contacts:
        if contact_hole(outline, contact) is None:
            raise FEAError(f"link {link.name!r}: {GUIDE_REFUSAL}")
        if np.shape(contact.force) != (loads.n_positions, 2) or not np.isfinite(contact.force).all():
            raise FEAError(f"link {link.name!r}: a sliding contact needs finite (P, 2) forces")
    n_pos, n_joints = loads.n_positions, len(link.joints)
    shapes = {
        "pin_forces": (n_pos, n_joints, 2),
        "joint_couples": (n_pos, n_joints),
        "alpha": (n_pos,),
        "origin_acceleration": (n_pos, 2),
        "gravity": (n_pos, 2),
    }
    for key, shape in shapes.items():
        value = np.asarray(getattr(loads, key))
        if value.shape != shape:
            raise FEAError(f"link {link.name!r}: load case {key} has shape {value.shape}, expected {shape}")
        if not np.isfinite(value).all():
            raise FEAError(f"link {link.name!r}: load case {key} has non-finite values")
    for point in loads.point_forces:
        if np.shape(point.force) != (n_pos, 2) or not np.isfinite(point.force).all():
            raise FEAError(
                f"link {link.name!r}: a point force at {np.asarray(point.at).tolist()} needs finite (P, 2) forces"
            )
