"""A picture of a sketch's links: outline, holes, joints and member axis in the sketch frame, and
U(x), L(x) in each link's member frame (matplotlib, Agg backend, no screen)."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the backend)
import numpy as np  # noqa: E402

from linkstress.importers.sketch import Sketch  # noqa: E402
from linkstress.importers.summary import NO_PROFILE  # noqa: E402


def sketch_png(sketch: Sketch) -> bytes:
    """PNG bytes: one row per link; left the link in the sketch frame [m], right U(x), L(x) [m]."""
    rows = max(len(sketch.links), 1)
    fig, axes = plt.subplots(rows, 2, figsize=(11, 3.2 * rows), squeeze=False)
    try:
        for (left, right), link in zip(axes, sketch.links):
            _outline(left, link)
            _bounds(right, link)
        fig.suptitle(f"{sketch.path.name} ({sketch.units}, shown in m)")
        fig.tight_layout()
        buffer = io.BytesIO()
        fig.savefig(buffer, format="png", dpi=100)
        return buffer.getvalue()
    finally:
        plt.close(fig)


def _outline(ax, link) -> None:
    x, y = link.outline.exterior.xy
    ax.fill(x, y, color="0.85", zorder=1)
    ax.plot(x, y, color="k", lw=1, zorder=2, label="outline")
    for k, ring in enumerate(link.outline.interiors):
        hx, hy = ring.xy
        ax.fill(hx, hy, color="w", zorder=2)
        ax.plot(hx, hy, color="tab:blue", lw=1, zorder=3, label="holes" if k == 0 else None)
    if len(link.joints):
        ax.plot(*link.joints.T, "o", color="tab:red", ms=5, zorder=4, label="joints")
        for k, (p, rule) in enumerate(zip(link.joints, link.joint_rules)):
            ax.annotate(f"{k} ({rule})", p, textcoords="offset points", xytext=(4, 4), fontsize=7)
    if len(link.joints) >= 2:
        profile = link.profile(1.0)
        frame = profile.frame(0, 1)
        lo, hi = profile.x_extent(0, 1)
        axis = frame.to_global(np.array([[lo, 0.0], [hi, 0.0]]))
        ax.plot(*axis.T, "--", color="tab:red", lw=0.8, zorder=4, label="member axis")
    ax.set_aspect("equal")
    ax.set_title(f"{link.name}: sketch frame [m]", fontsize=9)
    ax.legend(fontsize=7, loc="best")


def _bounds(ax, link) -> None:
    if len(link.joints) < 2:
        ax.text(0.5, 0.5, NO_PROFILE.format(n=len(link.joints)), ha="center", va="center", wrap=True,
                fontsize=8, transform=ax.transAxes)
        ax.set_axis_off()
        return
    x, upper, lower = link.profile(1.0).bounds(0, 1).polyline()
    ax.fill_between(x, lower, upper, color="0.9")
    ax.plot(x, upper, color="tab:green", lw=1, label="U(x)")
    ax.plot(x, lower, color="tab:purple", lw=1, label="L(x)")
    ax.axhline(0.0, color="tab:red", ls="--", lw=0.8)
    ax.set_xlabel("x along joint 0 -> joint 1 [m]", fontsize=8)
    ax.set_title(f"{link.name}: bounding functions, member frame [m]", fontsize=9)
    ax.legend(fontsize=7)
