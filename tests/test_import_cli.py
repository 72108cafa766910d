"""``linkstress import``: tables, the JSON of docs/design.md, the picture, and exit 2 on bad input with
no output file written."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from linkstress.cli import main
from test_import_dxf import draw, plate_entities, save

REPO = Path(__file__).resolve().parents[1]
SEED = REPO / "validation" / "cases" / "seed_ansys_fourbar" / "ansys_four_bars.dxf"


def test_import_prints_a_table_per_link(capsys):
    assert main(["import", str(SEED)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("ansys_four_bars.dxf: DXF AC1027, units m ($INSUNITS), 4 link(s)")
    for name in ("crank", "coupler", "output", "ground"):
        assert f"link {name} (layer {name})" in out
    # crank: 1.2 x 0.5 m less two 20 mm holes = 0.6 - 2 pi 1e-4 = 0.599372 m^2
    assert "0.599372" in out and "(1, 0) (point)" in out and "2 (2 circular, diameter 0.02 m (circle), 0.02 m (circle))" in out


def test_import_writes_round_off_of_coordinates_and_gaps_as_zero(capsys):
    """The tutorial's drawing in mm: its ground's centroid lies on the x axis and its arcs close exactly,
    yet their arithmetic leaves -4e-19 m and 3e-18 m: noise against a 0.11 m link, written 0."""
    import re

    assert main(["import", str(REPO / "docs" / "tutorial" / "fourbar.dxf")]) == 0
    out = capsys.readouterr().out
    assert "centroid [m]" in out and "(0.055, 0)" in out
    assert not re.search(r"e-1[0-9]", out), out


def test_import_json_has_the_design_shape(tmp_path, capsys):
    out = tmp_path / "links.json"
    assert main(["import", str(SEED), "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert [link["name"] for link in data["links"]] == ["crank", "coupler", "output", "ground"]
    crank = data["links"][0]
    assert {"name", "area_m2", "centroid_m", "polar_moment_area_m4", "joints_m", "holes", "profile"} <= set(crank)
    assert set(crank["profile"]) == {"x_m", "upper_m", "lower_m"}
    assert crank["area_m2"] == pytest.approx(0.6 - 2 * np.pi * 1e-4, rel=1e-12)
    assert crank["joints_m"] == [[0.0, 0.0], [1.0, 0.0]] and crank["joint_rules"] == ["point", "point"]
    assert crank["holes"][0]["diameter_m"] == pytest.approx(0.02, rel=1e-12)
    # U(x), L(x) of the bar in the frame of its joints: +-0.25 m from x = -0.1 to 1.1 m.
    x, upper, lower = (np.array(crank["profile"][k]) for k in ("x_m", "upper_m", "lower_m"))
    assert x[0] == pytest.approx(-0.1, abs=1e-12) and x[-1] == pytest.approx(1.1, abs=1e-12)
    assert np.allclose(upper, 0.25, atol=1e-12) and np.allclose(lower, -0.25, atol=1e-12)
    assert not list(tmp_path.glob(".*.tmp"))


def test_a_link_with_fewer_than_two_joints_gets_a_note_instead_of_a_profile(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    doc.modelspace().add_lwpolyline([(0, 0), (1, 0), (1, 1), (0, 1)], close=True)
    out = tmp_path / "links.json"
    assert main(["import", str(save(doc, tmp_path)), "--json", str(out)]) == 0
    link = json.loads(out.read_text())["links"][0]
    assert link["profile"] is None
    assert link["profile_note"].startswith("a profile U(x), L(x) needs a member frame, which needs two joints")


def test_import_draws_a_png(tmp_path):
    out = tmp_path / "links.png"
    assert main(["import", str(SEED), "--plot", str(out)]) == 0
    assert out.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")


def run_cli(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "linkstress", *args], capture_output=True, text=True, cwd=cwd)


@pytest.mark.parametrize("case", ["open", "not dxf", "csv junk"])
def test_bad_input_exits_2_with_one_message_and_writes_only_the_json_of_its_problems(tmp_path, case):
    if case == "open":
        doc = ezdxf.new("R2013", units=4)
        draw(doc.modelspace(), [r for r in plate_entities() if r[0] != "line"])
        doc.modelspace().add_line((0, 0), (99.5, 0))
        sketch = save(doc, tmp_path)
        expected = ("linkstress: error: sketch.dxf: no link imports, 2 problems (1 open chain, 1 outline left out with "
                    "another's problem): (1) open outline: the end of LINE")
    elif case == "not dxf":
        sketch = tmp_path / "sketch.dxf"
        sketch.write_text("hello\nworld\n")
        expected = "linkstress: error: sketch.dxf: not a DXF file"
    else:
        sketch = tmp_path / "sketch.csv"
        sketch.write_text("X, Y\nNew Line\n0, 0\n1, oops\n")
        expected = "linkstress: error: sketch.csv: line 4: 'oops' is not a number"
    result = run_cli("import", str(sketch), "--json", "out.json", "--plot", "out.png", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.startswith(expected) and result.stderr.count("\n") == 1
    assert "Traceback" not in result.stderr and result.stdout == ""
    # A sketch refused for its problems writes them (only them); a file at fault writes nothing.
    written = ["out.json"] if case == "open" else []
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([sketch.name, *written])
    if case == "open":
        data = json.loads((tmp_path / "out.json").read_text())
        assert data["links"] == [] and result.stderr == f"linkstress: error: {data['refused']} (every problem in out.json)\n"
        assert [p["kind"] for p in data["problems"]] == ["open_chain", "left_out_with_another"]


def test_an_unwritable_output_exits_2_and_leaves_no_file(tmp_path):
    result = run_cli("import", str(SEED), "--json", "links.json", "--plot", "no/such/folder/x.png", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.startswith("linkstress: error: --plot: folder 'no/such/folder' does not exist")
    assert list(tmp_path.iterdir()) == []


def _crossing(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    doc.modelspace().add_lwpolyline([(0, 0), (2, 0), (2, 1), (0, 1)], close=True)
    doc.modelspace().add_lwpolyline([(1, 0.5), (3, 0.5), (3, 2), (1, 2)], close=True)
    return save(doc, tmp_path), "outlines cross or touch at"


def _empty(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    doc.modelspace().add_text("nothing")
    return save(doc, tmp_path), "no outline: the drawing has no curves it reads"


def _truncated(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    draw(doc.modelspace(), plate_entities())
    data = save(doc, tmp_path).read_bytes()
    (tmp_path / "sketch.dxf").write_bytes(data[:data.index(b"ENTITIES") + 300])
    return tmp_path / "sketch.dxf", "(note: the file is damaged"


@pytest.mark.parametrize("make", [_crossing, _empty, _truncated])
def test_more_bad_sketches_exit_2_in_process_with_one_line(tmp_path, capsys, monkeypatch, make):
    sketch, expected = make(tmp_path)
    monkeypatch.chdir(tmp_path)
    assert main(["import", str(sketch), "--json", "out.json", "--plot", "out.png"]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith("linkstress: error: sketch.dxf: ") and expected in captured.err
    assert captured.err.count("\n") == 1 and captured.out == ""
    # Refused for its problems (the crossing), the sketch writes their JSON alone; refused as a file, nothing.
    written = ["out.json"] if make is _crossing else []
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["sketch.dxf", *written])
