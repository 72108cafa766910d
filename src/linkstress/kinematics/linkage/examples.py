"""Reference linkages drawn assembled, for tests, benches and documentation: Theo Jansen's leg with
his published lengths, a Whitworth quick-return and a six-bar that needs a triad.

Each pose is built step by step from circle intersections, so that the drawing closes exactly.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from linkstress.kinematics.linkage.graph import Input, Joint, LinkageGraph, Slider

JANSEN_CM = {"a": 38.0, "b": 41.5, "c": 39.3, "d": 40.1, "e": 55.8, "f": 39.4, "g": 36.7, "h": 65.7, "i": 49.0,
             "j": 50.0, "k": 61.9, "l": 7.8, "m": 15.0}
"""Theo Jansen's "holy numbers" [cm]: crank m about O, fixed pivot B at (-a, -l) from O; j = AC,
b = BC, e = CE, d = BE (the upper triangle), k = AD, c = BD, f = EF, g = DF, h = FG, i = DG (the
leg's triangle, G the foot)."""


def circles(p: NDArray[np.float64], r: float, q: NDArray[np.float64], s: float, pick) -> NDArray[np.float64]:
    """The intersection of the circles (p, r) and (q, s) that ``pick`` (a function of the two
    candidates) chooses: law of cosines at p."""
    d = q - p
    dist = math.hypot(*d)
    base = math.atan2(d[1], d[0])
    beta = math.acos((r * r + dist * dist - s * s) / (2 * r * dist))
    candidates = [p + r * np.array([math.cos(base + t), math.sin(base + t)]) for t in (beta, -beta)]
    return pick(*candidates)


def jansen_pose(crank_deg: float, scale: float = 0.01) -> dict[str, NDArray[np.float64]]:
    """Jansen's leg at a crank angle [deg], lengths in metres (``scale`` m per cm): O, A, B, C, D, E, F, G."""
    L = {k: v * scale for k, v in JANSEN_CM.items()}
    o = np.zeros(2)
    b = np.array([-L["a"], -L["l"]])
    t = math.radians(crank_deg)
    a = L["m"] * np.array([math.cos(t), math.sin(t)])
    upper = lambda p, q: p if p[1] > q[1] else q  # noqa: E731
    lower = lambda p, q: p if p[1] < q[1] else q  # noqa: E731
    left = lambda p, q: p if p[0] < q[0] else q  # noqa: E731
    c = circles(a, L["j"], b, L["b"], upper)
    d = circles(a, L["k"], b, L["c"], lower)
    e = circles(b, L["d"], c, L["e"], left)
    f = circles(e, L["f"], d, L["g"], left)
    g = circles(f, L["h"], d, L["i"], lower)
    return {"O": o, "A": a, "B": b, "C": c, "D": d, "E": e, "F": f, "G": g}


def jansen_leg(crank_deg: float = 0.0) -> LinkageGraph:
    """Jansen's leg drawn at ``crank_deg``: links frame (O, B), crank (O, A), upper_j (A, C),
    lower_k (A, D), triangle (B, C, E), rocker_c (B, D), link_f (E, F), leg (D, F, G)."""
    p = jansen_pose(crank_deg)
    links = {
        "frame": [p["O"], p["B"]], "crank": [p["O"], p["A"]], "upper_j": [p["A"], p["C"]], "lower_k": [p["A"], p["D"]],
        "triangle": [p["B"], p["C"], p["E"]], "rocker_c": [p["B"], p["D"]], "link_f": [p["E"], p["F"]],
        "leg": [p["D"], p["F"], p["G"]],
    }
    pins = [("frame:0", "crank:0"), ("crank:1", "upper_j:0", "lower_k:0"), ("frame:1", "triangle:0", "rocker_c:0"),
            ("upper_j:1", "triangle:1"), ("lower_k:1", "rocker_c:1", "leg:0"), ("triangle:2", "link_f:0"),
            ("link_f:1", "leg:1")]
    return LinkageGraph("leg", links, "frame", _pins(pins), (), Input("crank", 0, 1))


def whitworth(crank: float = 0.05, centres: float = 0.12, lever: float = 0.3, crank_deg: float = 30.0,
              rod: float = 0.25, ram_height: float = 0.28) -> LinkageGraph:
    """A Whitworth (crank-shaper) quick-return: the crank (pivot O2, ``centres`` [m] above the
    lever's pivot O4) carries a collar that slides in the slotted lever; the lever's end drives a
    rod pinned to a ram that slides on a horizontal guide ``ram_height`` above O4."""
    t = math.radians(crank_deg)
    o4, o2 = np.zeros(2), np.array([0.0, centres])
    p = o2 + crank * np.array([math.cos(t), math.sin(t)])
    tip = p / math.hypot(*p) * lever
    ram = np.array([tip[0] + math.sqrt(rod * rod - (ram_height - tip[1]) ** 2), ram_height])
    links = {
        "frame": [o4, o2, [-1.0, ram_height], [1.0, ram_height]], "crank": [o2, p], "lever": [o4, tip],
        "collar": [p], "rod": [tip, ram], "ram": [ram],
    }
    pins = [("frame:1", "crank:0"), ("frame:0", "lever:0"), ("lever:1", "rod:0")]
    sliders = (Slider(Joint("crank", 1), "lever", (0, 1), "collar"), Slider(Joint("rod", 1), "frame", (2, 3), "ram"))
    return LinkageGraph("shaper", links, "frame", _pins(pins), sliders, Input("crank", 0, 1))


def triad_six_bar(crank_deg: float = 20.0) -> LinkageGraph:
    """A six-bar whose ternary link ``plate`` floats, held by three binary links: ``l1`` from the
    crank's pin, ``l2`` and ``l3`` from ground pivots (a class-3 group: no dyad order solves it)."""
    g0, g1, g2 = np.array([0.0, 0.0]), np.array([0.25, 0.05]), np.array([0.05, -0.2])
    t = math.radians(crank_deg)
    a = 0.05 * np.array([math.cos(t), math.sin(t)])
    plate = [np.array([0.12, 0.1]), np.array([0.22, 0.16]), np.array([0.16, 0.02])]
    links = {"ground": [g0, g1, g2], "crank": [g0, a], "l1": [a, plate[0]], "l2": [g1, plate[1]],
             "l3": [g2, plate[2]], "plate": plate}
    pins = [("ground:0", "crank:0"), ("crank:1", "l1:0"), ("l1:1", "plate:0"), ("ground:1", "l2:0"),
            ("l2:1", "plate:1"), ("ground:2", "l3:0"), ("l3:1", "plate:2")]
    return LinkageGraph("triad", links, "ground", _pins(pins), (), Input("crank", 0, 1))


def _pins(pins) -> tuple[tuple[Joint, ...], ...]:
    out = []
    for pin in pins:
        out.append(tuple(Joint(text.rsplit(":", 1)[0], int(text.rsplit(":", 1)[1])) for text in pin))
    return tuple(out)


def loader_arm(stroke: float = 0.45) -> LinkageGraph:
    """A loader's arm lifted by a hydraulic cylinder: the arm turns about O1 = (0, 0) and carries
    the rod's pin P 0.3 m out; the barrel turns about O2 = (0.1, -0.35) and its line runs from O2
    through its joint 1; the rod is the block pinned at P, sliding in the barrel. The input is the
    stroke: P's distance from O2 along the barrel (|P - O2|), drawn at ``stroke`` [m]."""
    o1, o2 = np.array([0.0, 0.0]), np.array([0.1, -0.35])
    p = circles(o1, 0.3, o2, stroke, lambda a, b: a if a[0] > b[0] else b)
    tip = o1 + (p - o1) / 0.3 * 1.2
    barrel_end = o2 + (p - o2) / stroke * 0.25
    links = {"frame": [o1, o2], "arm": [o1, p, tip], "barrel": [o2, barrel_end], "rod": [p]}
    pins = [("frame:0", "arm:0"), ("frame:1", "barrel:0")]
    sliders = (Slider(Joint("arm", 1), "barrel", (0, 1), "rod"),)
    return LinkageGraph("loader", links, "frame", _pins(pins), sliders, Input(slider=0))


def slotted_arm(crank_deg: float = 40.0) -> LinkageGraph:
    """A crank-rocker (crank 0.04 m about O2, coupler 0.15, rocker 0.1 about O4 = (0.12, 0)) whose
    coupler is slotted: an ``arm`` pivoted at O6 = (0.05, 0.16) holds a block ``pad`` at its end E
    that slides along the coupler's line (an RRP dyad on a moving, turning guide)."""
    o2, o4, o6 = np.zeros(2), np.array([0.12, 0.0]), np.array([0.05, 0.16])
    t = math.radians(crank_deg)
    a = 0.04 * np.array([math.cos(t), math.sin(t)])
    b = circles(a, 0.15, o4, 0.1, lambda p, q: p if p[1] > q[1] else q)
    u = (b - a) / math.hypot(*(b - a))
    e = a + u * (u @ (o6 - a)) + u * 0.06  # a point of the slot 0.06 m past the foot from O6
    links = {"ground": [o2, o4, o6], "crank": [o2, a], "coupler": [a, b], "rocker": [o4, b], "arm": [o6, e],
             "pad": [e]}
    pins = [("ground:0", "crank:0"), ("crank:1", "coupler:0"), ("coupler:1", "rocker:1"), ("ground:1", "rocker:0"),
            ("ground:2", "arm:0")]
    return LinkageGraph("slotted", links, "ground", _pins(pins), (Slider(Joint("arm", 1), "coupler", (0, 1), "pad"),),
                        Input("crank", 0, 1))
