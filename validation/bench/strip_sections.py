"""The original program's (KSAM) section stresses on midpoint strips: the baseline ``bench`` measures.

A faithful port of what the KSAM thesis describes (section 6.3.3, and annex 12.3 ``Link.centroid``),
deliberately not vectorised, like ``strip_sum``: its cost is part of what is measured.

- Bounds: U(x) and L(x) are piecewise functions evaluated one abscissa at a time (the original's
  concatenated ``Function`` objects); here a bisection over the link's exact bounding functions.
- Mass properties: ``strip_sum_properties`` (strips of width dx for area and centroid, a dx-by-dx
  grid for the polar moment); holes are invisible to them.
- Sections: one per strip, at its centre x, solid from L(x) to U(x): A = t (U - L),
  I = t (U - L)^3 / 12, neutral axis at (U + L) / 2, extreme fibres (U - L) / 2 from it.
- Stresses: the joint forces and couples on the part left of the station, translated to the
  station's neutral-axis point (no distributed d'Alembert load along the link), then
  sigma = |N| / A + |M| c / I at the extreme fibre, the average shear tau = V / A ("para reducir el
  tiempo de computo") and von Mises sqrt(sigma^2 + 3 tau^2) (thesis eq. 7).
"""

from __future__ import annotations

import math
import time
from bisect import bisect_right
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.machine_forces import machine_forces
from linkstress.kinematics import MachineMotion
from linkstress.loads import LinkLoadCase
from linkstress.geometry.profile import LinkProfile
from linkstress.scene import Scene
from linkstress.scene.model import MassData
from linkstress.validation.bench.strip_sum import StripSumProperties, strip_sum_properties


def piecewise_bounds(link: LinkProfile, frame_joints: tuple[int, int]) -> tuple[Callable[[float], float], Callable[[float], float]]:
    """U(x) and L(x) [m] of ``link`` in the member frame of ``frame_joints``, as scalar functions
    that find their piece by bisection, as the original's piecewise functions did."""
    bounds = link.bounds(*frame_joints)
    breaks = bounds.breaks.tolist()
    last = len(breaks) - 2

    def piece(values_start, values_end) -> Callable[[float], float]:
        start, end = values_start.tolist(), values_end.tolist()

        def evaluate(x: float) -> float:
            k = min(max(bisect_right(breaks, x) - 1, 0), last)
            x0, x1 = breaks[k], breaks[k + 1]
            return start[k] + (end[k] - start[k]) * (x - x0) / (x1 - x0)

        return evaluate

    return piece(bounds.upper_start, bounds.upper_end), piece(bounds.lower_start, bounds.lower_end)


def strip_mass_properties(link: LinkProfile, frame_joints: tuple[int, int], dx: float) -> StripSumProperties:
    """Area [m^2], centroid [m, member frame] and polar moment [m^4] per unit thickness by the strip sums."""
    upper, lower = piecewise_bounds(link, frame_joints)
    start, end = link.x_extent(*frame_joints)
    return strip_sum_properties(upper, lower, start, end, dx)


@dataclass(frozen=True)
class StripSections:
    """One solid section per strip of width ``dx`` [m]: centre ``x`` (S,) [m], neutral axis ``y_na``
    [m], ``area`` [m^2], second moment ``inertia`` [m^4], extreme fibre distance ``half_depth`` [m]."""

    dx: float
    x: NDArray[np.float64]
    y_na: NDArray[np.float64]
    area: NDArray[np.float64]
    inertia: NDArray[np.float64]
    half_depth: NDArray[np.float64]


def strip_sections(link: LinkProfile, frame_joints: tuple[int, int], dx: float) -> StripSections:
    """The original's section lists, strip by strip (annex 12.3: ``areas``, ``inertias``, ``heights``)."""
    upper, lower = piecewise_bounds(link, frame_joints)
    start, end = link.x_extent(*frame_joints)
    t = link.thickness
    xs, centres, areas, inertias, heights = [], [], [], [], []
    position = start + dx / 2
    while position < end:
        high, low = upper(position), lower(position)
        depth = high - low
        xs.append(position)
        centres.append(depth / 2 + low)
        areas.append(t * depth)
        inertias.append(t / 12 * depth * depth * depth)
        heights.append(depth / 2)
        position += dx
    return StripSections(dx, *(np.array(v) for v in (xs, centres, areas, inertias, heights)))


@dataclass(frozen=True)
class StripStresses:
    """The original's N [N], V [N], M [N m] and von Mises [Pa], each (P, S), at ``sections.x``."""

    sections: StripSections
    normal: NDArray[np.float64]
    shear: NDArray[np.float64]
    moment: NDArray[np.float64]
    von_mises: NDArray[np.float64]


def strip_stresses(link: LinkProfile, loads: LinkLoadCase, sections: StripSections) -> StripStresses:
    """Stresses at every strip and position from the loads applied at points left of the station.

    Sign convention as ``internal_forces``: (N, V) = -F_L and M = M_L about the station's
    neutral-axis point, F_L and M_L the forces and couples on the part left of the cut.
    """
    joints = link.frame(*loads.frame_joints).to_local(link.joints).tolist()
    points = [(np.asarray(pf.at, float).tolist(), pf.force) for pf in loads.point_forces]
    n_pos, n_sta = loads.n_positions, len(sections.x)
    normal, shear, moment, von_mises = (np.zeros((n_pos, n_sta)) for _ in range(4))
    for p in range(n_pos):
        applied = [(xy, loads.pin_forces[p, j].tolist(), float(loads.joint_couples[p, j])) for j, xy in enumerate(joints)]
        applied += [(xy, force[p].tolist(), 0.0) for xy, force in points]
        for s in range(n_sta):
            x, y = float(sections.x[s]), float(sections.y_na[s])
            fx = fy = m = 0.0
            for (px, py), (gx, gy), couple in applied:
                if px < x:
                    fx += gx
                    fy += gy
                    m += (px - x) * gy - (py - y) * gx + couple
            normal[p, s], shear[p, s], moment[p, s] = -fx, -fy, m
            area, inertia, c = float(sections.area[s]), float(sections.inertia[s]), float(sections.half_depth[s])
            if area > 0:  # a strip at a pointed end can have no depth
                sigma = abs(fx) / area + abs(m) * c / inertia
                tau = abs(fy) / area
                von_mises[p, s] = math.sqrt(sigma * sigma + 3 * tau * tau)
    return StripStresses(sections, normal, shear, moment, von_mises)


@dataclass(frozen=True)
class StripBaseline:
    """The original program's answer at strip width ``dx`` [m].

    ``seconds`` [s]: strip-sum mass properties of every moving link with a profile, then strip
    sections and stresses of the compared links (the joint-force solve between them, the same for
    every method, is not counted). ``mass_errors[name]``: relative area error, centroid offset over
    the link's length and relative polar moment error against the exact (Green) values.
    """

    dx: float
    seconds: float
    mass_errors: dict[str, tuple[float, float, float]]
    stresses: dict[str, StripStresses]


def strip_baseline(scene: Scene, kinematics: MachineMotion, names: tuple[str, ...], positions: NDArray[np.intp], dx: float) -> StripBaseline:
    """Mass properties by strip sums, the joint forces they give, and the original's section
    stresses of links ``names`` at sweep ``positions`` (indices)."""
    start = time.perf_counter()
    strips = {
        name: strip_mass_properties(link.profile, link.frame_joints, dx)
        for name, link in scene.links.items()
        if name in scene.moving_links and link.profile is not None and link.material is not None
    }
    mass_seconds = time.perf_counter() - start
    links = dict(scene.links)
    errors = {}
    for name, props in strips.items():
        link = links[name]
        rho_t = link.profile.density * link.profile.thickness
        links[name] = replace(link, explicit_mass=MassData(rho_t * props.area, rho_t * props.polar, np.array(props.centroid)))
        exact = link.profile
        centroid = exact.frame(*link.frame_joints).to_local(exact.centroid)
        length = float(np.subtract(*exact.x_extent(*link.frame_joints)[::-1]))
        errors[name] = (
            abs(props.area - exact.area) / exact.area,
            float(np.hypot(*(np.array(props.centroid) - centroid))) / length,
            abs(props.polar - exact.polar_moment_area) / exact.polar_moment_area,
        )
    forces = machine_forces(replace(scene, links=links), kinematics)
    start = time.perf_counter()
    stresses = {}
    for name in names:
        link = scene.links[name]
        sections = strip_sections(link.profile, link.frame_joints, dx)
        stresses[name] = strip_stresses(link.profile, forces.link_loads[name].at(positions), sections)
    return StripBaseline(dx, mass_seconds + time.perf_counter() - start, errors, stresses)
