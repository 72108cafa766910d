"""``analyze --table OUT.npz``: the JSON's per-position numbers as named NumPy arrays, read back
equal to the JSON (every number, text and null, on every kind of mechanism), checked before the
work, written all or none, never a NaN."""

from __future__ import annotations

import errno
import json
import re
import subprocess
import sys
from pathlib import Path
from urllib.parse import unquote

import numpy as np
import pytest

from linkstress.cli import main
from linkstress.errors import InputError
from linkstress.output import RowBlocks, npz_stream, write_all
from linkstress.report import table

REPO = Path(__file__).resolve().parents[1]
CASES = REPO / "validation" / "cases"
SEED = CASES / "seed_ansys_fourbar"
STRENGTH = "yield_strength = 250e6\nendurance_limit = 200e6\nultimate_strength = 400e6\n"
SHARED = {"curved", "joints", "beam_theory", "joint", "hole_diameter_m", "depth_m", "kt", "basis", "torque", "point", "on"}
"""What every position shares, stored once (docs/design.md, "The table")."""
DESCRIBED = ("links", "mechanisms", "transmission_angle_deg")
"""The top-level parts of a record that an infeasible position leaves empty."""


def seed_scene(folder: Path, sweep: str) -> Path:
    """The seed four-bar (docs/reference/seed-ansys-fourbar.md) over ``sweep``, its steel given a
    yield strength and fatigue data so that the safety factors are written too."""
    (folder / "ansys_four_bars.dxf").write_bytes((SEED / "ansys_four_bars.dxf").read_bytes())
    text = re.sub(r"(?m)^input_angle_deg = .*$", f"input_angle_deg = {sweep}", (SEED / "scene.toml").read_text())
    path = folder / "seed.toml"
    path.write_text(text.replace("poisson_ratio = 0.3\n", "poisson_ratio = 0.3\n" + STRENGTH))
    return path


UNREACHABLE = """
[links."cr/ank 50%"]
joints = [[0.0, 0.0], [1.0, 0.0]]
mass = 471.0
inertia = 66.33
center_of_mass = [0.5, 0.0]

[links.coupler]
joints = [[0.0, 0.0], [1.5, 0.0]]
mass = 667.25
inertia = 171.6
center_of_mass = [0.75, 0.0]

[links.output]
joints = [[0.0, 0.0], [1.5, 0.0]]
mass = 300.0
inertia = 60.0
center_of_mass = [0.75, 0.0]

[links.ground]
joints = [[0.0, 0.0], [2.9, 0.0]]

[mechanisms.main]
type = "four-bar"
crank = "cr/ank 50%"
coupler = "coupler"
output = "output"
ground = "ground"

[motion]
input_angle_deg = {start = 0.0, stop = 359.0, num = 73}
input_speed_rad_s = -1.0
"""
"""A bare-joints four-bar whose crank cannot turn round (ground 2.9 > 1 + 1.5 + ... at some angles):
rows unreachable, and a crank named with a slash, a space and a percent sign."""


def scene_of(name: str, folder: Path) -> Path:
    if name == "seed with its change point":
        # 0, 10, ..., 360: 180 deg is the change point (infeasible), 360 repeats 0
        return seed_scene(folder, "{ start = 0.0, stop = 360.0, num = 37 }")
    if name == "seed crossing its change point":
        # 165 -> 195 passes 180 deg between samples: a warning on the row at 195
        return seed_scene(folder, "{ start = 15.0, stop = 345.0, num = 12 }")
    if name == "unreachable angles":
        path = folder / "unreachable.toml"
        path.write_text(UNREACHABLE)
        return path
    if name == "kinematics only":  # the output without mass data: no joint forces
        path = folder / "kinematics.toml"
        path.write_text(UNREACHABLE.replace("mass = 300.0\ninertia = 60.0\ncenter_of_mass = [0.75, 0.0]\n", ""))
        return path
    return CASES / name / "scene.toml"


def json_leaves(value: object, path: tuple[str, ...] = ()):
    """(path, value) of every leaf of a JSON record: numbers, texts, nulls and lists of numbers (a
    point, a force) are leaves; records and lists of records (members, pin holes, pins) are walked by
    key and index."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield from json_leaves(item, (*path, key))
    elif isinstance(value, list) and value and isinstance(value[0], dict):
        for k, item in enumerate(value):
            yield from json_leaves(item, (*path, str(k)))
    else:
        yield path, value


def assert_table_is_the_json(data: dict, arrays) -> None:
    """Every value of every position record in ``data`` (analyze's JSON) is in ``arrays`` (the table
    read by np.load) under the documented name, and the table holds nothing else."""
    by_path = {tuple(unquote(part) for part in name.split("/")): name for name in arrays.files}
    positions = data["positions"]
    count = len(positions)
    feasible = arrays["feasible"]
    assert feasible.tolist() == [p["feasible"] for p in positions]
    read: set[str] = {"feasible"}
    for k, record in enumerate(positions):
        record.setdefault("warnings", [])
        for path, value in json_leaves(record):
            if path == ("feasible",):
                continue
            if path[-1] == "warnings":
                value = "\n".join(value)
            if (*path[:-1], path[-1] + "_code") in by_path:  # a text per position
                code = by_path[(*path[:-1], path[-1] + "_code")]
                texts = by_path[(*path[:-1], path[-1] + "_texts")]
                assert arrays[texts][arrays[code][k]] == ("" if value is None else value), (path, k)
                read |= {code, texts}
                continue
            if path[-1] in SHARED and value is None or value == []:  # a pin hole's kt where no position is
                assert path not in by_path, path  # inside the tables; a linkage without sliders
                continue
            name = by_path[path]
            read.add(name)
            if path[-1] in SHARED:
                assert arrays[name].tolist() == value, path
            elif value is None:  # a factor without stress, an estimate outside the Kt tables
                assert arrays[name][k] == 0, (path, k)
                if path[-1] in ("estimate_pa", "kt_at_position"):
                    assert arrays[by_path[(*path[:-1], "kt_outside_table")]][k], (path, k)
            else:
                assert arrays[name].shape[0] == count, path
                assert arrays[name][k].tolist() == value, (path, k)
    assert read == set(arrays.files), "arrays the JSON does not have"
    for name in arrays.files:
        array = arrays[name]
        assert array.dtype != object
        if name.endswith("_code"):  # texts some row uses, and the first
            assert set(np.unique(array)) | {0} == set(range(len(arrays[name[:-5] + "_texts"]))), name
        if array.dtype.kind == "f":
            assert np.isfinite(array).all(), name
        if name.split("/")[0] in DESCRIBED and array.ndim and not name.endswith("_texts") and array.shape[0] == count:
            assert not array[~feasible].any(), f"{name}: infeasible rows hold 0"


@pytest.mark.parametrize("block", [5, table.TABLE_BLOCK])
@pytest.mark.parametrize("case", [
    "seed with its change point",  # a four-bar with stresses, pin holes, safety factors, an infeasible row
    "seed crossing its change point",  # a row with a warning
    "slider_crank_curved_rod",  # a slider-crank with a curved rod
    "loader_arm_cylinder",  # a linkage driven by a slider's stroke: pins, a slider, a driving force
    "whitworth_shaper",  # a linkage with sliders driven by a crank
    "bell_crank",  # a link of two members
    "jansen_leg",  # a linkage without sliders (an empty list: no arrays)
    "unreachable angles",  # unreachable rows; forces without stresses; a link name to escape
    "kinematics only",  # no mechanisms
])
def test_the_table_reads_back_equal_to_the_json_at_every_position(tmp_path, monkeypatch, case, block):
    monkeypatch.setattr(table, "TABLE_BLOCK", block)
    scene = scene_of(case, tmp_path)
    out, npz = tmp_path / "out.json", tmp_path / "out.npz"
    assert main(["analyze", str(scene), "--json", str(out), "--table", str(npz)]) == 0
    data = json.loads(out.read_text())
    with np.load(npz) as arrays:  # allow_pickle=False: no object arrays
        assert_table_is_the_json(data, arrays)
        if case == "seed with its change point":
            assert not arrays["feasible"][18] and arrays["reason_texts"][arrays["reason_code"][18]].startswith("change point")
            assert arrays["links/crank/yield_safety_factor"][0] > 0
            assert arrays["links/crank/pin_holes/0/kt_outside_table"].any()
        if case == "seed crossing its change point":
            assert arrays["warnings_code"].tolist().count(0) == 11
        if case == "kinematics only":
            assert not any(name.startswith("mechanisms/") for name in arrays.files)
        if case == "unreachable angles":
            assert 0 < arrays["feasible"].sum() < 73
            assert "links/cr%2Fank 50%25/angle_deg" in arrays.files


def test_the_table_of_a_run_with_fea_peaks_has_each_positions_peak(tmp_path):
    scene = seed_scene(tmp_path, "{ start = 0.0, stop = 360.0, num = 5 }")  # 180 deg infeasible
    out, npz = tmp_path / "out.json", tmp_path / "out.npz"
    assert main(["analyze", str(scene), "--json", str(out), "--table", str(npz), "--peaks"]) == 0
    data = json.loads(out.read_text())
    with np.load(npz) as arrays:
        assert_table_is_the_json(data, arrays)
        peaks = arrays["links/coupler/peak_von_mises_pa"]
        assert peaks[2] == 0 and (peaks[[0, 1, 3, 4]] > arrays["links/coupler/max_von_mises_pa"][[0, 1, 3, 4]]).all()
        factors = arrays["links/coupler/peak_yield_safety_factor"]
        np.testing.assert_allclose(factors[[0, 1, 3, 4]], 250e6 / peaks[[0, 1, 3, 4]], rtol=1e-15)


def test_the_table_alone_is_written_without_the_json(tmp_path):
    scene = seed_scene(tmp_path, "{ start = 0.0, stop = 350.0, num = 36 }")
    npz = tmp_path / "sweep.npz"
    assert main(["analyze", str(scene), "--table", str(npz)]) == 0
    with np.load(npz) as arrays:
        assert arrays["input_angle_deg"].tolist() == [10.0 * k for k in range(36)]
        assert arrays["links/crank/angle_deg"][3] == pytest.approx(30.0, abs=1e-12)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ansys_four_bars.dxf", "seed.toml", "sweep.npz"]


@pytest.mark.parametrize(("args", "says"), [
    (["--table", "{tmp}"], "is a folder"),
    (["--table", "{tmp}/out.json"], "does not end in .npz"),
    (["--table", "{tmp}/out.npz", "--json", "{tmp}/out.npz"], "name the same file"),
    (["--table", "{tmp}/x.npz", "--html", "{tmp}/x.npz"], "name the same file"),
    (["--table", "{tmp}/missing/out.npz"], "does not exist"),
])
def test_a_table_path_that_cannot_be_written_is_refused_before_any_work(tmp_path, monkeypatch, capsys, args, says):
    scene = seed_scene(tmp_path, "{ start = 0.0, stop = 350.0, num = 36 }")
    from linkstress.commands import analyze

    monkeypatch.setattr(analyze, "run_analysis", lambda *a: pytest.fail("the analysis ran"))
    assert main(["analyze", str(scene), *(a.format(tmp=tmp_path) for a in args)]) == 2
    message = capsys.readouterr().err
    assert "--table" in message and says in message and "Traceback" not in message


def test_a_table_over_the_scene_itself_is_refused(tmp_path, capsys):
    scene = seed_scene(tmp_path, "60.0")
    link = tmp_path / "scene.npz"
    link.symlink_to(scene)
    assert main(["analyze", str(scene), "--table", str(link)]) == 2
    assert "is an input" in capsys.readouterr().err


class FillsUp:
    """A binary stream whose disk fills after ``room`` bytes."""

    def __init__(self, stream, room: int) -> None:
        self.stream, self.room = stream, room

    def write(self, data) -> int:
        self.room -= len(data)
        if self.room < 0:
            raise OSError(errno.ENOSPC, "No space left on device")
        return self.stream.write(data)

    def __getattr__(self, name):
        return getattr(self.stream, name)


def test_a_table_that_fails_part_way_leaves_no_file_and_writes_no_other_output(tmp_path, monkeypatch, capsys):
    scene = seed_scene(tmp_path, "{ start = 0.0, stop = 350.0, num = 36 }")
    out, npz = tmp_path / "out.json", tmp_path / "out.npz"
    out.write_text("old json")
    npz.write_text("old table")
    from linkstress.commands import analyze

    real = analyze.table_stream
    written = []

    def disk_fills(result):
        write = real(result)

        def failing(stream):
            write(FillsUp(stream, 20_000))
            written.append(stream.tell())

        return failing

    monkeypatch.setattr(analyze, "table_stream", disk_fills)
    assert main(["analyze", str(scene), "--json", str(out), "--table", str(npz)]) == 2
    message = capsys.readouterr().err
    assert "out.npz" in message and "No space left on device" in message and "Traceback" not in message
    assert written == []  # it failed part way through
    assert out.read_text() == "old json" and npz.read_text() == "old table"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ansys_four_bars.dxf", "out.json", "out.npz", "seed.toml"]


@pytest.mark.parametrize("rows", [1, 7, 64])
@pytest.mark.parametrize("block", [1, 3, 64])
def test_npz_stream_writes_what_np_load_reads_back_whatever_the_blocks(tmp_path, rows, block):
    rng = np.random.default_rng(rows * 100 + block)
    per_row = {
        "a": rng.normal(size=rows),
        "b/c": rng.normal(size=(rows, 2)),
        "d": rng.normal(size=(rows, 3, 2)),
        "mask": rng.random(rows) > 0.5,
        "codes": rng.integers(-5, 5, rows).astype(np.int8),
    }
    shared = {"name": np.array("coupler"), "texts": np.array(["", "a longer text"]), "pair": np.array([0, 1])}
    blocks = [slice(k, min(k + block, rows)) for k in range(0, rows, block)]
    arrays = {**{k: RowBlocks(rows, lambda b, v=v: v[b]) for k, v in per_row.items()}, **shared}
    write_all([(tmp_path / "t.npz", npz_stream(arrays, blocks, "--table"))])
    with np.load(tmp_path / "t.npz") as read:
        assert read.files == list(arrays)
        for key, value in {**per_row, **shared}.items():
            assert read[key].dtype == value.dtype and read[key].shape == value.shape
            np.testing.assert_array_equal(read[key], value)


def test_npz_stream_refuses_a_non_finite_number_and_writes_nothing(tmp_path):
    values = np.array([1.0, 2.0, np.inf, 4.0])
    target = tmp_path / "t.npz"
    target.write_text("old")
    stream = npz_stream({"a": RowBlocks(4, lambda b: values[b])}, [slice(0, 2), slice(2, 4)], "--table")
    with pytest.raises(InputError, match="--table: the results hold a non-finite number"):
        write_all([(target, stream)])
    assert target.read_text() == "old" and [p.name for p in tmp_path.iterdir()] == ["t.npz"]


def test_npz_stream_refuses_blocks_that_do_not_cover_the_rows(tmp_path):
    with pytest.raises(ValueError, match="rows"):
        npz_stream({"a": RowBlocks(5, lambda b: np.zeros(5)[b])}, [slice(0, 2), slice(2, 4)], "--table")
    with pytest.raises(ValueError, match="consecutive"):
        npz_stream({"a": RowBlocks(4, lambda b: np.zeros(4)[b])}, [slice(0, 2), slice(3, 4)], "--table")


@pytest.mark.parametrize(("text", "part"), [
    ("crank", "crank"),
    ("pin crank:1-rod:0", "pin crank:1-rod:0"),
    ("a/b", "a%2Fb"),
    ("50%", "50%25"),
    ("line\nbreak\u200b", "line%0Abreak%E2%80%8B"),
    ("连杆", "连杆"),
])
def test_a_name_part_escapes_only_the_separator_the_escape_and_control_characters(text, part):
    assert table.key_part(text) == part
    assert unquote(part) == text


def test_texts_are_coded_by_their_first_appearance_after_the_empty_one():
    coded = table.text_codes(("", "toggle", "", "unreachable", "toggle"))
    assert coded.texts == ("", "toggle", "unreachable")
    assert coded.codes.tolist() == [0, 1, 0, 2, 1] and coded.codes.dtype == np.int32


def test_the_reading_example_of_docs_python_md_runs_on_a_table(tmp_path):
    # The example reads a table of the seed; its printed worst stress is the table's own.
    text = (REPO / "docs" / "python.md").read_text()
    example = text.split("## Reading a table", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    scene = seed_scene(tmp_path, "{ start = 0.0, stop = 360.0, num = 37 }")
    assert main(["analyze", str(scene), "--table", str(tmp_path / "sweep.npz")]) == 0
    done = subprocess.run([sys.executable, "-c", example], cwd=tmp_path, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    first, second = done.stdout.splitlines()
    assert first == "['input_angle_deg', 'feasible', 'reason_code', 'reason_texts']"
    with np.load(tmp_path / "sweep.npz") as t:
        stress = t["links/crank/max_von_mises_pa"]
    assert second.startswith(f"crank: {stress.max() / 1e6:.3g} MPa at input ")


def test_warnings_are_coded_per_position_with_several_on_one_row_joined_by_newlines():
    coded = table.warning_codes(((2, "passes a toggle"), (5, "change point"), (5, "toggle of loop b"), (7, "passes a toggle")), 9)
    assert coded.texts == ("", "passes a toggle", "change point\ntoggle of loop b")
    assert coded.codes.tolist() == [0, 0, 1, 0, 0, 2, 0, 1, 0]


@pytest.mark.parametrize("positions", [20_000, 60_000])
def test_writing_the_table_holds_a_block_at_a_time_not_the_table(tmp_path, monkeypatch, positions):
    # The table of the seed is about 720 bytes per position; written in blocks of 1,000 positions,
    # what the writer allocates at its peak (traced: numpy's arrays count) stays under half of it:
    # the sweep-long columns it shares with the JSON (accelerations, factor masks, text codes) and
    # one block of one array. Holding every array at once would take at least the file's size.
    import tracemalloc

    from linkstress.analysis import run_analysis
    from linkstress.scene import load_scene

    monkeypatch.setattr(table, "TABLE_BLOCK", 1_000)
    result = run_analysis(load_scene(seed_scene(tmp_path, f"{{ start = 0.0, stop = 359.0, num = {positions} }}")))
    tracemalloc.start()
    try:
        write_all([(tmp_path / "t.npz", table.table_stream(result))])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    size = (tmp_path / "t.npz").stat().st_size
    assert size > 700 * positions
    assert peak < 0.5 * size, (peak, size)
