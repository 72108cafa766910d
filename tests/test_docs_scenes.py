"""docs/scenes.md names every key the scene reader accepts, in its table's section, and its
example scenes read as scenes.

The keys come from the reader's own tuples, so a key added to the code without a line in the
docs fails here, naming it."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from linkstress.scene import load_scene
from linkstress.scene.keys import RANGES
from linkstress.scene.links import LINK_KEYS, MATERIAL_KEYS
from linkstress.scene.loads import ANALYSIS_KEYS, COUPLE_KEYS, FORCE_KEYS, LOAD_KEYS
from linkstress.scene.linkage import INPUT_KEYS, LINKAGE_KEYS, SLIDER_KEYS
from linkstress.scene.mechanisms import MECHANISM_KEYS, ROLE_KEYS
from linkstress.scene.motion import EXPRESSION_KEYS, MOTION_KEYS, RANGE_KEYS, STROKE_KEYS
from linkstress.scene.reader import TOP_KEYS

REPO = Path(__file__).resolve().parents[1]
DOC = REPO / "docs" / "scenes.md"
SEED = REPO / "validation" / "cases" / "seed_ansys_fourbar"

# Each section heading of docs/scenes.md (its text after "## ") and the keys the reader accepts
# in that table and in the inline tables nested in it.
SECTIONS = {
    "Top level": TOP_KEYS,
    "`[materials.NAME]`": MATERIAL_KEYS,
    "`[links.NAME]`": LINK_KEYS,
    "`[mechanisms.NAME]`": MECHANISM_KEYS + ROLE_KEYS + LINKAGE_KEYS + INPUT_KEYS + SLIDER_KEYS,
    "`[motion]`": MOTION_KEYS + RANGE_KEYS + EXPRESSION_KEYS + STROKE_KEYS,
    "`[loads]`": LOAD_KEYS + COUPLE_KEYS + FORCE_KEYS,
    "`[analysis]`": ANALYSIS_KEYS,
}


def sections(text: str) -> dict[str, str]:
    """The text of each "## " section, by its heading."""
    parts = re.split(r"^## (.+)$", text, flags=re.MULTILINE)
    return dict(zip(parts[1::2], parts[2::2]))


def examples(text: str) -> list[str]:
    return re.findall(r"```toml\n(.*?)```", text, flags=re.DOTALL)


def test_every_key_the_reader_accepts_is_named_in_its_tables_section():
    found = sections(DOC.read_text())
    missing_sections = [heading for heading in SECTIONS if heading not in found]
    assert not missing_sections, f"docs/scenes.md lacks the sections: {missing_sections}"
    missing = [
        f"{heading}: `{key}`" for heading, keys in SECTIONS.items() for key in keys if f"`{key}`" not in found[heading]
    ]
    assert not missing, "docs/scenes.md does not name these keys in their table's section: " + ", ".join(missing)


def test_the_ranges_table_is_the_readers():
    # "| kg/m^3 | a density | 1e-2 | 1e5 |": each unit's smallest (when > 0) and largest size
    table = DOC.read_text().split("| unit | quantity |", 1)[1].split("\n\n", 1)[0]
    rows = [line.strip("|").split(" | ") for line in table.splitlines()[2:]]
    documented = {unit.strip(): (float(smallest), float(largest), what) for unit, what, smallest, largest in rows}
    assert documented == RANGES


def test_every_table_of_the_scene_has_a_section():
    # the top level's keys are three plain values and one table each; a table added to the reader
    # without a section here fails
    tables = set(TOP_KEYS) - {"title", "notes", "units"}
    assert {heading.strip("`[]").split(".")[0] for heading in SECTIONS if heading != "Top level"} == tables


def test_the_docs_have_four_example_scenes():
    assert len(examples(DOC.read_text())) == 4


@pytest.mark.parametrize(("index", "title"), [(0, "Seed ANSYS four-bar"), (1, "Six-bar, two loops"),
                                                 (2, "Norton's four-bar, problem 4-1 g"),
                                                 (3, "Crank-shaper quick-return")])
def test_each_example_scene_reads(tmp_path, index, title):
    text = examples(DOC.read_text())[index]
    shutil.copy(SEED / "ansys_four_bars.dxf", tmp_path)
    path = tmp_path / "example.toml"
    path.write_text(text)
    scene = load_scene(path)
    assert scene.title == title


def test_the_seed_example_is_the_seed_case(tmp_path):
    # the same machine as validation/cases/seed_ansys_fourbar: links, motion and loads
    shutil.copy(SEED / "ansys_four_bars.dxf", tmp_path)
    path = tmp_path / "seed.toml"
    path.write_text(examples(DOC.read_text())[0])
    doc, case = load_scene(path), load_scene(SEED / "scene.toml")
    assert list(doc.links) == list(case.links) == ["crank", "coupler", "output", "ground"]
    for name in doc.links:
        assert doc.links[name].joints.tolist() == case.links[name].joints.tolist()
        assert doc.links[name].thickness == case.links[name].thickness == 0.1
    assert doc.motion.angle_deg.tolist() == case.motion.angle_deg.tolist() == [60.0]
    assert doc.motion.speed.tolist() == case.motion.speed.tolist() == [-1.0]
    assert doc.loads.couples == case.loads.couples
    assert doc.analysis is case.analysis is None


def test_the_two_loop_example_has_two_loops_driven_by_the_main_output(tmp_path):
    path = tmp_path / "six_bar.toml"
    path.write_text(examples(DOC.read_text())[1])
    scene = load_scene(path)
    assert [loop.name for loop in scene.machine.loops] == ["main", "second"]
    assert scene.machine.loops[1].driven_by.role == "output"
    # {start = 0.0, stop = 350.0, num = 36}: stop included, every 10 deg
    assert scene.motion.angle_deg[0] == 0.0 and scene.motion.angle_deg[-1] == 350.0
    assert len(scene.motion.angle_deg) == 36


def test_the_two_loop_example_moves_as_the_drawn_six_bar_case(tmp_path):
    # its bare joints are the case's drawn ones (validation/cases/six_bar), so every link turns alike
    from linkstress.kinematics import solve_machine

    path = tmp_path / "six_bar.toml"
    path.write_text(examples(DOC.read_text())[1])
    doc, case = load_scene(path), load_scene(REPO / "validation" / "cases" / "six_bar" / "scene.toml")
    doc_motion, case_motion = solve_machine(doc.machine, doc.motion), solve_machine(case.machine, case.motion)
    assert doc_motion.feasible.all() and case_motion.feasible.all()
    for name in case.links:
        assert doc_motion.links[name].angle == pytest.approx(case_motion.links[name].angle, abs=1e-9)
        assert doc_motion.links[name].omega == pytest.approx(case_motion.links[name].omega, rel=1e-9, abs=1e-9)
