"""What kind of linkage a loop is, and where it can go: Grashof class, Barker type, toggles, limits.

Four-bar lengths in Norton's numbering (Design of Machinery, sec. 2.12-2.15): L1 = ground d,
L2 = crank a, L3 = coupler b, L4 = output c; S, L the shortest and longest, P, Q the other two.
Input angles [rad] are crank angles counter-clockwise from the ground frame's +x; an interval
(start, stop) runs counter-clockwise from start to stop (stop > start, stop - start <= 2 pi).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkstress.kinematics.crossings import CHANGE_POINT_TOLERANCE
from linkstress.kinematics.fourbar import FourBar
from linkstress.kinematics.fourbar import branch_points as fourbar_branch_points
from linkstress.kinematics.slider_crank import SliderCrank
from linkstress.kinematics.slider_crank import branch_points as slider_branch_points

# Norton, Design of Machinery, table 2-4 (Barker's classification), by type number.
BARKER_TYPES = {
    1: ("I-1", "GCCC", "Grashof crank-crank-crank (double crank)"),
    2: ("I-2", "GCRR", "Grashof crank-rocker-rocker (crank-rocker)"),
    3: ("I-3", "GRCR", "Grashof rocker-crank-rocker (double rocker, coupler turns fully)"),
    4: ("I-4", "GRRC", "Grashof rocker-rocker-crank (rocker-crank)"),
    5: ("II-1", "RRR1", "non-Grashof triple rocker, ground longest"),
    6: ("II-2", "RRR2", "non-Grashof triple rocker, crank longest"),
    7: ("II-3", "RRR3", "non-Grashof triple rocker, coupler longest"),
    8: ("II-4", "RRR4", "non-Grashof triple rocker, output longest"),
    9: ("III-1", "SCCC", "change-point crank-crank-crank"),
    10: ("III-2", "SCRR", "change-point crank-rocker-rocker"),
    11: ("III-3", "SRCR", "change-point rocker-crank-rocker"),
    12: ("III-4", "SRRC", "change-point rocker-rocker-crank"),
    13: ("III-5", "S2X", "double change point (parallelogram, antiparallelogram or kite)"),
    14: ("III-6", "S3X", "triple change point (all links equal)"),
}


@dataclass(frozen=True)
class LinkageClass:
    """Grashof condition ("grashof", "non-grashof", "change-point") and Barker's type of a four-bar."""

    grashof: str
    barker_type: int
    barker_class: str
    code: str
    description: str


@dataclass(frozen=True)
class LimitPosition:
    """An input angle [rad] where the output stops and reverses: the output angle [rad] (four-bar)
    or slider position [m] (slider-crank) there, and whether crank and coupler are "extended"
    (in line, pointing the same way) or "folded" (overlapping)."""

    input_angle: float
    output: float
    kind: str


def classify(linkage: FourBar) -> LinkageClass:
    """Grashof condition and Barker type (Norton eqs. 2.8, table 2-4) of ``linkage``."""
    lengths = [linkage.ground, linkage.crank, linkage.coupler, linkage.output]  # L1..L4
    s, p, q, l = sorted(lengths)
    tol = CHANGE_POINT_TOLERANCE * sum(lengths)
    excess = (s + l) - (p + q)
    shortest = 1 + int(np.argmin(lengths))
    if excess < -tol:
        grashof, barker = "grashof", shortest
    elif excess > tol:
        grashof, barker = "non-grashof", 4 + 1 + int(np.argmax(lengths))
    elif l - s <= tol:
        grashof, barker = "change-point", 14
    elif p - s <= tol or l - q <= tol:
        grashof, barker = "change-point", 13
    else:
        grashof, barker = "change-point", 8 + shortest
    barker_class, code, description = BARKER_TYPES[barker]
    return LinkageClass(grashof, barker, barker_class, code, description)


def toggle_angles(linkage: FourBar) -> tuple[float, ...]:
    """Input angles [rad] where coupler and output are aligned (|A O4| = b + c or |b - c|), sorted
    in [theta1 - pi, theta1 + pi). At these the crank cannot drive the output (transmission angle 0).
    A change point (a + d = b + c or |a - d| = |b - c| to ``CHANGE_POINT_TOLERANCE``) is one of them."""
    return _sorted_around([point.angle for point in fourbar_branch_points(linkage)], linkage.ground_angle)


def feasible_input_ranges(linkage: FourBar) -> tuple[tuple[float, float], ...]:
    """Intervals of input angle [rad] over which the loop assembles; ends are toggles.

    |A O4|^2 = a^2 + d^2 - 2 a d cos(phi), phi = theta2 - theta1, grows with |phi| on [0, pi], so the
    set where |b - c| <= |A O4| <= b + c is |phi| in [phi_lo, phi_hi]: one interval, two mirror
    intervals, or a full turn (a Grashof crank). Empty when the lengths can never assemble.
    """
    a, b, c, d = linkage.lengths
    phi_hi = _angle_at_distance(a, d, b + c, default=math.pi)
    phi_lo = _angle_at_distance(a, d, abs(b - c), default=0.0)
    if abs(d - a) >= b + c or a + d <= abs(b - c):
        return ()
    return _mirror_intervals(phi_lo, phi_hi, linkage.ground_angle)


def output_limits(linkage: FourBar) -> tuple[LimitPosition, ...]:
    """The output's limit positions on the linkage's branch (omega4 = 0: crank and coupler aligned).

    B lies on the circle (O4, c) at distance r = a + b (extended) or |a - b| (folded) from O2.
    Each of the (up to four) candidates is kept when B lies on the linkage's side of A -> O4.
    """
    a, b, c, d = linkage.lengths
    o2, o4 = np.asarray(linkage.o2), np.asarray(linkage.o4)
    back = math.atan2(o2[1] - o4[1], o2[0] - o4[0])  # direction O4 -> O2
    limits = []
    for kind, r in (("extended", a + b), ("folded", abs(a - b))):
        if r == 0:
            continue
        cos_beta = (c * c + d * d - r * r) / (2 * c * d)
        if not -1.0 <= cos_beta <= 1.0:
            continue
        for beta in {math.acos(cos_beta), -math.acos(cos_beta)}:
            theta4 = back + beta
            point_b = o4 + c * np.array([math.cos(theta4), math.sin(theta4)])
            to_b = point_b - o2
            theta2 = math.atan2(to_b[1], to_b[0])
            if kind == "folded" and b > a:
                theta2 += math.pi
            point_a = o2 + a * np.array([math.cos(theta2), math.sin(theta2)])
            side = _cross(o4 - point_a, point_b - point_a)
            if side * linkage.sigma > 0:
                limits.append(LimitPosition(_wrap(theta2), _wrap(theta4), kind))
    return tuple(sorted(limits, key=lambda lim: lim.input_angle))


def slider_toggle_angles(linkage: SliderCrank) -> tuple[float, ...]:
    """Input angles [rad] where the rod is perpendicular to the slider line: e - a sin(phi) = +-b
    (a change point where |e -+ b| = a to ``CHANGE_POINT_TOLERANCE``)."""
    return _sorted_around([point.angle for point in slider_branch_points(linkage)], linkage.slider_angle)


def slider_feasible_input_ranges(linkage: SliderCrank) -> tuple[tuple[float, float], ...]:
    """Intervals of input angle [rad] over which the slider-crank assembles: |e - a sin(phi)| <= b."""
    a, b, e = linkage.crank, linkage.rod, linkage.offset
    lo, hi = (e - b) / a, (e + b) / a
    if lo >= 1.0 or hi <= -1.0:
        return ()
    t1 = linkage.slider_angle
    if lo <= -1.0 and hi >= 1.0:
        return ((t1 - math.pi, t1 + math.pi),)
    if lo <= -1.0:
        return ((t1 + math.pi - math.asin(hi), t1 + 2 * math.pi + math.asin(hi)),)
    if hi >= 1.0:
        return ((t1 + math.asin(lo), t1 + math.pi - math.asin(lo)),)
    return (
        (t1 + math.asin(lo), t1 + math.asin(hi)),
        (t1 + math.pi - math.asin(hi), t1 + math.pi - math.asin(lo)),
    )


def slider_limits(linkage: SliderCrank) -> tuple[LimitPosition, ...]:
    """The slider's dead centres on the linkage's branch (crank and rod aligned): input angle [rad]
    and slider position x [m] along the line. |B - O2| = r = a + b or |a - b| and B on the line
    give x = +-sqrt(r^2 - e^2); a candidate is kept when the rod points the branch's way along u."""
    a, b, e = linkage.crank, linkage.rod, linkage.offset
    u, n = np.array(linkage.direction), np.array([-linkage.direction[1], linkage.direction[0]])
    limits = []
    for kind, r in (("extended", a + b), ("folded", abs(a - b))):
        if r == 0 or r * r < e * e:
            continue
        reach = math.sqrt(r * r - e * e)
        for x in {reach, -reach}:
            to_b = e * n + x * u
            theta2 = math.atan2(to_b[1], to_b[0])
            if kind == "folded" and b > a:
                theta2 += math.pi
            rod = to_b - a * np.array([math.cos(theta2), math.sin(theta2)])
            if float(rod @ u) * linkage.sigma > 0:
                limits.append(LimitPosition(_wrap(theta2), x, kind))
    return tuple(sorted(limits, key=lambda lim: lim.input_angle))


def stroke(linkage: SliderCrank) -> float:
    """Distance [m] between the slider's two dead centres on the linkage's branch (0 if fewer than two)."""
    x = [lim.output for lim in slider_limits(linkage)]
    return max(x) - min(x) if len(x) >= 2 else 0.0


def _angle_at_distance(a: float, d: float, target: float, default: float) -> float:
    """|phi| in [0, pi] where |A O4| = target; ``default`` when the distance is never reached."""
    cos_phi = (a * a + d * d - target * target) / (2 * a * d)
    if not -1.0 < cos_phi < 1.0:
        return default
    return math.acos(cos_phi)


def _mirror_intervals(phi_lo: float, phi_hi: float, theta1: float) -> tuple[tuple[float, float], ...]:
    if phi_lo == 0.0 and phi_hi == math.pi:
        return ((theta1 - math.pi, theta1 + math.pi),)
    if phi_lo == 0.0:
        return ((theta1 - phi_hi, theta1 + phi_hi),)
    if phi_hi == math.pi:
        return ((theta1 + phi_lo, theta1 + 2 * math.pi - phi_lo),)
    return ((theta1 - phi_hi, theta1 - phi_lo), (theta1 + phi_lo, theta1 + phi_hi))


def _sorted_around(angles: list[float], theta1: float) -> tuple[float, ...]:
    """Angles relative to ground angle ``theta1`` moved into [theta1 - pi, theta1 + pi), sorted."""
    relative = sorted({(x - theta1 + math.pi) % (2 * math.pi) - math.pi for x in angles})
    return tuple(theta1 + x for x in relative)


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def _cross(u: np.ndarray, v: np.ndarray) -> float:
    return float(u[0] * v[1] - u[1] * v[0])
