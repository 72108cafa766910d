"""Drawing links into a DXF with ezdxf, for the cases' reproducible sketches: straight and curved
round-ended bars, bent (bell crank) links and arc bars with round lugs.

A link is drawn on its own layer as a closed outline of LINE and ARC entities (in any CAD's
manner: separate entities the importer must chain), a CIRCLE for each pin hole and a POINT at
each joint. Coordinates are in the drawing's units.
"""

from __future__ import annotations

import math
from pathlib import Path

import ezdxf
import numpy as np


def new_drawing(units: int) -> ezdxf.document.Drawing:
    """An empty R2013 drawing with ``$INSUNITS`` = ``units`` (4 mm, 6 m) and fixed metadata."""
    ezdxf.options.write_fixed_meta_data_for_testing = True
    return ezdxf.new("R2013", units=units)


def save(doc: ezdxf.document.Drawing, path: Path) -> None:
    """Save byte-for-byte reproducibly (CLASS entries sorted: ezdxf orders them by hash)."""
    doc.classes.add_required_classes(doc.dxfversion)
    doc.classes.classes = dict(sorted(doc.classes.classes.items()))
    doc.saveas(path)


def straight_link(msp, layer: str, joints: list[tuple[float, float]], width: float, hole: float) -> None:
    """A stadium along the x axis through ``joints`` (all at y = joints[0][1]), round ends centred
    on the first and last joint, a pin hole of diameter ``hole`` and a POINT at every joint."""
    xs = sorted(x for x, _ in joints)
    y, r = joints[0][1], width / 2
    attrs = {"layer": layer}
    msp.add_line((xs[0], y - r), (xs[-1], y - r), dxfattribs=attrs)
    msp.add_arc((xs[-1], y), r, -90, 90, dxfattribs=attrs)
    msp.add_line((xs[-1], y + r), (xs[0], y + r), dxfattribs=attrs)
    msp.add_arc((xs[0], y), r, 90, 270, dxfattribs=attrs)
    _pins(msp, layer, joints, hole)


def plate_link(msp, layer: str, joints: list[tuple[float, float]], depth: float, end: float, hole: float) -> None:
    """A rectangle ``depth`` deep along the x axis through ``joints`` (all at y = joints[0][1]), its
    square ends ``end`` past the first and last joint, a pin hole of diameter ``hole`` and a POINT
    at every joint."""
    xs = sorted(x for x, _ in joints)
    y, h = joints[0][1], depth / 2
    corners = [(xs[0] - end, y - h), (xs[-1] + end, y - h), (xs[-1] + end, y + h), (xs[0] - end, y + h)]
    msp.add_lwpolyline(corners, close=True, dxfattribs={"layer": layer})
    _pins(msp, layer, joints, hole)


def curved_link(msp, layer: str, start: tuple[float, float], length: float, sag: float, width: float, hole: float) -> None:
    """A banana: the centre line is a circular arc from ``start`` to ``start + (length, 0)`` bulging
    up by ``sag``; the edges are concentric arcs ``width`` apart, the ends semicircles on the joints."""
    radius = (length**2 / 4 + sag**2) / (2 * sag)
    cx, cy = start[0] + length / 2, start[1] + sag - radius
    right = math.degrees(math.atan2(start[1] - cy, start[0] + length - cx))
    left = math.degrees(math.atan2(start[1] - cy, start[0] - cx))
    attrs = {"layer": layer}
    r = width / 2
    msp.add_arc((cx, cy), radius + r, right, left, dxfattribs=attrs)
    msp.add_arc((cx, cy), radius - r, right, left, dxfattribs=attrs)
    msp.add_arc((start[0] + length, start[1]), r, right + 180, right + 360, dxfattribs=attrs)
    msp.add_arc(start, r, left, left + 180, dxfattribs=attrs)
    _pins(msp, layer, [start, (start[0] + length, start[1])], hole)


def bent_link(
    msp, layer: str, pivot: tuple[float, float], ends: tuple[tuple[float, float], tuple[float, float]],
    width: float, fillet: float, hole: float,
) -> None:
    """A bell crank: two straight arms of ``width`` from ``pivot`` to each of ``ends``, bent by less
    than 180 degrees between them. Each arm ends in a semicircle on its end joint; the outer corner
    is an arc of radius ``width / 2`` about the pivot; the inner corner is a fillet of radius
    ``fillet`` tangent to both inner edges. A pin hole of diameter ``hole`` and a POINT at the pivot
    and at both ends."""
    p = _vec(pivot)
    first, second = (_vec(e) for e in ends)
    if _cross(first - p, second - p) < 0:  # the outline is built with the second arm counter-clockwise of the first
        first, second = second, first
    u1, u2 = (first - p) / _norm(first - p), (second - p) / _norm(second - p)
    n1, n2 = _left(u1), _left(u2)
    r = width / 2
    # The fillet's centre is (r + fillet) inside both inner edges: +n1 of the first arm, -n2 of the second.
    s = _solve2(u1, -u2, -(r + fillet) * (n1 + n2))
    centre = p + (r + fillet) * n1 + s[0] * u1
    t1, t2 = centre - fillet * n1, centre + fillet * n2
    attrs = {"layer": layer}
    msp.add_line(_pt(p - r * n1), _pt(first - r * n1), dxfattribs=attrs)
    msp.add_arc(_pt(first), r, _deg(-n1), _deg(n1), dxfattribs=attrs)
    msp.add_line(_pt(first + r * n1), _pt(t1), dxfattribs=attrs)
    msp.add_arc(_pt(centre), fillet, _deg(t2 - centre), _deg(t1 - centre), dxfattribs=attrs)
    msp.add_line(_pt(t2), _pt(second - r * n2), dxfattribs=attrs)
    msp.add_arc(_pt(second), r, _deg(-n2), _deg(n2), dxfattribs=attrs)
    msp.add_line(_pt(second + r * n2), _pt(p + r * n2), dxfattribs=attrs)
    msp.add_arc(_pt(p), r, _deg(n2), _deg(-n1), dxfattribs=attrs)
    _pins(msp, layer, [pivot, *ends], hole)


def arc_link(
    msp, layer: str, centre: tuple[float, float], radius: float, start_deg: float, end_deg: float,
    depth: float, lug: float, fillet: float, hole: float,
) -> None:
    """A circular-arc bar: its centre line is the arc of ``radius`` about ``centre`` from
    ``start_deg`` counter-clockwise to ``end_deg`` (less than 360 degrees), its edges the concentric
    arcs ``depth`` apart; at each end of the centre line a round lug of diameter ``lug`` (larger
    than ``depth``), joined to both edges by fillets of radius ``fillet`` (> 0), with a pin hole of
    diameter ``hole`` and a POINT at its centre."""
    c = _vec(centre)
    a = lug / 2
    attrs = {"layer": layer}
    # Each edge's radius and its fillets' centres' radius about the arc's centre.
    edges = {
        "outer": (radius + depth / 2, radius + depth / 2 + fillet),
        "inner": (radius - depth / 2, radius - depth / 2 - fillet),
    }
    # A fillet's centre is ``fillet`` off its edge (outside the bar) and a + fillet from the lug's
    # centre, which is ``radius`` from the arc's: gamma is its angle from the lug, seen from the arc's centre.
    gamma = {
        side: math.degrees(math.acos((rho_f**2 + radius**2 - (a + fillet) ** 2) / (2 * rho_f * radius)))
        for side, (_, rho_f) in edges.items()
    }
    for side, (rho, _) in edges.items():
        msp.add_arc(_pt(c), rho, start_deg + gamma[side], end_deg - gamma[side], dxfattribs=attrs)
    joints = []
    for edge_deg, sign in ((start_deg, 1), (end_deg, -1)):
        joint = c + radius * _unit(edge_deg)
        joints.append(_pt(joint))
        on_lug = {}
        for side, (rho, rho_f) in edges.items():
            angle = edge_deg + sign * gamma[side]
            f_centre = c + rho_f * _unit(angle)
            on_lug[side] = joint + a * (f_centre - joint) / _norm(f_centre - joint)
            ends = sorted([_deg(c + rho * _unit(angle) - f_centre), _deg(on_lug[side] - f_centre)])
            # The fillet is the short way round its centre between its two tangent points.
            first, last = ends if ends[1] - ends[0] < 180 else ends[::-1]
            msp.add_arc(_pt(f_centre), fillet, first, last, dxfattribs=attrs)
        # The lug's free arc runs counter-clockwise about the joint from one edge to the other, away from the bar.
        first, last = (on_lug["inner"], on_lug["outer"]) if sign > 0 else (on_lug["outer"], on_lug["inner"])
        msp.add_arc(_pt(joint), a, _deg(first - joint), _deg(last - joint), dxfattribs=attrs)
    _pins(msp, layer, joints, hole)


def _vec(p) -> np.ndarray:
    return np.asarray(p, float)


def _norm(v) -> float:
    return float(np.hypot(*v))


def _left(u):
    return np.array([-u[1], u[0]])


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _unit(deg: float):
    return np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])


def _deg(v) -> float:
    return math.degrees(math.atan2(v[1], v[0]))


def _pt(v) -> tuple[float, float]:
    return float(v[0]), float(v[1])


def _solve2(a, b, rhs):
    """(s, t) with s a + t b = rhs."""
    return np.linalg.solve(np.column_stack([a, b]), rhs)


def _pins(msp, layer: str, joints, hole: float) -> None:
    for x, y in joints:
        msp.add_circle((x, y), hole / 2, dxfattribs={"layer": layer})
        msp.add_point((x, y), dxfattribs={"layer": layer})
