"""``linkstress import``: the links of a DXF or iLogic CSV sketch, as tables, JSON and a picture."""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

from linkstress.commands import HelpFormatter, examples
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
            "out; the rest imports (exit 0) unless --strict. The problems print first, grouped by kind. What is no "
            "part (a page frame, text glyphs, drill marks, layers named for annotation) is skipped and listed. "
            "With --scene, a mechanism drawn assembled (each "
            "link on its own layer, pin centres meeting) also becomes a scene to edit and analyze: four-bar loops "
            "and slider-cranks, or any other one-DOF linkage of pins, slots and sliding blocks (docs/importing.md); "
            "a sheet of links drawn apart has none."
        ),
        epilog=examples(
            "linkstress import validation/cases/six_bar/six_bar.dxf --plot six_bar.png",
            "linkstress import validation/cases/bell_crank/bell_crank.dxf --layers crank,bellcrank --json links.json",
        ),
        formatter_class=HelpFormatter,
    )
    parser.add_argument("sketch", metavar="SKETCH", help="a .dxf or .csv sketch")
    parser.add_argument("--units", help="units of the sketch (mm, cm, m, in, ft; pt and px for 1/72 and 1/96 inch, pica for 1/6 inch): needed when it does not say, and overriding it when it does; the old iLogic CSV defaults to cm")
    parser.add_argument("--tolerance", type=float, metavar="FRACTION",
                        help="endpoint gap tolerance as a fraction of the drawing size (default 1e-4; 1e-2 for the old iLogic CSV)")
    parser.add_argument("--sagitta", type=float, metavar="FRACTION",
                        help="chord tolerance of arcs as a fraction of each arc's radius (default 1e-4)")
    parser.add_argument("--layers", type=_names, metavar="A,B",
                        help="read only these layers (comma-separated); a layer named for annotation (TEXT, DIM, "
                             "TITLE, BORDER...) is read only when named here")
    parser.add_argument("--exclude-layers", type=_names, default=(), metavar="C,D",
                        help="leave these layers out (comma-separated), e.g. engraving or dimensions")
    parser.add_argument("--hole-layers", type=_names, default=(), metavar="H,K",
                        help="take the closed outlines on these layers as holes (a round one a pin hole) of the links "
                             "they lie in, for drawings that keep holes and slots on a layer of their own")
    parser.add_argument("--strict", action="store_true",
                        help="refuse the sketch (exit 2) if any part of it is left out as a problem")
    parser.add_argument("--json", metavar="OUT",
                        help="write the links as JSON (docs/design.md's import shape), with every problem; a sketch "
                             "refused for its problems (no link imports, or --strict) still writes it, its only output")
    parser.add_argument("--plot", metavar="OUT.png", help="draw an overview of every link, named, then per link its outline, joints, member axis and U(x)/L(x) (up to 12 links)")
    parser.add_argument(
        "--scene", metavar="OUT.toml",
        help="write a scene of the mechanism drawn assembled (each link on its own layer, pinned where pin centres "
             "meet): four-bar and slider-crank loops, or a linkage of pins and sliders, with its ground, input and "
             "the drawn pose; edit thickness, material, motion, loads",
    )
    parser.set_defaults(run=run)


def _names(text: str) -> tuple[str, ...]:
    """Layer names from ``A,B`` (spaces around each name dropped)."""
    names = tuple(name.strip() for name in text.split(","))
    if not all(names):
        raise argparse.ArgumentTypeError(f"layer names separated by commas, got {text!r}")
    return names


def run(args: argparse.Namespace) -> int:
    from linkstress.importers.problems import listed
    from linkstress.importers.sketch import SketchRefused, read_sketch
    from linkstress.importers.summary import sketch_text

    outputs = {
        "--json": args.json and Path(args.json), "--plot": args.plot and Path(args.plot),
        "--scene": args.scene and Path(args.scene),
    }
    check_outputs(outputs, [Path(args.sketch)])
    if args.scene and (args.tolerance is not None or args.sagitta is not None):
        raise InputError(
            "--scene: a scene reads its sketches with the default --tolerance and --sagitta (it has no keys for "
            "them); import without them, closing the drawing's gaps, or drop --scene"
        )
    try:
        sketch = read_sketch(args.sketch, args.units, args.tolerance, args.sagitta, args.layers, args.exclude_layers,
                             hole_layers=args.hole_layers)
    except SketchRefused as refused:
        _refuse(refused.sketch, str(refused), args.json)
    if args.strict and sketch.problems:
        _refuse(sketch, f"{sketch.path.name}: --strict: {listed(sketch.problems)}", args.json)
    files: list[tuple[Path, bytes]] = []
    if args.json:
        files.append((Path(args.json), _json(sketch)))
    if args.plot:
        from linkstress.importers.figure import sketch_png

        files.append((Path(args.plot), sketch_png(sketch)))
    found = []
    if args.scene:
        text, found = _scene(sketch, Path(args.scene), args.units, args.hole_layers)
        files.append((Path(args.scene), text))
    write_all(files)
    print(sketch_text(sketch))
    if args.scene:
        print("\n".join(["", f"scene {args.scene}:", *found]))
    return 0


def _json(sketch, refused: str | None = None) -> bytes:
    """The import JSON of ``sketch`` (``refused``: why it was refused), checked to hold only finite numbers."""
    from linkstress.importers.summary import finite, sketch_json

    data = sketch_json(sketch, refused)
    if not finite(data):
        raise InputError(
            f"{sketch.path.name}: the results hold a non-finite number; nothing written (a linkstress "
            "defect: please report it with the sketch)"
        )
    return json.dumps(data, indent=1).encode()


def _refuse(sketch, message: str, json_path: str | None) -> None:
    """Refuse ``sketch`` with ``message`` (exit 2), first writing its JSON (every problem) when asked:
    the only output of a refused import."""
    if json_path:
        write_all([(Path(json_path), _json(sketch, message))])
    raise SketchError(message + (f" (every problem in {json_path})" if json_path else ""))


def _scene(sketch, out: Path, units: str | None, hole_layers: tuple[str, ...]) -> tuple[bytes, list[str]]:
    """The scene of the mechanism drawn in ``sketch``, checked by reading it back as file ``out`` and
    solving it at the drawn angle, and a line per mechanism found."""
    from linkstress.importers.drawn_mechanism import mechanism_scene

    try:
        text, found = mechanism_scene(sketch, out, _relative(sketch.path, out), units, hole_layers)
    except InputError as error:
        raise InputError(f"{sketch.path.name}: --scene: {error}") from None
    return text.encode("utf-8"), found


def _relative(sketch: Path, out: Path) -> str:
    """The sketch's path from the scene's folder, with forward slashes (absolute across drives)."""
    try:
        return Path(os.path.relpath(sketch.resolve(), out.resolve().parent)).as_posix()
    except ValueError:
        return sketch.resolve().as_posix()
