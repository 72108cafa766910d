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
    with pytest.raises(SketchError, match=r"pair.dxf: no link imports, 2 problems \(.*\): \(1\) outlines cross or touch at \(100, 10\) mm.* \(2\) the outline through CIRCLE .* is left out: it lies inside the outline through LWPOLYLINE"):
        read_sketch(tmp_path / "pair.dxf")


def assembled_four_bar(path, extra=None) -> None:
    """A four-bar drawn assembled in mm, crank at 50 deg, each moving link on its own layer, the
    ground not drawn; ``extra(layout)`` adds more."""
    import math

    doc = ezdxf.new("R2018", units=4)
    msp = doc.modelspace()
    o2, o4 = (0.0, 0.0), (120.0, 0.0)
    a = (40 * math.cos(math.radians(50)), 40 * math.sin(math.radians(50)))
    d = math.dist(a, o4)
    along = (130**2 - 90**2 + d**2) / (2 * d)
    up = math.sqrt(130**2 - along**2)
    ex, ey = (o4[0] - a[0]) / d, (o4[1] - a[1]) / d
    b = (a[0] + along * ex - up * ey, a[1] + along * ey + up * ex)
    for layer, p, q in (("crank", o2, a), ("coupler", a, b), ("rocker", o4, b)):
        angle = math.atan2(q[1] - p[1], q[0] - p[0])
        c, s = math.cos(angle), math.sin(angle)
        length = math.dist(p, q)
        corners = [(0, -10, 0), (length, -10, 1), (length, 10, 0), (0, 10, 1)]
        msp.add_lwpolyline([(p[0] + c * x - s * y, p[1] + s * x + c * y, bulge) for x, y, bulge in corners],
                           format="xyb", close=True, dxfattribs={"layer": layer})
        for centre in (p, q):
            msp.add_circle(centre, 4.0, dxfattribs={"layer": layer})
    if extra is not None:
        extra(msp)
    doc.saveas(path)


def test_an_assembled_drawing_with_an_engraving_layer_imports_as_a_scene_once_that_layer_is_left_out(tmp_path, capsys):
    from linkstress.cli import main

    engraving = lambda msp: msp.add_lwpolyline([(-20, -30), (140, -30), (140, -12), (-20, -12)], close=True,
                                               dxfattribs={"layer": "ENGRAVING"})
    assembled_four_bar(tmp_path / "asm.dxf", engraving)
    scene = tmp_path / "scene.toml"
    assert main(["import", str(tmp_path / "asm.dxf"), "--scene", str(scene)]) == 2
    assert "'ENGRAVING' are in no four-bar loop" in capsys.readouterr().err and not scene.exists()
    assert main(["import", str(tmp_path / "asm.dxf"), "--scene", str(scene), "--exclude-layers", "ENGRAVING"]) == 0
    assert main(["analyze", str(scene)]) == 0


def test_a_stray_line_on_a_links_own_layer_refuses_that_link_in_a_scene_with_the_problem(tmp_path, capsys):
    # What was left out on a link's layer may be part of it (a slot whose outline does not close): the
    # link imports for a look with `linkstress import`, but a scene that uses it is refused.
    from linkstress.cli import main

    assembled_four_bar(tmp_path / "asm.dxf", lambda msp: msp.add_line((200, 0), (260, 40), dxfattribs={"layer": "crank"}))
    sketch = read_sketch(tmp_path / "asm.dxf")
    assert [link.name for link in sketch.links] == ["crank", "coupler", "rocker"] and len(sketch.problems) == 1
    with pytest.raises(SketchError, match=r"asm.dxf: layer 'crank': open curve: LINE \(handle \w+, layer 'crank'\)"):
        sketch.link("crank")
    assert sketch.link("coupler").layer == "coupler"
    assert main(["import", str(tmp_path / "asm.dxf"), "--scene", str(tmp_path / "scene.toml")]) == 2
    assert "layer 'crank': open curve: LINE" in capsys.readouterr().err


@pytest.mark.parametrize("version", ["R2000", "R2013"])
def test_a_layer_named_with_a_unicode_escape_that_is_not_hex_reads_as_written(tmp_path, version):
    doc = ezdxf.new(version, units=4)
    bar(doc.modelspace(), "\\U+zzzz", 0.0, 0.0, 100.0)
    path = tmp_path / "odd.dxf"
    doc.saveas(path)
    sketch = read_sketch(path, layers=["\\U+zzzz"])
    assert [link.layer for link in sketch.links] == ["\\U+zzzz"]


def test_a_layer_option_with_a_unicode_escape_that_is_not_hex_is_refused_by_name(tmp_path):
    doc = ezdxf.new("R2000", units=4)
    bar(doc.modelspace(), "crank", 0.0, 0.0, 100.0)
    path = tmp_path / "bar.dxf"
    doc.saveas(path)
    with pytest.raises(SketchError, match=r"no layer '\\\\U\+zzzz' in the drawing"):
        read_sketch(path, layers=["\\U+zzzz"])


def test_a_point_whose_own_layers_outline_was_left_out_is_no_joint_of_the_link_under_it(tmp_path):
    """A lever's outline crosses itself (left out as a problem); its POINT lies on the frame's plate.
    The frame keeps its own two POINTs: the lever's is not taken for a third pivot of the frame."""
    import ezdxf

    from linkstress.importers import read_sketch

    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (200, 0), (200, 50), (0, 50)], close=True, dxfattribs={"layer": "frame"})
    for x in (20, 180):
        msp.add_point((x, 25), dxfattribs={"layer": "frame"})
    # a bow tie: its two sides cross at (100, 25)
    msp.add_lwpolyline([(60, 10), (140, 40), (140, 10), (60, 40)], close=True, dxfattribs={"layer": "lever"})
    msp.add_point((80, 25), dxfattribs={"layer": "lever"})
    path = tmp_path / "frame.dxf"
    doc.saveas(path)
    sketch = read_sketch(path)
    assert [link.name for link in sketch.links] == ["frame"]
    assert sketch.links[0].joints.tolist() == [[0.02, 0.025], [0.18, 0.025]]
    assert any(problem.layer == "lever" for problem in sketch.problems)
