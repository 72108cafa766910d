"""The seed's ANSYS four-bar sketch: the first regression case and the README demo.

Source: docs/reference/seed-ansys-fourbar.md (KSAM thesis, section 6.3.5): four steel bars 0.5 m
high, lengths 1.2 / 1.7 / 1.7 / 2.2 m, each with 20 mm pin holes at mid-height 0.1 m from its ends.
"""

from __future__ import annotations

import math
import runpy
from pathlib import Path

import numpy as np
import pytest

from linkstress.importers import read_sketch
from linkstress.materials import STRUCTURAL_STEEL

CASE = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar"
BARS = {"crank": (1.2, 0.0), "coupler": (1.7, 1.0), "output": (1.7, 2.0), "ground": (2.2, 3.0)}  # length, axis y [m]


def test_the_seed_sketch_has_four_bars_with_exact_areas_and_joints():
    sketch = read_sketch(CASE / "ansys_four_bars.dxf")
    assert sketch.units == "m" and [link.name for link in sketch.links] == list(BARS)
    assert not sketch.fixes and not sketch.ignored
    for name, (length, y) in BARS.items():
        link = sketch.link(name)
        # Area of a bar less two 20 mm holes: L x 0.5 - 2 pi (0.01)^2 (the flattened holes keep it exactly).
        assert link.outline.area == pytest.approx(length * 0.5 - 2 * math.pi * 1e-4, rel=1e-6)
        assert np.abs(link.joints - [[0.0, y], [length - 0.2, y]]).max() <= 1e-9
        assert link.hole_diameters_m == pytest.approx((0.02, 0.02), rel=1e-12)


def test_the_seed_crank_has_the_theses_mass():
    # Thesis table: crank 471.0 kg as a solid bar (7850 x 0.1 x 1.2 x 0.5); with its two holes 470.507 kg.
    crank = read_sketch(CASE / "ansys_four_bars.dxf").link("crank").profile(0.1, STRUCTURAL_STEEL)
    assert crank.mass == pytest.approx(7850 * 0.1 * (0.6 - 2 * math.pi * 1e-4), rel=1e-6)
    assert crank.mass == pytest.approx(470.507, abs=5e-4)


def test_the_sketch_script_reproduces_the_committed_file(tmp_path, monkeypatch):
    script = runpy.run_path(str(CASE / "make_sketch.py"))
    script["write"](tmp_path / "again.dxf")
    assert (tmp_path / "again.dxf").read_bytes() == (CASE / "ansys_four_bars.dxf").read_bytes()
