"""Benchmark: the ``linkstress import --plot`` picture of a whole sheet of parts.

Run ``python -m linkstress.validation.bench.plot [--links N]``. Writes a nested sheet of ``N`` parts
(default 91, as a laser-cut sheet) with ezdxf, reads it, and prints the best time of drawing its PNG
and the PNG's size. Asserts nothing about time (machines are shared and noisy). Target:
the 91-part sheet under 3 s; the per-link picture of every link took 28 s.
"""

from __future__ import annotations

import argparse
import math
import struct
import tempfile
from pathlib import Path

import ezdxf

from linkstress.importers import read_sketch
from linkstress.importers.figure import sketch_png
from linkstress.tables import format_table
from linkstress.validation.bench.timing import best_run

CELL_MM = 300.0
"""Pitch of the sheet's grid of parts [mm]: every part below fits in a 260 mm square."""


def _bar(msp, x: float, y: float, length: float, width: float, hole: float, att: dict) -> None:
    """A bar along x [mm] with round ends (two ARCs, two LINEs) and a pin hole (CIRCLE + POINT) at
    each end's centre, the left centre at (x, y)."""
    r = width / 2
    msp.add_line((x, y - r), (x + length, y - r), dxfattribs=att)
    msp.add_arc((x + length, y), r, -90, 90, dxfattribs=att)
    msp.add_line((x + length, y + r), (x, y + r), dxfattribs=att)
    msp.add_arc((x, y), r, 90, 270, dxfattribs=att)
    for cx in (x, x + length):
        msp.add_circle((cx, y), hole / 2, dxfattribs=att)
        msp.add_point((cx, y), dxfattribs=att)


def _strip(msp, x: float, y: float, att: dict) -> None:
    """A narrow strip 10 x 200 mm upright (LWPOLYLINE), its lower left corner at (x, y), with
    4 mm pin holes 10 mm from each end: the link whose ticks used to run together."""
    msp.add_lwpolyline([(x, y), (x + 10, y), (x + 10, y + 200), (x, y + 200)], close=True, dxfattribs=att)
    for cy in (y + 10, y + 190):
        msp.add_circle((x + 5, cy), 2, dxfattribs=att)
        msp.add_point((x + 5, cy), dxfattribs=att)


def _bell_crank(msp, x: float, y: float, att: dict) -> None:
    """An L-shaped bell crank [mm] with its pivot at (x, y): arms 200 mm along +x and +y, 40 mm
    wide, round ends and a round outer corner (bulges), pin holes at the pivot and both arm ends."""
    quarter = math.tan(math.radians(90) / 4)  # the bulge of a quarter circle
    corners = [  # (x, y, bulge of the segment to the next vertex), counter-clockwise
        (x - 20, y, quarter), (x, y - 20, 0), (x + 200, y - 20, 1), (x + 200, y + 20, 0),
        (x + 20, y + 20, 0), (x + 20, y + 200, 1), (x - 20, y + 200, 0),
    ]
    msp.add_lwpolyline(corners, format="xyb", close=True, dxfattribs=att)
    for px, py in ((x, y), (x + 200, y), (x, y + 200)):
        msp.add_circle((px, py), 6, dxfattribs=att)
        msp.add_point((px, py), dxfattribs=att)


def _plate(msp, x: float, y: float, att: dict) -> None:
    """A 220 x 120 mm plate [mm] with a rounded slot (LINEs and ARCs) and two pin holes; its lower
    left corner at (x, y)."""
    msp.add_lwpolyline([(x, y), (x + 220, y), (x + 220, y + 120), (x, y + 120)], close=True, dxfattribs=att)
    cx, cy, half, r = x + 110, y + 60, 50.0, 10.0
    msp.add_line((cx - half, cy - r), (cx + half, cy - r), dxfattribs=att)
    msp.add_arc((cx + half, cy), r, -90, 90, dxfattribs=att)
    msp.add_line((cx + half, cy + r), (cx - half, cy + r), dxfattribs=att)
    msp.add_arc((cx - half, cy), r, 90, 270, dxfattribs=att)
    for px in (x + 20, x + 200):
        msp.add_circle((px, y + 60), 5, dxfattribs=att)
        msp.add_point((px, y + 60), dxfattribs=att)


def sheet_drawing(path: Path, links: int = 91, columns: int = 13) -> int:
    """Write a sheet of ``links`` parts [mm] in a grid of ``columns`` columns, ``CELL_MM`` apart,
    each on its own layer ``part-NN``: bars of three lengths, narrow strips, bell cranks and slotted
    plates in turn. Returns the number of entities."""
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for k in range(links):
        x, y = CELL_MM * (k % columns), -CELL_MM * (k // columns)
        att = {"layer": f"part-{k + 1:02d}"}
        kind = k % 6
        if kind < 3:
            _bar(msp, x + 50, y + 150, 120 + 40 * kind, 40 + 10 * kind, 12, att)
        elif kind == 3:
            _strip(msp, x + 145, y + 50, att)
        elif kind == 4:
            _bell_crank(msp, x + 40, y + 40, att)
        else:
            _plate(msp, x + 40, y + 90, att)
    doc.saveas(path)
    return len(msp)


def png_pixels(png: bytes) -> tuple[int, int]:
    """(width, height) [px] from a PNG's header chunk."""
    return struct.unpack(">II", png[16:24])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, default=91, help="parts on the sheet (default 91)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "sheet.dxf"
        entities = sheet_drawing(path, args.links)
        read, sketch = best_run(lambda: read_sketch(path), 1)
        sketch_png(sketch)  # start-up: font cache and first-call costs
        seconds, png = best_run(lambda: sketch_png(sketch), 3)
    width, height = png_pixels(png)
    print(f"plotting a sheet of parts (best of 3 runs after start-up; reading it took {read:.2f} s)")
    print(format_table(
        ("parts", "entities", "plot time [s]", "target [s]", "PNG [kB]", "PNG [px]"),
        [(len(sketch.links), entities, seconds, 3.0, len(png) / 1e3, f"{width} x {height}")],
    ))


if __name__ == "__main__":
    main()
