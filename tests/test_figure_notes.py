"""What matplotlib warns while a figure is drawn never reaches the terminal: it becomes a note.

The fonts matplotlib ships (DejaVu) have no CJK ideographs: a link or layer named 曲柄 (crank) makes
it warn "Glyph 26354 (...) missing from font(s) DejaVu Sans." for each character, with the path of
the line that drew it. Every figure writer draws inside ``figure_warnings``.
"""

from __future__ import annotations

import io
import subprocess
import sys
import textwrap
from pathlib import Path

import ezdxf
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from linkstress.report.figure_notes import MAX_NOTES, figure_notes, figure_warnings
from linkstress.report.figures import png_bytes

CJK = "曲柄连杆"
"""crank, coupler: four ideographs, code points 26354, 26564, 36830, 26438."""


def labelled_figure(text: str, **options) -> Figure:
    fig = Figure(figsize=(2, 1))
    FigureCanvasAgg(fig)
    fig.add_subplot().text(0.1, 0.5, text, **options)
    return fig


def test_missing_glyphs_become_one_note_naming_the_characters():
    notes: list[str] = []
    png = png_bytes(labelled_figure(CJK + " " + CJK[:2]), notes=notes)
    assert png.startswith(b"\x89PNG")
    assert notes == [f"the figure's font lacks 4 character(s): {CJK} (drawn as empty boxes)"]


def test_a_font_family_matplotlib_cannot_find_is_a_note_not_a_log_line(capsys):
    with figure_warnings() as notes:
        labelled_figure("x", family="No Such Font Family").savefig(io.BytesIO(), format="png")
    assert any(note.startswith("library warning: findfont: Font family") and "No Such Font Family" in note for note in notes)
    assert capsys.readouterr().err == ""


def test_notes_are_distinct_and_capped():
    messages = [f"UserWarning: warning {k % 8}" for k in range(40)] + ["Glyph 26354 (x) missing from font(s) A."] * 3
    notes = figure_notes(messages)
    assert notes[0] == "the figure's font lacks 1 character(s): 曲 (drawn as empty boxes)"
    assert notes[1:] == [f"library warning: UserWarning: warning {k}" for k in range(MAX_NOTES)] + [
        f"library warning: {8 - MAX_NOTES} more not listed"
    ]


def run(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "linkstress", *args], capture_output=True, text=True, cwd=cwd, timeout=120)


def test_import_plot_of_cjk_layers_prints_nothing_on_stderr(tmp_path):
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for k, layer in enumerate(("曲柄", "连杆")):
        y = 100 * k
        msp.add_lwpolyline([(-20, y - 15), (120, y - 15), (120, y + 15), (-20, y + 15)], close=True, dxfattribs={"layer": layer})
        for x in (0, 100):
            msp.add_circle((x, y), 5, dxfattribs={"layer": layer})
    doc.saveas(tmp_path / "cjk.dxf")
    done = run("import", "cjk.dxf", "--plot", "cjk.png", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""
    assert (tmp_path / "cjk.png").read_bytes().startswith(b"\x89PNG")


def test_analyze_html_of_a_link_named_in_cjk_prints_nothing_on_stderr(tmp_path):
    scene = textwrap.dedent("""
        [links."曲柄"]
        joints = [[0.0, 0.0], [0.08, 0.0]]
        [links."连杆"]
        joints = [[0.0, 0.0], [0.08, 0.0]]
        [links.output]
        joints = [[0.0, 0.0], [0.09, 0.0]]
        [links.ground]
        joints = [[0.0, 0.0], [0.06, 0.0]]

        [mechanisms.main]
        type = "four-bar"
        crank = "曲柄"
        coupler = "连杆"
        output = "output"
        ground = "ground"

        [motion]
        input_angle_deg = {start = 0.0, stop = 350.0, num = 36}
        input_speed_rad_s = 10.0
    """)
    (tmp_path / "scene.toml").write_text(scene, encoding="utf-8")
    done = run("analyze", "scene.toml", "--html", "report.html", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""
    assert "曲柄" in (tmp_path / "report.html").read_text(encoding="utf-8")
