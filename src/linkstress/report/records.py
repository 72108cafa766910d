"""JSON records of an analysis: docs/design.md's ``analyze`` shape, extended, never renamed.

Per position: ``input_angle_deg``, ``feasible``, ``reason``, ``warnings`` (only where the step into
this position passed a loop's toggle or change point: one message each, see
``kinematics.crossings``), ``transmission_angle_deg`` per loop (feasible positions); per link ``angle_deg``,
``omega_rad_s``, ``alpha_rad_s2``, ``acc_G_m_s2`` (where the centre of mass is known),
``curved`` (some member of the link is curved: sectioned square to its centreline,
``linkstress.geometry.members``), ``max_von_mises_pa`` and ``max_at_m`` (ground frame, the largest over the
link's members) with ``max_von_mises_away_from_holes_pa`` (when
some station is at least a section depth from every pin hole), ``equilibrium_mismatch`` and
``pin_holes`` (per pin hole: Kt, the net-section stress of its pin force and the Kt x nominal
estimate, labelled as such, with the width, end distance and end shape the force sees and whether
that is outside the Kt tables) where stresses were computed, ``yield_safety_factor`` (yield strength
over ``max_von_mises_pa``) and
``pin_hole_yield_safety_factor_estimate`` (over the largest pin-hole
estimate) where the material gives ``yield_strength`` (null where the stress is zero), and with
``stations`` the arrays along the link's first member; ``members`` (per member of the link: its
``joints``, the ``beam_theory`` its sections took, "straight" or "curved" (Winkler-Bach), and its
own ``max_von_mises_pa`` and ``max_at_m``); per mechanism ``forces_n`` (Norton names) and
``driving_torque_nm`` (or ``driving_force_n`` for an actuated slider) where forces were computed;
with FEA peaks, per link ``peak_von_mises_pa``, ``peak_at_m`` and ``peak_yield_safety_factor``
(``linkstress.report.peak_records``).
A ``type = "linkage"`` mechanism adds per link ``joints_m`` (its joints in the ground frame, in the
link's joint order) and per mechanism ``pins`` (each pin's ``joints``, ``at_m`` and ``forces_n``: the
force it puts on each joint's link), ``sliders`` (``point``, ``on``, ``stroke_m``,
``normal_force_n``, ``couple_nm``, ``friction_force_n``, ``pin_force_n``) and ``driving_torque_nm``
or ``driving_force_n``; a linkage driven by a slider's stroke gives ``input_stroke_m`` in place of
``input_angle_deg``. After the positions, ``links_record``: the top-level ``links`` table, per
stressed link its ``model`` and ``model_reason`` (``linkstress.model_choice``) and, for a link whose
FEA peaks ran, their summary (``report.peak_records``); then ``summary_record``: the verdict, the
scene's warnings and the joint forces' names.
Infeasible positions carry no link or mechanism data. Angles in degrees in [0, 360); SI units.
The records are made a block of positions at a time (``stream_position_records``), for
``output.write_json_stream`` to write as they come, from columns (``link_value_columns``,
``mechanism_columns``) that ``report.table`` writes as arrays too.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import partial

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.dynamics.pin_holes import SHAPE_NAMES
from linkstress.dynamics.section_stress import StressSummary
from linkstress.report.peak_records import peak_columns, peak_summaries, peak_yield_factors
from linkstress.report.places import force_names
from linkstress.report.verdict import Verdict
from linkstress.safety import link_safety_factors
from linkstress.threads import even_blocks


@dataclass(frozen=True)
class LinkColumns:
    """One link's kinematic values at every position: angle_deg in [0, 360), omega [rad/s],
    alpha [rad/s^2], acc_g (P, 2) [m/s^2] or None when its centre of mass is unknown."""

    angle_deg: NDArray[np.float64]
    omega: NDArray[np.float64]
    alpha: NDArray[np.float64]
    acc_g: NDArray[np.float64] | None


def degrees_360(angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """Angles [rad] in degrees in [0, 360)."""
    value = np.mod(np.rad2deg(angle), 360.0) + 0.0
    return np.where(value >= 360.0, 0.0, value)


def link_columns(result: AnalysisResult) -> dict[str, LinkColumns]:
    """Every link's kinematic columns, in the scene's order."""
    columns = {}
    for name, link in result.scene.links.items():
        motion = result.kinematics.links[name]
        com = link.center_of_mass
        acc_g = None if com is None else motion.point(com)[2]
        columns[name] = LinkColumns(degrees_360(motion.angle), motion.omega, motion.alpha, acc_g)
    return columns


def links_record(result: AnalysisResult) -> dict[str, dict[str, object]]:
    """The top-level ``links`` table: per stressed link (in the analysis's order) its ``model`` and
    ``model_reason``, with the FEA peaks' summary keys where they ran; empty without stresses."""
    summaries = peak_summaries(result) if result.peaks else {}
    return {name: {**result.models[name].record(), **summaries.get(name, {})} for name in result.stresses
            if name in result.models}


@dataclass(frozen=True)
class Nullable:
    """Per-position ``values`` (P,) that are null where ``null`` (P,) is true (a factor where there
    is no stress, an estimate outside the Kt tables): JSON null there, 0 in ``analyze --table``."""

    values: NDArray[np.float64]
    null: NDArray[np.bool_]


@dataclass(frozen=True)
class Coded:
    """A text per position: ``texts[codes[k]]`` at position k, None for JSON null."""

    codes: NDArray[np.integer]
    texts: tuple[str | None, ...]


def link_value_columns(result: AnalysisResult, stations: bool = False) -> dict[str, dict[str, object]]:
    """Per link, its per-position values nested as the JSON's link records nest them: numpy arrays
    (P, ...) (whole when the key is ``SHARED``), functions of a block of positions (giving arrays,
    or lists), ``Nullable`` and ``Coded`` columns, lists of such dicts (members, pin holes), and what
    every position shares (names, flags). ``stations`` adds the arrays along the link's first member."""
    analysis = result.scene.analysis
    link_values: dict[str, dict[str, object]] = {}
    if analysis is None or analysis.kinematics:
        for name, c in link_columns(result).items():
            values = {"angle_deg": c.angle_deg, "omega_rad_s": c.omega, "alpha_rad_s2": c.alpha}
            if c.acc_g is not None:
                values["acc_G_m_s2"] = c.acc_g
            if result.scene.linkage is not None:
                values["joints_m"] = partial(joint_positions, result, name)
            link_values[name] = values
    for name, stress in result.stresses.items():
        values = link_values.setdefault(name, {})
        values["curved"] = result.curved(name)
        values["max_von_mises_pa"] = stress.max_von_mises
        values["max_at_m"] = partial(_ground_rows, result, name, stress.max_at)
        if stress.max_away_from_holes is not None:
            values["max_von_mises_away_from_holes_pa"] = stress.max_away_from_holes
        values["equilibrium_mismatch"] = stress.mismatch
        if stress.pin_holes:
            values["pin_holes"] = [_pin_hole_lists(h) for h in stress.pin_holes]
        if stations:
            values["stations"] = partial(_block_station_lists, stress)
        values["members"] = [
            {"joints": list(m.joints), "beam_theory": m.theory, "max_von_mises_pa": m.max_von_mises,
             "max_at_m": partial(_ground_rows, result, name, m.max_at)}
            for m in stress.members
        ]
    for name in result.peaks:
        values = link_values.setdefault(name, {})
        values.update(peak_columns(result, name))
        factors = peak_yield_factors(result, name)
        if factors is not None:
            values["peak_yield_safety_factor"] = _factor(factors)
    for name, factors in link_safety_factors(result).items():
        link_values[name]["yield_safety_factor"] = _factor(factors.sections)
        if factors.pin_holes is not None:
            link_values[name]["pin_hole_yield_safety_factor_estimate"] = _factor(factors.pin_holes)
    return link_values


def _factor(values: NDArray[np.float64]) -> Nullable:
    """Safety factors, null where infinite (no stress, or no estimate there)."""
    return Nullable(values, ~np.isfinite(values))


def _ground_rows(result: AnalysisResult, name: str, local: NDArray[np.float64], block: slice) -> NDArray[np.float64]:
    """Points ``local`` (P, 2) [m] of link ``name``'s member frame at the positions ``block``, in the
    ground frame (B, 2) [m]."""
    return result.to_ground(name, local[block], np.arange(*block.indices(len(local))))


def summary_record(result: AnalysisResult, verdict: Verdict) -> dict[str, object]:
    """The top-level keys that follow the positions: ``verdict`` (its rows and next step,
    ``report.verdict``), the scene's ``warnings`` (a list, empty when none) and, where joint forces
    were computed, ``force_names``: per mechanism, each force's name by the links it acts between
    ("F32": "coupler on crank at A")."""
    record: dict[str, object] = {"verdict": verdict.record(), "warnings": list(result.scene.warnings)}
    if result.forces is not None:
        record["force_names"] = force_names(result.scene)
    return record


def position_records(result: AnalysisResult, stations: bool = False) -> list[dict]:
    """One JSON-ready dict per position; ``stations`` adds N, V, M and von Mises along each link.
    All of them at once: for a long sweep, ``stream_position_records``."""
    return list(stream_position_records(result, stations))


def stream_position_records(result: AnalysisResult, stations: bool = False) -> Iterator[dict]:
    """``position_records``, made one block of positions at a time (``record_blocks``): columns stay
    numpy arrays until their block is turned into lists, and the arrays along the links are
    recomputed per block (``StressSummary.at``), so that memory does not grow with the sweep."""
    link_values = link_value_columns(result, stations)
    mechanism_values = mechanism_columns(result)
    transmission = {name: np.degrees(loop.transmission_angle) for name, loop in result.kinematics.loops.items()}
    for block in record_blocks(result):
        links = {name: _rows(values, block) for name, values in link_values.items()}
        mechanisms = {name: _rows(values, block) for name, values in mechanism_values.items()}
        angles_of = {name: angles[block].tolist() for name, angles in transmission.items()}
        feasible = result.feasible[block].tolist()
        reasons = result.reasons[block]
        warnings = result.kinematics.warnings[block]
        input_key = "input_stroke_m" if result.scene.motion.is_stroke else "input_angle_deg"
        for k, angle in enumerate(result.scene.motion.angle_deg[block].tolist()):
            record = {input_key: angle, "feasible": feasible[k], "reason": reasons[k]}
            if warnings[k]:
                record["warnings"] = list(warnings[k])
            record["links"] = {}
            if feasible[k]:
                record["links"] = {name: _at(values, k) for name, values in links.items()}
                record["transmission_angle_deg"] = {name: angles[k] for name, angles in angles_of.items()}
            if result.forces is not None:
                record["mechanisms"] = {name: _at(values, k) for name, values in mechanisms.items()} if feasible[k] else {}
            yield record


RECORD_BLOCK = 2048
"""Positions whose records are made together where no stress sweep sets the blocks: a block's lists
take about 30 MB with stations, a few MB without."""


def record_blocks(result: AnalysisResult) -> list[slice]:
    """The blocks records are made in: those the section stresses were evaluated in (so that the
    arrays along the links recomputed per block are exactly those the reductions came from), else
    blocks of at most ``RECORD_BLOCK`` positions."""
    for stress in result.stresses.values():
        return list(stress.blocks)
    count = len(result.scene.motion.angle_deg)
    return even_blocks(count, -(-count // RECORD_BLOCK))


def _block_station_lists(stress: StressSummary, block: slice) -> dict[str, object]:
    return _station_lists(stress.at(block))


def _station_lists(stress) -> dict[str, object]:
    """Arrays along the link's first member: where the stations are (``x_m`` and ``s_m``, the arc
    length from its joint i along its axis; ``at_member_m``, the axis point, and ``normal_member``,
    the unit normal the fibres' ``fibre_y_m`` runs along, in the link's member frame) and their
    flags, shared; the rest one list per position."""
    return {
        "x_m": stress.x.tolist(),
        "s_m": stress.x.tolist(),
        "at_member_m": stress.cuts.origin.tolist(),
        "normal_member": stress.cuts.normal.tolist(),
        "near_hole": stress.near_hole.tolist(),
        "normal_n": stress.forces.normal.tolist(),
        "shear_n": stress.forces.shear.tolist(),
        "moment_nm": stress.forces.moment.tolist(),
        "von_mises_pa": stress.von_mises.tolist(),
        "fibre_y_m": stress.fibre_y.tolist(),
    }


def _pin_hole_lists(hole) -> dict[str, object]:
    """One pin hole's record: what all positions share, then per position lists (Kt and the
    estimate null where the geometry the pin force sees is outside the Kt tables)."""
    return {
        "joint": hole.joint, "hole_diameter_m": hole.diameter, "depth_m": hole.depth, "kt": hole.kt,
        "nominal_pa": hole.nominal,
        "estimate_pa": Nullable(hole.estimate, hole.outside),
        "basis": hole.source,
        "kt_at_position": Nullable(hole.kts, hole.outside),
        "kt_outside_table": hole.outside,
        "kt_outside_reason": Coded(hole.reason_code, hole.reason_texts),
        "width_m": hole.width,
        "end_distance_m": hole.end_distance,
        "end_shape": Coded(hole.shape_code, SHAPE_NAMES),
    }


def mechanism_columns(result: AnalysisResult) -> dict[str, dict[str, object]]:
    """Per mechanism, its per-position arrays as the JSON nests them: ``forces_n`` (name -> (P, 2)
    [N], ground frame), ``driving_torque_nm`` (P,) with the ``torque``'s name, ``driving_force_n``
    (P,), and a linkage's ``pins`` and ``sliders``; {} without joint forces."""
    if result.forces is None:
        return {}
    out = {}
    for name, mech in result.forces.mechanisms.items():
        values: dict[str, object] = {"forces_n": dict(mech.forces)}
        if mech.driving_torque is not None:
            values["driving_torque_nm"] = mech.driving_torque
            values["torque"] = mech.torque_name
        if mech.driving_force is not None:
            values["driving_force_n"] = mech.driving_force
        if mech.linkage is not None:
            values.update(_linkage_lists(mech.linkage))
        out[name] = values
    return out


def _linkage_lists(detail) -> dict[str, object]:
    """A linkage's pins and sliders, per position (``dynamics.linkage_forces.LinkageForces``)."""
    pins = [
        {"joints": list(joints), "at_m": at, "forces_n": dict(forces)}
        for joints, at, forces in zip(detail.pins, detail.positions, detail.forces)
    ]
    sliders = [
        {"point": s.point, "on": s.on, "stroke_m": s.stroke, "normal_force_n": s.normal, "couple_nm": s.couple,
         "friction_force_n": s.friction, "pin_force_n": s.pin_force}
        for s in detail.sliders
    ]
    return {"pins": pins, "sliders": sliders}


def joint_positions(result: AnalysisResult, name: str, block: slice) -> NDArray[np.float64]:
    """Link ``name``'s joints in the ground frame, per position of ``block``: (B, J, 2) [m]."""
    local = result.scene.linkage.local[name]
    motion = result.kinematics.links[name]
    angle, origin = motion.angle[block], motion.origin[block]
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    x = origin[:, 0:1] + c * local[:, 0] - s * local[:, 1]
    y = origin[:, 1:2] + s * local[:, 0] + c * local[:, 1]
    return np.stack([x, y], axis=-1)


def _rows(values: dict, block: slice) -> dict:
    """The entries of the positions ``block`` as lists: per-position arrays and lists sliced (a
    ``Nullable``'s null rows None, a ``Coded`` column's texts), blocks made (functions of the
    block), dicts and lists of dicts recursed, and what all positions share kept whole."""
    out = {}
    for key, column in values.items():
        if isinstance(column, dict):
            out[key] = _rows(column, block)
        elif isinstance(column, Nullable):
            out[key] = np.where(column.null[block], None, column.values[block].astype(object)).tolist()
        elif isinstance(column, Coded):
            out[key] = np.array(column.texts, dtype=object)[column.codes[block]].tolist()
        elif callable(column):
            made = column(block)
            out[key] = made.tolist() if isinstance(made, np.ndarray) else made
        elif isinstance(column, np.ndarray):
            out[key] = column.tolist() if key in SHARED else column[block].tolist()
        elif isinstance(column, list) and column and isinstance(column[0], dict):
            out[key] = [_rows(item, block) for item in column]
        elif isinstance(column, list) and column and key not in SHARED:
            out[key] = column[block]
        else:
            out[key] = column
    return out


def _at(values: dict, k: int) -> dict:
    """The entries of position ``k``: per-position lists are indexed, dicts recursed, and what all
    positions share (names, station abscissae) kept whole."""
    out = {}
    for key, column in values.items():
        if isinstance(column, dict):
            out[key] = _at(column, k)
        elif isinstance(column, list) and column and isinstance(column[0], dict):
            out[key] = [_at(item, k) for item in column]
        elif isinstance(column, list) and column and key not in SHARED:
            out[key] = column[k]
        else:
            out[key] = column
    return out


SHARED = (
    "x_m", "s_m", "at_member_m", "normal_member", "near_hole", "joint", "hole_diameter_m", "depth_m", "kt", "basis",
    "joints",
)
