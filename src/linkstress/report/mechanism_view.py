"""The HTML report's interactive view of the mechanism: a slider over the sweep's positions that
redraws every link's outline in the ground frame, coloured by its largest von Mises at that
position, with the joint forces as arrows. The colour is the FEA peak anywhere in the link (pin
holes included) where the analysis ran the peaks (``--peaks``), else the beam's largest section value,
and the view says which.

The page carries the data once (JSON in a ``<script type="application/json">`` block) and a small
inline script draws it (``mechanism_view.js``, package data): no network, no external files. Each
link's rings are stored once in its member frame, with its pose (origin and angle) per position;
the script places them as ``origin + R(angle) local``. Coordinates are in metres, rounded to
``10**-decimals`` (about 1e-5 of the drawing's size), stresses in MPa and forces in N to four
significant digits of the sweep's largest. Infeasible positions carry null and are shown as such.
"""

from __future__ import annotations

import html
import json
import math
from importlib import resources

import matplotlib
import numpy as np
import shapely
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.report.figures import LINK_COLOURS, joint_forces, joint_paths, link_rings

MAX_VIEW_FRAMES = 720
"""At most this many positions in the view, evenly chosen over the sweep (both ends kept)."""
FORCE_ARROW_FRACTION = 0.25
"""The sweep's largest joint force is drawn this fraction of the mechanism's size long."""
SIMPLIFY_FRACTION = 2e-4
"""Ring vertices that move the outline less than this fraction of the mechanism's size (a fifth of
a pixel on a 1000-pixel drawing) are left out of the view: a hole's hundreds of vertices become a
few dozen."""
VIEW_MARGIN = 0.04
"""Room around the links and force arrows, as a fraction of the mechanism's size."""
COLOUR_STOPS = 11
COLOUR_MAP = "viridis"
FEA_PEAK, BEAM = "FEA peak von Mises, anywhere in the link", "largest section von Mises (beam theory)"
"""What a link's colour is: its FEA peak where the peaks ran, else the beam's largest section value."""


def view_frames(count: int) -> NDArray[np.intp]:
    """The positions (indices into a sweep of ``count``) the view shows: all of them, or
    MAX_VIEW_FRAMES evenly spread from the first to the last."""
    if count <= MAX_VIEW_FRAMES:
        return np.arange(count)
    return np.unique(np.linspace(0, count - 1, MAX_VIEW_FRAMES).round().astype(np.intp))


def view_data(result: AnalysisResult) -> dict:
    """Everything the view draws, JSON-ready: per shown position its input angle [deg] and
    feasibility; per link its rings (member frame [m]) and pose (origin [m], angle [rad]; ground
    frame), and where stresses were computed its largest von Mises [MPa] and where it is (ground
    frame [m]) with what that is (``stress_label``: the FEA peak where the peaks ran, else the beam's
    largest section value); per joint its position and per joint force (Fij, of link i on link j) its
    value [N], ground frame. Null at infeasible positions."""
    frames = view_frames(len(result.feasible))
    ok = result.feasible[frames]
    rings = {name: link_rings(result, name) for name in result.scene.links}
    bounds = _bounds(result, rings, frames[ok])
    size = float(np.max(bounds[1] - bounds[0])) if bounds is not None else 0.0
    size = size if size > 0 else 1.0
    decimals = max(0, 4 - math.floor(math.log10(size)))
    links = {}
    for index, (name, link_ring_list) in enumerate(rings.items()):
        motion = result.kinematics.links[name]
        pose = np.column_stack([motion.origin[frames], motion.angle[frames]])
        entry = {
            "colour": LINK_COLOURS[index % len(LINK_COLOURS)],
            "closed": result.scene.links[name].profile is not None and len(link_ring_list[0]) > 3,
            "rings": [np.round(_simplified(ring, SIMPLIFY_FRACTION * size), decimals).tolist() for ring in link_ring_list],
            "pose": _per_frame(np.column_stack([np.round(pose[:, :2], decimals), np.round(pose[:, 2], 6)]), ok),
        }
        links[name] = entry
    data = {
        "positions": int(len(result.feasible)),
        "frames": frames.tolist(),
        "input_angle_deg": np.round(result.scene.motion.angle_deg[frames], 6).tolist(),
        "feasible": ok.tolist(),
        "reason": [result.reasons[k] for k in frames.tolist()],
        "decimals": decimals,
        "size_m": size,
        "links": links,
        "extent_m": _extent(bounds, size),
    }
    if result.stresses:
        shown = {name: link_stress(result, name) for name in result.stresses}
        largest = max(float(np.max(value[frames[ok]], initial=0.0)) for value, _, _ in shown.values()) / 1e6
        digits = _digits(largest)
        for name, (value, at, label) in shown.items():
            links[name]["von_mises_mpa"] = _per_frame(np.round(value[frames] / 1e6, digits), ok)
            links[name]["max_at_m"] = _per_frame(np.round(result.to_ground(name, at[frames], frames), decimals), ok)
            links[name]["stress_label"] = label
        colours = matplotlib.colormaps[COLOUR_MAP](np.linspace(0.0, 1.0, COLOUR_STOPS))
        labels = sorted({label for _, _, label in shown.values()})
        data["stress_scale"] = {
            "max_mpa": round(largest, digits),
            "decimals": digits,
            "colours": [matplotlib.colors.to_hex(c) for c in colours],
            "label": " or ".join(labels),
        }
    if result.forces is not None:
        forces, tails = _force_data(result, frames, ok, size, decimals)
        data.update(forces)
        if bounds is not None:
            bounds = np.array([np.minimum(bounds[0], tails.min(axis=0)), np.maximum(bounds[1], tails.max(axis=0))])
            data["extent_m"] = _extent(bounds, size)
    return data


def link_stress(result: AnalysisResult, name: str) -> tuple[NDArray[np.float64], NDArray[np.float64], str]:
    """Link ``name``'s colour at every position of the sweep: its von Mises (P,) [Pa], where it is
    (P, 2) [m, member frame] and what it is: the FEA peak where the peaks ran, else the beam's
    largest section value (both finite filler or nan at infeasible positions, which show null)."""
    if name in result.peaks:
        peaks = result.peaks[name]
        return np.nan_to_num(peaks.peak), np.nan_to_num(peaks.peak_at), FEA_PEAK
    stress = result.stresses[name]
    return stress.max_von_mises, stress.max_at, BEAM


def _force_data(result: AnalysisResult, frames, ok, size: float, decimals: int) -> tuple[dict, NDArray[np.float64]]:
    """Joints and joint forces at the shown positions and the arrows' scale [m/N]; and where the
    arrows start (joint - scale x force) at the feasible shown positions (n, 2) [m], ground frame."""
    arrows = joint_forces(result)
    paths = joint_paths(result)
    forces = np.stack([force[frames] for _, _, force in arrows])
    magnitude = np.hypot(forces[..., 0], forces[..., 1])
    largest = float(np.max(magnitude[:, ok], initial=0.0))
    scale = FORCE_ARROW_FRACTION * size / largest if largest > 0 else 0.0
    digits = _digits(largest)
    used = dict.fromkeys(joint for _, joint, _ in arrows)
    at = np.stack([paths[joint][frames] for _, joint, _ in arrows])
    tails = (at - scale * forces)[:, ok].reshape(-1, 2)
    data = {
        "joints": {joint: _per_frame(np.round(paths[joint][frames], decimals), ok) for joint in used},
        "forces": [
            {"label": label, "joint": joint, "force_n": _per_frame(np.round(force[frames], digits), ok)}
            for label, joint, force in arrows
        ],
        "largest_force_n": round(largest, digits),
        "force_decimals": digits,
        "force_scale_m_per_n": scale,
    }
    return data, tails


def _simplified(ring: NDArray[np.float64], tolerance: float) -> NDArray[np.float64]:
    """A subset of the vertices (n, 2) of ``ring`` within ``tolerance`` [m] of it (Douglas-Peucker),
    ends kept."""
    if len(ring) < 3:
        return ring
    return np.asarray(shapely.LineString(ring).simplify(tolerance, preserve_topology=False).coords)


def _digits(largest: float) -> int:
    """Decimals that keep four significant digits of ``largest``."""
    return 3 - math.floor(math.log10(largest)) if largest > 0 else 0


def _per_frame(values: NDArray[np.float64], ok: NDArray[np.bool_]) -> list:
    """Rows of ``values`` (F, ...) as lists, null where the position is infeasible."""
    return [row if good else None for row, good in zip(values.tolist(), ok.tolist())]


def _bounds(result: AnalysisResult, rings: dict, frames: NDArray[np.intp]) -> NDArray[np.float64] | None:
    """[[xmin, ymin], [xmax, ymax]] [m] of every ring vertex of every link at each of ``frames``,
    ground frame; None without frames."""
    if not len(frames):
        return None
    lows, highs = [], []
    for name, ring_list in rings.items():
        motion = result.kinematics.links[name]
        local = np.vstack(ring_list)
        c, s = np.cos(motion.angle[frames])[:, None], np.sin(motion.angle[frames])[:, None]
        x = motion.origin[frames, 0][:, None] + c * local[:, 0] - s * local[:, 1]
        y = motion.origin[frames, 1][:, None] + s * local[:, 0] + c * local[:, 1]
        lows.append((x.min(), y.min()))
        highs.append((x.max(), y.max()))
    return np.array([np.min(lows, axis=0), np.max(highs, axis=0)])


def _extent(bounds: NDArray[np.float64] | None, size: float) -> list[float]:
    """[xmin, ymin, xmax, ymax] [m] of ``bounds`` ([[xmin, ymin], [xmax, ymax]]) with a margin of
    VIEW_MARGIN of the mechanism's ``size`` on every side."""
    if bounds is None:
        return [0.0, 0.0, size, size]
    margin = VIEW_MARGIN * size
    return [float(v) for v in (*(bounds[0] - margin), *(bounds[1] + margin))]


def view_html(result: AnalysisResult) -> str:
    """The section: the drawing, the slider, the colour bar and what the view shows, as HTML."""
    data = view_data(result)
    count = len(data["frames"])
    script = resources.files("linkstress.report").joinpath("mechanism_view.js").read_text(encoding="utf-8")
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    return (
        '<div id="mechanism-view">'
        f'<p class="note">{html.escape(_caption(result, data))}</p>'
        '<div class="view-controls"><button type="button" id="view-play">play</button> '
        f'<input type="range" id="view-slider" min="0" max="{count - 1}" step="1" value="0" '
        f'aria-label="position in the sweep"{" disabled" if count < 2 else ""}> '
        '<span id="view-angle"></span></div>'
        '<svg id="view-svg" role="img" aria-label="the mechanism at the chosen position"></svg>'
        '<div id="view-colour-bar"></div><div id="view-readout"></div>'
        f'<script type="application/json" id="view-data">{payload}</script>'
        f"<script>{script}</script></div>"
    )


def _caption(result: AnalysisResult, data: dict) -> str:
    """What the view draws, its scales, and what it leaves out."""
    count, positions = len(data["frames"]), data["positions"]
    parts = [
        "The mechanism at one position of the sweep (slider or arrow keys; play runs through them): every link's "
        "outline placed by its pose in the ground frame (x right, y up)."
    ]
    if count < positions:
        parts.append(f"{count} of the sweep's {positions} positions, evenly chosen (the JSON output has all).")
    if "stress_scale" in data:
        peaks = [name for name, link in data["links"].items() if link.get("stress_label") == FEA_PEAK]
        what = (
            "their FEA peak von Mises (anywhere in the link, pin holes included: the superposed plane-stress FEA of "
            "--peaks)" if peaks and len(peaks) == len(result.stresses)
            else f"their FEA peak von Mises ({', '.join(peaks)}) or else their largest section von Mises (beam theory)"
            if peaks else "their largest section von Mises (beam theory)"
        )
        parts.append(
            f"Links filled by {what} at that position, one colour scale for the whole sweep, 0 to "
            f"{data['stress_scale']['max_mpa']:.4g} MPa; the dot marks where it is."
        )
    else:
        parts.append("No section stresses were computed in this analysis: the links are not coloured.")
    if "forces" in data:
        largest = data["largest_force_n"]
        parts.append(
            f"Red arrows: joint forces Fij (of link i on link j) pointing at their joint; the sweep's largest, "
            f"{largest:.4g} N, is drawn {FORCE_ARROW_FRACTION * data['size_m']:.4g} m long "
            f"({FORCE_ARROW_FRACTION:g} of the mechanism's size)."
        )
    else:
        parts.append("No joint forces were computed in this analysis: no arrows.")
    return " ".join(parts)
