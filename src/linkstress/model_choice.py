"""Which stress model answers each stressed link within the accuracy asked: model only what a scene needs.

From what the beam run already has (no FEA to decide), per link:

- "beam": the link's governing stress is a section stress of beam theory, and every loaded pin hole
  is inside the Kt tables at every position, its estimate raised by the tables' error against FEA
  (``KT_ERROR_BY_TILT``, at the force's tilt to the shank) still below the beam's maximum;
- "beam+Kt": every loaded pin hole is inside the tables and the largest estimate so raised is
  within ``accuracy`` of the governing stress (the larger of the beam's maximum and the largest
  estimate): a pin-hole estimate may govern, and the tables answer it within the accuracy;
- "fea-peaks": something beam theory and the tables cannot answer may govern: a pin hole outside
  the tables at some position (an end neither round nor square, a pin pushing along the shank, a
  force more than 10 deg off the shank, a couple carried through the pin), tables not accurate
  enough at the force's tilt, a junction of members, a bend sharper than the curved-beam range, a
  curve so tight its inside nears its centre of curvature, a point force on the material, a hole at
  no joint (a lightening hole or a slot: beam sections through it are net, its edge's stress
  concentration is not), a member
  with no section a depth clear of its pins, or one whose sections change depth faster than beam
  theory follows (``TAPER_LIMIT``: a fillet, a tapering plate such as the Jansen leg's shin, 12 %
  off the nominal stress there).

A link a slider's block slides along (a guide, the slotted lever of a quick-return) is on
"fea-peaks": where the block runs in a closed slot of the link, the FEA bears it on the slot's
walls, solving each position (``validation.direct_peaks``); where its contact is not inside a
closed slot (a cylinder's barrel drawn as a plate, a fork open to the outline), the FEA cannot take
it, the reason says so and its verdict stays on its beam sections, trusted "beam only".

Every choice carries its reason in words. ``analyze`` runs the FEA peaks (superposed unit loads,
``linkstress.validation.peaks_scene``) for the links on "fea-peaks" only; ``--beam-only`` runs none
and ``--peaks`` runs them on every stressed link. The choice is tested against FEA on every shipped
case (``tests/test_model_choice_cases.py``): a link left on "beam" or "beam+Kt" never has an FEA
peak more than the accuracy above the governing stress its model reported.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from linkstress.dynamics.pin_holes import OPEN, PinHoleEstimate
from linkstress.loads import contacts_in_slots

if TYPE_CHECKING:
    from linkstress.analysis import AnalysisResult
    from linkstress.dynamics.section_stress import MemberSummary

BEAM, BEAM_KT, FEA_PEAKS = "beam", "beam+Kt", "fea-peaks"
MODELS = (BEAM, BEAM_KT, FEA_PEAKS)
NO_FEA = "; no FEA: "
"""What a model reason adds, with why, when its link needs FEA the run cannot do (no elastic
constants, a mesh too large)."""
GUIDE_FEA = ("a slider's block slides in its slot, bearing on the slot's walls where the block is (the FEA solves "
             "each position)")
"""Why a link whose slot a slider's block runs in is on the FEA peaks."""
GUIDE_NO_FEA = ("the block's contact is not inside a closed slot of the link at every position (it runs in the "
                "material, or in a slot open to the outline, or leaves its slot), and the FEA bears a block only on "
                "the walls of a closed slot; the beam sections take the contact where it is")
"""Why a link a slider's block slides along outside a slot (a cylinder's barrel drawn as a plate) has no FEA peaks."""
DEFAULT_ACCURACY = 0.05
"""The governing stress within 5 % unless the scene ([analysis] accuracy) or --accuracy says otherwise."""
ACCURACY_RANGE = (0.001, 0.5)
"""Accuracies one may ask for: 0.1 % (tighter than the FEA's own 5 % convergence limit still picks
FEA everywhere it can) to 50 %."""
KT_ERROR_BY_TILT = ((0.0, 0.021), (2.5, 0.021), (5.0, 0.070), (7.5, 0.167), (10.0, 0.262))
"""(tilt [deg], error [-]): how far the converged FEA peak at a pin hole may lie above the estimate
Kt x nominal inside the tables, per angle of the pin force to the shank's axis, linear between
(``python -m linkstress.validation.bench.kt_accuracy`` measures it: lugs between the tables' points,
square and round ends and bosses, d/H 0.15-0.7). Along the axis the tables are within 2.1 % (the
small holes, d/H 0.15, on the bearing asymptote); off it the lug bends, most where thin ligaments
beside a large hole carry it: a round end of d/H 0.65 on a 0.7 H shank is 6.9 %, 16.7 % and 26.2 %
above its estimate at 5, 7.5 and 10 deg, while most lugs stay within 5 % at 10 deg."""
TAPER_LIMIT = 0.1
"""Largest slope of a section edge against the member's axis (between its joints, away from holes
and junctions) that beam theory is taken to follow: 1 in 10. The shipped bars are straight-sided
(slopes under 1e-14) or gently curved (0.002), the Jansen crank's boss flanks reach 0.10, and the
Jansen shin, a triangular plate whose nominal stress is 12 % off the FEA's, 0.66."""


def accuracy_problem(accuracy: float) -> str | None:
    """Why ``accuracy`` [-] is not one to ask for, None when it is."""
    low, high = ACCURACY_RANGE
    if not low <= accuracy <= high:
        return (f"must be a fraction from {low:g} to {high:g} (0.05: the governing stress within 5 %), "
                f"got {accuracy!r}")
    return None


@dataclass(frozen=True)
class ModelChoice:
    """One link's stress ``model`` (``MODELS``) and the ``reason`` for it, in words; ``kt_bound``
    [Pa]: the largest pin-hole estimate raised by the tables' error at its tilt (0 without loaded
    pin holes inside the tables), ``beam_max`` [Pa] the beam's largest section stress over the
    feasible positions."""

    model: str
    reason: str
    kt_bound: float = 0.0
    beam_max: float = 0.0

    def record(self) -> dict[str, str]:
        """The JSON's ``model`` and ``model_reason``."""
        return {"model": self.model, "model_reason": self.reason}


def kt_error(tilt_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    """[-] per tilt [deg] (its size; beyond 10 deg the tables do not hold and inf is returned):
    ``KT_ERROR_BY_TILT`` interpolated linearly."""
    tilts, errors = np.array(KT_ERROR_BY_TILT).T
    tilt = np.abs(np.asarray(tilt_deg, float))
    return np.where(tilt <= tilts[-1], np.interp(tilt, tilts, errors), np.inf)


def choose_models(result: "AnalysisResult", accuracy: float) -> dict[str, ModelChoice]:
    """The model of every stressed link of ``result`` (in its order) for the governing stress within
    ``accuracy`` [-]; links with no feasible position stay on the beam (nothing to compute)."""
    from linkstress.report.places import joint_names

    names = joint_names(result.scene)
    ok = result.feasible
    choices = {}
    for name, stress in result.stresses.items():
        if not ok.any():
            choices[name] = ModelChoice(BEAM, "no feasible position")
            continue
        beam_max = float(stress.max_von_mises[ok].max())
        labels = [j.label for j in names[name]]
        raisers = [
            *_point_forces(result, name),
            *_free_holes(result, name),
            *_holes_outside(stress.pin_holes, ok, labels),
            *(words for m in stress.members for words in _member_raisers(m, labels)),
        ]
        bound, tilt = _kt_bound(stress.pin_holes, ok)
        if name in result.plan.guides:
            loads = result.forces.link_loads[name]
            outline = result.scene.links[name].profile.local_outline(*loads.frame_joints)
            in_slot = contacts_in_slots(outline, loads.at(np.flatnonzero(ok)))
            raisers.append(GUIDE_FEA if in_slot else "a slider's block slides along it")
            choices[name] = ModelChoice(FEA_PEAKS, "; ".join(raisers) + ("" if in_slot else NO_FEA + GUIDE_NO_FEA),
                                        bound, beam_max)
            continue
        if raisers:
            choices[name] = ModelChoice(FEA_PEAKS, "; ".join(raisers), bound, beam_max)
            continue
        choices[name] = _from_bounds(stress.pin_holes, ok, labels, beam_max, bound, tilt, accuracy)
    return choices


def _from_bounds(holes: tuple[PinHoleEstimate, ...], ok: NDArray[np.bool_], labels: list[str], beam_max: float,
                 bound: float, tilt: float, accuracy: float) -> ModelChoice:
    """The choice of a link whose every loaded pin hole is inside the tables and that has no other
    stress raiser, from the beam's maximum and the tables' bound."""
    loaded = [h for h in holes if (ok & (h.nominal > 0)).any()]
    if not loaded:
        return ModelChoice(BEAM, "beam sections; no pin hole carries a load", bound, beam_max)
    estimate = max(h.largest(ok & (h.nominal > 0)) or 0.0 for h in loaded)
    governing = max(beam_max, estimate)
    error = float(kt_error(np.array([tilt]))[0])
    tables = f"the Kt tables within {100 * error:.2g} % of FEA" + (
        f" at the pin force's {tilt:.2g} deg to the shank" if tilt > 0 else " (pin forces along the shank, or holes far "
        "from the edges)")
    holes = ", ".join(labels[h.joint] for h in loaded)
    if bound <= beam_max:
        return ModelChoice(BEAM, f"beam sections govern; pin holes {holes} inside the Kt tables, below them even "
                                 f"with {tables}", bound, beam_max)
    if bound <= (1 + accuracy) * governing:
        return ModelChoice(BEAM_KT, f"pin holes {holes} inside the Kt tables, {tables}: within the accuracy "
                                    f"({100 * accuracy:g} %)", bound, beam_max)
    return ModelChoice(FEA_PEAKS, f"pin holes {holes} inside the Kt tables but {tables}, more than the accuracy "
                                  f"({100 * accuracy:g} %) asked", bound, beam_max)


def _kt_bound(holes: tuple[PinHoleEstimate, ...], ok: NDArray[np.bool_]) -> tuple[float, float]:
    """[Pa], [deg]: the largest estimate raised by the tables' error at its tilt over the loaded
    positions inside the tables (``ok`` a mask), and the tilt where that bound is; (0, 0) when none."""
    bound, where = 0.0, 0.0
    for hole in holes:
        inside = ok & (hole.nominal > 0) & ~hole.outside
        if not inside.any():
            continue
        # The open plate's Kt is the larger of a pulled and a pushed pin's: the force's direction is no matter.
        # An estimate that does not know its tilt takes the tables' largest, 10 deg.
        tilts = hole.tilt[inside] if hole.tilt is not None else np.full(int(inside.sum()), KT_ERROR_BY_TILT[-1][0])
        tilt = np.where(hole.shape_code[inside] == OPEN, 0.0, tilts)
        raised = hole.estimate[inside] * (1 + kt_error(tilt))
        k = int(np.argmax(raised))
        if raised[k] > bound:
            bound, where = float(raised[k]), float(tilt[k])
    return bound, where


def _holes_outside(holes: tuple[PinHoleEstimate, ...], ok: NDArray[np.bool_], labels: list[str]) -> list[str]:
    """A phrase per loaded pin hole outside the Kt tables at some feasible position, with the reason
    at the first such position."""
    out = []
    for hole in holes:
        loaded = ok & (hole.nominal > 0)
        outside = loaded & hole.outside
        if not outside.any():
            continue
        first = int(np.flatnonzero(outside)[0])
        reason = hole.reasons_in(slice(first, first + 1))[0]
        share = "" if outside.sum() == loaded.sum() else f" at {int(outside.sum())} of {int(loaded.sum())} positions"
        out.append(f"pin hole {labels[hole.joint]} outside the Kt tables{share} ({_short(reason)})")
    return out


def _short(reason: str) -> str:
    """A Kt reason without its advice (what follows a colon), for a one-line model reason."""
    return reason.split(":")[0].split(" (")[0]


def _member_raisers(member: "MemberSummary", labels: list[str]) -> list[str]:
    """Why beam theory may not answer member ``member``: a junction, a sharp bend, a tight curve, no
    section clear of its pins, a taper or fillet steeper than TAPER_LIMIT."""
    cuts = member.sweep.cuts
    i, j = member.joints
    arm = f"arm {labels[i]}-{labels[j]}"
    out = []
    if cuts.junction.any():
        out.append(f"a junction of {arm} with another arm")
    if cuts.bend.any():
        out.append(f"a bend in {arm} sharper than the curved-beam range")
    if cuts.tight.any():
        out.append(f"a curve in {arm} whose inside nears its centre of curvature")
    s = cuts.s
    between = (s >= 0) & (s <= member.member.length) & ~cuts.nominal
    if not between.any():
        out.append(f"{arm} has no section a depth clear of its pins (beam values there are nominal)")
        return out
    slope = np.maximum(np.abs(np.gradient(cuts.table.top, s)), np.abs(np.gradient(cuts.table.bottom, s)))[between]
    if slope.max() > TAPER_LIMIT:
        out.append(f"{arm}'s edges slope 1 in {1 / slope.max():.2g} to its axis (a fillet or a tapering plate; beam "
                   f"theory follows 1 in {1 / TAPER_LIMIT:g})")
    return out


def _point_forces(result: "AnalysisResult", name: str) -> list[str]:
    """A phrase per point force on the material of link ``name`` (one in a hole is a pin's load)."""
    from linkstress.loads import hole_at

    profile = result.scene.links[name].profile
    loads = result.forces.link_loads[name]
    if not loads.point_forces:
        return []
    outline = profile.local_outline(*loads.frame_joints)
    return [
        f"a point force on the material at ({p.at[0]:.4g}, {p.at[1]:.4g}) m (its local stress is beyond beam theory)"
        for p in loads.point_forces if hole_at(outline, np.asarray(p.at, float)) is None
    ]


def _free_holes(result: "AnalysisResult", name: str) -> list[str]:
    """A phrase per hole of link ``name`` that no joint sits in: a lightening hole or a slot, whose
    edge raises the stress beyond the net section's that beam theory gives."""
    profile = result.scene.links[name].profile
    return [
        f"a hole at no joint ({1e3 * length:.3g} x {1e3 * width:.3g} mm, a lightening hole or a slot: the stress its "
        "edge raises is beyond beam theory)"
        for h, (length, width) in enumerate(profile.hole_sizes) if h not in profile.joint_holes
    ]
