"""The source tree mirrors the pipeline and its imports flow one way.

Layers, bottom to top: the core (``src/linkstress`` without ``commands``) and the importers; the FEA
engine (``validation/fea``); the comparison, peaks and regression at ``validation``'s top; the
benchmarks (``validation/bench``); the CLI's commands. A module may import from its own layer and
those below it. The core reaches up only inside a function, for an optional stage that loads the FEA
stack when asked (``analyze --peaks``).
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

LAYERS = {
    "core": 0,
    "importers": 0,
    "fea": 1,
    "validation": 2,
    "bench": 3,
    "commands": 4,
}
"""Rank of each layer: a module imports only from layers of its own rank or lower."""

LAZY_UPWARD = {"src/linkstress/analysis.py": {"linkstress.validation.peaks_scene"}}
"""Core modules allowed one import from above, inside a function (an optional, heavy stage)."""


FOLDERS = {"src/linkstress": "linkstress", "importers": "linkstress.importers", "validation": "linkstress.validation"}
"""Source folder -> import name, as pyproject.toml's package-dir maps them."""


def module_of_file(path: Path) -> str:
    """The import name of the module in ``path``."""
    relative = path.relative_to(ROOT).with_suffix("").as_posix()
    folder = next(f for f in FOLDERS if relative.startswith(f + "/"))
    return ".".join([FOLDERS[folder], *relative[len(folder) + 1:].split("/")])


def layer_of_module(name: str) -> str | None:
    if name.startswith("linkstress.validation.fea"):
        return "fea"
    if name.startswith("linkstress.validation.bench"):
        return "bench"
    if name.startswith("linkstress.validation"):
        return "validation"
    if name.startswith("linkstress.importers"):
        return "importers"
    if name.startswith("linkstress.commands") or name in ("linkstress.cli", "linkstress.__main__"):
        return "commands"
    if name.startswith("linkstress"):
        return "core"
    return None


def imports(path: Path) -> list[tuple[str, bool]]:
    """Every linkstress module ``path`` imports, and whether the import is inside a function."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    inside: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            inside.update(id(child) for child in ast.walk(node) if child is not node)
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module] + [f"{node.module}.{alias.name}" for alias in node.names]
            found += [(name, id(node) in inside) for name in names if name.startswith("linkstress")]
        elif isinstance(node, ast.Import):
            found += [(alias.name, id(node) in inside) for alias in node.names if alias.name.startswith("linkstress")]
    return found


SOURCES = sorted(
    p for folder in ("src/linkstress", "importers", "validation") for p in (ROOT / folder).rglob("*.py")
)


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_a_module_imports_only_from_its_own_layer_or_below(path):
    own = layer_of_module(module_of_file(path))
    allowed_lazy = LAZY_UPWARD.get(path.relative_to(ROOT).as_posix(), set())
    upward = [
        name
        for name, lazy in imports(path)
        if (target := layer_of_module(name)) is not None
        and LAYERS[target] > LAYERS[own]
        and not (lazy and any(name.startswith(module) for module in allowed_lazy))
    ]
    assert upward == [], f"{path.relative_to(ROOT)} ({own}) imports from above: {upward}"


def test_the_fea_engine_and_the_benchmarks_have_their_own_folders():
    fea = {p.stem for p in (ROOT / "validation/fea").glob("*.py")}
    bench = {p.stem for p in (ROOT / "validation/bench").glob("*.py")}
    assert {"mesh", "plane_stress", "loads", "recovery", "convergence", "vtu"} <= fea
    assert {"speed_error", "throughput", "stability", "strip_sum", "suite"} <= bench
    top = {p.stem for p in (ROOT / "validation").glob("*.py")}
    assert not any(name.startswith("bench") for name in top)
