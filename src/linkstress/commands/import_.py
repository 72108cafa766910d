"""``linkstress import``: the links of a DXF or iLogic CSV sketch, as tables, JSON and a picture."""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

from linkstress.errors import InputError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "import",
        help="read a DXF or iLogic CSV sketch into link outlines with joints",
        description=(
            "Read a DXF or Inventor iLogic CSV sketch and print, per link, its area, centroid and polar "
            "moment per unit thickness, its joints and the rule that found them, its holes and the "
            "largest gap closed. Coordinates in metres, sketch frame."
        ),
    )
    parser.add_argument("sketch", metavar="SKETCH", help="a .dxf or .csv sketch")
    parser.add_argument("--units", help="units of a sketch that does not say (mm, cm, m, in, ft); the old iLogic CSV defaults to cm")
    parser.add_argument("--tolerance", type=float, metavar="FRACTION",
                        help="endpoint gap tolerance as a fraction of the drawing size (default 1e-4; 1e-2 for the old iLogic CSV)")
    parser.add_argument("--sagitta", type=float, metavar="FRACTION",
                        help="chord tolerance of arcs as a fraction of each arc's radius (default 1e-4)")
    parser.add_argument("--json", metavar="OUT", help="write the links as JSON (DESIGN.md's import shape)")
    parser.add_argument("--plot", metavar="OUT.png", help="draw outline, holes, joints, member axis and U(x)/L(x)")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from linkstress.importers import read_sketch
    from linkstress.importers.summary import finite, sketch_json, sketch_text

    sketch = read_sketch(args.sketch, args.units, args.tolerance, args.sagitta)
    outputs: list[tuple[str, bytes]] = []
    if args.json:
        data = sketch_json(sketch)
        if not finite(data):
            raise InputError(
                f"{sketch.path.name}: the results hold a non-finite number; nothing written (a linkstress "
                "defect: please report it with the sketch)"
            )
        outputs.append((args.json, json.dumps(data, indent=1).encode()))
    if args.plot:
        from linkstress.importers.figure import sketch_png

        outputs.append((args.plot, sketch_png(sketch)))
    _write_all(outputs)
    print(sketch_text(sketch))
    return 0


def _write_all(outputs: list[tuple[str, bytes]]) -> None:
    """Write every output to a temporary file beside it, then rename them all: no half-written file,
    and none written at all when one of them cannot be."""
    staged: list[tuple[str, Path]] = []
    target = Path(".")
    try:
        for path, data in outputs:
            target = Path(path)
            handle, temporary = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
            staged.append((temporary, target))
            with os.fdopen(handle, "wb") as out:
                out.write(data)
        for temporary, target in staged:
            os.replace(temporary, target)
    except OSError as error:
        for temporary, _ in staged:
            Path(temporary).unlink(missing_ok=True)
        raise InputError(f"cannot write {str(target)!r}: {error.strerror or error}") from None
