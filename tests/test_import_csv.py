"""iLogic CSV sketches: the original program's format, linkstress-sketch v1 and the rule's sample."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from shapely.geometry import Polygon

from linkstress.errors import SketchError
from linkstress.importers import HOLE_RULE, POINT_RULE, read_sketch
from linkstress.importers.summary import sketch_text
from test_import_exact import (
    assert_matches, combine, disc, ellipse, half_ellipse_right, rectangle, regular_polygon, scaled, sector,
)

REPO = Path(__file__).resolve().parents[1]
REL = 1e-6


# -- the original program's format -------------------------------------------------------------


def old_rule_rows(points: bool = True) -> tuple[list[str], list[np.ndarray], list[np.ndarray]]:
    """The rows the original iLogic rule writes for a 10 x 5 cm plate with a round right end
    (radius 2.5 cm) and two 1 cm pin holes, and the outline and holes its samples describe [cm].

    Like the rule (KSAM thesis, section 12.5): numbers in VB's default 15 digits; an arc's run starts
    one step (sweep / 1000) after its start and ends with its end point; a circle runs from 0 while
    the angle, stepped by 0.01 rad, stays <= 2 pi, so it stops short of closing.
    """
    rows = ["X, Y"]
    shell: list[tuple[float, float]] = []

    def row(x, y):
        rows.append(f"{x:.15g}, {y:.15g}")

    rows.append("New Line")
    row(0, 0), row(10, 0)
    shell += [(0, 0), (10, 0)]
    rows.append("New Arc")
    start, total = -math.pi / 2, math.pi
    step = total / 1000
    angle = start + step
    while angle <= start + total:
        p = (10 + 2.5 * math.cos(angle), 2.5 + 2.5 * math.sin(angle))
        row(*p)
        shell.append(p)
        angle += step
    row(10, 5)
    shell.append((10, 5))
    rows.append("New Line")
    row(10, 5), row(0, 5)
    rows.append("New Line")
    row(0, 5), row(0, 0)
    holes = []
    for cx in (2.0, 10.0):
        rows.append("New Circle")
        ring, angle = [], 0.0
        while angle <= 2 * math.pi:
            ring.append((cx + math.cos(angle), 2.5 + math.sin(angle)))
            row(*ring[-1])
            angle += 0.01
        holes.append(np.array(ring))
    if points:
        for cx in (2.0, 10.0):
            rows.append("Point ")
            row(cx, 2.5)
    return rows, [np.array(shell + [(0, 5)])], holes


def write(tmp_path, rows: list[str], name: str = "sketch.csv", newline: str = "\n", bom: bool = False) -> Path:
    path = tmp_path / name
    path.write_bytes((b"\xef\xbb\xbf" if bom else b"") + (newline.join(rows) + newline).encode())
    return path


def exact_old_plate() -> object:
    return combine(rectangle(0, 0, 10, 5), sector(10, 2.5, 2.5, -math.pi / 2, math.pi),
                   disc(2, 2.5, 1).hole(), disc(10, 2.5, 1).hole())


def test_old_format_reads_as_centimetres_and_says_so(tmp_path):
    rows, shells, holes = old_rule_rows()
    sketch = read_sketch(write(tmp_path, rows))
    assert sketch.units == "cm" and sketch.units_assumed
    assert "assumed" in sketch_text(sketch) and "centimetres" in sketch_text(sketch)
    link = sketch.link()
    # What the samples describe (their polygon, gaps closed) to 1e-6; the exact plate only to the
    # old rule's own sampling: arcs and circles lose about (step)^2 / 6 of their area, 2e-5 here.
    described = Polygon(shells[0], [h[::-1] for h in holes])
    assert_matches(link.outline, scaled(_as_part(described), 1e-2), REL, 0.15)
    assert_matches(link.outline, scaled(exact_old_plate(), 1e-2), 2e-5, 0.15)
    assert np.abs(link.joints - [[0.02, 0.025], [0.1, 0.025]]).max() <= 1e-9
    assert link.joint_rules == (POINT_RULE, POINT_RULE)


def _as_part(polygon: Polygon):
    from linkstress.geometry.mass_properties import area_properties
    from test_import_exact import Part

    props = area_properties(polygon)
    return Part(props.area, props.centroid, props.polar)


def test_old_format_circles_close_their_gap_and_give_their_centres(tmp_path):
    rows, _, _ = old_rule_rows(points=False)
    sketch = read_sketch(write(tmp_path, rows), units="mm")
    link = sketch.link()
    assert sketch.units == "mm" and not sketch.units_assumed
    # The fitted centres of the sampled circles, in mm -> m.
    assert np.abs(link.joints - [[0.002, 0.0025], [0.010, 0.0025]]).max() <= 1e-9
    assert link.joint_rules == (HOLE_RULE, HOLE_RULE)
    # Largest gap: a circle's, from 6.28 rad back to 0 (0.0032 mm), or an arc's missing first step.
    assert link.largest_gap_m == pytest.approx(1e-3 * 2.5 * math.pi / 1000, rel=1e-3)
    assert any("closed" in fix for fix in sketch.fixes)


@pytest.mark.parametrize("newline, bom", [("\r\n", False), ("\n", True), ("\r\n", True)])
def test_crlf_bom_and_blank_lines_read_the_same(tmp_path, newline, bom):
    rows, _, _ = old_rule_rows()
    plain = read_sketch(write(tmp_path, rows, "plain.csv")).link()
    spaced = [r for row in rows for r in (row, "", "  ")]
    other = read_sketch(write(tmp_path, spaced, "other.csv", newline, bom)).link()
    assert other.outline.equals_exact(plain.outline, 0.0)
    assert np.array_equal(other.joints, plain.joints)


def test_semicolons_with_decimal_commas_read_the_same(tmp_path):
    rows, _, _ = old_rule_rows()
    european = [r.replace(", ", "; ").replace(".", ",") for r in rows]
    assert european[3] != rows[3]
    plain = read_sketch(write(tmp_path, rows, "plain.csv")).link()
    other = read_sketch(write(tmp_path, european, "european.csv")).link()
    assert other.outline.equals_exact(plain.outline, 0.0)


@pytest.mark.parametrize("junk, message", [
    ("abc, 1", r"line 7: 'abc' is not a number"),
    ("1,5, 2,5", r"line 7: expected x, y \(2 numbers\), got '1,5,2,5'; if the numbers use decimal commas, separate fields with ';'"),
    ("1e400, 2", r"line 7: '1e400' is too large a number"),
    ("nan, 2", r"line 7: 'nan' is not a number"),
    ("New Line, 3", r"line 7: 'New Line' stands alone on its line"),
])
def test_junk_on_a_line_is_refused_with_its_number(tmp_path, junk, message):
    rows, _, _ = old_rule_rows()
    rows.insert(6, junk)
    with pytest.raises(SketchError, match=r"^sketch.csv: " + message):
        read_sketch(write(tmp_path, rows))


def test_old_format_structure_errors_name_the_line(tmp_path):
    with pytest.raises(SketchError, match=r"line 4: coordinates before the first 'New <entity>' line"):
        read_sketch(write(tmp_path, ["X, Y", "Point", "0, 0", "1, 2"]))
    with pytest.raises(SketchError, match=r"line 3: 'Point' must be followed by its x, y line"):
        read_sketch(write(tmp_path, ["X, Y", "New Line", "Point"]))
    with pytest.raises(SketchError, match=r"line 2: 'New Line' has 1 x, y line\(s\)"):
        read_sketch(write(tmp_path, ["X, Y", "New Line", "1, 2"]))
    with pytest.raises(SketchError, match=r"line 1: not UTF-8 text"):
        (tmp_path / "latin.csv").write_bytes("X, \xff\n".encode("latin-1"))
        read_sketch(tmp_path / "latin.csv")


# -- linkstress-sketch v1 --------------------------------------------------------------------------


def v1_rows(units: str | None = "mm") -> list[str]:
    """A 4 x 2 plate: bottom line, right end a half ellipse (partial ELLIPSE record), top line, left
    end a half circle (arc); holes: a circle, a whole ellipse and a 400-point "spline" ring; joints:
    the circle's centre and a point in material."""
    spline = [f"{3.3 + 0.2 * math.cos(t):.17g}, {1 + 0.2 * math.sin(t):.17g}"
              for t in 2 * math.pi * np.arange(401) / 400]
    return [
        "# linkstress-sketch v1" + (f" units={units}" if units else ""),
        "# a comment",
        "line, 0, 0, 4, 0",
        f"ellipse, 4, 1, 0, 1, 0.5, {-math.pi:.17g}, {math.pi:.17g}",
        "line, 4, 2, 0, 2",
        f"arc, 0, 1, 1, {math.pi / 2:.17g}, {math.pi:.17g}",
        "circle, 0, 1, 0.25",
        f"ellipse, 2, 1, 0.5, 0, 0.5, 0, {2 * math.pi:.17g}",
        "spline, " + ", ".join(spline),
        "point, 0, 1",
        "point, 2.6, 1.5",
    ]


def exact_v1_plate():
    return combine(
        rectangle(0, 0, 4, 2), half_ellipse_right(4, 1, 0.5, 1), sector(0, 1, 1, math.pi / 2, math.pi),
        disc(0, 1, 0.25).hole(), ellipse(2, 1, 0.5, 0.25).hole(), regular_polygon(3.3, 1, 0.2, 400).hole(),
    )


def test_v1_reads_every_primitive_exactly(tmp_path):
    sketch = read_sketch(write(tmp_path, v1_rows()))
    assert sketch.format == "linkstress-sketch v1 CSV" and sketch.units == "mm" and not sketch.units_assumed
    link = sketch.link()
    assert_matches(link.outline, scaled(exact_v1_plate(), 1e-3), REL, 0.006)
    assert np.abs(link.joints - [[0.0, 0.001], [0.0026, 0.0015]]).max() <= 1e-9
    assert link.hole_diameters_m[0] == pytest.approx(0.0005, rel=1e-12)


def test_v1_without_header_units_needs_units(tmp_path):
    path = write(tmp_path, v1_rows(units=None))
    with pytest.raises(SketchError, match=r"does not say its units .*pass --units"):
        read_sketch(path)
    assert read_sketch(path, units="in").link().outline.area == pytest.approx(exact_v1_plate().area * 0.0254 ** 2, rel=REL)


@pytest.mark.parametrize("row, message", [
    ("polygon, 1, 2", r"line 12: unknown record 'polygon'; expected line, arc, circle, ellipse, spline or point"),
    ("circle, 1, 2", r"line 12: expected cx, cy, r \(3 numbers\), got '1,2'"),
    ("circle, 1, 2, -3", r"line 12: the radius must be > 0, got -3.0"),
    ("arc, 0, 0, 1, 0, 7", r"line 12: the sweep must be non-zero and at most 2 pi in size, got 7.0"),
    ("ellipse, 0, 0, 1, 0, 1.5, 0, 1", r"line 12: the ratio minor/major must be in \(0, 1\], got 1.5"),
    ("spline, 1, 2, 3", r"line 12: a spline needs x, y pairs of two or more points, got 3 numbers"),
])
def test_v1_bad_records_are_refused_with_their_line(tmp_path, row, message):
    with pytest.raises(SketchError, match=message):
        read_sketch(write(tmp_path, v1_rows() + [row]))


def test_v1_header_must_be_understood(tmp_path):
    with pytest.raises(SketchError, match=r"line 1: linkstress-sketch v2 is not a version this linkstress reads"):
        read_sketch(write(tmp_path, ["# linkstress-sketch v2 units=mm", "line, 0, 0, 1, 0"]))
    with pytest.raises(SketchError, match=r"line 1: unknown header option 'scale=2'"):
        read_sketch(write(tmp_path, ["# linkstress-sketch v1 scale=2", "line, 0, 0, 1, 0"]))


def test_the_ilogic_rules_sample_reads_as_the_crank_it_draws():
    # cad_scripts/sample_crank.csv, as ExportSketchToLinkstress.iLogicVb writes it (CRLF, G17
    # numbers, cm): 10 x 4 cm with round ends r 2, pin holes r 0.5 at both joints, an ellipse
    # 1.5 x 0.6 and a 1000-point spline ring r 0.6 at x = 8.
    sketch = read_sketch(REPO / "cad_scripts" / "sample_crank.csv")
    assert sketch.units == "cm" and sketch.units_source == "the header's units="
    exact = combine(
        rectangle(0, -2, 10, 2), sector(10, 0, 2, -math.pi / 2, math.pi), sector(0, 0, 2, math.pi / 2, math.pi),
        disc(0, 0, 0.5).hole(), disc(10, 0, 0.5).hole(), ellipse(5, 0, 1.5, 0.6).hole(),
        regular_polygon(8, 0, 0.6, 1000).hole(),
    )
    link = sketch.link()
    assert_matches(link.outline, scaled(exact, 1e-2), REL, 0.14)
    assert np.abs(link.joints - [[0.0, 0.0], [0.1, 0.0]]).max() <= 1e-9
    assert link.joint_rules == (POINT_RULE, POINT_RULE)
