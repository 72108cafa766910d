"""Each layer is its own drawing: links drawn in place on their own layers may overlap at their
joints, while outlines on one layer must still stay apart."""

from __future__ import annotations

import ezdxf
import pytest

from linkstress.errors import SketchError
from linkstress.importers import read_sketch


def bar(layout, layer: str, x0: float, y0: float, x1: float, hole: float = 6.0) -> None:
    """A 20 mm deep bar from (x0, y0) to (x1, y0) with pin holes and POINTs at both ends (mm)."""
    att = {"layer": layer}
    layout.add_lwpolyline(
        [(x0, y0 - 10, 0.0), (x1, y0 - 10, 1.0), (x1, y0 + 10, 0.0), (x0, y0 + 10, 1.0)], format="xyb", close=True,
        dxfattribs=att,
    )
    for x in (x0, x1):
        layout.add_circle((x, y0), hole / 2, dxfattribs=att)
        layout.add_point((x, y0), dxfattribs=att)


def test_two_links_overlapping_at_their_shared_pin_on_their_own_layers_import_as_two_links(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    bar(msp, "crank", 0.0, 0.0, 100.0)
    bar(msp, "coupler", 100.0, 0.0, 250.0)  # its rounded end covers the crank's around the pin at x = 100
    doc.saveas(tmp_path / "pair.dxf")
    sketch = read_sketch(tmp_path / "pair.dxf")
    assert [link.name for link in sketch.links] == ["crank", "coupler"]
    assert sketch.link("crank").joints.tolist() == [[0.0, 0.0], [0.1, 0.0]]
    assert sketch.link("coupler").joints.tolist() == [[0.1, 0.0], [0.25, 0.0]]
    assert sketch.link("crank").outline.intersects(sketch.link("coupler").outline)


def test_the_same_overlap_on_one_layer_is_refused_with_the_pin_hole_they_share_left_out_not_taken_for_a_part(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    bar(msp, "links", 0.0, 0.0, 100.0)
    bar(msp, "links", 100.0, 0.0, 250.0)
    doc.saveas(tmp_path / "pair.dxf")
    with pytest.raises(SketchError, match=r"pair.dxf: no link imports, 2 problems: \(1\) outlines cross or touch at \(100, 10\) mm.* \(2\) the outline through CIRCLE .* is left out: it lies inside the outline through LWPOLYLINE"):
        read_sketch(tmp_path / "pair.dxf")
