"""Figures of an analysis (matplotlib, Agg): the mechanism with its real outlines and joint forces,
stresses along each link, and plots over a sweep's input angle. Ground frame, SI units."""

from __future__ import annotations

import io
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import LogNorm, Normalize  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402
from numpy.typing import NDArray  # noqa: E402

from linkstress.analysis import AnalysisResult  # noqa: E402
from linkstress.report.figure_notes import figure_warnings  # noqa: E402
from linkstress.report.labels import LabelPlacer  # noqa: E402

LINK_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf")
TICK_GAP_PX = 4.0
"""Tick labels closer than this (at the saved resolution) run together to the eye ("0.3250.350")."""
LABEL_ZORDER = 10
"""Above every line and fill of a figure: a label on a marked point is never hidden by a curve or cut."""
LOG_FIELD_RATIO = 10.0
"""A stress field whose largest value is more than this many times its median (a pin's peak over the
link's own field) is drawn on a logarithmic colour scale: on a linear one the rest of the link would
be one dark colour."""
FIELD_DECADES = 3
"""A logarithmic colour scale spans this many decades below the field's largest value; smaller
values take its lowest colour (and the colour bar says so)."""
COLOUR_BAR_WIDTH = 0.04
"""A field's colour bar: this fraction of its plot's width, beside it and exactly as tall."""


def png_bytes(fig: Figure, dpi: int = 110, notes: list[str] | None = None) -> bytes:
    """The figure as PNG, its x tick labels spread apart (``spread_x_ticks``); the figure is closed.
    What matplotlib warns while drawing goes to ``notes`` (``figure_warnings``), never the terminal."""
    with figure_warnings(notes):
        spread_x_ticks(fig, dpi)
        buffer = io.BytesIO()
        fig.savefig(buffer, format="png", dpi=dpi)
    plt.close(fig)
    return buffer.getvalue()


def outside_legend(ax, **options) -> None:
    """The axes' legend to the right of the plot, where it covers no data (the figure's layout makes
    room for it)."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, fontsize=8, **options)


def spread_x_ticks(fig: Figure, dpi: int = 110) -> None:
    """Fewer x ticks on every linear x axis of ``fig`` whose tick labels, drawn at ``dpi``, come
    closer than TICK_GAP_PX: matplotlib's own count allows about three characters a label, and
    "-0.025" has six."""
    fig.set_dpi(dpi)
    for ax in fig.axes:
        if ax.get_xscale() != "linear":
            continue
        gaps = drawn_tick_gaps(ax)
        bins = len(gaps) - 1
        while bins >= 1 and min(gaps, default=TICK_GAP_PX) < TICK_GAP_PX:
            ax.xaxis.set_major_locator(MaxNLocator(bins, steps=[1, 2, 5, 10], min_n_ticks=1))
            gaps = drawn_tick_gaps(ax)
            bins = min(bins, len(gaps)) - 1


def drawn_tick_gaps(ax) -> list[float]:
    """``x_tick_gaps`` of ``ax`` once its figure is drawn (what matplotlib warns while drawing, a
    glyph its font lacks, stays off the terminal: ``figure_warnings``)."""
    with figure_warnings():
        ax.figure.canvas.draw()
    return x_tick_gaps(ax, ax.figure.canvas.get_renderer())


def x_tick_gaps(ax, renderer) -> list[float]:
    """The gaps [pixels] between neighbouring x tick labels that ``ax`` shows (ticks inside its view),
    as last drawn."""
    low, high = sorted(ax.get_xlim())
    span = 1e-9 * (high - low)
    shown = [
        label for at, label in zip(ax.get_xticks(), ax.get_xticklabels())
        if low - span <= at <= high + span and label.get_visible() and label.get_text()
    ]
    boxes = sorted((label.get_window_extent(renderer) for label in shown), key=lambda box: box.x0)
    return [b.x0 - a.x1 for a, b in zip(boxes, boxes[1:])]


@dataclass(frozen=True)
class FieldScale:
    """How a stress field is coloured: ``norm`` (linear from 0, or logarithmic over FIELD_DECADES
    below the largest value) and ``label``, which says which, for the colour bar."""

    norm: Normalize
    label: str


def field_scale(values: NDArray[np.float64], quantity: str = "von Mises [MPa]") -> FieldScale:
    """The colour scale that shows the field ``values`` (in the unit of ``quantity``): logarithmic
    when its largest is more than LOG_FIELD_RATIO times its median, else linear from 0."""
    largest = float(np.max(values)) if np.size(values) else 0.0
    median = float(np.median(values)) if np.size(values) else 0.0
    if largest > 0 and largest > LOG_FIELD_RATIO * median:
        lowest = largest / 10**FIELD_DECADES
        return FieldScale(LogNorm(lowest, largest, clip=True), f"{quantity}, log scale\n(below {lowest:.2g}: lowest colour)")
    return FieldScale(Normalize(0.0, largest if largest > 0 else 1.0), f"{quantity}, linear scale")


def field_colour_bar(fig: Figure, ax, mappable, label: str):
    """A colour bar for ``mappable`` beside ``ax``, as tall as the plot as drawn (an equal-aspect
    drawing of a long link is much lower than its axes' space, where a plain colour bar would stand
    twice its height): an inset of the axes, which follows their drawn box."""
    bar = ax.inset_axes([1.0 + COLOUR_BAR_WIDTH, 0.0, COLOUR_BAR_WIDTH, 1.0])
    return fig.colorbar(mappable, cax=bar, label=label)


LABEL_BOX = dict(boxstyle="round,pad=0.2", fc="white", ec="0.6", lw=0.5, alpha=0.9)
"""The white box a label sits on, readable over lines, fills and cut marks."""


def boxed_label(ax, text: str, at, offset=(8, 8), **options) -> None:
    """``text`` beside the point ``at``, offset by ``offset`` points, on a white box above every
    other artist: readable over lines, fills and cut marks."""
    ax.annotate(text, at, textcoords="offset points", xytext=offset, zorder=LABEL_ZORDER, bbox=LABEL_BOX, **options)


def _to_ground(result: AnalysisResult, name: str, k: int, local: NDArray[np.float64]) -> NDArray[np.float64]:
    """Member-frame points (n, 2) of link ``name`` at position ``k`` in the ground frame."""
    motion = result.kinematics.links[name]
    c, s = np.cos(motion.angle[k]), np.sin(motion.angle[k])
    return motion.origin[k] + local @ np.array([[c, s], [-s, c]])


def link_rings(result: AnalysisResult, name: str) -> list[NDArray[np.float64]]:
    """The link's outline rings in its member frame, or the polyline through its joints."""
    link = result.scene.links[name]
    frame = result.kinematics.links[name].frame_joints
    if link.profile is not None and frame[0] != frame[1]:
        outline = link.profile.local_outline(*frame)
        return [np.asarray(r.coords) for r in [outline.exterior, *outline.interiors]]
    if link.profile is not None and result.scene.linkage is not None:  # a block, along its slider's line
        outline = link.profile.outline
        return [link.to_member(np.asarray(r.coords)) for r in [outline.exterior, *outline.interiors]]
    return [link.to_member(link.joints)]


def mechanism_figure(result: AnalysisResult, k: int) -> Figure:
    """Every link at position ``k`` with its outline, and the joint forces as arrows."""
    fig, ax = plt.subplots(figsize=(7.5, 5.5), layout="constrained")
    names = list(result.scene.links)
    points = []
    for index, name in enumerate(names):
        colour = LINK_COLOURS[index % len(LINK_COLOURS)]
        for ring_index, ring in enumerate(link_rings(result, name)):
            xy = _to_ground(result, name, k, ring)
            points.append(xy)
            style = dict(color=colour, lw=1.6 if ring_index == 0 else 1.0)
            ax.plot(xy[:, 0], xy[:, 1], label=name if ring_index == 0 else None, **style)
            if ring_index == 0 and len(ring) > 3:
                ax.fill(xy[:, 0], xy[:, 1], color=colour, alpha=0.15)
    cloud = np.vstack(points)
    size = float(np.ptp(cloud, axis=0).max()) or 1.0
    labels = LabelPlacer(ax)
    for name in result.stresses:
        where = result.max_location(name)[k]
        ax.plot(*where, marker="*", color="k", ms=12)
        labels.avoid(where)
        labels.add(f"max {name}", where, fontsize=8, zorder=LABEL_ZORDER, bbox=LABEL_BOX)
    if result.forces is not None:
        _force_arrows(ax, result, k, size, labels)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m], ground frame")
    ax.set_ylabel("y [m], ground frame")
    ax.set_title(f"input angle {result.scene.motion.angle_deg[k]:.4g} deg")
    ax.grid(alpha=0.3)
    outside_legend(ax)
    left_off = labels.place()
    if left_off:
        # No room beside its point on the drawing: the label is listed in the legend instead.
        for text in left_off:
            ax.plot([], [], " ", label=f"{text} (no room on the drawing)")
        outside_legend(ax)
    return fig


def mechanism_sweep_figure(result: AnalysisResult, positions: list[int]) -> Figure:
    """Every link's outline at each of ``positions`` (faint to dark in sweep order) and the paths
    of all joints over the feasible sweep."""
    fig, ax = plt.subplots(figsize=(7.5, 5.5), layout="constrained")
    names = list(result.scene.links)
    shades = np.linspace(0.25, 1.0, len(positions))
    for index, name in enumerate(names):
        colour = LINK_COLOURS[index % len(LINK_COLOURS)]
        rings = link_rings(result, name)
        for shade, k in zip(shades, positions):
            xy = _to_ground(result, name, k, rings[0])
            ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=0.8, alpha=float(shade),
                    label=name if k == positions[-1] else None)
    ok = result.feasible
    for position in joint_paths(result).values():
        path = position[ok]
        if np.ptp(path, axis=0).max() > 0:
            ax.plot(path[:, 0], path[:, 1], ":", color="0.4", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m], ground frame")
    ax.set_ylabel("y [m], ground frame")
    angles = result.scene.motion.angle_deg[positions]
    ax.set_title(f"{len(positions)} positions, input {angles[0]:.4g} to {angles[-1]:.4g} deg (dotted: joint paths)")
    outside_legend(ax)
    ax.grid(alpha=0.3)
    return fig


def joint_forces(result: AnalysisResult) -> list[tuple[str, str, NDArray[np.float64]]]:
    """Every joint force of the analysis as (label, joint, force): ``label`` "loop.Fij" (force of
    link i on link j), ``joint`` "loop.NAME" of the joint it acts at (``joint_paths``), ``force``
    (P, 2) [N], ground frame."""
    arrows = []
    linkage = result.kinematics.linkage
    if linkage is not None:
        detail = result.forces.mechanisms[linkage.graph.name].linkage
        for pin, forces in zip(detail.pins, detail.forces):
            moving = [j for j in pin if not j.startswith(linkage.graph.ground + ":")]
            label = linkage.graph.pin_label(tuple(linkage.graph.all_pins[detail.pins.index(pin)]))
            arrows += [(f"{label} on {j}" if len(pin) > 2 else label, j, forces[j]) for j in moving[-1:] if j in forces]
        return arrows
    for loop_name, mech in result.forces.mechanisms.items():
        joints = result.kinematics.loops[loop_name].joints
        at = {"F12": "O2", "F32": "A", "F43": "B", "F14": "O4" if "O4" in joints else "B"}
        arrows += [(f"{loop_name}.{label}", f"{loop_name}.{at[label]}", force) for label, force in mech.forces.items()]
    return arrows


def joint_paths(result: AnalysisResult) -> dict[str, NDArray[np.float64]]:
    """Every loop's joints as "loop.NAME" (a linkage's: "LINK:i"): position (P, 2) [m], ground frame."""
    if result.kinematics.linkage is not None:
        return {name: joint.position for name, joint in result.kinematics.linkage.joints.items()}
    return {
        f"{loop_name}.{name}": joint.position
        for loop_name, loop in result.kinematics.loops.items()
        for name, joint in loop.joints.items()
    }


def _force_arrows(ax, result: AnalysisResult, k: int, size: float, labels: LabelPlacer) -> None:
    """Fij at its joint (force of i on j), scaled so the largest is a quarter of the drawing, each
    labelled at its tail (through ``labels``, largest first)."""
    paths = joint_paths(result)
    arrows = [(label, paths[joint][k], force[k]) for label, joint, force in joint_forces(result)]
    largest = max((np.hypot(*f) for _, _, f in arrows), default=0.0)
    if largest <= 0:
        return
    scale = 0.25 * size / largest
    for label, p, f in sorted(arrows, key=lambda arrow: -np.hypot(*arrow[2])):
        ax.annotate(
            "", xy=p, xytext=p - scale * f,
            arrowprops=dict(arrowstyle="->", color="crimson", lw=1.5),
        )
        labels.add(f"{label} {np.hypot(*f):.4g} N", p - scale * f, fontsize=7, color="crimson", zorder=LABEL_ZORDER)


def stress_along_figure(
    result: AnalysisResult, name: str, k: int, fea_x=None, fea_von_mises=None,
) -> Figure:
    """Von Mises (largest over each section) and N, V, M along link ``name`` at position ``k``;
    FEA values at the comparison stations when given. The arrays along the link are recomputed
    for this one position (an analysis keeps only per-position reductions)."""
    stress = result.stresses[name].at(slice(k, k + 1))
    x = stress.x
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 5.5), sharex=True, layout="constrained")
    top.plot(x, stress.von_mises[0] / 1e6, label="beam sections", color="#1f77b4")
    if fea_x is not None:
        top.plot(fea_x, np.asarray(fea_von_mises) / 1e6, "o", label="FEA, same fibre", color="#d62728")
    for a, b in _runs(x, stress.near_hole):
        top.axvspan(a, b, color="0.85", lw=0)
    top.set_ylabel("von Mises [MPa]")
    top.set_title(f"{name} at input {result.scene.motion.angle_deg[k]:.4g} deg (grey: within a depth of a pin hole)")
    outside_legend(top)
    top.grid(alpha=0.3)
    bottom.plot(x, stress.forces.normal[0], label="N [N]")
    bottom.plot(x, stress.forces.shear[0], label="V [N]")
    bottom.plot(x, stress.forces.moment[0], label="M [N m]")
    bottom.set_xlabel("x along the member [m], member frame")
    outside_legend(bottom)
    bottom.grid(alpha=0.3)
    return fig


def _runs(x: NDArray[np.float64], flags: NDArray[np.bool_]) -> list[tuple[float, float]]:
    """(start, end) abscissae of each run of True flags."""
    runs, start = [], None
    for xi, flag in zip(x, flags):
        if flag and start is None:
            start = xi
        if not flag and start is not None:
            runs.append((start, xi))
            start = None
    if start is not None:
        runs.append((start, x[-1]))
    return runs


def sweep_figure(result: AnalysisResult) -> Figure:
    """Over the input angle: driving torque, largest section stress per link, transmission angle."""
    ok = result.feasible
    angle = result.scene.motion.angle_deg
    panels = 1 + (result.forces is not None) + bool(result.stresses)
    fig, axes = plt.subplots(panels, 1, figsize=(7.5, 2.6 * panels), sharex=True, squeeze=False, layout="constrained")
    axes = list(axes[:, 0])
    if result.forces is not None:
        ax = axes.pop(0)
        for name, mech in result.forces.mechanisms.items():
            if mech.driving_torque is not None:
                ax.plot(angle[ok], mech.driving_torque[ok], ".-", ms=3, label=f"{name} {mech.torque_name}")
            if mech.driving_force is not None:
                ax.plot(angle[ok], mech.driving_force[ok], ".-", ms=3, label=f"{name} {mech.force_name} [N]")
        ax.set_ylabel("driving torque [N m]")
        outside_legend(ax)
        ax.grid(alpha=0.3)
    if result.stresses:
        ax = axes.pop(0)
        for name, stress in result.stresses.items():
            ax.plot(angle[ok], stress.max_von_mises[ok] / 1e6, ".-", ms=3, label=name)
        ax.set_ylabel("max von Mises [MPa]")
        outside_legend(ax)
        ax.grid(alpha=0.3)
    ax = axes.pop(0)
    if result.kinematics.linkage is not None:  # no loops: every moving link's angle
        for name in result.scene.moving_links:
            ax.plot(angle[ok], np.degrees(np.unwrap(result.kinematics.links[name].angle[ok])), ".-", ms=3, label=name)
        ax.set_ylabel("link angle [deg]")
    for name, loop in result.kinematics.loops.items():
        ax.plot(angle[ok], np.degrees(loop.transmission_angle[ok]), ".-", ms=3, label=name)
        ax.set_ylabel("transmission angle [deg]")
    ax.set_xlabel("input angle [deg]")
    outside_legend(ax)
    ax.grid(alpha=0.3)
    return fig
