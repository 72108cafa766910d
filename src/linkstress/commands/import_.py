"""``linkstress import``: the links of a DXF or iLogic CSV sketch, as tables, JSON and a picture."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from linkstress.errors import InputError, SketchError
from linkstress.output import check_outputs, write_all


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "import",
        help="read a DXF or iLogic CSV sketch into link outlines with joints",
        description=(
            "Read a DXF or Inventor iLogic CSV sketch and print, per link, its area, centroid and polar "
            "moment per unit thickness, its joints and the rule that found them, its holes and the "
            "largest gap closed. Coordinates in metres, sketch frame. What cannot make a clean outline "
            "(an open chain, a crossing, a POINT off a hole's centre) is listed as a problem and left "
            "out; the rest imports (exit 0) unless --strict."
        ),
    )
    parser.add_argument("sketch", metavar="SKETCH", help="a .dxf or .csv sketch")
    parser.add_argument("--units", help="units of a sketch that does not say (mm, cm, m, in, ft); the old iLogic CSV defaults to cm")
    parser.add_argument("--tolerance", type=float, metavar="FRACTION",
                        help="endpoint gap tolerance as a fraction of the drawing size (default 1e-4; 1e-2 for the old iLogic CSV)")
    parser.add_argument("--sagitta", type=float, metavar="FRACTION",
                        help="chord tolerance of arcs as a fraction of each arc's radius (default 1e-4)")
    parser.add_argument("--layers", type=_names, metavar="A,B", help="read only these layers (comma-separated)")
    parser.add_argument("--exclude-layers", type=_names, default=(), metavar="C,D",
                        help="leave these layers out (comma-separated), e.g. engraving or dimensions")
    parser.add_argument("--strict", action="store_true",
                        help="refuse the sketch (exit 2) if any part of it is left out as a problem")
    parser.add_argument("--json", metavar="OUT", help="write the links as JSON (docs/design.md's import shape)")
    parser.add_argument("--plot", metavar="OUT.png", help="draw outline, holes, joints, member axis and U(x)/L(x)")
    parser.set_defaults(run=run)


def _names(text: str) -> tuple[str, ...]:
    """Layer names from ``A,B`` (spaces around each name dropped)."""
    names = tuple(name.strip() for name in text.split(","))
    if not all(names):
        raise argparse.ArgumentTypeError(f"layer names separated by commas, got {text!r}")
    return names


def run(args: argparse.Namespace) -> int:
    from linkstress.importers import read_sketch
    from linkstress.importers.problems import listed
    from linkstress.importers.summary import finite, sketch_json, sketch_text

    outputs = {"--json": args.json and Path(args.json), "--plot": args.plot and Path(args.plot)}
    check_outputs(outputs, [Path(args.sketch)])
    sketch = read_sketch(args.sketch, args.units, args.tolerance, args.sagitta, args.layers, args.exclude_layers)
    if args.strict and sketch.problems:
        raise SketchError(f"{sketch.path.name}: --strict: {listed(sketch.problems)}")
    files: list[tuple[Path, bytes]] = []
    if args.json:
        data = sketch_json(sketch)
        if not finite(data):
            raise InputError(
                f"{sketch.path.name}: the results hold a non-finite number; nothing written (a linkstress "
                "defect: please report it with the sketch)"
            )
        files.append((Path(args.json), json.dumps(data, indent=1).encode()))
    if args.plot:
        from linkstress.importers.figure import sketch_png

        files.append((Path(args.plot), sketch_png(sketch)))
    write_all(files)
    print(sketch_text(sketch))
    return 0
