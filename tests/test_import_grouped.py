"""What import prints about a dirty sheet: its problems first, grouped by kind with counts and the first
few of each; a refused import still writes every problem to --json; every list in a message is capped
("first 5 of N").

Every sheet is generated here with ezdxf, in mm.
"""

from __future__ import annotations

import json

import ezdxf
import pytest

from linkstress.cli import main
from test_import_dxf import save
from test_import_sheets import bar


def strays(msp, n: int, y0: float = 100.0) -> None:
    """``n`` short stray LINEs (tick marks) in rows above the parts."""
    for k in range(n):
        x, y = 5.0 * (k % 60), y0 + 10.0 * (k // 60)
        msp.add_line((x, y), (x, y + 3.0))


def crossing_pair(msp, x0: float) -> None:
    """Two rectangles of one layer that cross."""
    msp.add_lwpolyline([(x0, 0), (x0 + 20, 0), (x0 + 20, 10), (x0, 10)], close=True, dxfattribs={"layer": "plates"})
    msp.add_lwpolyline([(x0 + 10, 5), (x0 + 30, 5), (x0 + 30, 15), (x0 + 10, 15)], close=True, dxfattribs={"layer": "plates"})


@pytest.mark.parametrize("n_strays, n_pairs", [(183, 2), (7, 1), (61, 3)])
def test_problems_print_first_grouped_by_kind_with_counts_and_the_first_five_of_each(tmp_path, capsys, n_strays, n_pairs):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    bar(msp, 0, 0, 150, layer="crank")
    strays(msp, n_strays)
    for k in range(n_pairs):
        crossing_pair(msp, 200 + 50 * k)
    out = tmp_path / "links.json"
    assert main(["import", str(save(doc, tmp_path)), "--json", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    total = n_strays + n_pairs
    assert lines[0].endswith(f"1 link(s), {total} problem(s)")
    assert lines[2] == f"problems ({total}, left out of the links below; every one in --json):"
    first = f": first 5 of {n_strays}" if n_strays > 5 else ""
    assert lines[3] == f"- {n_strays} open chains{first}"
    shown = min(n_strays, 5)
    assert all(line.startswith("  - open curve: LINE") for line in lines[4:4 + shown])
    pairs = "1 pair of outlines crossing or touching" if n_pairs == 1 else f"{n_pairs} pairs of outlines crossing or touching"
    assert lines[4 + shown] == f"- {pairs}"
    assert all(line.startswith("  - outlines cross or touch at") for line in lines[5 + shown:5 + shown + n_pairs])
    assert lines.index("link crank (layer crank)") == 6 + shown + n_pairs
    problems = json.loads(out.read_text())["problems"]
    assert len(problems) == total
    assert sorted({p["kind"] for p in problems}) == ["crossing", "open_chain"]


def test_a_refused_sheet_writes_every_problem_to_json_and_one_capped_line_to_the_terminal(tmp_path, capsys):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    strays(msp, 183)
    crossing_pair(msp, 400)
    crossing_pair(msp, 450)
    out = tmp_path / "links.json"
    assert main(["import", str(save(doc, tmp_path)), "--json", str(out), "--plot", str(tmp_path / "links.png")]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert captured.err.startswith("linkstress: error: sketch.dxf: no link imports, 185 problems (183 open chains, 2 pairs "
                                   "of outlines crossing or touching): (1) open curve: LINE")
    # the first of each kind: the crossing that refused a part is not hidden behind the tick marks
    assert "; (2) outlines cross or touch at" in captured.err
    assert "; and 183 more (every one in linkstress import --json) (every problem in " in captured.err
    assert len(captured.err) < 2000
    data = json.loads(out.read_text())  # the only output written
    assert not (tmp_path / "links.png").exists()
    assert data["links"] == [] and len(data["problems"]) == 185 and data["refused"].startswith("sketch.dxf: no link imports")


def test_an_import_scene_refusal_of_a_sheet_of_sixty_parts_names_the_first_five(tmp_path, capsys):
    doc = ezdxf.new("R2013", units=4)
    for k in range(60):  # sixty links drawn apart: no joint shared, no mechanism
        bar(doc.modelspace(), 0, 40 * k, 100 + k, layer=f"link{k:02d}", points=True)
    path = save(doc, tmp_path)
    assert main(["import", str(path), "--scene", str(tmp_path / "scene.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and len(err) < 1000
    assert "no two of the links ('link00', 'link01', 'link02', 'link03', 'link04' (first 5 of 60)) share a joint" in err
