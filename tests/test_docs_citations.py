"""docs/ and the README cite nothing that is not in the repository: every relative link resolves to
a file in it, every path they name in backticks is one of its files or folders, and a file said to
be "beside this file" is there. (A thesis or book is cited by author, title and year instead.)

A path in backticks (with a folder) is looked for where the docs mean it: beside the page, from the repository's
root, or from one of the three source folders the package is made of (``src/`` holds
``linkstress/...``; ``validation/`` holds ``fea/...``; ``importers/``). A bare file name in backticks
(``members.py``) of a source, docs or text file must be some file of the repository. Names of files
a reader makes (``fourbar.toml``, ``fourbar.png``, ``report.html``) are not checked: they have no
folder and are not source or docs files.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PAGES = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
ROOTS = (Path(), Path("src"), Path("src/linkstress"), Path("validation"), Path("importers"))
REPO_FILES = (".py", ".md", ".js", ".txt", ".dxf", ".csv", ".png")
"""Backticked paths ending so are files this repository must hold."""
SOURCE_FILES = (".py", ".md", ".js", ".txt")
"""Backticked bare names ending so (source, docs, text) too; a bare drawing or image name may be one a
reader makes (the tutorial's ``fourbar.png``)."""
SKIPPED_DIRS = {".git", ".venv", "__pycache__", "linkstress.egg-info"}


def prose(page: Path) -> str:
    """The page without its code blocks (commands a reader runs name the files they make)."""
    return re.sub(r"```.*?```", "", page.read_text(encoding="utf-8"), flags=re.S)


def repo_names() -> set[str]:
    return {p.name for p in REPO.rglob("*") if p.is_file() and not SKIPPED_DIRS & set(p.relative_to(REPO).parts)}


def resolves(page: Path, target: str) -> bool:
    """Whether ``target`` names a file or folder of the repository as ``page`` means it."""
    candidates = [page.parent / target, *(REPO / root / target for root in ROOTS)]
    return any(c.exists() and REPO in c.resolve().parents for c in candidates)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(REPO)))
def test_every_relative_link_resolves_inside_the_repository(page):
    for target in re.findall(r"\]\(([^)\s]+)\)", prose(page)):
        if re.match(r"[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            continue
        path = (page.parent / target.split("#", 1)[0]).resolve()
        assert path.exists() and REPO in path.parents, f"{page.name}: link to {target}"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(REPO)))
def test_every_path_named_in_backticks_is_in_the_repository(page):
    names = repo_names()
    for token in re.findall(r"`([^`\s]+)`", prose(page)):
        if re.match(r"[a-z]+:", token):  # an address (tcp://, tls://), not a path
            continue
        if "/" in token and (token.endswith("/") or token.endswith(REPO_FILES)):
            assert resolves(page, token), f"{page.name}: `{token}` is not in the repository"
        elif "/" not in token and token.endswith(SOURCE_FILES):
            assert token in names, f"{page.name}: `{token}` is no file of the repository"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(REPO)))
def test_a_file_said_to_be_beside_a_page_is_there(page):
    text = prose(page)
    for match in re.finditer(r"beside this (?:file|page)", text):
        before = text[max(0, match.start() - 120):match.start()]
        named = re.findall(r"`([^`]+)`", before)
        assert named and (page.parent / named[-1]).exists(), f"{page.name}: {before[-60:]}{match.group(0)}"


def test_the_seed_case_cites_its_thesis_by_author_title_and_year():
    text = (REPO / "docs" / "reference" / "seed-ansys-fourbar.md").read_text(encoding="utf-8")
    assert "Lavarreda Urizar" in text and "Universidad del Valle de Guatemala, 2023" in text
    assert "beside this file" not in text
