"""The README tutorial's scene, built as the tutorial builds it: ``linkstress import`` of
``docs/tutorial/fourbar.dxf`` writes the scene, then the README's TOML block sets its keys (a whole
turn at 100 rad/s of 6 mm steel plate, 5 N m on the rocker). The benches time ``analyze`` on it;
``tests/test_readme_tutorial.py`` runs the tutorial's commands on the same scene.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

DRAWING = Path("docs") / "tutorial" / "fourbar.dxf"


def checkout() -> Path | None:
    """The linkstress source checkout whose README and drawing the tutorial follows: the tree this
    file lies in, or, where the package is installed rather than run from its source, the working
    directory or the nearest of its parents that holds both; None outside a checkout."""
    here = Path(__file__).resolve().parents[2]
    cwd = Path.cwd().resolve()
    for folder in (here, cwd, *cwd.parents):
        if (folder / "README.md").is_file() and (folder / DRAWING).is_file():
            return folder
    return None


def _checkout() -> Path:
    folder = checkout()
    if folder is None:
        raise FileNotFoundError(f"the README tutorial's scene needs a linkstress source checkout (README.md and "
                                f"{DRAWING.as_posix()}); run from one")
    return folder


def tutorial_text() -> str:
    """The README's tutorial section."""
    return (_checkout() / "README.md").read_text().split("## Tutorial", 1)[1].split("\n## ", 1)[0]


def edit_scene(text: str, edits: str) -> str:
    """``text`` with each ``key = value`` of ``edits`` set in its table: the line replaced where the
    key is (commented or not), else added at the table's end; a table ``text`` lacks is appended."""
    lines = text.splitlines()
    headers = [line.split("#", 1)[0].strip() for line in lines]
    table = None
    for line in edits.splitlines():
        if not line.strip():
            continue
        if line.startswith("["):
            table = line
            if table not in headers:
                lines += ["", table]
                headers += ["", table]
            continue
        key = line.split("=", 1)[0].strip()
        start = headers.index(table) + 1
        end = next((k for k in range(start, len(lines)) if lines[k].startswith("[")), len(lines))
        at = [k for k in range(start, end) if re.match(rf"#?\s*{re.escape(key)}\s*=", lines[k])]
        for k in at[1:]:
            lines[k] = ""
        if at:
            lines[at[0]] = line
        else:
            while end > start and not lines[end - 1].strip():
                end -= 1
            lines.insert(end, line)
            headers.insert(end, line)
    return "\n".join(lines) + "\n"


def tutorial_scene(folder: Path) -> Path:
    """Write the tutorial's edited scene ``fourbar.toml`` (and its drawing) into ``folder``: the
    tutorial's ``linkstress import`` as a command of its own (this interpreter's)."""
    folder.mkdir(parents=True, exist_ok=True)
    drawing = folder / DRAWING.name
    drawing.write_bytes((_checkout() / DRAWING).read_bytes())
    scene = folder / "fourbar.toml"
    subprocess.run([sys.executable, "-m", "linkstress", "import", str(drawing), "--scene", str(scene)], check=True,
                   stdout=subprocess.DEVNULL)
    edits = re.findall(r"```toml\n(.+?)\n```", tutorial_text(), re.S)[0]
    scene.write_text(edit_scene(scene.read_text(), edits))
    return scene
