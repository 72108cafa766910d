"""Both a regular and an editable install import all three packages of the one distribution.

Each wheel (regular or editable, PEP 660) is built by this environment's setuptools backend and
installed into a new virtual environment that sees this environment's dependencies (through a .pth
file listing a filtered copy of its site-packages) but not its linkstress.
"""

from __future__ import annotations

import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


def _venv_with_dependencies(tmp_path: Path) -> Path:
    subprocess.run([sys.executable, "-m", "venv", str(tmp_path / "venv")], check=True)
    python = tmp_path / "venv" / "bin" / "python"
    purelib = subprocess.check_output(
        [python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], text=True
    ).strip()
    deps = tmp_path / "deps"
    deps.mkdir()
    outer = Path(sysconfig.get_paths()["purelib"])
    for entry in outer.iterdir():
        name = entry.name.lower()
        if "linkstress" in name or name.endswith(".pth") or name.startswith("__editable__"):
            continue
        (deps / entry.name).symlink_to(entry)
    Path(purelib, "outer_dependencies.pth").write_text(f"{deps}\n")
    return python


def _install_and_import(tmp_path: Path, hook: str) -> str:
    """Build a wheel with the setuptools backend ``hook`` of this environment, install it into a new one."""
    python = _venv_with_dependencies(tmp_path)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    wheels = tmp_path / "wheels"
    build = f"import setuptools.build_meta as backend; print(backend.{hook}({str(wheels)!r}))"
    wheels.mkdir()
    name = subprocess.check_output([sys.executable, "-c", build], text=True, cwd=REPO, env=env).split()[-1]
    subprocess.run(
        [python, "-m", "pip", "install", "--quiet", "--no-deps", "--no-index", str(wheels / name)],
        check=True, env=env,
    )
    probe = (
        "import linkstress, linkstress.importers, linkstress.validation, linkstress.commands;"
        "print(linkstress.__file__); print(linkstress.importers.__file__); print(linkstress.validation.__file__)"
    )
    return subprocess.check_output([python, "-c", probe], text=True, cwd=tmp_path, env=env)


def test_regular_install_imports_all_three_packages_from_site_packages(tmp_path):
    out = _install_and_import(tmp_path, "build_wheel")
    files = out.split()
    assert all("site-packages" in f for f in files), files
    assert files[1].endswith(os.path.join("linkstress", "importers", "__init__.py"))


def test_editable_install_imports_all_three_packages_from_the_source_folders(tmp_path):
    out = _install_and_import(tmp_path, "build_editable")
    core, importers, validation = out.split()
    assert core == str(REPO / "src" / "linkstress" / "__init__.py")
    assert importers == str(REPO / "importers" / "__init__.py")
    assert validation == str(REPO / "validation" / "__init__.py")
