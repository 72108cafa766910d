"""Benchmark: importing sketches against the speed targets, and the flattening rule's accuracy.

Run ``python -m linkstress.validation.bench.sketch_import [--ezdxf] [--splines]``. Prints figures; asserts
nothing about time (machines are shared and noisy: each time is the best of several runs). Targets:
a typical link (under 200 entities) in under 50 ms after start-up; 20 links and 50,000
entities in under 2 s. ``--ezdxf`` also times the big drawing read entirely through ezdxf's document
loader (the fast tag table switched off), to show what the fast path buys. ``--splines`` reads a sheet
of 90 parts outlined by 13 SPLINEs through 40 fit points each (1,170 splines, the size of a sheet
that took 148 s and 545 MB only to be refused when splines were flattened by ezdxf to 1e-7 of the
drawing; that flattening refused this sheet too, after 5.8 s) in a fresh child process, for
its time and peak memory; targets under 10 s and 300 MB. Measured: 1.9 s and 146 MB, 67,000 vertices.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import subprocess
import sys
import tempfile
from pathlib import Path

import ezdxf
import numpy as np
from shapely.geometry import Polygon

from linkstress.importers import dxf, read_sketch
from linkstress.importers.dxf_tags import SimpleEntities
from linkstress.importers.flatten import Tolerance, flatten
from linkstress.importers.primitives import CurveSet
from linkstress.geometry.mass_properties import area_properties
from linkstress.tables import format_table
from linkstress.validation.bench.timing import best_time



def draw_link(msp, k: int, n_side: int, n_slots: int) -> None:
    """Link k [mm]: a 1000 mm bar with wavy sides of ``n_side`` LINEs each (shuffled, half reversed),
    round ends (ARCs), two 20 mm pin holes (CIRCLEs with POINTs) and ``n_slots`` rounded slots
    (4 LINEs + 4 ARCs each): 2 n_side + 6 + 8 n_slots entities."""
    att = {"layer": f"link{k}"}
    y0, length, half = 400.0 * k, 1000.0, 100.0
    x = np.linspace(0, length, n_side + 1)
    wave = 5 * np.sin(x / 50)
    edges = [((a, y0 + half + wa), (b, y0 + half + wb)) for a, b, wa, wb in zip(x[:-1], x[1:], wave[:-1], wave[1:])]
    edges += [((a, y0 - half + wa), (b, y0 - half + wb)) for a, b, wa, wb in zip(x[:-1], x[1:], wave[:-1], wave[1:])]
    random.shuffle(edges)
    for a, b in edges:
        msp.add_line(*((b, a) if random.random() < 0.5 else (a, b)), dxfattribs=att)
    msp.add_arc((length, y0 + wave[-1]), half, -90, 90, dxfattribs=att)
    msp.add_arc((0.0, y0 + wave[0]), half, 90, 270, dxfattribs=att)
    for xc, w in ((0.0, wave[0]), (length, wave[-1])):
        msp.add_circle((xc, y0 + w), 10, dxfattribs=att)
        msp.add_point((xc, y0 + w), dxfattribs=att)
    for j in range(n_slots):
        cx = 60 + j * 880 / max(n_slots - 1, 1)
        x0, x1, yb, yt, r = cx - 4, cx + 4, y0 - 15, y0 + 15, 3
        msp.add_line((x0 + r, yb), (x1 - r, yb), dxfattribs=att)
        msp.add_arc((x1 - r, yb + r), r, 270, 360, dxfattribs=att)
        msp.add_line((x1, yb + r), (x1, yt - r), dxfattribs=att)
        msp.add_arc((x1 - r, yt - r), r, 0, 90, dxfattribs=att)
        msp.add_line((x1 - r, yt), (x0 + r, yt), dxfattribs=att)
        msp.add_arc((x0 + r, yt - r), r, 90, 180, dxfattribs=att)
        msp.add_line((x0, yt - r), (x0, yb + r), dxfattribs=att)
        msp.add_arc((x0 + r, yb + r), r, 180, 270, dxfattribs=att)


def drawing(path: Path, links: int, n_side: int, n_slots: int) -> int:
    """Write the drawing; return its number of entities."""
    random.seed(1)
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    for k in range(links):
        draw_link(msp, k, n_side, n_slots)
    doc.saveas(path)
    return len(msp)


def spline_sheet(path: Path, parts: int = 90, edges: int = 13, points: int = 40) -> int:
    """A sheet [mm] of ``parts`` parts on a 10-wide grid, 150 mm apart: part k outlined by the closed
    curve r(t) = 50 + 8 sin(3 t + k) mm cut into ``edges`` SPLINEs through ``points`` fit points each
    (ends shared), around a 20 mm CIRCLE pin hole; return the number of splines."""
    doc = ezdxf.new("R2013", units=4)
    msp = doc.modelspace()
    cut = np.linspace(0, 2 * math.pi, edges + 1)
    for k in range(parts):
        cx, cy = 150.0 * (k % 10), 150.0 * (k // 10)
        for t0, t1 in zip(cut[:-1], cut[1:]):
            t = np.linspace(t0, t1, points)
            r = 50 + 8 * np.sin(3 * t + k)
            msp.add_spline(fit_points=np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)]).tolist(),
                           dxfattribs={"layer": f"part{k}"})
        msp.add_circle((cx, cy), 10, dxfattribs={"layer": f"part{k}"})
    doc.saveas(path)
    return parts * edges


SPLINE_CHILD = """
import json, re, sys, time
from linkstress.importers import read_sketch
start = time.perf_counter()
sketch = read_sketch(sys.argv[1])
seconds = time.perf_counter() - start
vertices = sum(len(l.outline.exterior.coords) + sum(len(r.coords) for r in l.outline.interiors) for l in sketch.links)
with open("/proc/self/status") as status:
    peak = 1024 * int(re.search(r"VmHWM:\\s*(\\d+) kB", status.read())[1])
print(json.dumps({"seconds": seconds, "peak_bytes": peak, "links": len(sketch.links), "vertices": vertices}))
"""
"""The child: ``read_sketch`` of the sheet, timed without the interpreter's start and imports; its peak
resident memory is the kernel's high-water mark of its own address space (``VmHWM``, Linux), imports
included. ``ru_maxrss`` would not do: Linux carries the parent's peak across ``exec`` into it."""


def spline_sheet_run(path: Path) -> dict:
    """Time [s], peak resident memory [bytes], links and outline vertices of reading ``path`` in a child."""
    done = subprocess.run([sys.executable, "-c", SPLINE_CHILD, str(path)], capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def ezdxf_only(path: Path) -> None:
    original = dxf.split_entities
    dxf.split_entities = lambda text: (SimpleEntities(), text)
    try:
        read_sketch(path)
    finally:
        dxf.split_entities = original


def flattening_table() -> list[tuple]:
    """Half-disc r = 1 bounded by one arc and its diameter: errors of area, centroid and polar moment
    with inscribed vertices and with this importer's area-preserving ones, per chord tolerance."""
    a, yc = math.pi / 2, 4 / (3 * math.pi)
    polar = math.pi / 4 - a * yc * yc
    rows = []
    for relative in (1e-3, 3e-4, 1e-4, 3e-5, 1e-5):
        curves = CurveSet()
        curves.add_arcs([(0.0, 0.0)], [1.0], [0.0], [math.pi], [("ARC", None, None, None)])
        xy = flatten(curves, Tolerance.for_size(1e9, relative)).vertices(0)
        preserved = area_properties(Polygon(xy))
        inscribed = area_properties(Polygon(np.vstack([xy[:1], xy[1:-1] / np.hypot(*xy[1:-1].T)[:, None], xy[-1:]])))
        n_turn = 2 * (len(xy) - 2)
        errors = []
        for props in (inscribed, preserved):
            errors += [abs(props.area - a) / a, abs(props.centroid[1] - yc) / yc, abs(props.polar - polar) / polar]
        rows.append((f"{relative:g}", n_turn, *errors))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ezdxf", action="store_true", help="also read the big drawing through ezdxf alone")
    parser.add_argument("--splines", action="store_true", help="also read a sheet of 1,170 splines in a child process")
    args = parser.parse_args()

    print("flattening a half disc (one arc and its diameter), relative errors; vertices per full turn")
    print(format_table(
        ("sagitta / r", "per turn", "area insc.", "centroid insc.", "polar insc.",
         "area kept", "centroid kept", "polar kept"),
        flattening_table(),
    ))

    with tempfile.TemporaryDirectory() as folder:
        one = Path(folder) / "one_link.dxf"
        big = Path(folder) / "twenty_links.dxf"
        n_one = drawing(one, 1, 60, 8)
        n_big = drawing(big, 20, 1087, 40)
        read_sketch(one)  # start-up: imports and first-call costs
        rows = []
        for label, path, n, repeat, target in (("typical link", one, n_one, 20, 50.0),
                                               ("20 links", big, n_big, 3, 2000.0)):
            sketch = read_sketch(path)
            vertices = sum(len(link.outline.exterior.coords) + sum(len(r.coords) for r in link.outline.interiors)
                           for link in sketch.links)
            rows.append((label, n, len(sketch.links), vertices, 1e3 * best_time(lambda: read_sketch(path), repeat), target))
        if args.ezdxf:
            rows.append(("20 links, ezdxf only", n_big, 20, "", 1e3 * best_time(lambda: ezdxf_only(big), 1), ""))
        print("\nimporting DXF drawings (best of several runs, after start-up)")
        print(format_table(("drawing", "entities", "links", "vertices", "time [ms]", "target [ms]"), rows))
        if args.splines:
            sheet = Path(folder) / "spline_sheet.dxf"
            n = spline_sheet(sheet)
            run = spline_sheet_run(sheet)
            print("\nreading a sheet of splines in a fresh child process (one run)")
            print(format_table(
                ("splines", "links", "vertices", "time [s]", "target [s]", "peak memory [MB]", "target [MB]"),
                [(n, run["links"], run["vertices"], run["seconds"], 10.0, run["peak_bytes"] / 1e6, 300.0)],
            ))


if __name__ == "__main__":
    main()
