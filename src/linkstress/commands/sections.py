"""``linkstress sections``: mass properties and the section table of a link."""

from __future__ import annotations

import argparse
import math

import numpy as np

from linkstress.geometry.builders import straight_bar
from linkstress.commands import HelpFormatter, examples
from linkstress.errors import InputError
from linkstress.materials import Material
from linkstress.geometry.profile import LinkProfile
from linkstress.scene.keys import MAX_STATIONS, range_problem
from linkstress.tables import format_table


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "sections",
        help="mass properties and section table of a link",
        description=(
            "Print a link's exact mass properties and its section table (chords, area, neutral axis, "
            "second moment, extreme fibres) at evenly spaced stations along its first two joints."
        ),
        epilog=examples("linkstress sections --bar 1.0 0.5 0.1 0.1 --hole 0.02"),
        formatter_class=HelpFormatter,
    )
    parser.add_argument(
        "--bar", nargs=4, type=float, required=True, metavar=("SPACING", "HEIGHT", "OVERHANG", "THICKNESS"),
        help="a straight bar [m]: joint spacing, height, overhang beyond each joint, plate thickness",
    )
    parser.add_argument("--hole", type=float, metavar="D", help="pin hole diameter at each joint [m]")
    parser.add_argument("--density", type=float, default=7850.0, help="material density [kg/m^3] (default steel, 7850)")
    parser.add_argument("--stations", type=int, default=13, help="number of stations over the bar's length (default 13)")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_arguments(args)
    spacing, height, overhang, thickness = args.bar
    material = Material("material", args.density)
    link = straight_bar(spacing, height, overhang, thickness, material, hole_diameter=args.hole)
    print(describe(link, max(args.stations, 2)))
    return 0


def check_arguments(args: argparse.Namespace) -> None:
    """Each number within the range accepted for its quantity (as in a scene), and a station count
    that fits, before any work."""
    names = ("SPACING", "HEIGHT", "OVERHANG", "THICKNESS")
    given = [(f"--bar {name}", value, "m") for name, value in zip(names, args.bar)]
    given += [("--hole", args.hole, "m"), ("--density", args.density, "kg/m^3")]
    for flag, value, unit in given:
        if value is None or not math.isfinite(value) or value <= 0:
            continue  # the profile builder refuses these with its own message
        if (problem := range_problem(value, unit, positive=True)) is not None:
            raise InputError(f"{flag}: {problem}")
    if args.stations > MAX_STATIONS:
        raise InputError(f"--stations: must be at most {MAX_STATIONS} (one table row each), got {args.stations}")


def describe(link: LinkProfile, n_stations: int) -> str:
    """Mass properties and section table of ``link`` as text (SI units)."""
    cx, cy = link.centroid
    mass_rows = [
        ("area [m^2]", link.area),
        ("centroid [m]", f"({cx:.6g}, {cy:.6g})"),
        ("polar moment of area [m^4]", link.polar_moment_area),
        ("mass [kg]", link.mass),
        ("mass moment of inertia about G [kg m^2]", link.mass_moment_of_inertia),
    ]
    lo, hi = link.x_extent()
    table = link.sections(np.linspace(lo, hi, n_stations))
    rows = [
        (float(table.x[i]), int(table.n_chords[i]), float(table.area[i]), float(table.neutral_axis[i]),
         float(table.second_moment[i]), float(table.c_top[i]), float(table.c_bottom[i]))
        for i in range(len(table.x))
    ]
    headers = ("x [m]", "chords", "A [m^2]", "y_na [m]", "I [m^4]", "c_top [m]", "c_bot [m]")
    return "\n\n".join([
        f"link {link.name}",
        format_table(("property", "value"), mass_rows),
        "sections along joint 0 -> joint 1 (member frame)",
        format_table(headers, rows),
    ])
