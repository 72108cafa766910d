"""Numerical stability on hard cases: the beam engine against FEA where beam theory or the
kinematics is pushed, and whether the engine said so.

Cases (four-bars of 6 mm steel plates drawn into a DXF at run time, except the seed):

- near toggle: a non-Grashof four-bar driven ever closer to the input angle where coupler and
  output align (transmission angle -> 0), and past it;
- change point: the seed's four-bar (s + l = p + q) at 170 to 180 degrees, where all four pins align;
- slender: a crank 50 times longer than it is deep;
- stubby: a crank 1.2 times longer than it is deep, all of it within a section depth of a pin;
- hole close to the edge: a crank with a lightening hole 2.5 mm from its edge, compared through the
  hole as well as away from it.

Each checked link is compared with one FEA mesh (validate's default refined by RATIO**k) at every
feasible position. The flags are what the engine reports on its own: infeasible positions and why,
stations within a section depth of a hole (nominal values), no station clear of the pins, the
curved-link note, an FEA that refuses the mesh.
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import ezdxf
import numpy as np

from linkstress.analysis import plan_for, run_analysis
from linkstress.kinematics.linkage_class import feasible_input_ranges
from linkstress.kinematics.motion import angle_motion
from linkstress.scene import Scene, load_scene
from linkstress.validation.compare import compare_link
from linkstress.validation.stations import comparison_stations, default_mesh
from linkstress.validation.fea.errors import FEAError
from linkstress.validation.report import curvature_note
from linkstress.validation.bench.speed_error import RATIO
from linkstress.validation.validate_scene import REACTION_LIMIT, RESULTANT_LIMIT

SEED = Path(__file__).resolve().parents[1] / "cases" / "seed_ansys_fourbar" / "scene.toml"
PLATE = 0.006
"""Plate thickness [m] of the drawn cases."""
EQUILIBRIUM_FLAG = 1e-6
"""A two-sided free-body mismatch above this says the joint forces lost their equilibrium (a
well-conditioned solve leaves ~1e-12)."""


@dataclass(frozen=True)
class HardCaseRow:
    """One checked link at one input angle. Errors [-] like validate's: ``nominal`` over the stations
    a section depth from every hole (None when there is none), ``near_hole`` over the others (the
    engine flags those as nominal), ``resultants`` N, V, M; ``peak_ratio``: FEA peak over the beam's
    largest value; ``transmission_deg``: the smallest transmission angle of the machine's loops;
    ``equilibrium``: the beam's two-sided free-body check (analyze prints it); ``reaction``: the FEA
    support reactions over the applied load (~0 for loads in equilibrium); ``flags``: what the
    engine says about this position (validate's failed checks among them)."""

    link: str
    input_angle_deg: float
    feasible: bool
    reason: str
    transmission_deg: float | None
    nominal: float | None = None
    near_hole: float | None = None
    resultants: float | None = None
    peak_ratio: float | None = None
    equilibrium: float | None = None
    reaction: float | None = None
    flags: tuple[str, ...] = ()

    @property
    def trusted(self) -> bool:
        """Feasible and not flagged: the nominal error here is what the engine vouches for."""
        return self.feasible and not self.flags and self.nominal is not None


@dataclass(frozen=True)
class HardCaseResult:
    name: str
    description: str
    rows: tuple[HardCaseRow, ...]
    flags: tuple[str, ...]


@dataclass(frozen=True)
class HardCase:
    """``scene`` builds the scene in a folder; ``angles`` picks the input angles [deg] from it;
    ``links`` are checked by FEA, with ``extra_stations`` [m] beside validate's comparison stations."""

    name: str
    description: str
    scene: Callable[[Path], Path]
    angles: Callable[[Scene], list[float]]
    links: tuple[str, ...]
    extra_stations: tuple[float, ...] = ()


def run_hard_case(case: HardCase, folder: Path, refinement_level: int) -> HardCaseResult:
    """Analyse ``case`` and compare its links with FEA at every feasible position."""
    scene = load_scene(case.scene(folder))
    angles = np.asarray(case.angles(scene), float)
    speed, acceleration = float(scene.motion.speed[0]), float(scene.motion.acceleration[0])
    scene = replace(scene, motion=angle_motion(angles, speed, acceleration))
    analysis = run_analysis(scene, plan_for(scene))
    feasible = analysis.feasible
    transmission = np.min([np.degrees(loop.transmission_angle) for loop in analysis.kinematics.loops.values()], axis=0)
    chosen = np.flatnonzero(feasible)
    flags = [
        f"input {angles[k]:.6g} deg infeasible: {analysis.reasons[k]}" for k in np.flatnonzero(~feasible)
    ]
    rows = []
    for name in case.links:
        link = scene.links[name].profile
        loads = analysis.forces.link_loads[name]
        stations = np.unique(np.concatenate([comparison_stations(link, loads.frame_joints), case.extra_stations]))
        mesh = default_mesh(link, loads.frame_joints, stations).refined(RATIO**refinement_level)
        comparison = None
        if len(chosen):
            try:
                comparison = compare_link(name, link, loads, chosen, mesh, 1, stations)
            except FEAError as error:
                flags.append(f"{name}: the FEA refuses it: {error}")
        if comparison is not None:
            flags += _link_flags(name, comparison)
        for k, angle in enumerate(angles):
            row = HardCaseRow(name, float(angle), bool(feasible[k]), analysis.reasons[k],
                              float(transmission[k]) if feasible[k] else None)
            if comparison is not None and feasible[k]:
                row = _compared(row, comparison, int(np.searchsorted(chosen, k)))
            rows.append(row)
    return HardCaseResult(case.name, case.description, tuple(rows), tuple(flags))


def _link_flags(name: str, c) -> list[str]:
    flags = []
    near = int((~c.away).sum())
    if near:
        flags.append(f"{name}: {near} of {len(c.away)} compared stations within a section depth of a hole (nominal values)")
    if not c.away.any():
        flags.append(f"{name}: no station is a section depth from every pin")
    bend = curvature_note(c)
    if bend:
        flags.append(f"{name}: {bend.split(':')[0]}")
    return flags


def _compared(row: HardCaseRow, c, p: int) -> HardCaseRow:
    def error(mask) -> float | None:
        if not mask.any():
            return None
        beam, fea = c.beam.von_mises[p, mask], c.fea_von_mises[p, mask]
        return float(np.abs(fea - beam).max() / beam.max()) if beam.max() > 0 else 0.0

    equilibrium, reaction = float(c.beam.forces.mismatch[p]), float(c.fea.reaction_ratio[p])
    resultants = float(c.resultant_error[p])
    flags = []
    if equilibrium > EQUILIBRIUM_FLAG:
        flags.append(f"equilibrium check {equilibrium:.2g} (analyze): the joint forces are ill-conditioned")
    if reaction > REACTION_LIMIT:
        flags.append(f"validate fails: FEA support reactions {reaction:.2g} of the load")
    if resultants > RESULTANT_LIMIT:
        flags.append(f"validate fails: resultants differ by {100 * resultants:.3g} %")
    return replace(
        row, nominal=error(c.away), near_hole=error(~c.away), resultants=resultants,
        peak_ratio=float(c.fea_peak[p] / c.beam_max[p]) if c.beam_max[p] > 0 else None, equilibrium=equilibrium, reaction=reaction, flags=tuple(flags),
    )


# -- the cases ----------------------------------------------------------------------------------

def _stadium(msp, layer: str, y: float, spacing: float, width: float, hole: float, extra_holes=()) -> None:
    """A round-ended link along y = const: pin holes with POINTs at (0, y) and (spacing, y)."""
    r, attrs = width / 2, {"layer": layer}
    msp.add_line((0, y - r), (spacing, y - r), dxfattribs=attrs)
    msp.add_arc((spacing, y), r, -90, 90, dxfattribs=attrs)
    msp.add_line((spacing, y + r), (0, y + r), dxfattribs=attrs)
    msp.add_arc((0, y), r, 90, 270, dxfattribs=attrs)
    for x in (0.0, spacing):
        msp.add_circle((x, y), hole / 2, dxfattribs=attrs)
        msp.add_point((x, y), dxfattribs=attrs)
    for (x, dy), diameter in extra_holes:
        msp.add_circle((x, y + dy), diameter / 2, dxfattribs=attrs)


def four_bar(folder: Path, name: str, links: dict, ground: float, speed: float, couple: float) -> Path:
    """Write ``name``.dxf (metres) and ``name``.toml: a four-bar whose crank, coupler and output are
    stadiums ``links[role] = (spacing, width, hole, extra holes)``, ground ``ground`` [m] long."""
    doc = ezdxf.new("R2013", units=6)
    msp = doc.modelspace()
    for k, (role, (spacing, width, hole, extra)) in enumerate(links.items()):
        doc.layers.add(role)
        _stadium(msp, role, 0.5 * k, spacing, width, hole, extra)
    doc.saveas(folder / f"{name}.dxf")
    parts = ["[materials.steel]\ndensity = 7850.0\nyoungs_modulus = 200e9\npoisson_ratio = 0.3\n"]
    parts += [
        f'[links.{role}]\nsketch = "{name}.dxf"\nlayer = "{role}"\nthickness = {PLATE}\nmaterial = "steel"\n'
        for role in links
    ]
    parts.append(f"[links.ground]\njoints = [[0.0, 0.0], [{ground}, 0.0]]\n")
    parts.append('[mechanisms.main]\ntype = "four-bar"\ncrank = "crank"\ncoupler = "coupler"\noutput = "output"\nground = "ground"\n')
    parts.append(f"[motion]\ninput_angle_deg = 30.0\ninput_speed_rad_s = {speed}\n")
    parts.append(f"[loads.couples]\noutput = {couple}\n")
    path = folder / f"{name}.toml"
    path.write_text("\n".join(parts))
    return path


def _approach_toggle(scene) -> list[float]:
    """Input angles [deg] ever closer to the end of the main loop's feasible range, then past it."""
    linkage = scene.machine.geometry(scene.machine.main)
    end = math.degrees(feasible_input_ranges(linkage)[0][1])
    return [end - d for d in (10.0, 1.0, 0.1, 0.01, 0.001)] + [end + 0.01]


HARD_CASES = (
    HardCase(
        "near toggle",
        "non-Grashof four-bar (crank 140, coupler 120, output 160, ground 220 mm) at 10, 1, 0.1, 0.01 and "
        "0.001 deg before the toggle where coupler and output align, and 0.01 deg past it; 10 rad/s",
        lambda folder: four_bar(folder, "toggle", {
            "crank": (0.14, 0.02, 0.006, ()), "coupler": (0.12, 0.02, 0.006, ()), "output": (0.16, 0.02, 0.006, ()),
        }, 0.22, 10.0, 0.5),
        _approach_toggle,
        ("coupler", "output"),
    ),
    HardCase(
        "change point",
        "the seed's four-bar (crank 1.0, coupler 1.5, output 1.5, ground 2.0 m: s + l = p + q) at 170, 179, "
        "179.9, 179.96 and 180 deg, where all four pins align (within 0.027 deg of it a sample is the change "
        "point: its forces are round-off there)",
        lambda folder: SEED,
        lambda scene: [170.0, 179.0, 179.9, 179.96, 180.0],
        ("coupler", "output"),
    ),
    HardCase(
        "slender link",
        "crank 500 mm between pins, 10 mm deep (50:1), 4 mm pins, in a crank-rocker; 5 rad/s, 2 N m on the output",
        lambda folder: four_bar(folder, "slender", {
            "crank": (0.5, 0.01, 0.004, ()), "coupler": (1.2, 0.03, 0.008, ()), "output": (0.9, 0.03, 0.008, ()),
        }, 1.0, 5.0, 2.0),
        lambda scene: [30.0, 120.0, 210.0, 300.0],
        ("crank",),
    ),
    HardCase(
        "stubby link",
        "crank 60 mm between pins, 50 mm deep (1.2:1), 10 mm pins, in a crank-rocker; 20 rad/s, 2 N m on the output",
        lambda folder: four_bar(folder, "stubby", {
            "crank": (0.06, 0.05, 0.01, ()), "coupler": (0.2, 0.02, 0.006, ()), "output": (0.15, 0.02, 0.006, ()),
        }, 0.2, 20.0, 2.0),
        lambda scene: [30.0, 120.0, 210.0, 300.0],
        ("crank",),
    ),
    HardCase(
        "hole close to the edge",
        "crank 200 mm between 8 mm pins, 30 mm deep, with a 12 mm lightening hole at mid-span 2.5 mm from "
        "its top edge; compared through the hole (x = 91, 100, 109 mm) and away from it; 20 rad/s, 2 N m",
        lambda folder: four_bar(folder, "edge_hole", {
            "crank": (0.2, 0.03, 0.008, (((0.1, 0.0065), 0.012),)), "coupler": (0.5, 0.02, 0.006, ()),
            "output": (0.4, 0.02, 0.006, ()),
        }, 0.45, 20.0, 2.0),
        lambda scene: [30.0, 120.0, 210.0, 300.0],
        ("crank",),
        (0.091, 0.1, 0.109),
    ),
)


def hard_cases(refinement_level: int) -> list[HardCaseResult]:
    """Every case of HARD_CASES, its scenes written to a temporary folder."""
    with tempfile.TemporaryDirectory(prefix="linkstress-bench-") as folder:
        return [run_hard_case(case, Path(folder), refinement_level) for case in HARD_CASES]
