"""The FEA's disk cache: entries read back as written, a damaged one is never trusted, the least
recently used go first, two processes share a key safely, the key changes with every input that
determines the unit-load solutions, and cached solutions are the computed ones to the bit."""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from linkstress.cli import main
from test_validate_blocks import without_timing
from linkstress.geometry.builders import straight_bar
from linkstress.loads import LinkLoadCase, PointForce
from linkstress.materials import STRUCTURAL_STEEL
from linkstress.validation.fea import cache as cache_module
from linkstress.validation.fea.cache import CacheSettings, DiskCache, cache_key, cache_settings
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.fea.link import link_region, solve_link
from linkstress.validation.fea.mesh import MeshSettings
from linkstress.validation.fea.unit_loads import UNIT_LOADS, unit_case_layout, unit_cases_key, unit_load_cases
from linkstress.validation.peaks import sweep_peaks

MESH = MeshSettings(0.02, 0.003)
SEED = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar"


def entry(seed: int, size: int = 1000) -> dict[str, np.ndarray]:
    """Arrays of every kind an entry holds: floats, integers, text."""
    rng = np.random.default_rng(seed)
    return {"stress": rng.standard_normal((size, 3)), "t": rng.integers(0, 99, (6, size // 10)),
            "labels": np.array(["pin 0: unit couple", "body: unit alpha"])}


def same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(a[k].dtype == b[k].dtype and np.array_equal(a[k], b[k]) for k in a)


@pytest.mark.parametrize("size", [0, 10, 20_000])
def test_an_entry_reads_back_as_stored(tmp_path, size):
    cache = DiskCache(CacheSettings(str(tmp_path)))
    key = cache_key("test", {"size": size})
    assert cache.load("test", key) is None
    cache.store("test", key, entry(size, size))
    assert same(cache.load("test", key), entry(size, size))


def test_a_truncated_entry_is_a_miss_and_is_deleted_then_rebuilt(tmp_path):
    cache = DiskCache(CacheSettings(str(tmp_path)))
    key = cache_key("test", {"n": 1})
    cache.store("test", key, entry(1))
    whole = cache.path("test", key).read_bytes()
    for length in np.linspace(0, len(whole) - 1, 17).astype(int):
        cache.path("test", key).write_bytes(whole[:length])
        assert cache.load("test", key) is None
        assert not cache.path("test", key).exists()
    cache.store("test", key, entry(1))
    assert same(cache.load("test", key), entry(1))


def test_a_flipped_byte_never_gives_other_arrays(tmp_path):
    """Anywhere in the file: a miss, or (a byte the zip format does not check, e.g. a timestamp)
    exactly the stored arrays; in the arrays' own bytes: always a miss."""
    cache = DiskCache(CacheSettings(str(tmp_path)))
    key = cache_key("test", {"n": 2})
    stored = entry(2, 300)
    cache.store("test", key, stored)
    whole = cache.path("test", key).read_bytes()
    data = whole.find(stored["stress"].tobytes())
    assert data > 0  # .npz entries are stored, not compressed
    offsets = sorted(set(np.linspace(0, len(whole) - 1, 97).astype(int)) | {data, data + 1000, data + 7199})
    misses = 0
    for offset in offsets:
        flipped = bytearray(whole)
        flipped[offset] ^= 0x10
        cache.path("test", key).write_bytes(bytes(flipped))
        loaded = cache.load("test", key)
        in_data = data <= offset < data + stored["stress"].nbytes
        assert loaded is None if in_data else (loaded is None or same(loaded, stored)), offset
        misses += loaded is None
    assert misses > len(offsets) // 2


def test_a_well_formed_entry_whose_arrays_do_not_match_its_checksum_is_refused(tmp_path):
    """Damage the zip format's own CRC cannot see: an entry rewritten whole, with other arrays under
    the first one's checksum (a writer that went wrong)."""
    cache = DiskCache(CacheSettings(str(tmp_path)))
    key = cache_key("test", {"n": 3})
    cache.store("test", key, entry(3))
    with np.load(cache.path("test", key)) as stored:
        arrays = {name: stored[name] for name in stored.files}
    arrays["stress"] = arrays["stress"] * (1 + 1e-15)
    with open(cache.path("test", key), "wb") as file:
        np.savez(file, **arrays)
    assert cache.load("test", key) is None and not cache.path("test", key).exists()


def test_an_entry_moved_under_another_key_is_refused(tmp_path):
    cache = DiskCache(CacheSettings(str(tmp_path)))
    first, second = cache_key("test", {"n": 1}), cache_key("test", {"n": 2})
    cache.store("test", first, entry(1))
    cache.path("test", first).rename(cache.path("test", second))
    assert cache.load("test", second) is None


def test_the_least_recently_used_entries_go_first(tmp_path):
    one = sum(a.nbytes for a in entry(0).values())
    cache = DiskCache(CacheSettings(str(tmp_path), max_bytes=int(3.5 * (one + 2000))))
    keys = [cache_key("test", {"n": n}) for n in range(5)]
    now = time.time()
    for n, key in enumerate(keys[:3]):
        cache.store("test", key, entry(n))
        os.utime(cache.path("test", key), (now - 100 + n, now - 100 + n))  # stored 0, 1, 2 in that order
    assert cache.load("test", keys[0]) is not None  # 0 used again: 1 is now the least recently used
    cache.store("test", keys[3], entry(3))
    assert [cache.path("test", k).exists() for k in keys[:4]] == [True, False, True, True]
    assert cache.size() <= cache.settings.max_bytes
    cache.store("test", keys[4], entry(4, 100_000))  # larger than the whole cache: not kept
    assert not cache.path("test", keys[4]).exists() and cache.path("test", keys[3]).exists()


def test_a_temporary_file_left_by_a_dead_writer_is_removed_after_an_hour(tmp_path):
    cache = DiskCache(CacheSettings(str(tmp_path)))
    (tmp_path / "test").mkdir()
    old, fresh = tmp_path / "test" / ".old.tmp", tmp_path / "test" / ".fresh.tmp"
    old.write_bytes(b"x" * 100)
    fresh.write_bytes(b"x" * 100)
    os.utime(old, (time.time() - 2 * cache_module.STALE_TEMPORARY_SECONDS,) * 2)
    cache.evict()
    assert not old.exists() and fresh.exists()


WRITER = """
import sys
import numpy as np
from linkstress.validation.fea.cache import CacheSettings, DiskCache, cache_key
cache = DiskCache(CacheSettings(sys.argv[1]))
key = cache_key("test", {"shared": True})
expected = np.random.default_rng(5).standard_normal((400_000, 3))
for _ in range(int(sys.argv[2])):
    cache.store("test", key, {"stress": expected})
    loaded = cache.load("test", key)  # this one's or the other's, both whole: never missing, never other
    assert loaded is not None and np.array_equal(loaded["stress"], expected), "a wrong entry was read"
print("ok")
"""


def test_two_processes_writing_and_reading_one_key_at_once_only_ever_read_the_whole_entry(tmp_path):
    script = tmp_path / "writer.py"
    script.write_text(WRITER)
    runs = [subprocess.Popen([sys.executable, str(script), str(tmp_path / "cache"), "25"], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True) for _ in range(2)]
    outcomes = [run.communicate(timeout=300) for run in runs]
    assert [run.returncode for run in runs] == [0, 0], outcomes
    files = list((tmp_path / "cache" / "test").iterdir())
    assert len(files) == 1 and files[0].suffix == ".npz"  # no temporary file left behind
    cache = DiskCache(CacheSettings(str(tmp_path / "cache")))
    assert np.array_equal(cache.load("test", files[0].stem)["stress"],
                          np.random.default_rng(5).standard_normal((400_000, 3)))


def test_keys_take_plain_values_and_arrays_only():
    assert cache_key("k", {"a": [1, 2.5, None, True, "x"], "b": np.arange(3.0)}) == cache_key(
        "k", {"b": np.arange(3.0), "a": (1, 2.5, None, True, "x")})
    assert cache_key("k", {"x": 0.1}) != cache_key("k", {"x": np.nextafter(0.1, 1)})
    assert cache_key("k", {"x": np.arange(3.0)}) != cache_key("k", {"x": np.arange(3)})  # dtype counts
    for bad in (object(), np.array([object()]), {1: 2}):
        with pytest.raises(TypeError):
            cache_key("k", {"x": bad})


def bar(**changes):
    """A steel bar 0.4 m between 12 mm pin holes, 0.06 m deep, 5 mm thick (``straight_bar`` arguments changed)."""
    arguments = {"spacing": 0.4, "height": 0.06, "overhang": 0.04, "thickness": 0.005, "material": STRUCTURAL_STEEL,
                 "hole_diameter": 0.012, "name": "bar"} | changes
    return straight_bar(**arguments)


def loads(positions: int = 4, couple: bool = True, point_at=(0.2, 0.01)) -> LinkLoadCase:
    rng = np.random.default_rng(positions)
    return LinkLoadCase(
        (0, 1), rng.uniform(-500, 500, (positions, 2, 2)),
        rng.uniform(-20, 20, (positions, 2)) * np.array([1.0, 1.0 if couple else 0.0]),
        omega=rng.uniform(-30, 30, positions), alpha=rng.uniform(-500, 500, positions),
        origin_acceleration=rng.uniform(-50, 50, (positions, 2)), gravity=np.zeros((positions, 2)),
        point_forces=(PointForce(np.array(point_at), rng.uniform(-300, 300, (positions, 2))),),
    )


def key_of(link, load_case, mesh=MESH, step=10.0) -> str:
    return unit_cases_key(link, load_case.frame_joints, link_region(link, load_case, mesh),
                          unit_case_layout(link, load_case, step))


def test_the_key_changes_with_every_input_that_determines_the_unit_solutions_and_only_with_those():
    base = key_of(bar(), loads())
    assert key_of(bar(), loads(positions=9)) == base  # other positions' loads of the same kinds: the same cases
    steel = STRUCTURAL_STEEL
    changed = {
        "a hole by one ulp": key_of(bar(hole_diameter=np.nextafter(0.012, 1)), loads()),
        "the outline": key_of(bar(height=0.061), loads()),
        "thickness": key_of(bar(thickness=0.006), loads()),
        "Young's modulus": key_of(bar(material=replace(steel, youngs_modulus=201e9)), loads()),
        "Poisson's ratio": key_of(bar(material=replace(steel, poisson_ratio=0.29)), loads()),
        "density": key_of(bar(material=replace(steel, density=7800.0)), loads()),
        "element size": key_of(bar(), loads(), replace(MESH, size=0.019)),
        "hole element size": key_of(bar(), loads(), replace(MESH, hole_size=0.0029)),
        "element order": key_of(bar(), loads(), replace(MESH, order=1)),
        "a refinement level": key_of(bar(), loads(), MESH.refined(1.5)),
        "bearing directions": key_of(bar(), loads(), step=15.0),
        "a couple through a pin": key_of(bar(), loads(couple=False)),
        "a point force's place": key_of(bar(), loads(point_at=(0.21, 0.01))),
        "a point force moved into a hole": key_of(bar(), loads(point_at=(0.402, 0.001))),
    }
    assert all(k != base for k in changed.values()), [what for what, k in changed.items() if k == base]
    assert len(set(changed.values())) == len(changed)


@pytest.mark.parametrize("order", [1, 2])
def test_cached_unit_solutions_are_the_computed_ones_to_the_bit(tmp_path, order):
    link, load_case, mesh = bar(), loads(6), replace(MESH, order=order)
    cache = DiskCache(CacheSettings(str(tmp_path)))
    computed = unit_load_cases(link, load_case, mesh)
    first = unit_load_cases(link, load_case, mesh, cache=cache)  # a miss: solved and stored
    second = unit_load_cases(link, load_case, mesh, cache=cache)  # a hit
    assert not first.cached and second.cached and second.seconds["solve"] == 0.0
    for cases in (first, second):
        assert np.array_equal(cases.stress, computed.stress) and np.array_equal(cases.reactions, computed.reactions)
        assert np.array_equal(cases.nodes, computed.nodes) and cases.labels == computed.labels
        assert np.array_equal(cases.model.scalar.element_dofs, computed.model.scalar.element_dofs)
    peaks, cached = sweep_peaks(computed, load_case), sweep_peaks(second, load_case)
    assert np.array_equal(peaks.peak, cached.peak) and np.array_equal(peaks.envelope, cached.envelope)
    assert len(list((tmp_path / UNIT_LOADS).iterdir())) == 1 and len(list((tmp_path / "mesh").iterdir())) == 1


def test_a_direct_solve_takes_its_mesh_from_the_cache_and_gives_the_same_stresses(tmp_path):
    link, load_case = bar(), loads(3)
    cache = DiskCache(CacheSettings(str(tmp_path)))
    computed = solve_link(link, load_case, MESH)
    solve_link(link, load_case, MESH, cache)
    cached = solve_link(link, load_case, MESH, cache)
    assert np.array_equal(cached.nodal_stress, computed.nodal_stress)
    assert np.array_equal(cached.plane.holes[0], computed.plane.holes[0]) and len(cached.plane.holes) == 2


def test_a_damaged_unit_load_entry_is_solved_again(tmp_path):
    link, load_case = bar(), loads(2)
    cache = DiskCache(CacheSettings(str(tmp_path)))
    computed = unit_load_cases(link, load_case, MESH, cache=cache)
    path = next((tmp_path / UNIT_LOADS).iterdir())
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    again = unit_load_cases(link, load_case, MESH, cache=cache)
    assert not again.cached and np.array_equal(again.stress, computed.stress)
    assert unit_load_cases(link, load_case, MESH, cache=cache).cached


def seed_sweep(folder: Path) -> Path:
    (folder / "ansys_four_bars.dxf").write_bytes((SEED / "ansys_four_bars.dxf").read_bytes())
    text = (SEED / "scene.toml").read_text().replace("input_angle_deg = 60.0", "input_angle_deg = {start = 0.0, stop = 350.0, num = 8}")
    (folder / "scene.toml").write_text(text)
    return folder / "scene.toml"


@pytest.mark.slow
def test_two_analyze_runs_at_once_share_one_cache_and_a_third_reads_it(tmp_path):
    """Both write the same entries at the same moment; each result is the one without a cache, and a
    later run, reading every entry, gives it again."""
    scene = seed_sweep(tmp_path)
    folder = tmp_path / "cache"
    command = [sys.executable, "-m", "linkstress", "analyze", str(scene), "--peaks", "--cache", str(folder), "--json"]
    runs = [subprocess.Popen(command + [str(tmp_path / f"run{k}.json")], stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, text=True) for k in range(2)]
    assert [run.wait(timeout=600) for run in runs] == [0, 0], [run.stderr.read() for run in runs]
    assert main(["analyze", str(scene), "--peaks", "--no-cache", "--json", str(tmp_path / "plain.json")]) == 0
    assert main(["analyze", str(scene), "--peaks", "--cache", str(folder), "--json", str(tmp_path / "warm.json")]) == 0
    plain = without_timing(json.loads((tmp_path / "plain.json").read_text()))
    for name in ("run0", "run1", "warm"):
        assert without_timing(json.loads((tmp_path / f"{name}.json").read_text())) == plain, name
    kinds = {p.parent.name for p in folder.glob("*/*.npz")}
    assert kinds == {"mesh", UNIT_LOADS, "direct-peak", "sweep-peaks"} and not list(folder.glob("*/*.tmp"))


def test_no_cache_writes_nothing_and_a_cache_folder_that_is_a_file_is_refused(tmp_path, monkeypatch, capsys):
    scene = seed_sweep(tmp_path)
    monkeypatch.setenv("LINKSTRESS_CACHE", str(tmp_path / "default"))
    assert main(["analyze", str(scene), "--peaks", "--no-cache"]) == 0
    assert not (tmp_path / "default").exists()
    (tmp_path / "file").write_text("not a folder")
    assert main(["analyze", str(scene), "--peaks", "--cache", str(tmp_path / "file")]) == 2
    assert "--cache: cannot make the cache folder" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exit:  # argparse refuses both at once
        main(["analyze", str(scene), "--peaks", "--cache", str(tmp_path / "x"), "--no-cache"])
    assert exit.value.code == 2


def test_the_variables_choose_the_folder_and_bound_the_size(tmp_path, monkeypatch):
    monkeypatch.setenv("LINKSTRESS_CACHE", str(tmp_path / "from-variable"))
    monkeypatch.setenv("LINKSTRESS_CACHE_SIZE", "5e8")
    assert cache_settings(None) == CacheSettings(str(tmp_path / "from-variable"), 500_000_000)
    assert cache_settings(tmp_path / "option").directory == str(tmp_path / "option")
    assert cache_settings(None, off=True) is None
    monkeypatch.delenv("LINKSTRESS_CACHE")
    monkeypatch.delenv("LINKSTRESS_CACHE_SIZE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_settings(None) == CacheSettings(str(tmp_path / "xdg" / "linkstress"), cache_module.DEFAULT_MAX_BYTES)
    for bad in ("lots", "-1", "nan", "inf"):
        monkeypatch.setenv("LINKSTRESS_CACHE_SIZE", bad)
        with pytest.raises(FEAError, match=f"LINKSTRESS_CACHE_SIZE: '{bad}' is not a size in bytes"):
            cache_settings(None)
    assert math.isfinite(cache_module.DEFAULT_MAX_BYTES)


def test_validate_and_regress_keep_their_meshes_in_the_cache_and_refuse_a_bad_solver(tmp_path, monkeypatch, capsys):
    case = tmp_path / "slider_crank_curved_rod"
    shutil.copytree(SEED.parent / "slider_crank_curved_rod", case)
    for run in ("cold", "warm"):
        assert main(["regress", str(case), "--cache", str(tmp_path / "regress")]) == 0, run
    meshes = list((tmp_path / "regress" / "mesh").glob("*.npz"))
    assert meshes and not (tmp_path / "regress" / UNIT_LOADS).exists()  # validate's solves are not kept
    scene = SEED / "scene.toml"
    assert main(["validate", str(scene), "--mesh-levels", "1", "--cache", str(tmp_path / "validate")]) == 0
    assert len(list((tmp_path / "validate" / "mesh").glob("*.npz"))) == 3  # a mesh per link
    monkeypatch.setenv("LINKSTRESS_SOLVER", "bogus")
    capsys.readouterr()
    assert main(["validate", str(scene), "--mesh-levels", "1"]) == 2
    assert main(["regress", str(case)]) == 2
    assert capsys.readouterr().err.count("LINKSTRESS_SOLVER: 'bogus' is not a solver") == 2
