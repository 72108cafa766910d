"""A report's page is titled by its scene: the scene's ``title``, else its file's name (a case's
``scene.toml`` with its folder's), then the command; never "linkstress analyze: scene"."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from linkstress.cli import main

CASES = Path(__file__).resolve().parents[1] / "validation" / "cases"


def page_title(path: Path) -> tuple[str, str]:
    text = path.read_text()
    return re.search(r"<title>(.*?)</title>", text).group(1), re.search(r"<h1>(.*?)</h1>", text).group(1)


def textbook_copy(folder: Path, name: str, title: str = "") -> Path:
    """The textbook four-bar (bare joints, one position; it gives no title) as ``folder/name``,
    with ``title`` if given."""
    folder.mkdir(parents=True)
    text = (CASES / "textbook_fourbar" / "scene.toml").read_text()
    assert not re.search(r"(?m)^title =", text)
    (folder / name).write_text((f"title = {title!r}\n" if title else "") + text)
    return folder / name


def test_a_titled_scene_titles_its_analyze_page(tmp_path):
    scene = textbook_copy(tmp_path / "case", "scene.toml", title="Norton 4-1 g")
    assert main(["analyze", str(scene), "--html", str(tmp_path / "r.html")]) == 0
    assert page_title(tmp_path / "r.html") == ("Norton 4-1 g: linkstress analyze",) * 2


@pytest.mark.parametrize("folder, name, expected", [
    ("press", "scene.toml", "press/scene.toml: linkstress analyze"),
    ("work", "fourbar.toml", "fourbar.toml: linkstress analyze"),
])
def test_an_untitled_scene_is_named_by_its_file(tmp_path, folder, name, expected):
    scene = textbook_copy(tmp_path / folder, name)
    assert main(["analyze", str(scene), "--html", str(tmp_path / "r.html")]) == 0
    assert page_title(tmp_path / "r.html") == (expected, expected)


def test_validate_titles_its_page_by_the_scene_too(tmp_path):
    case = shutil.copytree(CASES / "seed_ansys_fourbar", tmp_path / "seed")
    out = tmp_path / "v.html"
    assert main(["validate", str(case / "scene.toml"), "--mesh-levels", "1", "--positions", "1", "--html", str(out)]) == 0
    title, _ = page_title(out)
    assert title == "Seed ANSYS four-bar (KSAM thesis, section 6.3.5): linkstress validate"
