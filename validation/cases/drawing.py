"""Drawing round-ended links into a DXF with ezdxf, for the cases' reproducible sketches.

A link is drawn on its own layer as a closed outline of LINE and ARC entities (in any CAD's
manner: separate entities the importer must chain), a CIRCLE for each pin hole and a POINT at
each joint. Coordinates are in the drawing's units.
"""

from __future__ import annotations

import math
from pathlib import Path

import ezdxf


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


def _pins(msp, layer: str, joints, hole: float) -> None:
    for x, y in joints:
        msp.add_circle((x, y), hole / 2, dxfattribs={"layer": layer})
        msp.add_point((x, y), dxfattribs={"layer": layer})
