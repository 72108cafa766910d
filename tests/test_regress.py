"""linkstress regress: the shipped cases pass; a tightened tolerance or a changed result fails."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from linkstress.cli import main

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"


@pytest.fixture
def seed_copy(tmp_path):
    folder = tmp_path / "cases" / "seed"
    shutil.copytree(CASES / "seed_ansys_fourbar", folder)
    return folder


def edit_reference(folder: Path, change) -> None:
    path = folder / "reference.json"
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))


def test_the_shipped_cases_pass(capsys):
    assert main(["regress"]) == 0
    out = capsys.readouterr().out
    assert "15 of 15 cases passed" in out


def test_a_tolerance_tightened_below_the_current_error_fails(seed_copy, capsys):
    # The seed's coupler nominal error is about 0.65 % against converged FEA; a 0.1 % limit must fail.
    edit_reference(seed_copy, lambda d: d["limits"].update(nominal_error_pct=0.1))
    assert main(["regress", str(seed_copy.parent)]) == 1
    out = capsys.readouterr().out
    assert "REGRESSION" in out and "coupler nominal_error_pct limit" in out and "regressions in seed" in out


def test_a_changed_stored_force_fails_the_forces_check(seed_copy, capsys):
    def nudge(data):
        f12 = data["analysis"][0]["mechanisms"]["main"]["forces_n"]["F12"]
        f12[0] *= 1.001
    edit_reference(seed_copy, nudge)
    assert main(["regress", str(seed_copy)]) == 1
    assert "forces" in capsys.readouterr().out


def test_update_rewrites_the_reference_and_a_missing_one_is_an_error(seed_copy, capsys):
    (seed_copy / "reference.json").unlink()
    assert main(["regress", str(seed_copy)]) == 1
    assert "no reference.json: run linkstress regress --update" in capsys.readouterr().out
    assert main(["regress", str(seed_copy), "--update"]) == 0
    stored = json.loads((seed_copy / "reference.json").read_text())
    assert stored["tolerances"]["forces"] == 1e-7 and stored["analysis"][0]["feasible"] is True
    assert main(["regress", str(seed_copy)]) == 0


def test_update_keeps_the_stored_numbers_this_run_reproduces(seed_copy, capsys):
    # Stored numbers 1e-13 off this run's (the FEA figures vary by about that between runs) are kept
    # by a rewrite; a force 0.1 % off takes this run's value. So the reference's diff after an
    # intended change shows only what changed.
    f12 = ("analysis", 0, "mechanisms", "main", "forces_n", "F12", 0)

    def off(data):
        for part in ("analysis", "validation"):
            data[part] = scaled(data[part], 1 + 1e-13)
        set_(data, f12, get(data, f12) * 1.001)

    original = json.loads((seed_copy / "reference.json").read_text())
    edit_reference(seed_copy, off)
    stored = json.loads((seed_copy / "reference.json").read_text())
    assert main(["regress", str(seed_copy), "--update"]) == 0
    now = json.loads((seed_copy / "reference.json").read_text())
    assert get(now, f12) == pytest.approx(get(original, f12), rel=1e-12)
    set_(now, f12, get(stored, f12))
    assert now == stored


def scaled(data, factor):
    """``data`` with every number (not a boolean) times ``factor``."""
    if isinstance(data, dict):
        return {key: scaled(value, factor) for key, value in data.items()}
    if isinstance(data, list):
        return [scaled(value, factor) for value in data]
    if isinstance(data, float):
        return data * factor
    return data


def get(data, path):
    for key in path:
        data = data[key]
    return data


def set_(data, path, value):
    get(data, path[:-1])[path[-1]] = value


def test_a_folder_without_cases_exits_2(tmp_path, capsys):
    assert main(["regress", str(tmp_path)]) == 2
    assert "holds no case" in capsys.readouterr().err


def test_a_case_whose_sketch_path_is_wrong_is_bad_input_naming_the_case_and_the_path(seed_copy, capsys):
    # The scene points into a folder that does not exist: exit 2 before any case runs (not 1, a
    # failed check), one message with the case, the key and the path as the scene resolves it.
    scene = seed_copy / "scene.toml"
    scene.write_text(scene.read_text().replace('sketch = "ansys_four_bars.dxf"', 'sketch = "drawings/ansys_four_bars.dxf"'))
    shutil.copytree(CASES / "textbook_fourbar", seed_copy.parent / "textbook")
    assert main(["regress", str(seed_copy.parent)]) == 2
    captured = capsys.readouterr()
    (line,) = captured.err.strip().splitlines()
    assert line.startswith("linkstress: error: case seed: scene.toml: links.crank.sketch: file ")
    assert "seed/drawings/ansys_four_bars.dxf' not found" in line
    assert "cases passed" not in captured.out


def test_a_vector_component_near_zero_is_judged_against_the_whole_vector():
    # A ram along a level guide: its acceleration's y is 0 in the reference and 2.3e-16 m/s2 (float
    # noise) in a run, against an x of 4.2 m/s2; judged against its own largest stored value it would
    # be a 100 % regression, against the vector's 4.2 m/s2 it is 5e-17.
    from validation.regression import compare_analysis

    def position(acc):
        return {"feasible": True, "links": {"ram": {"acc_G_m_s2": acc}}}

    stored = [position([-4.232, 0.0]), position([-3.684, 1e-17])]
    current = [position([-4.232, -2.35e-16]), position([-3.684, -2.0e-16])]
    (check,) = [c for c in compare_analysis("ram", stored, current, {"kinematics": 1e-9}) if c.what == "kinematics"]
    assert check.worst < 1e-15
    moved = [position([-4.232, 0.0]), position([-3.684, 1e-3])]
    (check,) = [c for c in compare_analysis("ram", stored, moved, {"kinematics": 1e-9}) if c.what == "kinematics"]
    assert check.worst == pytest.approx(1e-3 / 4.232, rel=1e-6)
