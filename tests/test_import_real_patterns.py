"""Patterns of real drawings: curves that dangle from an outline (tick marks, leaders), slits cut into
a part (a living hinge), and a layer mixing closed curves with open chains of every length."""

from __future__ import annotations

import ezdxf
import pytest

from linkstress.errors import SketchError
from linkstress.importers import read_sketch


def saved(doc, tmp_path, name: str = "sheet.dxf"):
    doc.saveas(tmp_path / name)
    return tmp_path / name


def test_a_layer_of_circles_open_arcs_and_open_lines_lists_its_problems_without_a_traceback(tmp_path):
    # Open chains of different vertex counts beside closed curves on one layer (a real R12 export).
    doc = ezdxf.new("R12", units=4)
    msp = doc.modelspace()
    msp.add_polyline2d([(0, 0), (60, 0), (60, 40), (0, 40)], close=True)
    for x in (15, 30, 45):
        msp.add_circle((x, 20), 3)
    msp.add_arc((100, 20), 10, 0, 90)
    msp.add_arc((100, 20), 10, 90, 200)  # an open two-arc chain
    msp.add_line((130, 0), (140, 10))
    msp.add_line((140, 10), (150, 0))
    msp.add_line((160, 0), (170, 0))
    sketch = read_sketch(saved(doc, tmp_path), units="mm")  # R12 keeps no $INSUNITS
    assert len(sketch.links) == 1 and len(sketch.links[0].outline.interiors) == 3
    assert len(sketch.problems) == 3 and all(p.problem.startswith(("open curve", "open outline")) for p in sketch.problems)


def test_a_living_hinges_slits_leave_their_panel_out_rather_than_import_it_solid(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(10, 20), (110, 20), (110, 60), (10, 60)], close=True)
    for x in range(20, 105, 5):
        y0, y1 = (20, 50) if x % 10 == 0 else (30, 60)  # slits from the bottom and the top edges, alternately
        msp.add_line((x, y0), (x, y1))
    msp.add_lwpolyline([(150, 20), (190, 20), (190, 60), (150, 60)], close=True)  # a clean part beside it
    msp.add_circle((170, 40), 4)
    sketch = read_sketch(saved(doc, tmp_path))
    assert [link.outline.bounds for link in sketch.links] == [(0.15, 0.02, 0.19, 0.06)]
    cut = [p for p in sketch.problems if "cut into its material" in p.problem]
    assert len(cut) == 1 and cut[0].problem.startswith("the outline through LWPOLYLINE")
    assert "17 open chain(s) cut into its material" in cut[0].problem
    assert cut[0].fix == "draw a slit or slot as a closed outline, or move marks and engraving to a layer of their own"


def test_tick_marks_and_a_leader_touching_an_outline_from_outside_leave_it_in(tmp_path):
    # A bracket drawn with LINEs on the same layer as its dimension ticks and a leader that end on
    # its corners: the curves that dangle come off, the outline closes, and they are listed.
    doc = ezdxf.new("R12", units=1)
    msp = doc.modelspace()
    corners = [(0, 0), (4, 0), (4, 1.5), (3.5, 1.5), (3.5, 3), (0, 3)]
    for a, b in zip(corners, corners[1:] + corners[:1]):
        msp.add_line(a, b)
    msp.add_circle((1.5, 1.5), 0.4)
    msp.add_line((4, 0), (4.6, -0.6))  # a tick from a corner
    msp.add_line((3.5, 1.5), (4.5, 2.5))  # a leader from the re-entrant corner, outward
    msp.add_line((4.5, 2.5), (5.5, 2.5))
    sketch = read_sketch(saved(doc, tmp_path), units="in")  # R12 keeps no $INSUNITS
    (link,) = sketch.links
    assert link.outline.area == pytest.approx((4 * 3 - 0.5 * 1.5) * 0.0254**2 - 3.14159 * (0.4 * 0.0254) ** 2, rel=1e-3)
    assert len(sketch.problems) == 2 and all("LINE" in p.problem for p in sketch.problems)
    with pytest.raises(SketchError, match=r"sheet.dxf: layer '0': "):
        sketch.link("0")
