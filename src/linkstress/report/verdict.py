"""The verdict: per stressed link, the stress that governs it, where and when, how safe, and how far
to trust it. Reports show it first; text, HTML and JSON are rendered from the same rows.

The governing stress is the largest credible one the run computed for the link:

- the FEA peak (anywhere in the link, pin holes included) when FEA ran and its peak converged; the
  yield and fatigue safety factors come from it;
- else the larger of the beam's section maximum and the largest pin-hole estimate (Kt x nominal,
  where the geometry the pin force sees is inside the Kt tables). An FEA peak that did not converge
  is shown instead when it is larger (as a lower bound, with no safety factor).

A moving link drawn with a profile that gets no section stresses (a slider's block, one without a
material) is listed under the table as not analysed, with why: its
stress is not checked, and the reader is told so rather than left to notice a missing row.

The trust says in a word what the number rests on, and its reason what is not covered: "FEA" (its
change over the last mesh refinement), "NOT converged", "Kt estimate", "beam + Kt" (every loaded pin
hole has an estimate at every position, all below the beam's maximum), "beam" (no pin holes) or "beam
only" (some loaded pin hole has no estimate at some position: beam theory is silent at a hole, so
nothing here covers it). A factor taken over fewer positions than the sweep's feasible ones says so
beside the number ("at 1 of 36 positions"), and a factor that leaves pin holes uncovered is named for
what it covers ("sections only"). Where a stress the run computed is higher than the governing one,
the reason says which and why it does not govern.

``model`` names the stress model the row comes from: "beam" (beam sections alone), "beam+Kt" (with
pin-hole estimates), "fea-peaks" (the FEA peaks ``analyze`` ran for the link), "fea" (``validate``'s
FEA at its compared positions). Under the table, each link's chosen model and why
(``linkstress.model_choice``); a link whose model is "fea-peaks" but whose FEA did not run
(``--beam-only``, or the FEA cannot take it) keeps its beam row, trusted "beam only", and the next
step says what to run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.model_choice import FEA_PEAKS, NO_FEA
from linkstress.report.cells import mpa, significant, text_table
from linkstress.report.peak_records import peak_summaries
from linkstress.report.places import LinkPlaces, joint_names, link_places

FEA_PEAK, ESTIMATE, BEAM = "FEA peak", "pin-hole estimate", "beam nominal"
"""What governs a link: the FEA's largest von Mises, Kt x nominal at a pin hole, or beam theory's."""
HEADERS = ("link", "governing stress", "[MPa]", "where", "at input [deg]", "yield factor", "fatigue factor", "trust")


@dataclass(frozen=True)
class Factor:
    """A safety factor ``value`` [-] (None: no factor) and the ``note`` beside it: what it covers when
    not the whole sweep or link, or why there is none."""

    value: float | None
    note: str = ""

    def text(self) -> str:
        """"10.5", "27.7 (at 1 of 36 positions)", "- (no yield_strength)"."""
        number = "-" if self.value is None else significant(self.value)
        return f"{number} ({self.note})" if self.note else number


@dataclass(frozen=True)
class Stress:
    """One stress the run computed for a link over the sweep: what ``governing`` kind it is, its
    ``value`` [Pa], ``input_angle_deg`` [deg] and ``where`` on the link."""

    governing: str
    value: float
    input_angle_deg: float
    where: str


@dataclass(frozen=True)
class VerdictRow:
    """One stressed link's verdict (see the module's docstring)."""

    link: str
    model: str
    stress: Stress
    yield_factor: Factor
    fatigue_factor: Factor
    trust: str
    reason: str
    uncovered: tuple[str, ...] = ()
    """The pin holes nothing in the row covers at some position (for the next step)."""

    def cells(self) -> tuple[str, ...]:
        """The row as text cells, figures rounded as ``record`` rounds nothing: to 3 significant digits."""
        return (
            self.link, self.stress.governing, mpa(self.stress.value), self.stress.where,
            f"{self.stress.input_angle_deg:.6g}", self.yield_factor.text(), self.fatigue_factor.text(),
            self.trust_text(),
        )

    def trust_text(self) -> str:
        return f"{self.trust}: {self.reason}" if self.reason else self.trust

    def record(self) -> dict[str, object]:
        """The row for the JSON's ``verdict`` (full precision; the text rounds these)."""
        return {
            "link": self.link,
            "model": self.model,
            "governing": self.stress.governing,
            "stress_pa": self.stress.value,
            "where": self.stress.where,
            "input_angle_deg": self.stress.input_angle_deg,
            "yield_safety_factor": self.yield_factor.value,
            "yield_safety_factor_note": self.yield_factor.note or None,
            "fatigue_safety_factor": self.fatigue_factor.value,
            "fatigue_safety_factor_note": self.fatigue_factor.note or None,
            "trust": self.trust,
            "trust_reason": self.reason,
            "uncovered": list(self.uncovered),
        }


@dataclass(frozen=True)
class Verdict:
    """Every stressed link's ``rows``, and the ``next_step`` when something is not covered ("" when
    everything is); ``models`` (link, model, reason) per stressed link and the ``accuracy`` [-] they
    were chosen for (an analysis's; none for a validation)."""

    rows: tuple[VerdictRow, ...]
    next_step: str = ""
    positions: str = ""
    """Over which positions, in words ("361 feasible positions")."""
    models: tuple[tuple[str, str, str], ...] = ()
    accuracy: float | None = None
    unanalysed: tuple[tuple[str, str], ...] = ()
    """(link, why) per moving link drawn with a profile that has no row: nothing here checks its stress."""

    def unanalysed_lines(self) -> list[str]:
        """"lever: not analysed: a slider's block slides along it, ...", one per link without a row."""
        return [f"{link}: not analysed: {why}" for link, why in self.unanalysed]

    def models_heading(self) -> str:
        return f"models: each link's, for its governing stress within {100 * self.accuracy:g} %, and why"

    def models_lines(self) -> list[str]:
        """"crank: fea-peaks: pin hole O2 outside the Kt tables (...)", one per stressed link."""
        return [f"{link}: {model}: {reason}" for link, model, reason in self.models]

    def record(self) -> dict[str, object]:
        return {"rows": [row.record() for row in self.rows], "next_step": self.next_step or None,
                "not_analysed": [{"link": link, "reason": why} for link, why in self.unanalysed]}

    def heading(self) -> str:
        return (
            f"verdict: the stress that governs each link over {self.positions}, where, its safety factors "
            "and how far to trust it"
        )

    def text(self) -> str:
        """The verdict as a terminal table, its next step under it."""
        if not self.rows:
            return "\n".join(["verdict: no link with section stresses at a feasible position", *self.unanalysed_lines()])
        lines = [self.heading(), text_table(HEADERS, [row.cells() for row in self.rows]), *self.unanalysed_lines()]
        if self.next_step:
            lines.append(f"next: {self.next_step}")
        if self.models:
            lines += ["", self.models_heading(), *(f"  {line}" for line in self.models_lines())]
        return "\n".join(lines)


def higher_words(stress: Stress, position: str = "") -> str:
    """Why a higher stress the run computed does not govern over a converged FEA peak."""
    why = "an estimate" if stress.governing == ESTIMATE else "beam theory's, nominal" if "nominal)" in stress.where else "beam theory's"
    return f"the {stress.governing} {mpa(stress.value)} MPa at {stress.where}{position} is higher: {why}, the FEA governs"


def yield_factor(strength: float | None, stress: float, note: str = "") -> Factor:
    """``strength`` [Pa] over ``stress`` [Pa] with ``note``; none without a strength or a stress."""
    if strength is None:
        return Factor(None, "no yield_strength")
    if not stress > 0:
        return Factor(None, "no stress")
    return Factor(strength / stress, note)


def percent(fraction: float) -> str:
    return f"{significant(100 * fraction, 2)} %"


@dataclass(frozen=True)
class HoleCover:
    """How far the Kt estimates cover one loaded pin hole (``name`` in full, ``label`` its joint's)
    over the feasible positions: at ``inside`` of the ``loaded`` positions (where its pin carries a
    force) the geometry is inside the Kt tables; ``largest`` its largest estimate there (None when at
    none)."""

    name: str
    label: str
    loaded: int
    inside: int
    largest: Stress | None

    @property
    def covered(self) -> bool:
        return self.inside == self.loaded


def hole_covers(result: AnalysisResult, name: str, places: LinkPlaces, ok: NDArray[np.bool_]) -> list[HoleCover]:
    """Each loaded pin hole of link ``name`` and how far its estimates cover it over the positions ``ok`` (a mask)."""
    angles = result.scene.motion.angle_deg
    covers = []
    for hole in result.stresses[name].pin_holes:
        loaded = ok & (hole.nominal > 0)
        if not loaded.any():
            continue
        inside = loaded & ~hole.outside
        largest = None
        if inside.any():
            k = int(np.flatnonzero(inside)[np.argmax(hole.estimate[inside])])
            largest = Stress(ESTIMATE, float(hole.estimate[k]), float(angles[k]), places.pin_hole(hole.joint))
        covers.append(HoleCover(places.pin_hole(hole.joint), places.joint(hole.joint), int(loaded.sum()),
                                int(inside.sum()), largest))
    return covers


def holes_words(covers: list[HoleCover]) -> str:
    """"pin hole O2" or "pin holes O2, A"."""
    labels = [c.label for c in covers]
    return f"pin hole{'s' if len(labels) > 1 else ''} {', '.join(labels)}"


def analysis_places(result: AnalysisResult, name: str, names=None) -> LinkPlaces:
    """The places of stressed link ``name``, named from its members' sections."""
    members = [(m.joints, m.member.length, m.sweep.cuts) for m in result.stresses[name].members]
    return link_places(result.scene, name, members, names)


def positions_words(feasible: NDArray[np.bool_]) -> str:
    """"the 361 feasible positions", "the 30 feasible positions of 36", "the one feasible position"."""
    count, total = int(feasible.sum()), len(feasible)
    words = "the one feasible position" if count == 1 else f"the {count} feasible positions"
    return words + (f" of {total}" if count < total else "")


def analysis_verdict(result: AnalysisResult) -> Verdict:
    """The verdict of an analysis (``analyze``, with its FEA peaks when it ran them)."""
    ok = result.feasible
    positions = positions_words(ok)
    unanalysed = result.plan.unstressed
    if not ok.any():
        return Verdict((), positions=positions, unanalysed=unanalysed)
    names = joint_names(result.scene)
    summaries = peak_summaries(result) if result.peaks else {}
    rows = []
    for name in result.stresses:
        places = analysis_places(result, name, names)
        beam = beam_stress(result, name, places, ok)
        covers = hole_covers(result, name, places, ok)
        if name in result.peaks:
            rows.append(_peak_row(result, name, places, beam, covers, summaries[name]))
        else:
            rows.append(_section_row(result, name, beam, covers))
    models = tuple((name, m.model, m.reason) for name, m in result.models.items())
    return Verdict(tuple(rows), analysis_next_step(result, tuple(rows)), positions, models, result.plan.accuracy,
                   unanalysed)


def beam_stress(result: AnalysisResult, name: str, places: LinkPlaces, positions: NDArray[np.intp] | NDArray[np.bool_]) -> Stress:
    """The beam's largest section von Mises of link ``name`` over ``positions`` (a mask or indices), where."""
    stress = result.stresses[name]
    chosen = np.arange(len(stress.max_von_mises))[positions]
    k = int(chosen[np.argmax(stress.max_von_mises[chosen])])
    m = int(np.argmax([member.max_von_mises[k] for member in stress.members]))
    where = places.name(stress.members[m].max_at[k])
    return Stress(BEAM, float(stress.max_von_mises[k]), float(result.scene.motion.angle_deg[k]), where)


def largest_estimate(covers: list[HoleCover]) -> Stress | None:
    """The largest pin-hole estimate of ``covers``, None where no hole has one."""
    return max((c.largest for c in covers if c.largest is not None), key=lambda s: s.value, default=None)


def _section_row(result: AnalysisResult, name: str, beam: Stress, covers: list[HoleCover]) -> VerdictRow:
    """The row of a link without FEA: the larger of its beam maximum and its pin-hole estimates. A
    link whose chosen model is "fea-peaks" (its FEA not run) says that it needs them."""
    material = result.scene.links[name].material
    estimate = largest_estimate(covers)
    fatigue = Factor(None, "needs the FEA peaks" if material.fatigue_strength is not None else "")
    chosen = result.models.get(name)
    unanswered = chosen is not None and chosen.model == FEA_PEAKS
    model = chosen.model if chosen is not None and not unanswered else "beam+Kt" if covers else "beam"
    pending = _pending(result, chosen) if unanswered else ""
    if estimate is not None and estimate.value > beam.value:
        return _estimate_row(name, model, estimate, covers, material.yield_strength, fatigue,
                             pending or _within(result), bool(pending))
    missing = [c for c in covers if not c.covered]
    if unanswered:
        trust, note, reason = "beam only", "sections only", pending
    elif missing:
        trust, note, reason = "beam only", "sections only", f"{holes_words(missing)} outside the Kt tables, needs the FEA peaks"
    elif covers:
        trust, note, reason = "beam + Kt", "", f"every pin hole's Kt estimate is below it{_within(result)}"
    else:
        trust, note, reason = "beam", "", f"no pin holes{_within(result)}"
    curved = any(m.theory == "curved" for m in result.stresses[name].members)
    reason = "; ".join(filter(None, ["curved beam (Winkler-Bach)" if curved else "", reason]))
    return VerdictRow(name, model, beam, yield_factor(material.yield_strength, beam.value, note), fatigue, trust, reason,
                      tuple(c.name for c in missing))


def _pending(result: AnalysisResult, chosen) -> str:
    """"needs the FEA peaks (--beam-only): see its model": a link whose model is "fea-peaks" without them."""
    why = (" (--beam-only)" if result.plan.beam_only else " (the FEA cannot take it)" if NO_FEA in chosen.reason
           else ", not run")
    return f"needs the FEA peaks{why}: see its model"


def _within(result: AnalysisResult) -> str:
    """", within 5 %": the accuracy the link's model was chosen for."""
    return f", within {100 * result.plan.accuracy:g} %"


def _estimate_row(name: str, model: str, estimate: Stress, covers: list[HoleCover], strength: float | None,
                  fatigue: Factor, after: str = "", pending: bool = False) -> VerdictRow:
    """The row of a link whose largest stress is a pin-hole estimate: over how many positions it
    exists, and which other holes nothing covers; ``after`` ends the reason (the accuracy, or what
    is pending when ``pending``: the link's FEA peaks)."""
    cover = next(c for c in covers if c.largest is estimate)
    missing = [c for c in covers if not c.covered]
    others = [c for c in missing if c is not cover]
    share = "" if cover.covered else f"at {cover.inside} of {cover.loaded} positions"
    reason = "; ".join(filter(None, [
        f"inside the Kt tables {share}".strip() + ("" if missing or pending else after),
        others and f"{holes_words(others)} outside the Kt tables",
        after if pending else "needs the FEA peaks" if missing else "",
    ]))
    note = ", ".join(filter(None, [share, f"{', '.join(c.label for c in others)} not covered" if others else ""]))
    return VerdictRow(name, model, estimate, yield_factor(strength, estimate.value, note), fatigue, "Kt estimate", reason,
                      tuple(c.name for c in missing))


def _peak_row(result: AnalysisResult, name: str, places: LinkPlaces, beam: Stress, covers: list[HoleCover],
              summary: dict[str, object]) -> VerdictRow:
    """The row of a link with FEA peaks over the sweep (``summary``: its ``peak_summaries`` record)."""
    peaks = result.peaks[name]
    strength = result.scene.links[name].material.yield_strength
    worst = peaks.worst_position
    where = places.name(peaks.peak_at[worst], beam=False)
    fea = Stress(FEA_PEAK, peaks.peak_max, float(result.scene.motion.angle_deg[worst]), where)
    count, solved = int(result.feasible.sum()), len(peaks.sweep.positions)
    note = "" if solved == count else f"at {solved} of {count} positions"
    estimate = largest_estimate(covers)
    best = beam if estimate is None or beam.value >= estimate.value else estimate
    if peaks.trusted:
        reason = f"converged {percent(peaks.check.change)}"
        if best.value > fea.value:
            reason += f"; {higher_words(best)}"
        return VerdictRow(name, "fea-peaks", fea, yield_factor(strength, fea.value, note),
                          _fatigue(summary, note, peaks.fatigue_criterion), "FEA", reason)
    change = (f"{percent(max(peaks.check.change, peaks.check.previous_change))} over a mesh refinement "
              f"(limit {100 * peaks.check.limit:g} %)")
    withheld = Factor(None, "withheld: FEA NOT converged")
    if fea.value >= best.value:
        return VerdictRow(name, "fea-peaks", fea, withheld, withheld, "NOT converged",
                          f"{change}: a lower bound, no safety factor")
    note = "sections only" if best is beam and not all(c.covered for c in covers) else ""
    return VerdictRow(name, "fea-peaks", best, yield_factor(strength, best.value, note), withheld, "NOT converged",
                      f"the FEA peak {mpa(fea.value)} MPa changed {change}; the {best.governing} governs")


CRITERION_NAMES = {"goodman": "Goodman", "gerber": "Gerber", "asme-elliptic": "ASME-elliptic"}


def _fatigue(summary: dict[str, object], note: str, criterion: str) -> Factor:
    """The FEA peaks' fatigue factor of ``criterion`` with what it covers, or why there is none."""
    factor = summary["fatigue_safety_factor"]
    if factor is None:
        return Factor(None, "no fatigue check" if "fatigue_safety_factors" not in summary else "nothing cycles")
    cycle = "" if not summary["fatigue_note"] else "not a whole cycle"
    return Factor(factor, ", ".join(filter(None, [CRITERION_NAMES[criterion], note, cycle])))


def analysis_next_step(result: AnalysisResult, rows: tuple[VerdictRow, ...]) -> str:
    """What to run when some link is not covered: the FEA peaks for the pin holes, or a finer mesh
    for a peak that did not converge; "" when every link is covered."""
    parts = []
    needing = [row.link for row in rows if row.link not in result.peaks and row.link in result.models
               and result.models[row.link].model == FEA_PEAKS]
    unable = [name for name in needing if NO_FEA in result.models[name].reason]
    runnable = [name for name in needing if name not in unable]
    if runnable:
        parts.append(f"run `linkstress analyze {result.scene.path}`{' without --beam-only' if result.plan.beam_only else ''} "
                     f"for the FEA peaks of {', '.join(runnable)}")
    if unable:
        parts.append(f"the FEA cannot take {', '.join(unable)}: see {'its' if len(unable) == 1 else 'their'} model's reason")
    uncovered = [row.link for row in rows if row.uncovered and row.model != "fea-peaks" and row.link not in needing]
    if uncovered:
        parts.append(f"run `linkstress analyze {result.scene.path} --peaks` for the pin holes of {', '.join(uncovered)}")
    unsettled = [row.link for row in rows if row.trust == "NOT converged"]
    if unsettled:
        parts.append(
            f"the FEA peak of {', '.join(unsettled)} did not converge: round the sharp corner in the drawing or give a "
            "finer [analysis] mesh_size_m"
        )
    return "; ".join(parts)
