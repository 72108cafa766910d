"""Long sweeps in bounded memory: the analysis keeps per-position reductions of the section
stresses, ``analyze --json`` is written block by block, and the arrays along a link are recomputed
where they are needed (a block of records with ``--stations``, the positions the HTML draws)."""

from __future__ import annotations

import errno
import io
import json
from dataclasses import replace

import numpy as np
import pytest

from linkstress.analysis import plan_for, run_analysis
from linkstress.cli import main
from linkstress.dynamics import section_stress
from linkstress.dynamics.section_stress import StressSummary
from linkstress.output import json_bytes, json_stream, write_json, write_json_stream
from linkstress.report.records import links_record, position_records, summary_record
from linkstress.report.verdict import analysis_verdict
from linkstress.scene import load_scene
from linkstress.validation.bench.memory import analyze_in_child, seed_sweep_scene

LINKS = ("crank", "coupler", "output")


@pytest.fixture
def blocks_of_five(monkeypatch):
    """Section stresses evaluated in blocks of at most 5 positions on the calling thread."""
    monkeypatch.setattr(section_stress, "POSITION_BLOCK", 5)
    monkeypatch.setattr(section_stress, "THREADED_PAIRS", 10**12)


def test_streamed_json_with_stations_is_the_json_of_the_records_built_in_memory(tmp_path, blocks_of_five):
    # 23 positions of the seed four-bar in blocks of 5, 4, 5, 4, 5 (even_blocks): the streamed file
    # is json.dumps of every record at once, byte for byte, and each block's arrays along the links
    # are those its reductions came from.
    scene_path = seed_sweep_scene(tmp_path, 23)
    out = tmp_path / "out.json"
    # --beam-only: the stream of the beam's columns (the FEA peaks' columns have their own tests)
    assert main(["analyze", str(scene_path), "--json", str(out), "--stations", "--beam-only"]) == 0
    scene = load_scene(scene_path)
    result = run_analysis(scene, replace(plan_for(scene), beam_only=True))
    assert [b.stop - b.start for b in result.stresses["crank"].blocks] == [5, 4, 5, 4, 5]
    records = position_records(result, stations=True)
    after = {"links": links_record(result), **summary_record(result, analysis_verdict(result))}
    assert out.read_bytes() == (json.dumps({"positions": records, **after}, indent=1, allow_nan=False) + "\n").encode()
    ok = result.feasible
    assert ok.sum() == 23
    for name in LINKS:
        links = [r["links"][name] for r in records]
        along = np.array([link["stations"]["von_mises_pa"] for link in links])
        # the largest of each record's own arrays is its max_von_mises_pa, exactly
        np.testing.assert_array_equal(along.max(axis=1), [link["max_von_mises_pa"] for link in links])
        # and the whole sweep evaluated in one block gives the same arrays to rounding
        whole = result.stresses[name].at(slice(None))
        np.testing.assert_allclose(along, whole.von_mises, rtol=1e-12)
        moment = np.array([link["stations"]["moment_nm"] for link in links])
        np.testing.assert_allclose(moment, whole.forces.moment, rtol=0, atol=1e-12 * np.abs(whole.forces.moment).max())


@pytest.mark.parametrize("items", [[], [{}], [1.5, {"a": [1, 2.25], "b": {"c": None, "d": []}}, "line\nbreak", [True]]])
def test_json_stream_writes_the_bytes_of_write_json(tmp_path, items):
    write_json_stream(tmp_path / "streamed.json", "positions", iter(items))
    write_json(tmp_path / "whole.json", {"positions": items})
    assert (tmp_path / "streamed.json").read_bytes() == (tmp_path / "whole.json").read_bytes()


def test_a_json_stream_that_fails_part_way_leaves_no_file_and_the_old_one_untouched(tmp_path):
    def items():
        yield {"input_angle_deg": 0.0}
        raise RuntimeError("the records could not be made")

    target = tmp_path / "out.json"
    with pytest.raises(RuntimeError):
        write_json_stream(target, "positions", items())
    assert list(tmp_path.iterdir()) == []
    target.write_text("old")
    with pytest.raises(ValueError):  # NaN is never written
        write_json_stream(target, "positions", iter([{"a": 1.0}, {"b": float("nan")}]))
    assert target.read_text() == "old"
    assert list(tmp_path.iterdir()) == [target]


def test_analyze_on_a_full_disk_says_which_file_and_leaves_no_part_of_it(tmp_path, monkeypatch, capsys):
    scene_path = seed_sweep_scene(tmp_path, 7)
    out = tmp_path / "out.json"
    out.write_text("old")
    from linkstress.commands import analyze

    real = analyze.stream_position_records

    def disk_fills(result, stations=False):
        records = real(result, stations)
        yield next(records)
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(analyze, "stream_position_records", disk_fills)
    assert main(["analyze", str(scene_path), "--json", str(out)]) == 2
    message = capsys.readouterr().err
    assert "out.json" in message and "No space left on device" in message and "Traceback" not in message
    assert out.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["out.json", scene_path.name, "ansys_four_bars.dxf"])


def test_the_html_recomputes_the_arrays_along_a_link_only_at_the_positions_it_draws(tmp_path, monkeypatch):
    # 40 positions: each link's figure of stresses along it is at that link's worst position, and
    # only that one position is evaluated again for it.
    scene_path = seed_sweep_scene(tmp_path, 40)
    asked = []
    real = StressSummary.at

    def spy(self, positions):
        asked.append((positions, self))
        return real(self, positions)

    monkeypatch.setattr(StressSummary, "at", spy)
    out = tmp_path / "report.html"
    assert main(["analyze", str(scene_path), "--html", str(out)]) == 0
    text = out.read_text()
    for name in LINKS:
        assert f'alt="stresses along {name}"' in text
    result = run_analysis(load_scene(scene_path))
    worst = [int(np.argmax(result.stresses[name].max_von_mises)) for name in LINKS]
    # One position at a time, never a block of the sweep: each link's worst (its figure) and where
    # its largest value away from holes is (the text and the HTML each name that point).
    assert all(p.stop - p.start == 1 for p, _ in asked) and len(asked) <= 3 * len(LINKS)
    assert {(p.start, p.stop) for p, _ in asked} >= {(k, k + 1) for k in worst}
    drawn = text.count('alt="mechanism at position ')
    assert 1 <= drawn <= 4


@pytest.mark.slow
def test_a_200000_position_sweep_with_stresses_stays_under_600_mb(tmp_path):
    # A sweep used to hold every link's (P, S) arrays of N, V, M, von Mises and fibre y:
    # 3 links x 101 stations x 5 x 8 bytes = 12 kB per position, 2.4 GB here (2.7 GB peak measured).
    # Now per position: kinematics, joint forces, load coefficients and the reductions (about
    # 1.3 kB, 1.36 GB peak at 1,000,000 positions). Beam only: the FEA peaks the crank's model
    # chooses superpose a bounded block of positions at a time (peaks.BLOCK_VALUES) but add their
    # own working arrays (382 MB beam only against 627 MB with them, measured at this size).
    run = analyze_in_child(seed_sweep_scene(tmp_path, 200_000), None, "--beam-only")
    assert run.code == 0
    assert run.peak_bytes < 600e6


@pytest.mark.slow
def test_writing_the_json_of_a_10000_position_sweep_adds_under_60_mb(tmp_path):
    # Before, the records were built whole as Python lists first: about 34 kB per position
    # (4.8 GB peak against 1.4 GB without --json at 100,000 positions), 340 MB here. Streamed, a
    # block of 2,048 records at a time.
    scene = seed_sweep_scene(tmp_path, 10_000)
    without = analyze_in_child(scene)
    out = tmp_path / "out.json"
    with_json = analyze_in_child(scene, out)
    assert without.code == with_json.code == 0
    assert with_json.json_bytes > 50e6
    assert with_json.peak_bytes - without.peak_bytes < 60e6


@pytest.mark.parametrize("after", [{}, {"links": {}}, {"links": {"crank": {"a": [1.0, 2.5], "b": None}}, "more": [1]}])
def test_json_stream_writes_the_keys_after_the_list_as_write_json_would(after):
    stream = io.BytesIO()
    json_stream("positions", iter([{"x": 1.0}, {"y": [2]}]), "--json", lambda: after)(stream)
    assert stream.getvalue() == json_bytes({"positions": [{"x": 1.0}, {"y": [2]}], **after}, "--json")
