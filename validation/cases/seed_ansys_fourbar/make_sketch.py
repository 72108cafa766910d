"""Writes ``ansys_four_bars.dxf``: the seed's four steel bars of the ANSYS check, drawn in metres.

Source: docs/reference/seed-ansys-fourbar.md (KSAM thesis, section 6.3.5). Each bar is a
rectangle 0.5 m high (a closed LWPOLYLINE) with a 20 mm pin hole (CIRCLE) at mid-height 0.1 m from
each end and a POINT at each hole's centre, on a layer named after the link. The bars lie
horizontally, one above the other 1 m apart (crank lowest), each with its first joint on x = 0.

Run ``python make_sketch.py`` in this folder; the output is byte-for-byte reproducible.
"""

from __future__ import annotations

from pathlib import Path

import ezdxf

BARS = {"crank": 1.2, "coupler": 1.7, "output": 1.7, "ground": 2.2}  # bar length [m]
HEIGHT = 0.5  # [m]
END_TO_JOINT = 0.1  # [m]
HOLE_DIAMETER = 0.02  # [m]
SPACING = 1.0  # vertical distance between the bars' axes [m]


def write(path: Path) -> None:
    ezdxf.options.write_fixed_meta_data_for_testing = True
    doc = ezdxf.new("R2013", units=6)  # $INSUNITS 6: metres
    msp = doc.modelspace()
    for k, (name, length) in enumerate(BARS.items()):
        doc.layers.add(name)
        y = k * SPACING
        x0, x1 = -END_TO_JOINT, length - END_TO_JOINT
        corners = [(x0, y - HEIGHT / 2), (x1, y - HEIGHT / 2), (x1, y + HEIGHT / 2), (x0, y + HEIGHT / 2)]
        msp.add_lwpolyline(corners, close=True, dxfattribs={"layer": name})
        for x in (0.0, length - 2 * END_TO_JOINT):
            msp.add_circle((x, y), HOLE_DIAMETER / 2, dxfattribs={"layer": name})
            msp.add_point((x, y), dxfattribs={"layer": name})
    # ezdxf lists the CLASS definitions of the entity types in use from a set, in an order that
    # follows Python's hash seed: add them now, sorted, so the file is the same on every run.
    doc.classes.add_required_classes(doc.dxfversion)
    doc.classes.classes = dict(sorted(doc.classes.classes.items()))
    doc.saveas(path)


if __name__ == "__main__":
    write(Path(__file__).with_name("ansys_four_bars.dxf"))
