"""Hostile sketches at the command line: each gets exit code 2 and ONE line on stderr naming the file,
the culprit and what to do, within a bounded time and without writing the JSON, or imports correctly
with stderr empty. Every file is generated here; every run is a fresh ``linkstress import`` process,
so that what libraries print (ezdxf's log, numpy's warnings) would show on its stderr."""

from __future__ import annotations

import json
import math
import random
import resource
import subprocess
import sys
import time
import warnings

import ezdxf
import numpy as np
import pytest

from linkstress.cli import main
from linkstress.errors import SceneError, SketchError
from linkstress.importers import flatten, read_sketch, summary
from linkstress.scene import load_scene
from test_scene_errors import BASE
from linkstress.importers import sketch as sketch_module

BOUND_S = 30.0
"""Wall time a refusal may take, process start included: a guard against a hostile file that makes the
import blow up (minutes, or never), loose enough for a shared machine under load (a refusal takes
about a second; 12 s was seen with five heavy processes on two cores)."""


def linkstress_import(tmp_path, sketch, *options):
    """``linkstress import SKETCH OPTIONS --json OUT`` in a fresh process: (process, seconds, OUT)."""
    out = tmp_path / f"{sketch.name}.json"
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "linkstress", "import", str(sketch), *options, "--json", str(out)],
        capture_output=True, text=True, timeout=60,
    )
    return done, time.perf_counter() - start, out


def refused(tmp_path, sketch, *options) -> str:
    """The one error message of a refused import (checked: exit 2, one stderr line, no traceback, no
    output file, within ``BOUND_S``), without its ``linkstress: error: `` prefix."""
    done, seconds, out = linkstress_import(tmp_path, sketch, *options)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr and done.stdout == ""
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkstress: error: "), done.stderr
    assert not out.exists() and not list(tmp_path.glob(".*.tmp"))
    assert seconds < BOUND_S
    return lines[0].removeprefix("linkstress: error: ")


def imported(tmp_path, sketch, *options) -> dict:
    """The JSON of an import that succeeded with nothing on stderr."""
    done, _, out = linkstress_import(tmp_path, sketch, *options)
    assert done.returncode == 0 and done.stderr == "", done.stderr
    return json.loads(out.read_text())


def rectangle(msp, x0, y0, x1, y1, layer="0"):
    for a, b in (((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)), ((x1, y1), (x0, y1)), ((x0, y1), (x0, y0))):
        msp.add_line(a, b, dxfattribs={"layer": layer})


def drawing(tmp_path, name="sketch.dxf", units=6, draw=None):
    """A DXF in ``units`` ($INSUNITS; 6 = m) with what ``draw(msp)`` adds: its path."""
    doc = ezdxf.new("R2013", units=units)
    draw(doc.modelspace())
    doc.saveas(tmp_path / name)
    return tmp_path / name


# -- DXF tags and numbers ---------------------------------------------------------------------------


def test_a_twenty_digit_group_code_is_read_in_recover_mode_and_noted(tmp_path):
    text = drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2, 1)).read_text()
    first_line = text.index("\nLINE\n")
    (tmp_path / "code.dxf").write_text(text[:first_line] + text[first_line:].replace("\n330\n", "\n12345678901234567890\n", 1))
    data = imported(tmp_path, tmp_path / "code.dxf")
    assert data["links"][0]["area_m2"] == pytest.approx(2.0, rel=1e-12)
    assert any("'12345678901234567890' is not a group code); read in ezdxf's recover mode" in f for f in data["fixes"])


@pytest.mark.parametrize("tag", [" \x00", " \x000"])
def test_a_damaged_tag_holding_a_nul_is_quoted_on_one_printable_line(tmp_path, tag):
    """ezdxf quotes the bad tag in its message; the file's control characters must not reach ours
    (recoverable or not)."""
    text = drawing(tmp_path, units=0, draw=lambda msp: rectangle(msp, 0, 0, 2, 1)).read_text()
    first_line = text.index("\nLINE\n")
    (tmp_path / "nul.dxf").write_text(text[:first_line] + text[first_line:].replace("\n330\n", f"\n{tag}\n", 1))
    with pytest.raises(SketchError) as refused:
        read_sketch(tmp_path / "nul.dxf")
    message = str(refused.value)
    assert "damaged" in message and message.isprintable()


def test_a_line_to_x_1e300_is_refused_naming_it(tmp_path):
    def draw(msp):
        rectangle(msp, 0, 0, 2, 1)
        msp.add_line((0, 0), (1e300, 0), dxfattribs={"layer": "stray"})

    message = refused(tmp_path, drawing(tmp_path, draw=draw))
    assert message.startswith("sketch.dxf: LINE (handle ")
    assert ", layer 'stray') reaches 1e+300 m from the origin, beyond the 1e+06 m a sketch may span; " in message
    assert message.endswith("fix or delete it, or check the drawing's units (m, $INSUNITS)")


def test_a_drawing_scaled_to_1e300_is_refused(tmp_path):
    message = refused(tmp_path, drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2e300, 1e300)))
    assert "reaches 2e+300 m from the origin, beyond the 1e+06 m" in message


def test_a_drawing_placed_at_1e308_is_refused(tmp_path):
    message = refused(tmp_path, drawing(tmp_path, draw=lambda msp: rectangle(msp, 1e308, 1e308, 1e308 + 2e292, 1e308 + 1e292)))
    assert "reaches 1e+308 m from the origin" in message


def test_the_reach_limit_is_in_metres_after_units(tmp_path):
    # 2e8 mm = 2e5 m is within 1e6 m; 2e9 mm is not.
    near = drawing(tmp_path, "near.dxf", units=4, draw=lambda msp: rectangle(msp, 0, 0, 2e8, 1e8))
    assert imported(tmp_path, near)["links"][0]["area_m2"] == pytest.approx(2e10, rel=1e-12)
    far = drawing(tmp_path, "far.dxf", units=4, draw=lambda msp: rectangle(msp, 0, 0, 2e9, 1e9))
    assert "reaches 2e+06 m from the origin" in refused(tmp_path, far)


def test_a_small_part_far_from_the_origin_is_refused(tmp_path):
    # A 2 x 1 mm part at 10 km: 4.5e6 sizes out, where rounding (1e4 m x 1.1e-16) nears the merging distance.
    path = drawing(tmp_path, units=4, draw=lambda msp: rectangle(msp, 1e7, 1e7, 1e7 + 2, 1e7 + 1))
    message = refused(tmp_path, path)
    assert "the drawing is 2.24 mm across but lies 1e+07 mm from the origin, more than 1e+06 times its size" in message
    assert message.endswith("move the drawing near the origin")


def test_a_drawing_smaller_than_a_nanometre_is_refused(tmp_path):
    message = refused(tmp_path, drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2e-10, 1e-10)))
    assert "the drawing is 2.24e-10 m across, smaller than 1e-09 m; check the drawing's units (m, $INSUNITS)" in message


def test_a_file_holding_only_a_zero_radius_circle_says_so(tmp_path):
    message = refused(tmp_path, drawing(tmp_path, draw=lambda msp: msp.add_circle((1, 1), 0)))
    assert message == ("sketch.dxf: no outline: the drawing has no curves it reads (only 1 CIRCLE (radius <= 0) "
                       "was found, which is not outline geometry)")


def test_a_spline_with_a_control_point_at_1e300_is_refused_before_flattening(tmp_path):
    def draw(msp):
        rectangle(msp, 0, 0, 2, 1)
        msp.add_open_spline([(0, 0), (1, 1e300), (2, 0), (3, 1)], dxfattribs={"layer": "curve"})

    message = refused(tmp_path, drawing(tmp_path, draw=draw))
    assert "SPLINE (handle " in message and ", layer 'curve') reaches 1e+300 m from the origin" in message


def test_spline_flattening_is_bounded(tmp_path, monkeypatch):
    # A circle-like spline needs thousands of vertices at 1e-7 of the drawing; allow it 100.
    monkeypatch.setattr(flatten, "MAX_SPLINE_VERTICES", 100)
    points = [(math.cos(t), math.sin(t)) for t in np.linspace(0, 2 * math.pi, 13)]
    path = drawing(tmp_path, draw=lambda msp: msp.add_spline(points, dxfattribs={"layer": "cam"}))
    with pytest.raises(SketchError, match=r"the splines up to SPLINE \(handle \w+, layer 'cam'\) need more than the 100 vertices all splines may take"):
        read_sketch(path)


# -- settings that ask for unbounded work ---------------------------------------------------------


def test_sagitta_1e_minus_15_is_refused_before_any_vertex_is_made(tmp_path):
    message = refused(tmp_path, drawing(tmp_path, draw=lambda msp: msp.add_circle((0, 0), 1)), "--sagitta", "1e-15")
    # One circle: steps of 2 acos(1 - 1e-15) = 8.9e-8 rad, 70.3 million per turn.
    assert message.startswith("sketch.dxf: the chord tolerance --sagitta 1e-15 asks for about 70,276,241 vertices "
                              "(70,276,239 on 1 arc(s)), more than the limit of 5,000,000; use --sagitta ")
    # Steps go as 1 / sqrt(sagitta): 1e-15 x (70.3e6 / 5e6)^2 = 1.98e-13, rounded up.
    assert message.endswith("use --sagitta 2e-13 or more (the default is 0.0001)")


@pytest.mark.parametrize("sagitta", ["0", "-1", "nan", "inf", "0.5"])
def test_sagitta_outside_a_fraction_is_refused(tmp_path, sagitta):
    path = drawing(tmp_path, draw=lambda msp: msp.add_circle((0, 0), 1))
    with pytest.raises(SketchError, match=r"^sketch.dxf: the chord tolerance \(--sagitta\) must be a fraction of the "
                                          r"radius in \(0, 0.5\), got "):
        read_sketch(path, sagitta=float(sagitta))


@pytest.mark.parametrize("tolerance", ["1e-300", "5e-324", "0", "-1", "nan", "inf", "0.5", "1e300"])
def test_gap_tolerance_extremes_are_refused(tmp_path, tolerance):
    path = drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2, 1))
    with pytest.raises(SketchError, match=r"^sketch.dxf: the gap tolerance \(--tolerance\) is a fraction of the "
                                          r"drawing size in \[1e-09, 0.5\), got "):
        read_sketch(path, tolerance=float(tolerance))


def test_a_tiny_gap_tolerance_is_refused_at_the_command_line(tmp_path):
    message = refused(tmp_path, drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2, 1)), "--tolerance", "1e-300")
    assert message == "sketch.dxf: the gap tolerance (--tolerance) is a fraction of the drawing size in [1e-09, 0.5), got 1e-300"


# -- blocks ---------------------------------------------------------------------------------------


def test_a_block_that_inserts_itself_is_named(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    block = doc.blocks.new("WHEEL")
    block.add_circle((0, 0), 1)
    block.add_blockref("WHEEL", (5, 0))
    doc.modelspace().add_blockref("WHEEL", (0, 0))
    doc.saveas(tmp_path / "self.dxf")
    message = refused(tmp_path, tmp_path / "self.dxf")
    assert message.startswith("self.dxf: block 'WHEEL' inserts itself (INSERT (handle ")
    assert message.endswith("a block cannot contain itself: delete the reference to 'WHEEL' from its definition in CAD")


def test_a_block_that_inserts_itself_through_another_is_named(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    doc.blocks.new("A").add_blockref("B", (0, 0))
    b = doc.blocks.new("B")
    b.add_circle((0, 0), 1)
    b.add_blockref("A", (0, 0))
    doc.modelspace().add_blockref("A", (0, 0))
    doc.saveas(tmp_path / "loop.dxf")
    assert refused(tmp_path, tmp_path / "loop.dxf").startswith("loop.dxf: block 'A' inserts itself through block 'B' (INSERT")


def test_blocks_nested_20_deep_are_read(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    doc.blocks.new("L0").add_circle((0, 0), 1)
    for k in range(1, 20):
        doc.blocks.new(f"L{k}").add_blockref(f"L{k - 1}", (0.5, 0))  # each level moves the disc 0.5 m
    doc.modelspace().add_blockref("L19", (0, 0))
    doc.saveas(tmp_path / "deep.dxf")
    link = imported(tmp_path, tmp_path / "deep.dxf")["links"][0]
    assert link["area_m2"] == pytest.approx(math.pi, rel=1e-9)
    assert link["centroid_m"] == pytest.approx([19 * 0.5, 0.0], abs=1e-9)


def test_block_expansion_is_counted_before_expanding(tmp_path):
    # Two references per level, 18 levels: 2^17 = 131,072 lines, refused without building them.
    doc = ezdxf.new("R2013", units=6)
    doc.blocks.new("T0").add_line((0, 0), (1, 0))
    for k in range(1, 18):
        level = doc.blocks.new(f"T{k}")
        level.add_blockref(f"T{k - 1}", (0, 0))
        level.add_blockref(f"T{k - 1}", (0, 1))
    doc.modelspace().add_blockref("T17", (0, 0))
    doc.saveas(tmp_path / "tree.dxf")
    message = refused(tmp_path, tmp_path / "tree.dxf")
    assert "of block 'T17' expands to 131,072 entities, more than the 20,000 linkstress expands" in message


# -- CSV ------------------------------------------------------------------------------------------


def test_a_csv_header_with_two_units_is_refused(tmp_path):
    path = tmp_path / "plate.csv"
    path.write_text("# linkstress-sketch v1 units=mm units=cm\ncircle, 0, 0, 10\n")
    assert refused(tmp_path, path) == "plate.csv: line 1: the header gives two units, mm and cm; keep the one the numbers are in"


def test_a_csv_circle_at_1e300_cm_is_refused_naming_its_line(tmp_path):
    path = tmp_path / "plate.csv"
    path.write_text("# linkstress-sketch v1 units=cm\ncircle, 0, 0, 10\ncircle, 1e300, 0, 1\n")
    # 1e300 cm + the radius is 1e298 m from the origin.
    assert refused(tmp_path, path) == (
        "plate.csv: circle on line 3 reaches 1e+298 m from the origin, beyond the 1e+06 m a sketch may span; "
        "fix or delete it, or check the drawing's units (cm, the header's units=)")


# -- files that are not sketches --------------------------------------------------------------------


def test_a_file_that_is_not_a_sketch_is_never_quoted(tmp_path):
    secret = "daemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin"
    path = tmp_path / "passwd"
    path.write_text(f"root:x:0:0:root:/root:/bin/bash\n{secret}\n")
    message = refused(tmp_path, path)
    assert message == ("passwd: line 2: not a DXF or linkstress CSV sketch (an iLogic CSV's data starts with a "
                       "'New <entity>' line, a linkstress-sketch CSV with '# linkstress-sketch v1'); give a sketch "
                       "exported from CAD")
    assert "daemon" not in message


def test_a_scene_pointing_its_sketch_at_a_system_file_does_not_echo_it(tmp_path):
    (tmp_path / "etc").mkdir()
    (tmp_path / "etc" / "passwd").write_text("root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin\n")
    (tmp_path / "a" / "b").mkdir(parents=True)
    scene = tmp_path / "a" / "b" / "scene.toml"
    scene.write_text(BASE.replace("[links.crank]\njoints = [[0.0, 0.0], [0.02, 0.0]]",
                                  '[links.crank]\nsketch = "../../etc/passwd"'))
    with pytest.raises(SceneError) as error:
        load_scene(scene)
    message = str(error.value)
    assert message.startswith("scene.toml: links.crank.sketch: passwd: line 2: not a DXF or linkstress CSV sketch")
    assert "daemon" not in message and "root" not in message


def test_a_non_utf8_text_file_is_refused_without_quoting_it(tmp_path):
    path = tmp_path / "notes.csv"
    path.write_bytes("x, y\nCafé au lait, 3\n".encode("latin-1"))
    assert refused(tmp_path, path) == (
        "notes.csv: line 2: not UTF-8 text (byte 0xe9): not a DXF or linkstress CSV sketch, or one saved in another "
        "encoding; save the sketch as UTF-8 text")


@pytest.mark.parametrize("name, message", [
    ("empty.dxf", "empty.dxf: not a DXF file (no DXF SECTION at its start); export the sketch from CAD as DXF, or give a .csv sketch"),
    ("empty.csv", "empty.csv: no outline: the drawing has no curves"),
    ("empty", "empty: no outline: the drawing has no curves"),
])
def test_an_empty_file_is_refused(tmp_path, name, message):
    (tmp_path / name).write_bytes(b"")
    assert refused(tmp_path, tmp_path / name) == message


def test_a_directory_as_the_sketch_is_refused(tmp_path):
    (tmp_path / "plate.dxf").mkdir()
    message = refused(tmp_path, tmp_path / "plate.dxf")
    assert message.startswith("the sketch ") and "plate.dxf' is a folder, not a file: give the path of a sketch saved as a file" in message


def test_a_dxf_truncated_in_its_header_is_refused_with_the_damage_noted(tmp_path):
    data = drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2, 1)).read_bytes()
    (tmp_path / "cut.dxf").write_bytes(data[:data.index(b"$INSUNITS")])
    message = refused(tmp_path, tmp_path / "cut.dxf")
    # Cut before its entities, it has no curves: said before the units it lacks too (they would not matter).
    assert message.startswith("cut.dxf: no outline: the drawing has no curves (note: the file is damaged")
    assert message.endswith("(note: the file is damaged (the file ends before its structure does (truncated?)); read in ezdxf's recover mode)")


def test_a_binary_dxf_is_read(tmp_path):
    doc = ezdxf.new("R2013", units=6)
    rectangle(doc.modelspace(), 0, 0, 2, 1)
    doc.saveas(tmp_path / "binary.dxf", fmt="bin")
    assert (tmp_path / "binary.dxf").read_bytes().startswith(b"AutoCAD Binary DXF")
    assert imported(tmp_path, tmp_path / "binary.dxf")["links"][0]["area_m2"] == pytest.approx(2.0, rel=1e-12)


def test_a_dxf_without_a_header_section_is_read_with_given_units(tmp_path):
    lines = "".join(f"0\nLINE\n8\nbar\n10\n{a}\n20\n{b}\n11\n{c}\n21\n{d}\n"
                    for a, b, c, d in ((0, 0, 2, 0), (2, 0, 2, 1), (2, 1, 0, 1), (0, 1, 0, 0)))
    path = tmp_path / "bare.dxf"
    path.write_text(f"0\nSECTION\n2\nENTITIES\n{lines}0\nENDSEC\n0\nEOF\n")
    assert refused(tmp_path, path).startswith(
        "bare.dxf: the file does not say its units (it has no HEADER section, so no $INSUNITS): pass --units")
    assert imported(tmp_path, path, "--units", "mm")["links"][0]["area_m2"] == pytest.approx(2e-6, rel=1e-12)


# -- what libraries print ---------------------------------------------------------------------------


def test_ezdxf_recover_warnings_go_into_the_fixes_not_onto_stderr(tmp_path):
    text = drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2, 1)).read_text()
    # A garbled number and no EOF: ezdxf's recover mode repairs both and logs what it did.
    damaged = text.replace("\n 11\n2.0\n", "\n 11\n2.0x\n", 1)
    (tmp_path / "damaged.dxf").write_text(damaged[:damaged.rindex("EOF")])
    data = imported(tmp_path, tmp_path / "damaged.dxf")
    assert data["links"][0]["area_m2"] == pytest.approx(2.0, rel=1e-12)
    assert 'ezdxf recover: recovered invalid floating point value "2.0x" near line ' in " ".join(data["fixes"])
    assert len(data["fixes"]) == len(set(data["fixes"]))


def test_numpy_warnings_while_reading_go_into_the_fixes(tmp_path, monkeypatch):
    real = sketch_module.flatten

    def overflowing(curves, tolerance):
        np.float64(1e308) * 10.0  # noqa: B018 - the overflow warning is the point
        return real(curves, tolerance)

    monkeypatch.setattr(sketch_module, "flatten", overflowing)
    path = drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2, 1))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning that escaped read_sketch would fail the test
        sketch = read_sketch(path)
    assert "library warning: RuntimeWarning: overflow encountered in scalar multiply" in sketch.fixes


def test_a_non_finite_result_is_not_written(tmp_path, monkeypatch, capsys):
    real = summary.sketch_json
    monkeypatch.setattr(summary, "sketch_json",
                        lambda sketch, refused=None: {**real(sketch, refused), "gap_tolerance_m": math.nan})
    path = drawing(tmp_path, draw=lambda msp: rectangle(msp, 0, 0, 2, 1))
    assert main(["import", str(path), "--json", str(tmp_path / "links.json")]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and not (tmp_path / "links.json").exists()
    assert captured.err.startswith("linkstress: error: sketch.dxf: the results hold a non-finite number; nothing written")


# -- piles of repeats -------------------------------------------------------------------------------


def test_thirty_thousand_points_on_one_spot_are_dropped_as_repeats_in_bounded_memory(tmp_path):
    # They made 450 million close pairs (2.2 GB); exact repeats are now dropped by a sort first.
    def draw(msp):
        rectangle(msp, 0, 0, 0.1, 0.05)
        for _ in range(30_000):
            msp.add_point((0.01, 0.01))

    sketch = drawing(tmp_path, draw=draw)
    done = subprocess.run(
        [sys.executable, "-m", "linkstress", "import", str(sketch)], capture_output=True, text=True, timeout=60,
        preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (2 * 2**30, resource.RLIM_INFINITY)),
    )
    assert done.returncode == 0, done.stderr
    assert "dropped 29999 POINT(s) repeating another" in done.stdout


def test_a_cloud_of_points_within_the_gap_tolerance_is_refused_naming_the_flag(tmp_path):
    # 30,000 distinct POINTs within 0.1 micrometre of one spot on a 100 mm plate (tolerance 1e-4 x
    # its size, 0.011 mm): 450 million close pairs, counted without listing them.
    rng = random.Random(7)

    def draw(msp):
        rectangle(msp, 0, 0, 0.1, 0.05)
        for _ in range(30_000):
            msp.add_point((0.01 + rng.uniform(-1e-7, 1e-7), 0.01 + rng.uniform(-1e-7, 1e-7)))

    message = refused(tmp_path, drawing(tmp_path, draw=draw))
    assert "pairs of POINTs lie within the gap tolerance" in message and "more than 1,000,000" in message
    assert message.endswith("give a smaller --tolerance")
