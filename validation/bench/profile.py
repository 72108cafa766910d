"""Benchmark: section tables and mass properties against their speed targets and the seed's strip sums.

Run ``python -m linkstress.validation.bench.profile [--full]``. Prints figures; asserts nothing about
time (machines are shared and noisy: compare the ratios measured in one run). ``--full`` also runs
the strip sums at dx = 1e-4 m, the seed's recommended setting (minutes).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from shapely.geometry import Polygon

from linkstress.geometry.builders import straight_bar
from linkstress.geometry.mass_properties import area_properties
from linkstress.tables import format_table
from linkstress.validation.bench.strip_sum import strip_sum_properties
from linkstress.validation.bench.timing import best_time

SEED_BARS = {"crank": 1.0, "coupler": 1.5, "output": 1.5, "ground": 2.0}  # joint spacing [m]



def wavy_link(n_vertices: int) -> Polygon:
    """A 1 m link with wavy edges and two round holes, ``n_vertices`` vertices in all."""
    n_hole = n_vertices // 10
    n_side = (n_vertices - 2 * n_hole) // 2
    x = np.linspace(0, 1, n_side)
    top = np.column_stack([x, 0.1 + 0.01 * np.sin(40 * x)])
    bottom = np.column_stack([x[::-1], -0.1 + 0.01 * np.cos(30 * x[::-1])])
    phi = np.linspace(0, 2 * math.pi, n_hole, endpoint=False)[::-1]
    holes = [np.column_stack([c + 0.03 * np.cos(phi), 0.03 * np.sin(phi)]) for c in (0.1, 0.9)]
    return Polygon(np.vstack([top, bottom]), holes)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="also run the strip sums at dx = 1e-4 m")
    args = parser.parse_args()

    from linkstress.geometry.sections import section_table

    outline = wavy_link(10_000)
    n_vertices = sum(len(r.coords) - 1 for r in [outline.exterior, *outline.interiors])
    stations = np.linspace(0, 1, 1000)
    t_sections = best_time(lambda: section_table(outline, stations, 0.01))
    t_mass = best_time(lambda: area_properties(outline))
    print(f"outline of {n_vertices} vertices")
    print(format_table(
        ("task", "time [ms]", "target [ms]"),
        [("section table, 1000 stations", 1e3 * t_sections, 50.0), ("mass properties", 1e3 * t_mass, 5.0)],
    ))

    bars = {name: straight_bar(s, 0.5, 0.1, 0.1) for name, s in SEED_BARS.items()}
    t_exact = best_time(lambda: [area_properties(b.outline) for b in bars.values()])
    rows = [("exact (Green)", "-", 1e3 * t_exact, 1.0, 0.0)]
    steps = [1e-2, 1e-3] + ([1e-4] if args.full else [])
    for dx in steps:
        t0 = time.perf_counter()
        errors = []
        for b in bars.values():
            lo, hi = b.x_extent()
            props = strip_sum_properties(lambda x: 0.25, lambda x: -0.25, lo, hi, dx)
            errors.append(abs(props.polar - b.polar_moment_area) / b.polar_moment_area)
        elapsed = time.perf_counter() - t0
        rows.append((f"strip sums dx = {dx:g} m", "measured", 1e3 * elapsed, elapsed / t_exact, max(errors)))
    print("\nmass properties of the seed's four rectangular bars")
    print(format_table(("method", "", "time [ms]", "x exact time", "max polar error [-]"), rows))
    if not args.full:
        print("(the seed's own setting, dx = 1e-4 m, costs about 100x the dx = 1e-3 m row: run with --full to measure it)")


if __name__ == "__main__":
    main()
