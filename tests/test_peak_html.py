"""The HTML report's FEA peaks and fatigue (analyze --peaks --html): a table, the peak along the
sweep and the von Mises field at the worst position, per link; and the split of the quadratic
triangles the field is drawn on."""

from __future__ import annotations

import html
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from skfem import Basis, ElementTriP2, MeshTri

from linkstress.analysis import plan_for, run_analysis
from linkstress.report.cells import mpa
from linkstress.report.html import analysis_html
from linkstress.report.peak_html import linear_triangles, peak_field_figure, peak_sweep_figure
from linkstress.report.peak_records import peak_summaries
from linkstress.scene.reader import load_scene
from test_report_html import embedded_images

SEED = Path(__file__).resolve().parents[1] / "validation" / "cases" / "seed_ansys_fourbar"
LINKS = ("crank", "coupler", "output")
YIELD, ENDURANCE, ULTIMATE = 250e6, 200e6, 400e6


def seed_sweep(folder: Path) -> Path:
    """The seed case over a whole turn in 13 positions (180 deg, where all four bars align, is
    infeasible), its steel given a yield strength and fatigue data."""
    case = shutil.copytree(SEED, folder / "seed")
    scene = case / "scene.toml"
    text = scene.read_text()
    text = text.replace("input_angle_deg = 60.0", "input_angle_deg = { start = 0.0, stop = 360.0, num = 13 }")
    text = text.replace(
        "poisson_ratio = 0.3\n",
        f"poisson_ratio = 0.3\nyield_strength = {YIELD}\nendurance_limit = {ENDURANCE}\nultimate_strength = {ULTIMATE}\n",
        1,
    )
    scene.write_text(text)
    return scene


def analysed(scene: Path):
    """The analysis of ``scene`` with FEA peaks for every stressed link."""
    loaded = load_scene(scene)
    return run_analysis(loaded, plan_for(loaded).with_peaks())


@pytest.fixture(scope="module")
def seed(tmp_path_factory):
    result = analysed(seed_sweep(tmp_path_factory.mktemp("peaks")))
    return result, analysis_html(result)


def peak_table(text: str, name: str) -> dict[str, str]:
    """The rows (quantity -> value, unescaped) of link ``name``'s table in the peaks section, and its
    notes under "notes" (one per line)."""
    part = text[text.index("<h2>FEA peak stresses and fatigue</h2>"):]
    part = part[part.index(f"<h3>{name}</h3>"):]
    table, after = part.split("</table>", 1)
    rows = {
        html.unescape(label): html.unescape(value)
        for label, value in re.findall(r"<tr><td[^>]*>([^<]*)</td><td[^>]*>([^<]*)</td></tr>", table)
    }
    notes = after[:after.index("<img")]
    rows["notes"] = "\n".join(html.unescape(item) for item in re.findall(r"<li>([^<]*)</li>", notes))
    return rows


def test_the_peak_section_has_a_table_and_two_figures_per_link(seed):
    result, text = seed
    assert text.count("<h2>FEA peak stresses and fatigue</h2>") == 1
    for name in LINKS:
        assert text.count(f"<h3>{name}</h3>") == 1
        assert text.count(f'alt="FEA peak of {name} over the sweep"') == 1
        assert text.count(f'alt="von Mises in {name} at its worst position"') == 1
    section = text[text.index("<h2>FEA peak stresses and fatigue</h2>"):text.index("<h2>Timings</h2>")]
    images = embedded_images(section)
    assert len(images) == 2 * len(LINKS)
    for image in images:
        assert image.shape[:2] == (440, 660)  # 6 x 4 in at the report's 110 dpi
        assert image[..., :3].std() > 0.05


def test_the_table_gives_the_peak_summary_and_the_factors_from_the_fea_peak(seed):
    result, text = seed
    summaries = peak_summaries(result)
    for name in LINKS:
        s, rows = summaries[name], peak_table(text, name)
        peak = s["peak_max_von_mises_pa"]
        assert rows["FEA peak von Mises, largest over the sweep [MPa]"] == mpa(peak)
        assert rows["at input angle [deg]"] == f"{s['peak_max_input_angle_deg']:.6g}"
        assert rows["peak convergence: change over the last mesh refinement, over the one before"] == (
            f"{s['peak_change_pct']:.3g} %, {s['peak_previous_change_pct']:.3g} % (limit 5 % each): converged")
        # The yield factor is the material's 250 MPa over the FEA peak, not over the beam's maximum.
        assert rows["yield safety factor, from the FEA peak"] == f"{YIELD / peak:.3g}"
        factors = s["fatigue_safety_factors"]
        assert rows["fatigue safety factor (Goodman), other criteria beside it"] == (
            f"{factors['goodman']:.3g} (Goodman); Gerber {factors['gerber']:.3g}, "
            f"ASME-elliptic {factors['asme-elliptic']:.3g}"
        )
        assert rows["corrected endurance limit S_e [MPa]"] == mpa(ENDURANCE)
        x, y = s["fatigue_critical_at_m"]
        assert rows["fatigue critical point (x, y) [m], drawing frame (the sketch's coordinates)"] == f"({x:.4g}, {y:.4g})"
        # 12 of the 13 positions are feasible: the note says the history is not a whole cycle.
        assert "over the 12 feasible positions of 13 only" in rows["notes"]
    assert not re.search(r"\b(nan|inf|None)\b", text, re.IGNORECASE)


def test_the_sweep_figure_leaves_the_infeasible_position_a_gap_and_marks_the_worst(seed):
    result, _ = seed
    angle = result.scene.motion.angle_deg
    assert not result.feasible[6] and angle[6] == 180.0
    fig = peak_sweep_figure(result, "crank")
    ax = fig.axes[0]
    fea, beam, worst = ax.lines
    peaks = result.peaks["crank"]
    for line in (fea, beam):
        y = line.get_ydata()
        assert np.isnan(y[6]) and np.isfinite(np.delete(y, 6)).all()
    np.testing.assert_allclose(fea.get_ydata()[result.feasible], peaks.sweep.peak / 1e6)
    np.testing.assert_allclose(beam.get_ydata()[result.feasible], result.stresses["crank"].max_von_mises[result.feasible] / 1e6)
    assert worst.get_xdata()[0] == angle[peaks.worst_position]
    assert worst.get_ydata()[0] == pytest.approx(peaks.peak_max / 1e6)
    # The crank's peak is ~100 times its beam maximum (the pin holes): a log axis keeps both curves' shape.
    assert ax.get_yscale() == "log"
    fig.canvas.draw()
    legend = fig.legends[0].get_window_extent()
    assert not legend.overlaps(ax.get_window_extent())


def test_the_field_figure_is_in_the_ground_frame_at_the_worst_position_with_both_points_marked(seed):
    result, _ = seed
    summaries = peak_summaries(result)
    for name in LINKS:
        peaks = result.peaks[name]
        fig = peak_field_figure(result, name)
        ax = fig.axes[0]
        peak_mark, critical_mark = ax.lines
        # The same ground-frame point as the JSON's peak_max_at_m.
        np.testing.assert_allclose(np.ravel(peak_mark.get_xydata()), summaries[name]["peak_max_at_m"], atol=1e-12)
        node = peaks.sweep.cases.nodes[peaks.fatigue.critical_node]
        expected = result.to_ground(name, node[None], np.array([peaks.worst_position]))[0]
        np.testing.assert_allclose(np.ravel(critical_mark.get_xydata()), expected, atol=1e-12)
        assert f"{name} at input {result.scene.motion.angle_deg[peaks.worst_position]:.4g} deg" in ax.get_title()
        assert "MPa" in ax.child_axes[0].get_ylabel()  # the colour bar, an inset beside the plot
        assert ax.get_aspect() == 1.0
        fig.canvas.draw()
        for axis in (ax.xaxis, ax.yaxis):
            boxes = [t.get_window_extent() for t in axis.get_ticklabels() if t.get_text()]
            assert len(boxes) >= 2
            assert not any(a.overlaps(b) for a, b in zip(boxes, boxes[1:]))


def test_an_unconverged_peak_shows_its_factors_withheld_and_why(tmp_path):
    # The sharply notched crank of the validate story (test_analyze_peaks): its notch corner's peak
    # moves more than 5 % over one of the last two refinements, so no factor is taken from it.
    from test_validate_story import write_notched_crank

    scene = write_notched_crank(tmp_path)
    text = scene.read_text().replace('validate = ["crank"]', 'validate = ["crank"]\npeaks = true\nmesh_size_m = 0.004')
    scene.write_text(text.replace(
        "yield_strength = 250000000.0\n", "yield_strength = 250e6\nendurance_limit = 200e6\nultimate_strength = 400e6\n"))
    loaded = load_scene(scene)
    result = run_analysis(loaded, plan_for(loaded))
    s = peak_summaries(result)["crank"]
    assert s["peak_converged"] is False
    page = analysis_html(result)
    rows = peak_table(page, "crank")
    assert rows["peak convergence: change over the last mesh refinement, over the one before"] == (
        f"{s['peak_change_pct']:.3g} %, {s['peak_previous_change_pct']:.3g} % (limit 5 % each): NOT converged")
    assert rows["yield safety factor, from the FEA peak"].startswith("withheld: the FEA peak is NOT converged")
    assert rows["fatigue safety factor (Goodman), other criteria beside it"].startswith("withheld")
    assert s["peak_note"] in rows["notes"] and s["peak_note"].startswith("the FEA peak is NOT converged")
    assert not re.search(r"\b(nan|inf|None)\b", page, re.IGNORECASE)


def test_skfem_numbers_a_quadratic_triangles_mid_edge_nodes_after_edges_01_12_02():
    basis = Basis(MeshTri().refined(2), ElementTriP2())
    x, dofs = basis.doflocs, basis.element_dofs
    for row, (a, b) in zip((3, 4, 5), ((0, 1), (1, 2), (0, 2))):
        np.testing.assert_allclose(x[:, dofs[row]], 0.5 * (x[:, dofs[a]] + x[:, dofs[b]]), atol=1e-15)


def signed_areas(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    a, b, c = (points[triangles[:, i]] for i in range(3))
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))


def test_a_quadratic_triangle_splits_into_four_quarter_triangles_of_its_orientation():
    # Vertices (0, 0), (2, 0), (0, 2) (area 2, counter-clockwise), then the midpoints of edges 01, 12, 02.
    points = np.array([[0, 0], [2, 0], [0, 2], [1, 0], [1, 1], [0, 1]], float)
    triangles = linear_triangles(np.arange(6).reshape(6, 1))
    np.testing.assert_allclose(signed_areas(points, triangles), [0.5, 0.5, 0.5, 0.5])
    assert set(map(frozenset, triangles)) == {frozenset(t) for t in ([0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5])}


def test_the_split_of_a_real_peak_mesh_has_positive_areas_and_covers_the_link(seed):
    result, _ = seed
    model = result.peaks["crank"].sweep.cases.model
    points = model.scalar.doflocs.T
    triangles = linear_triangles(model.scalar.element_dofs)
    assert len(triangles) == 4 * model.scalar.element_dofs.shape[1]
    areas = signed_areas(points, triangles)
    assert areas.min() > 0
    # The seed's crank: a 1.2 m x 0.5 m bar with two 20 mm pin holes. Chords instead of the holes'
    # arcs leave ~1e-7 of it; crossed triangles would fold over and miss by far more.
    drawn = 1.2 * 0.5 - 2 * np.pi * 0.01**2
    assert areas.sum() == pytest.approx(drawn, rel=1e-5)


def test_linear_meshes_are_drawn_on_their_own_triangles():
    dofs = np.array([[0, 1], [1, 3], [2, 2]])
    np.testing.assert_array_equal(linear_triangles(dofs), [[0, 1, 2], [1, 3, 2]])
