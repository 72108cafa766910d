"""Hostile inputs through every command, generated: no traceback, no nan, no half-written file.

A seeded generator (one ``random.Random`` per case, seeded with the case's name, so that a failure
names a case that reproduces) mutates valid inputs the way the tester's 594 did: numbers replaced by
extremes (1e300, 1e-300, nan, inf, 20-digit integers), wrong types, group codes and keys corrupted,
files truncated, cut or flipped, paths that lead nowhere or out of the tree, and settings that ask
for unbounded work. Four families: DXF sketches (``import``), CSV sketches (``import``), scenes
(``analyze``, a few ``validate`` and ``regress``) and command-line flags (every command).

Every case runs ``linkstress.cli.main`` in this process (a subprocess each would take minutes) and
asserts what a user must see:

- the exit code is 0, 1 or 2 and no exception escapes (an escaping one is a traceback at the
  command line);
- nothing on stdout, and nothing in an output file, spells nan or inf;
- an output file exists only after exit 0 (and then parses as strict JSON), and no temporary file
  is left beside it;
- an error is one ``linkstress: error:`` line on stderr;
- the case finishes within ``TIME_LIMIT`` seconds.

A handful of the same cases also run as real processes, where the terminal's stderr is checked
whole (library warnings and log lines would show there).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import random
import re
import resource
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
from pathlib import Path

import ezdxf
import pytest

from linkstress.cli import main
from linkstress.inputs import SCENE_BYTES, SKETCH_BYTES
from linkstress.scene import load_scene
from linkstress.scene.plausibility import RULES

REPO = Path(__file__).resolve().parents[1]
SEED = REPO / "validation" / "cases" / "seed_ansys_fourbar"
SAMPLE_CSV = REPO / "cad_scripts" / "sample_crank.csv"
TIME_LIMIT = 20.0
"""Seconds a single hostile case may take (the valid analyses among them take well under one)."""
MEMORY_LIMIT = 4 * 2**30
"""Bytes of address space a single case may add to the test process: a case that asks for more
fails with MemoryError here instead of taking the machine's memory."""
NON_FINITE = re.compile(r"(?i)(?<![a-z])(nan|-?inf|-?infinity)(?![a-z])")

HOSTILE_NUMBERS = (
    "1e300", "-1e300", "1e308", "-1.7976931348623157e308", "1e-300", "-1e-300", "5e-324", "0", "-0",
    "nan", "inf", "-inf", "1e400", "123456789012345678901234567890", "-99999999999999999999",
    "0x1F", "1,5", "", " ", "abc", "1e", "--1", "1.0.0", "\u0661\u0662",
)
TOML_HOSTILE = (
    "1e300", "-1e300", "1e-300", "0", "-1", "0.0", "nan", "inf", "-inf", "true", "false", '"abc"',
    '""', "[]", "[1e300, 1e300]", "[nan, 0]", "{}", "{value = 1e300}", "12345678901234567890",
    "9223372036854775807", "-9223372036854775808", "1e18", '"' + "x" * 5000 + '"', "[[1, 2], [3]]",
    "2.5", "[0.0, 0.0, 0.0]", '"../../../../../../etc/passwd"',
)


class CaseTimeout(Exception):
    """Raised by the alarm when a case runs past TIME_LIMIT."""


@contextlib.contextmanager
def bounded(seconds: float, extra_bytes: int):
    """Raise CaseTimeout after ``seconds``, MemoryError past ``extra_bytes`` more address space."""
    def alarm(signum, frame):
        raise CaseTimeout(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    in_use = int(Path("/proc/self/statm").read_text().split()[0]) * resource.getpagesize()
    resource.setrlimit(resource.RLIMIT_AS, (in_use + extra_bytes, hard))
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def run_hostile(argv: list[str], outputs: list[Path]) -> tuple[int, str, str]:
    """Run the CLI on ``argv`` and check everything a hostile input must never cause."""
    out, err = io.StringIO(), io.StringIO()
    with bounded(TIME_LIMIT, MEMORY_LIMIT), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main([str(a) for a in argv])
        except SystemExit as exit_:  # argparse refusing a flag: its usage line, exit 2
            code = exit_.code
    stdout, stderr = out.getvalue(), err.getvalue()
    assert code in (0, 1, 2), (code, stderr[-2000:])
    assert "Traceback" not in stdout + stderr, stderr[-2000:]
    assert not NON_FINITE.search(stdout), NON_FINITE.search(stdout)
    if code == 2:
        errors = [line for line in stderr.splitlines() if line.startswith("linkstress: error:")]
        usage = "usage:" in stderr  # argparse's own refusal
        assert usage or len(errors) == 1, stderr
    for path in outputs:
        siblings = [p.name for p in path.parent.iterdir() if p.name.startswith(f".{path.name}.")]
        assert not siblings, f"temporary files left: {siblings}"
        if path.is_dir():
            continue
        if code != 0:
            # The one output of a failed run: an import refused for its problems writes them (docs/importing.md).
            refused = code == 2 and path.suffix == ".json" and path.exists() and "refused" in json.loads(path.read_text())
            assert refused or not path.exists(), f"exit {code} left {path.name}: {stderr}"
        elif path.exists() and path.suffix == ".json":
            text = path.read_text()
            assert not NON_FINITE.search(text), NON_FINITE.search(text)
            json.loads(text, parse_constant=lambda c: pytest.fail(f"{path.name} holds {c}"))
    return code, stdout, stderr


# ---------------------------------------------------------------------------------------------------
# Valid material to mutate


def plate_dxf(path: Path, units: int = 4) -> Path:
    """A 100 x 50 mm round-ended plate with two 10 mm pin holes and POINTs at their centres."""
    doc = ezdxf.new("R2013", units=units)
    msp = doc.modelspace()
    msp.add_line((0, 0), (100, 0), dxfattribs={"layer": "plate"})
    msp.add_arc((100, 25), 25, -90, 90, dxfattribs={"layer": "plate"})
    msp.add_line((100, 50), (0, 50), dxfattribs={"layer": "plate"})
    msp.add_arc((0, 25), 25, 90, 270, dxfattribs={"layer": "plate"})
    for x in (0, 100):
        msp.add_circle((x, 25), 5, dxfattribs={"layer": "plate"})
        msp.add_point((x, 25), dxfattribs={"layer": "plate"})
    msp.add_spline_control_frame([(20, 10), (40, 20), (60, 10), (80, 20)], dxfattribs={"layer": "notes"})
    doc.saveas(path)
    return path


@pytest.fixture(scope="module")
def corpus(tmp_path_factory) -> dict[str, object]:
    folder = tmp_path_factory.mktemp("corpus")
    shutil.copy(SEED / "ansys_four_bars.dxf", folder)
    return {
        "folder": folder,
        "plate_dxf": plate_dxf(folder / "plate.dxf").read_text().splitlines(),
        "seed_dxf": (folder / "ansys_four_bars.dxf").read_text().splitlines(),
        "sample_csv": SAMPLE_CSV.read_text().splitlines(),
        "scene": (SEED / "scene.toml").read_text(),
    }


def case_folder(tmp_path: Path, corpus: dict) -> Path:
    shutil.copy(corpus["folder"] / "ansys_four_bars.dxf", tmp_path)
    return tmp_path


# ---------------------------------------------------------------------------------------------------
# DXF


def mutate_dxf(rng: random.Random, lines: list[str]) -> str:
    """A DXF text (group code / value line pairs) with one to three hostile edits."""
    lines = list(lines)
    for _ in range(rng.randint(1, 3)):
        if not lines:
            break
        kind = rng.choice(("number", "number", "number", "code", "truncate", "delete", "duplicate", "swap", "bytes"))
        k = rng.randrange(len(lines))
        if kind == "number":
            values = [i for i in range(1, len(lines), 2) if _is_number(lines[i])]
            k = rng.choice(values) if values else k
            lines[k] = rng.choice(HOSTILE_NUMBERS)
        elif kind == "code":
            k -= k % 2
            lines[k] = rng.choice(("12345678901234567890", "-1", "999999", "abc", "", "10.5", "1e3"))
        elif kind == "truncate":
            lines = lines[:k]
        elif kind == "delete":
            del lines[k:k + rng.randint(1, 40)]
        elif kind == "duplicate":
            span = lines[k:k + rng.randint(2, 60)]
            lines[k:k] = span * rng.randint(1, 30)
        elif kind == "swap":
            j = rng.randrange(len(lines))
            lines[k], lines[j] = lines[j], lines[k]
        else:
            lines[k] = "".join(chr(rng.randrange(1, 0x2FF)) for _ in range(rng.randint(1, 30)))
    return "\n".join(lines) + "\n"


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def structural_dxf(rng: random.Random, path: Path) -> None:
    """A DXF built with ezdxf whose geometry is hostile (huge, tiny, degenerate, self-referencing)."""
    kind = rng.choice((
        "zero circle", "far line", "spline", "scaled block", "placed block", "self block", "deep blocks",
        "zero ellipse", "bulge", "tiny plate", "points only", "empty",
    ))
    # R12 has no ELLIPSE, SPLINE or LWPOLYLINE
    versions = ("R2000", "R2013", "R2018") if kind in ("spline", "zero ellipse", "bulge", "tiny plate") else ("R12", "R2000", "R2018")
    doc = ezdxf.new(rng.choice(versions), units=rng.choice((0, 1, 4, 5, 6)))
    msp = doc.modelspace()
    big = rng.choice((1e300, 1e308, -1e300, 1e150, 1e-300, 0.0))
    if kind == "zero circle":
        msp.add_circle((0, 0), rng.choice((0.0, 1e-300, 5e-324)))
    elif kind == "far line":
        msp.add_line((0, 0), (big, rng.choice((0.0, big))))
        msp.add_line((big, 0), (0, 0))
    elif kind == "spline":
        points = [(0, 0), (10, 10), (big, 5), (30, 0)]
        spline = msp.add_open_spline(points, degree=rng.choice((2, 3)))  # control points as given: no fitting
        spline.closed = rng.random() < 0.5
    elif kind in ("scaled block", "placed block"):
        block = doc.blocks.new("LINK")
        block.add_circle((0, 0), 10)
        block.add_circle((0, 0), 2)
        scale = big if kind == "scaled block" else 1.0
        place = (big, big) if kind == "placed block" else (0, 0)
        msp.add_blockref("LINK", place, dxfattribs={"xscale": scale, "yscale": scale})
    elif kind == "self block":
        block = doc.blocks.new("LOOP")
        block.add_circle((0, 0), 10)
        block.add_blockref("LOOP", (1, 1))
        msp.add_blockref("LOOP", (0, 0))
    elif kind == "deep blocks":
        depth = rng.choice((20, 40, 200))
        doc.blocks.new("B0").add_circle((0, 0), 10)
        for level in range(1, depth):
            doc.blocks.new(f"B{level}").add_blockref(f"B{level - 1}", (0, 0))
        msp.add_blockref(f"B{depth - 1}", (0, 0))
    elif kind == "zero ellipse":
        # (ezdxf writes no zero axis; the text mutations above reach those)
        major = (rng.choice((1e-9, 10.0, 1e300)), 0.0)
        msp.add_ellipse((0, 0), major_axis=major, ratio=rng.choice((1e-6, 1.0, 0.5)))
    elif kind == "bulge":
        msp.add_lwpolyline([(0, 0, rng.choice((1e300, 1e-300, 1.0))), (10, 0, 0.0)], format="xyb", close=True)
    elif kind == "tiny plate":
        msp.add_lwpolyline([(0, 0), (1e-12, 0), (1e-12, 1e-12), (0, 1e-12)], close=True)
    elif kind == "points only":
        for _ in range(rng.randint(1, 5)):
            msp.add_point((rng.uniform(-big, big) if math.isfinite(big) else 0.0, 0))
    doc.saveas(path)


def dxf_flags(rng: random.Random) -> list[str]:
    flags = []
    if rng.random() < 0.5:
        flags += ["--units", rng.choice(("mm", "cm", "m", "in", "parsec", "", "1e300", "MM"))]
    if rng.random() < 0.3:
        flags += ["--sagitta", rng.choice(("1e-15", "1e-300", "0", "-1", "nan", "inf", "1e300", "0.5"))]
    if rng.random() < 0.3:
        flags += ["--tolerance", rng.choice(("1e-300", "0", "-1", "nan", "inf", "1e300", "0.5", "1"))]
    return flags


DXF_CASES = 120


@pytest.mark.parametrize("case", range(DXF_CASES))
def test_hostile_dxf_import(tmp_path, corpus, case):
    rng = random.Random(f"dxf-{case}")
    sketch = tmp_path / rng.choice(("sketch.dxf", "sketch.DXF", "noext"))
    if case % 4 == 3:
        structural_dxf(rng, sketch)
    else:
        base = corpus["plate_dxf"] if rng.random() < 0.6 else corpus["seed_dxf"]
        sketch.write_text(mutate_dxf(rng, base), errors="surrogatepass")
    out = tmp_path / "links.json"
    argv = ["import", sketch, "--json", out, *dxf_flags(rng)]
    if sketch.name == "noext" or rng.random() < 0.3:
        argv += ["--units", "mm"] if "--units" not in argv else []
    run_hostile(argv, [out])


# ---------------------------------------------------------------------------------------------------
# CSV


def mutate_csv(rng: random.Random, lines: list[str]) -> str:
    lines = list(lines)
    for _ in range(rng.randint(1, 3)):
        if not lines:
            break
        kind = rng.choice(("number", "number", "units", "truncate", "columns", "delimiter", "entity", "bom", "blank"))
        k = rng.randrange(len(lines))
        if kind == "number":
            rows = [i for i, line in enumerate(lines) if "," in line and not line.startswith("#")]
            k = rng.choice(rows) if rows else k
            cells = lines[k].split(",")
            cells[rng.randrange(len(cells))] = " " + rng.choice(HOSTILE_NUMBERS)
            lines[k] = ",".join(cells)
        elif kind == "units":
            header = rng.choice((
                "# linkstress-sketch v1 units=mm units=in", "# linkstress-sketch v1 units=parsec",
                "# linkstress-sketch v1 units=", "# linkstress-sketch v2 units=mm", "# linkstress-sketch v1 units=1e300",
            ))
            lines.insert(0, header) if rng.random() < 0.5 else lines.__setitem__(0, header)
        elif kind == "truncate":
            lines = lines[:k]
        elif kind == "columns":
            lines[k] = lines[k] + ", 1" * rng.randint(1, 200)
        elif kind == "delimiter":
            lines[k] = lines[k].replace(",", rng.choice((";", "\t", ",,", " ")))
        elif kind == "entity":
            lines[k] = rng.choice(("circle, 0, 0, 0", "circle, 0, 0, -1", "arc, 0, 0, 1, 0, 1e300",
                                   "line, 0, 0, 0, 0", "ellipse, 0, 0, 0, 0, 0, 0, 1", "spline, 1",
                                   "point", "New Line", "bogus, 1, 2", "spline, " + ", ".join(["1e300"] * 8)))
        elif kind == "bom":
            lines[0] = "\ufeff" + lines[0]
        else:
            lines[k:k] = [""] * rng.randint(1, 5)
    return "\r\n".join(lines) + "\r\n" if rng.random() < 0.3 else "\n".join(lines) + "\n"


CSV_CASES = 60


@pytest.mark.parametrize("case", range(CSV_CASES))
def test_hostile_csv_import(tmp_path, corpus, case):
    rng = random.Random(f"csv-{case}")
    sketch = tmp_path / "sketch.csv"
    sketch.write_text(mutate_csv(rng, corpus["sample_csv"]))
    out = tmp_path / "links.json"
    run_hostile(["import", sketch, "--json", out, *dxf_flags(rng)], [out])


# ---------------------------------------------------------------------------------------------------
# Scenes


SCENE_EDITS = (
    ("materials.steel", "density"), ("materials.steel", "youngs_modulus"), ("materials.steel", "poisson_ratio"),
    ("materials.steel", "yield_strength"), ("links.crank", "thickness"), ("links.coupler", "thickness"),
    ("links.crank", "sketch"), ("links.output", "layer"), ("links.crank", "material"), ("links.crank", "units"),
    ("mechanisms.main", "type"), ("mechanisms.main", "crank"), ("mechanisms.main", "branch"),
    ("mechanisms.main", "output"), ("motion", "input_angle_deg"), ("motion", "input_speed_rad_s"),
    ("motion", "input_acceleration_rad_s2"), ("motion", "actuator"), ("loads", "gravity_m_s2"),
    ("loads.couples", "output"), ("analysis", "stations"), ("analysis", "mesh_size_m"),
    ("analysis", "element_order"), ("analysis", "stresses"), ("analysis", "body_load_near_holes"),
    ("", "title"), ("", "units"), ("links.crank", "mass"),
)
MOTION_HOSTILE = (
    "{start = 0, stop = 360, num = 10000001}", "{start = 0, stop = 360, num = 0}", "{start = 0, stop = 360, num = -5}",
    "{start = 0, stop = 1e300, num = 5}", "{start = nan, stop = 1, num = 3}", "{start = 0, stop = 360}",
    '{expression = "__import__(\'os\').system(\'true\')", t = {start = 0, stop = 1, num = 3}}',
    '{expression = "9**9**9", t = {start = 0, stop = 1, num = 3}}',
    '{expression = "exp(1e300*t)", t = {start = 0, stop = 1, num = 3}}',
    '{expression = "' + "(" * 2000 + "t" + ")" * 2000 + '", t = {start = 0, stop = 1, num = 3}}',
    '{expression = "t/0", t = {start = 0, stop = 1, num = 3}}', "[]", "[1e300, 2]", "[nan]",
)


def set_key(text: str, table: str, key: str, value: str) -> str:
    """The scene ``text`` with ``table``'s ``key`` set to the raw TOML ``value`` (added when absent)."""
    header = f"[{table}]" if table else None
    lines = text.splitlines()
    start = 0 if header is None else next((i + 1 for i, line in enumerate(lines) if line.strip() == header), None)
    if start is None:
        return text + f"\n[{table}]\n{key} = {value}\n"
    end = next((i for i in range(start, len(lines)) if lines[i].startswith("[")), len(lines))
    for i in range(start, end):
        if lines[i].split("=")[0].strip() == key:
            lines[i] = f"{key} = {value}"
            return "\n".join(lines) + "\n"
    lines.insert(start if header else 0, f"{key} = {value}")
    return "\n".join(lines) + "\n"


def mutate_scene(rng: random.Random, text: str) -> str:
    for _ in range(rng.randint(1, 3)):
        kind = rng.choice(("value", "value", "value", "motion", "force", "structure", "sketch", "bytes"))
        if kind == "value":
            table, key = rng.choice(SCENE_EDITS)
            text = set_key(text, table, key, rng.choice(TOML_HOSTILE))
        elif kind == "motion":
            text = set_key(text, "motion", "input_angle_deg", rng.choice(MOTION_HOSTILE))
        elif kind == "force":
            at = rng.choice(("[0.5, 0.0]", "[1e300, 0]", "[5.0, 5.0]", "[nan, 0]", "[0.0, 0.0]", "[1]"))
            force = rng.choice(("[0.0, -100.0]", "[1e300, 0]", "[inf, 0]", "[0, 0]", '"x"'))
            link = rng.choice(('"coupler"', '"ground"', '"nope"', "3"))
            text += f"\n[[loads.forces]]\nlink = {link}\nat_m = {at}\nforce_n = {force}\n"
        elif kind == "structure":
            choice = rng.randrange(6)
            if choice == 0:
                text = "\ufeff" + text
            elif choice == 1:
                text += "\nnested = " + "[" * 5000 + "]" * 5000 + "\n"
            elif choice == 2:
                text = text[: rng.randrange(len(text))]
            elif choice == 3:
                text += "\n[links.crank]\nthickness = 0.1\n"  # a table defined twice
            elif choice == 4:
                text += "\n[unknown_table]\nkey = 1\n"
            else:
                text = text.replace("[links.ground]", "[links.ground2]")
        elif kind == "sketch":
            value = rng.choice((
                '"' + "a" * 5000 + '.dxf"', '"../../../../../../../../etc/passwd"', '"/"', '""', '"."',
                '"missing.dxf"', '"/dev/null"', '"ansys_four_bars.dxf\\u0000x"', '"scene.toml"',
            ))
            text = set_key(text, rng.choice(("links.crank", "links.coupler")), "sketch", value)
        else:
            k = rng.randrange(len(text))
            text = text[:k] + "".join(chr(rng.randrange(1, 0x7F)) for _ in range(rng.randint(1, 8))) + text[k:]
    return text


SCENE_CASES = 110


@pytest.mark.parametrize("case", range(SCENE_CASES))
def test_hostile_scene_analyze(tmp_path, corpus, case):
    rng = random.Random(f"scene-{case}")
    folder = case_folder(tmp_path, corpus)
    scene = folder / "scene.toml"
    scene.write_text(mutate_scene(rng, corpus["scene"]), errors="surrogatepass")
    out, html = folder / "out.json", folder / "out.html"
    argv = ["analyze", scene, "--json", out]
    if rng.random() < 0.3:
        argv.append("--stations")
    outputs = [out]
    if rng.random() < 0.05:
        argv += ["--html", html]
        outputs.append(html)
    run_hostile(argv, outputs)


# ---------------------------------------------------------------------------------------------------
# Flags and output paths, every command


def hostile_flag_case(rng: random.Random, folder: Path, corpus: dict) -> tuple[list, list[Path]]:
    scene = folder / "scene.toml"
    scene.write_text(corpus["scene"])
    out = folder / "out.json"
    command = rng.choice(("sections", "sections", "validate", "validate", "analyze-paths", "regress", "import-paths"))
    pick = lambda: rng.choice(HOSTILE_NUMBERS)  # noqa: E731
    if command == "sections":
        argv = ["sections", "--bar", *[rng.choice((pick(), "1.0", "0.5", "0.1")) for _ in range(4)]]
        if rng.random() < 0.5:
            argv += ["--hole", rng.choice((pick(), "0.02", "0.6"))]
        if rng.random() < 0.5:
            argv += ["--density", rng.choice((pick(), "7850"))]
        if rng.random() < 0.5:
            argv += ["--stations", rng.choice(("100000000", "0", "1", "-3", "2.5", "1e9", "abc", "5"))]
        return argv, []
    if command == "validate":
        flag = rng.choice(("--mesh-size", "--positions", "--mesh-levels", "--jobs"))
        value = rng.choice((pick(), "1e-7", "1e-9", "100", "1e6", "-1", "0"))
        if flag == "--mesh-size" and value in ("100", "1e6"):
            value = "inf"
        return ["validate", scene, "--mesh-levels", "1", flag, value, "--json", out], [out]
    if command == "analyze-paths":
        target = rng.choice(("folder", "scene", "sketch", "same", "missing-folder"))
        html = folder / "out.html"
        argv = ["analyze", scene]
        if target == "folder":
            (folder / "adir").mkdir()
            argv += ["--json", folder / "adir"]
        elif target == "scene":
            argv += ["--json", scene]
        elif target == "sketch":
            argv += ["--json", folder / "ansys_four_bars.dxf"]
        elif target == "same":
            argv += ["--json", out, "--html", out]
        else:
            argv += ["--json", folder / "no" / "out.json"]
        return argv, [out, html]
    if command == "regress":
        case = folder / "cases" / "seed"
        case.mkdir(parents=True)
        shutil.copy(folder / "ansys_four_bars.dxf", case)
        (case / "scene.toml").write_text(corpus["scene"])
        (case / "reference.json").write_text(rng.choice((
            "", "not json", "[]", "3", "null", '{"positions": "x"}', "{" * 5000, '{"links": {"crank": 1e400}}',
            '"' + "x" * 100 + '"', "{}", '{"a": NaN}',
        )))
        return ["regress", folder / "cases"], []
    sketch = folder / "ansys_four_bars.dxf"
    target = rng.choice(("folder", "input", "missing-folder", "plot-folder"))
    if target == "folder":
        (folder / "adir").mkdir()
        return ["import", sketch, "--json", folder / "adir"], []
    if target == "input":
        return ["import", sketch, "--json", sketch], []
    if target == "missing-folder":
        return ["import", sketch, "--json", folder / "no" / "links.json"], []
    (folder / "pdir").mkdir()
    return ["import", sketch, "--plot", folder / "pdir"], []


FLAG_CASES = 60


@pytest.mark.parametrize("case", range(FLAG_CASES))
def test_hostile_flags(tmp_path, corpus, case):
    rng = random.Random(f"flags-{case}")
    folder = case_folder(tmp_path, corpus)
    before = (folder / "ansys_four_bars.dxf").read_bytes()
    argv, outputs = hostile_flag_case(rng, folder, corpus)
    run_hostile(argv, outputs)
    assert (folder / "ansys_four_bars.dxf").read_bytes() == before, "an input was overwritten"
    assert (folder / "scene.toml").read_text() == corpus["scene"], "the scene was overwritten"


def test_the_generator_covers_at_least_300_cases():
    assert DXF_CASES + CSV_CASES + SCENE_CASES + FLAG_CASES >= 300


# ---------------------------------------------------------------------------------------------------
# The same families as real processes: the terminal's whole stderr


PROCESS_CASES = (("dxf", 3), ("dxf", 7), ("dxf", 1), ("csv", 2), ("scene", 5), ("scene", 11), ("flags", 4))


@pytest.mark.parametrize("family, case", PROCESS_CASES)
def test_a_hostile_case_prints_one_line_at_most_on_stderr(tmp_path, corpus, family, case):
    rng = random.Random(f"{family}-{case}")
    folder = case_folder(tmp_path, corpus)
    if family == "dxf":
        sketch = folder / "sketch.dxf"
        structural_dxf(rng, sketch)
        argv = ["import", sketch, "--units", "mm"]
    elif family == "csv":
        sketch = folder / "sketch.csv"
        sketch.write_text(mutate_csv(rng, corpus["sample_csv"]))
        argv = ["import", sketch]
    elif family == "scene":
        scene = folder / "scene.toml"
        scene.write_text(mutate_scene(rng, corpus["scene"]), errors="surrogatepass")
        argv = ["analyze", scene]
    else:
        argv, _ = hostile_flag_case(rng, folder, corpus)
    done = subprocess.run(
        [sys.executable, "-m", "linkstress", *map(str, argv)], capture_output=True, text=True,
        timeout=TIME_LIMIT + 30, cwd=folder,
        preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (8 * 2**30, resource.RLIM_INFINITY)),
    )
    assert done.returncode in (0, 1, 2), done.stderr
    assert "Traceback" not in done.stderr
    if done.returncode == 2:
        lines = done.stderr.strip().splitlines()
        assert len(lines) == 1 or "usage:" in done.stderr, done.stderr


# ---------------------------------------------------------------------------------------------------
# Issue 28: motion expressions, inputs that are not files, unit slips, holes on layers of their own,
# scheduler addresses and a case with no load. A refusal here is also short: one line of at most
# MESSAGE_LIMIT characters (lists capped at five, long text cut).

MESSAGE_LIMIT = 400
"""Characters an error line (after "linkstress: error: ") may have in these families."""
IMPORT_MESSAGE_LIMIT = 2000
"""The same for ``import``, whose refusal spells out capped lists: a drawn mechanism's links and the
links with fewer than two joints (five of each), or the first problem of each kind (five kinds at
most, each naming its entities and its fix)."""


def run_short(argv: list, outputs: list[Path], limit: int = MESSAGE_LIMIT) -> tuple[int, str, str]:
    """``run_hostile``, and a refusal is one error line of at most ``limit`` characters."""
    code, stdout, stderr = run_hostile(argv, outputs)
    assert code in (0, 2), (code, stderr[-2000:])
    if code == 2 and "usage:" not in stderr:
        (line,) = [line for line in stderr.splitlines() if line.startswith("linkstress: error:")]
        message = line.removeprefix("linkstress: error: ")
        assert len(message) <= limit, (len(message), message[:600])
        assert not NON_FINITE.search(message), message
    return code, stdout, stderr


BARE_FOURBAR = """
[links.crank]
joints = [[0.0, 0.0], [0.1, 0.0]]
mass = 0.5
inertia = 0.001
center_of_mass = [0.05, 0.0]

[links.coupler]
joints = [[0.0, 0.0], [0.3, 0.0]]
mass = 1.0
inertia = 0.01
center_of_mass = [0.15, 0.0]

[links.output]
joints = [[0.0, 0.0], [0.25, 0.0]]
mass = 0.8
inertia = 0.005
center_of_mass = [0.125, 0.0]

[links.ground]
joints = [[0.0, 0.0], [0.3, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "crank"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
"""
"""A Grashof four-bar of bare joints (crank 0.1 m, coupler 0.3 m, output 0.25 m, ground 0.3 m):
kinematics and joint forces, no sketch to read."""


# --- motion expressions ----------------------------------------------------------------------------

EXPRESSION_ATOMS = ("t", "t", "t", "1", "90", "360", "pi", "e", "0", "0.5", "1e7", "1e17", "1e300", "1e-300", "5729577.9",
                    "3e6", "1e12")
EXPRESSION_CALLS = ("sin", "cos", "tan", "exp", "log", "sqrt", "asin", "atan", "sinh", "cosh", "tanh", "abs",
                    "max", "eval", "__import__", "pow")
TIMES = ("[0.0, 1.0]", "[0.0]", "[0.0, 0.001, 0.002]", "{start = 0.0, stop = 1.0, num = 11}",
         "{start = -1.0, stop = 1.0, num = 7}", "{start = 0.0, stop = 1e9, num = 3}", "[1e9]", "{start = 0.0, stop = 1e-9, num = 5}",
         "{start = 0.0, stop = 0.01, num = 50}", "[1e300]", "[-0.0, 0.5]")


def random_expression(rng: random.Random, depth: int) -> str:
    """An expression of ``t`` up to ``depth`` levels deep: allowed calls and numbers, mostly, and
    now and then a call outside the whitelist or a number no angle can be."""
    if depth == 0 or rng.random() < 0.3:
        return rng.choice(EXPRESSION_ATOMS)
    kind = rng.random()
    if kind < 0.35:
        return f"{rng.choice(EXPRESSION_CALLS)}({random_expression(rng, depth - 1)})"
    if kind < 0.45:
        return f"-{random_expression(rng, depth - 1)}"
    operator = rng.choice(("+", "-", "*", "/", "**", "*", "+"))
    return f"({random_expression(rng, depth - 1)}{operator}{random_expression(rng, depth - 1)})"


EXPRESSION_CASES = 40


@pytest.mark.parametrize("case", range(EXPRESSION_CASES))
def test_hostile_motion_expression(tmp_path, case):
    rng = random.Random(f"expression-{case}")
    expression = random_expression(rng, rng.randint(1, 4))
    scene = tmp_path / "scene.toml"
    scene.write_text(BARE_FOURBAR + f'input_angle_deg = {{expression = "{expression}", t = {rng.choice(TIMES)}}}\n')
    out = tmp_path / "out.json"
    code, _, stderr = run_short(["analyze", scene, "--json", out], [out])
    if code == 2:
        assert "scene.toml: motion.input_angle_deg" in stderr, stderr
        return
    # a run that goes ahead stays inside the ranges of plain values (docs/design.md, Limits)
    for position in json.loads(out.read_text())["positions"]:
        assert abs(position["input_angle_deg"]) <= 1e7, position["input_angle_deg"]
        if position["feasible"]:
            crank = position["links"]["crank"]
            assert abs(crank["omega_rad_s"]) <= 1e5 and abs(crank["alpha_rad_s2"]) <= 1e9, crank


# --- inputs that are not regular files -------------------------------------------------------------

SPECIAL_KINDS = ("fifo", "dev-zero", "dev-null", "socket", "folder", "link-to-fifo", "link-to-dev-zero", "oversize",
                 "broken-link")
SPECIAL_TARGETS = ("analyze-scene", "validate-scene", "import-sketch", "scene-sketch")
SPECIAL_WORDS = {
    "fifo": "is a FIFO (named pipe), not a file", "dev-zero": "is a character device, not a file",
    "dev-null": "is a character device, not a file", "socket": "is a socket, not a file", "folder": "folder",
    "link-to-fifo": "is a FIFO (named pipe), not a file", "link-to-dev-zero": "is a character device, not a file",
    "oversize": "MiB), more than the", "broken-link": "",
}
"""What the one error line says for each kind (a broken link is simply not found, in each reader's words)."""


@contextlib.contextmanager
def special_path(kind: str, folder: Path, name: str, oversize: int):
    """A path named ``name`` in ``folder`` (a short folder of its own for a socket, whose path the
    system limits to about 100 bytes) that is ``kind``; ``oversize``: a sparse file's size."""
    path = folder / name
    if kind in ("fifo", "link-to-fifo"):
        os.mkfifo(folder / "pipe")
        if kind == "fifo":
            (folder / "pipe").rename(path)
        else:
            path.symlink_to(folder / "pipe")
    elif kind in ("dev-zero", "dev-null"):
        path = Path(f"/dev/{kind[4:]}")
    elif kind == "link-to-dev-zero":
        path.symlink_to("/dev/zero")
    elif kind == "folder":
        path.mkdir()
    elif kind == "oversize":
        with path.open("wb") as stream:
            stream.truncate(oversize)
    elif kind == "broken-link":
        path.symlink_to(folder / "nowhere")
    else:
        short = Path(tempfile.mkdtemp(prefix="ls"))
        server = socket.socket(socket.AF_UNIX)
        server.bind(str(short / name))
        try:
            yield short / name
        finally:
            server.close()
            shutil.rmtree(short)
        return
    yield path


@pytest.mark.parametrize("target", SPECIAL_TARGETS)
@pytest.mark.parametrize("kind", SPECIAL_KINDS)
def test_hostile_special_file(tmp_path, corpus, kind, target):
    folder = case_folder(tmp_path, corpus)
    name = "input.dxf" if target in ("import-sketch", "scene-sketch") else "input.toml"
    oversize = (SKETCH_BYTES if name.endswith(".dxf") else SCENE_BYTES) + 1
    with special_path(kind, folder, name, oversize) as path:
        if target == "analyze-scene":
            argv = ["analyze", path]
        elif target == "validate-scene":
            argv = ["validate", path, "--mesh-levels", "1"]
        elif target == "import-sketch":
            argv = ["import", path, "--units", "mm"]
        else:
            scene = folder / "scene.toml"
            scene.write_text(set_key(corpus["scene"], "links.crank", "sketch", json.dumps(str(path))))
            argv = ["analyze", scene]
        code, _, stderr = run_short(argv, [])
    assert code == 2, stderr
    assert SPECIAL_WORDS[kind] in stderr, stderr
    if target == "scene-sketch":
        assert "scene.toml: links.crank.sketch: " in stderr, stderr


# --- unit slips ------------------------------------------------------------------------------------

PSI_PA = 6894.757293168361
SLIP_VALUES = {
    "thickness": (0.003, 0.006, 0.01, 0.02), "density": (1200.0, 2700.0, 7850.0, 8900.0),
    "youngs_modulus": (2.5e9, 70e9, 110e9, 200e9), "yield_strength": (40e6, 250e6, 350e6, 900e6),
    "endurance_limit": (60e6, 100e6, 150e6), "ultimate_strength": (400e6, 600e6, 1000e6),
}
"""Real values of each key [SI], as a designer means them: plates 3-20 mm; nylon, aluminium, steel,
copper; strengths of a polymer to a high-strength steel. Endurance limits stay below, and yield
strengths are paired with, ultimate strengths of at least 400 MPa."""
SLIP_UNITS = {
    "thickness": (("mm", 1e-3), ("cm", 1e-2), ("in", 0.0254), ("um", 1e-6)),
    "density": (("g/cm^3", 1e3), ("lb/in^3", 0.45359237 / 0.0254**3), ("t/mm^3", 1e12), ("N/m^3", 1 / 9.80665)),
    "youngs_modulus": (("GPa", 1e9), ("MPa", 1e6), ("psi", PSI_PA), ("ksi", 1e3 * PSI_PA), ("Msi", 1e6 * PSI_PA)),
    "yield_strength": (("MPa", 1e6), ("kPa", 1e3), ("ksi", 1e3 * PSI_PA), ("psi", PSI_PA), ("GPa", 1e9)),
}
"""The units a value may be written in by mistake, (name, its size in SI units); the fatigue
strengths take the yield strength's."""
SLIP_BAR = {"length": 0.1, "height": 0.04, "overhang": 0.03}
"""The drawn crank of the unit-slip cases [m]: its outline is 0.16 m by 0.04 m."""


def slip_scene(folder: Path, key: str, written: float) -> Path:
    """The drawn crank and bare four-bar, its steel with fatigue data and ``key`` = ``written``."""
    length, h, overhang = SLIP_BAR["length"], SLIP_BAR["height"] / 2, SLIP_BAR["overhang"]
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    msp.add_lwpolyline([(-overhang, -h), (length + overhang, -h), (length + overhang, h), (-overhang, h)], close=True)
    for x in (0.0, length):
        msp.add_circle((x, 0.0), 0.005)
        msp.add_point((x, 0.0))
    doc.saveas(folder / "crank.dxf")
    material = {"density": 7850.0, "youngs_modulus": 200e9, "poisson_ratio": 0.3, "yield_strength": 350e6,
                "endurance_limit": 200e6, "ultimate_strength": 600e6}
    thickness = 0.01
    if key == "thickness":
        thickness = written
    else:
        material[key] = written
    lines = "".join(f"{name} = {value!r}\n" for name, value in material.items())
    crank_start, crank_end = BARE_FOURBAR.index("[links.crank]"), BARE_FOURBAR.index("[links.coupler]")
    text = (f"[materials.steel]\n{lines}\n" + BARE_FOURBAR[:crank_start]
            + f'[links.crank]\nsketch = "crank.dxf"\nthickness = {thickness!r}\nmaterial = "steel"\n\n'
            + BARE_FOURBAR[crank_end:] + "input_angle_deg = [30.0, 120.0]\ninput_speed_rad_s = 10.0\n")
    path = folder / "scene.toml"
    path.write_text(text)
    return path


SLIP_CASES = 40


@pytest.mark.parametrize("case", range(SLIP_CASES))
def test_hostile_unit_slip(tmp_path, case):
    rng = random.Random(f"slip-{case}")
    key = rng.choice(sorted(SLIP_VALUES))
    meant = rng.choice(SLIP_VALUES[key])
    unit, size = rng.choice(SLIP_UNITS.get(key, SLIP_UNITS["yield_strength"]))
    written = float(f"{meant / size:.6g}")
    scene = slip_scene(tmp_path, key, written)
    out = tmp_path / "out.json"
    code, _, stderr = run_short(["analyze", scene, "--json", out], [out])
    path = f"links.crank.{key}" if key == "thickness" else f"materials.steel.{key}"
    if code == 2:
        # refused only where a plain range refuses it ("check the unit") or the fatigue data clash
        assert "scene.toml: " in stderr and ("check the unit" in stderr or "ultimate_strength" in stderr), stderr
        return
    warnings = [w for w in load_scene(scene).warnings if w.startswith(f"{path} ")]
    rule = RULES[key]
    diagonal = math.hypot(SLIP_BAR["length"] + 2 * SLIP_BAR["overhang"], SLIP_BAR["height"])
    implausible = not rule.low <= written <= rule.high or (key == "thickness" and written > diagonal)
    assert bool(warnings) == implausible, (written, warnings)
    if not warnings:
        return
    (warning,) = warnings
    assert warning.startswith(f"{path} = {written:g} ") and len(warning) < 250 and "\n" not in warning
    fitting = [name for name, s in rule.slips if rule.low <= written * s <= rule.high and
               (key != "thickness" or written * s <= diagonal)]
    if fitting[:1] == [unit]:
        assert f"did you mean {written:g} {unit} = " in warning, warning


# --- holes and slots on layers of their own --------------------------------------------------------

def holed_sketch(rng: random.Random, path: Path) -> list[str]:
    """A DXF of a crank (and sometimes a coupler pinned to it) whose pin holes, a slot or a lightening
    hole are drawn on other layers than the outlines; the layers they are on."""
    doc = ezdxf.new(rng.choice(("R12", "R2000", "R2013")), units=4)
    msp = doc.modelspace()
    hole_layer = rng.choice(("holes", "HOLES", "crank", "0", "Bohrungen", "穴"))
    layers = {"crank", hole_layer}
    links = [("crank", 0.0, 0.0, 100.0)]
    if rng.random() < 0.5:
        links.append(("coupler", 100.0, 0.0, 300.0))
    for name, x0, y0, length in links:
        layers.add(name)
        h = rng.choice((10.0, 15.0, 20.0))
        corners = [(x0 - h, y0 - h), (x0 + length + h, y0 - h), (x0 + length + h, y0 + h), (x0 - h, y0 + h)]
        if doc.dxfversion == "AC1009":
            msp.add_polyline2d(corners, close=True, dxfattribs={"layer": name})
        else:
            msp.add_lwpolyline(corners, close=True, dxfattribs={"layer": name})
        for x in (x0, x0 + length):
            msp.add_circle((x, y0), rng.choice((2.5, 5.0, h * 0.9, h * 1.5)), dxfattribs={"layer": hole_layer})
            if rng.random() < 0.6:
                msp.add_point((x, y0), dxfattribs={"layer": rng.choice((name, hole_layer))})
        kind = rng.choice(("slot", "lightening", "none", "overlap"))
        middle = x0 + length / 2
        if kind == "slot":
            slot = rng.choice(("slots", hole_layer))
            layers.add(slot)
            r = h / 3
            msp.add_line((middle - 10, y0 - r), (middle + 10, y0 - r), dxfattribs={"layer": slot})
            msp.add_arc((middle + 10, y0), r, -90, 90, dxfattribs={"layer": slot})
            msp.add_line((middle + 10, y0 + r), (middle - 10, y0 + r), dxfattribs={"layer": slot})
            msp.add_arc((middle - 10, y0), r, 90, 270, dxfattribs={"layer": slot})
        elif kind == "lightening":
            msp.add_circle((middle, y0), h / 2, dxfattribs={"layer": rng.choice(("light", hole_layer))})
        elif kind == "overlap":
            # a "hole" that crosses the outline: no hole, a crossing
            msp.add_circle((x0 + length + h, y0), h / 2, dxfattribs={"layer": hole_layer})
    doc.saveas(path)
    return sorted(layers)


HOLE_CASES = 24


@pytest.mark.parametrize("case", range(HOLE_CASES))
def test_hostile_holes_on_their_own_layers(tmp_path, case):
    rng = random.Random(f"holes-{case}")
    sketch = tmp_path / "sheet.dxf"
    layers = holed_sketch(rng, sketch)
    out, scene = tmp_path / "links.json", tmp_path / "scene.toml"
    argv: list = ["import", sketch, "--json", out]
    if rng.random() < 0.4:
        argv += ["--hole-layers", rng.choice((",".join(layers), "holes", "nope", "holes,slots,light"))]
    if rng.random() < 0.4:
        argv += ["--scene", scene]
    if rng.random() < 0.2:
        argv += ["--strict"]
    if rng.random() < 0.2:
        argv += ["--layers", ",".join(rng.sample(layers, rng.randint(1, len(layers))))]
    run_short(argv, [out, scene], IMPORT_MESSAGE_LIMIT)


# --- scheduler addresses ---------------------------------------------------------------------------

SCHEDULER_CASES = 8


@pytest.mark.parametrize("case", range(SCHEDULER_CASES))
def test_hostile_scheduler_address(tmp_path, corpus, case, monkeypatch):
    rng = random.Random(f"scheduler-{case}")
    address = rng.choice(("tcp://10.0.0.5:8786", "local", "tls://node-3:8786"))
    k = rng.randrange(len(address) + 1)
    address = address[:k] + rng.choice(("\n", "\r\n", "\t", "\x1b[2J", "\x7f", "\u202e", "\u200b", "\x85")) + address[k:]
    folder = case_folder(tmp_path, corpus)
    (folder / "scene.toml").write_text(corpus["scene"])
    command = rng.choice((["validate", folder / "scene.toml"], ["regress", folder / "no-cases"]))
    if rng.random() < 0.5:
        argv = [*command, "--scheduler", address]
    else:
        monkeypatch.setenv("LINKSTRESS_SCHEDULER", address)
        argv = command
    code, _, stderr = run_short(argv, [])
    assert code == 2 and "holds the control character" in stderr and repr(address.strip(" ")) in stderr, stderr


# --- a valid case with no load, through the FEA peaks ----------------------------------------------

def test_a_case_with_no_load_through_the_peaks_gives_zeros(tmp_path, corpus):
    folder = case_folder(tmp_path, corpus)
    scene = folder / "scene.toml"
    text = set_key(corpus["scene"], "motion", "input_speed_rad_s", "0.0")
    text = set_key(text, "materials.steel", "yield_strength", "250e6")
    scene.write_text(text.split("[loads")[0])
    out = folder / "out.json"
    code, _, stderr = run_short(["analyze", scene, "--peaks", "--json", out], [out])
    assert code == 0, stderr
    summaries = json.loads(out.read_text())["links"]
    assert {s["peak_max_von_mises_pa"] for s in summaries.values()} == {0.0}
    assert {s["peak_yield_safety_factor"] for s in summaries.values()} == {None}


def test_the_issue_28_families_add_at_least_100_cases():
    special = len(SPECIAL_KINDS) * len(SPECIAL_TARGETS)
    assert EXPRESSION_CASES + special + SLIP_CASES + HOLE_CASES + SCHEDULER_CASES + 1 >= 100
