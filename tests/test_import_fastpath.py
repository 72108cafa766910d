"""The fast tag-table reader and ezdxf read the simple entities (LINE, ARC, CIRCLE, POINT, LWPOLYLINE)
into exactly the same primitives, mirrored, hidden and on any layer."""

from __future__ import annotations

import ezdxf
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from linkstress.importers import dxf
from linkstress.importers.dxf_tags import SimpleEntities, split_entities

coordinate = st.floats(-1e4, 1e4, allow_nan=False)
extrusion = st.sampled_from([(0.0, 0.0, 1.0), (0.0, 0.0, -1.0)])
layer = st.sampled_from(["0", "crank", "hidden", "Defpoints"])
entity = st.one_of(
    st.tuples(st.just("line"), coordinate, coordinate, coordinate, coordinate, layer),
    st.tuples(st.just("arc"), coordinate, coordinate, st.floats(1e-3, 1e3), st.floats(-720, 720), st.floats(-720, 720), extrusion, layer),
    st.tuples(st.just("circle"), coordinate, coordinate, st.floats(-1, 1e3), extrusion, layer),
    st.tuples(st.just("point"), coordinate, coordinate, layer),
    st.tuples(st.just("lwpolyline"), st.lists(st.tuples(coordinate, coordinate, st.floats(-2, 2)), min_size=1, max_size=6),
              st.booleans(), extrusion, layer),
)


def write(path, entities) -> None:
    doc = ezdxf.new("R2013", units=4)
    doc.layers.add("hidden").off()
    msp = doc.modelspace()
    for e in entities:
        kind, att = e[0], {"layer": e[-1]}
        if kind == "line":
            msp.add_line(e[1:3], e[3:5], dxfattribs=att)
        elif kind == "arc":
            msp.add_arc(e[1:3], e[3], e[4], e[5], dxfattribs={**att, "extrusion": e[6]})
        elif kind == "circle":
            msp.add_circle(e[1:3], e[3], dxfattribs={**att, "extrusion": e[4]})
        elif kind == "point":
            msp.add_point(e[1:3], dxfattribs=att)
        else:
            msp.add_lwpolyline(e[1], format="xyb", close=e[2], dxfattribs={**att, "extrusion": e[3]})
    doc.saveas(path)


def read_both(path, monkeypatch):
    data = path.read_bytes()
    fast = dxf.read_dxf(path, data, None)
    with monkeypatch.context() as patch:
        patch.setattr(dxf, "split_entities", lambda text: (SimpleEntities(), text))
        slow = dxf.read_dxf(path, data, None)
    return fast, slow


def rows(chunks, width):
    array = np.concatenate(chunks) if chunks else np.empty((0, width))
    return array[np.lexsort(array.T[::-1])]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(entities=st.lists(entity, max_size=12))
def test_both_readers_give_the_same_primitives(tmp_path, monkeypatch, entities):
    path = tmp_path / "simple.dxf"
    write(path, entities)
    fast, slow = read_both(path, monkeypatch)
    a, b = fast.curves, slow.curves
    assert np.array_equal(rows(a.lines, 4), rows(b.lines, 4))
    assert np.array_equal(rows(a.conics, 9), rows(b.conics, 9))
    assert np.array_equal(rows(a.points, 2), rows(b.points, 2))
    key = lambda p: (p.vertices.tolist(), p.bulges.tolist(), p.closed)  # noqa: E731
    assert sorted(map(key, a.polylines)) == sorted(map(key, b.polylines))
    assert sorted(o for k in a.origins for o in a.origins[k]) == sorted(o for k in b.origins for o in b.origins[k])
    assert fast.ignored == slow.ignored


def test_the_fast_path_takes_simple_entities_and_leaves_the_rest(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    msp.add_line((0, 0), (1, 0))
    msp.add_ellipse((0, 0), (2, 0), 0.5)
    msp.add_line((0, 0), (0, 1), dxfattribs={"layer": "paper"}).dxf.paperspace = 1
    doc.saveas(tmp_path / "mixed.dxf")
    found, rest = split_entities((tmp_path / "mixed.dxf").read_text())
    assert found.count("LINE") == 1 and found.columns["LINE"][11].tolist() == [1.0]
    assert "ELLIPSE" in rest and "\nLINE\n" in rest  # the paper-space line stays for ezdxf
    assert ezdxf.read(__import__("io").StringIO(rest)).modelspace().query("ELLIPSE")


@pytest.mark.parametrize("text, reason", [
    ("  0\nSECTION\n  2\nENTITIES\n  0\nENDSEC\n", "does not end with the EOF marker"),
    ("  0\nSECTION\n  2\nENTITIES\n  0\n", "ends in the middle of a group code/value pair"),
    ("  0\nSECTION\nxx\nENTITIES\n  0\nEOF\n", "line 3: 'xx' is not a group code"),
])
def test_broken_structure_is_reported_as_damage(text, reason):
    with pytest.raises(dxf.DamagedDXF, match=reason):
        split_entities(text)
