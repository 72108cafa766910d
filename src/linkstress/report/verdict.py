"""The verdict: per stressed link, the stress that governs it, where and when, how safe, and how far
to trust it. Reports show it first; text, HTML and JSON are rendered from the same rows.

The governing stress is the largest credible one the run computed for the link:

- the FEA peak (anywhere in the link, pin holes included) when FEA ran and its peak converged; the
  yield and fatigue safety factors come from it;
- else the larger of the beam's section maximum and the largest pin-hole estimate (Kt x nominal,
  where the geometry the pin force sees is inside the Kt tables). An FEA peak that did not converge
  is shown instead when it is larger (as a lower bound, with no safety factor).

The trust says in a word what the number rests on, and its reason what is not covered: "FEA" (its
change over the last mesh refinement), "NOT converged", "Kt estimate", "beam + Kt" (every loaded pin
hole has an estimate at every position, all below the beam's maximum), "beam" (no pin holes) or "beam
only" (some loaded pin hole has no estimate at some position: beam theory is silent at a hole, so
nothing here covers it). A factor taken over fewer positions than the sweep's feasible ones says so
beside the number ("at 1 of 36 positions"), and a factor that leaves pin holes uncovered is named for
what it covers ("sections only"). Where a stress the run computed is higher than the governing one,
the reason says which and why it does not govern.

``model`` names the stress model the row comes from: "beam" (beam sections alone), "beam+Kt" (with
pin-hole estimates), "fea-peaks" (``analyze --peaks``), "fea" (``validate``'s FEA at its compared
positions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from linkstress.analysis import AnalysisResult
from linkstress.report.peak_records import peak_summaries
from linkstress.report.places import LinkPlaces, joint_names, link_places
from linkstress.report.cells import mpa, significant, text_table

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
    everything is)."""

    rows: tuple[VerdictRow, ...]
    next_step: str = ""
    positions: str = ""
    """Over which positions, in words ("361 feasible positions")."""

    def record(self) -> dict[str, object]:
        return {"rows": [row.record() for row in self.rows], "next_step": self.next_step or None}

    def heading(self) -> str:
        return (
            f"verdict: the stress that governs each link over {self.positions}, where, its safety factors "
            "and how far to trust it"
        )

    def text(self) -> str:
        """The verdict as a terminal table, its next step under it."""
        if not self.rows:
            return "verdict: no link with section stresses at a feasible position"
        lines = [self.heading(), text_table(HEADERS, [row.cells() for row in self.rows])]
        if self.next_step:
            lines.append(f"next: {self.next_step}")
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
    if not ok.any():
        return Verdict((), positions=positions)
    names = joint_names(result.scene)
    rows = tuple(_analysis_row(result, name, analysis_places(result, name, names), ok) for name in result.stresses)
    return Verdict(rows, analysis_next_step(result, rows), positions)


def beam_stress(result: AnalysisResult, name: str, places: LinkPlaces, positions: NDArray[np.intp] | NDArray[np.bool_]) -> Stress:
    """The beam's largest section von Mises of link ``name`` over ``positions`` (a mask or indices), where."""
    stress = result.stresses[name]
    chosen = np.arange(len(stress.max_von_mises))[positions]
    k = int(chosen[np.argmax(stress.max_von_mises[chosen])])
    m = int(np.argmax([member.max_von_mises[k] for member in stress.members]))
    where = places.name(stress.members[m].max_at[k])
    return Stress(BEAM, float(stress.max_von_mises[k]), float(result.scene.motion.angle_deg[k]), where)


def _analysis_row(result: AnalysisResult, name: str, places: LinkPlaces, ok: NDArray[np.bool_]) -> VerdictRow:
    count = int(ok.sum())
    material = result.scene.links[name].material
    strength = material.yield_strength
    beam = beam_stress(result, name, places, ok)
    covers = hole_covers(result, name, places, ok)
    uncovered = tuple(c.name for c in covers if not c.covered)
    estimates = [c.largest for c in covers if c.largest is not None]
    estimate = max(estimates, key=lambda s: s.value, default=None)
    peaks = result.peaks.get(name)
    curved = any(m.theory == "curved" for m in result.stresses[name].members)
    if peaks is not None:
        return _peak_row(result, name, places, beam, estimate, count)
    governing = beam if estimate is None or beam.value >= estimate.value else estimate
    model = "beam+Kt" if covers else "beam"
    fatigue = Factor(None, "run --peaks" if material.fatigue_strength is not None else "")
    missing = [c for c in covers if not c.covered]
    if governing is estimate:
        cover = next(c for c in covers if c.largest is estimate)
        others = [c for c in missing if c is not cover]
        share = "" if cover.covered else f"at {cover.inside} of {cover.loaded} positions"
        unknown = f"{', '.join(c.label for c in others)} not covered" if others else ""
        reason = "; ".join(filter(None, [
            f"inside the Kt tables {share}".strip(),
            others and f"{holes_words(others)} outside the Kt tables",
        ]))
        reason += ", run --peaks" if missing else ""
        note = ", ".join(filter(None, [share, unknown]))
        return VerdictRow(name, model, governing, yield_factor(strength, governing.value, note), fatigue, "Kt estimate",
                          reason, uncovered)
    if missing:
        trust, note, reason = "beam only", "sections only", f"{holes_words(missing)} outside the Kt tables, run --peaks"
    elif covers:
        trust, note, reason = "beam + Kt", "", "every pin hole's Kt estimate is below it"
    else:
        trust, note, reason = "beam", "", "no pin holes"
    reason = "; ".join(filter(None, ["curved beam (Winkler-Bach)" if curved else "", reason]))
    return VerdictRow(name, model, governing, yield_factor(strength, governing.value, note), fatigue, trust, reason, uncovered)


def _peak_row(result: AnalysisResult, name: str, places: LinkPlaces, beam: Stress, estimate: Stress | None,
              count: int) -> VerdictRow:
    """The row of a link with FEA peaks over the sweep."""
    peaks = result.peaks[name]
    summary = peak_summaries_of(result, name)
    material = result.scene.links[name].material
    worst = peaks.worst_position
    fea = Stress(FEA_PEAK, peaks.peak_max, float(result.scene.motion.angle_deg[worst]), places.name(peaks.peak_at[worst], beam=False))
    covered_positions = len(peaks.sweep.positions)
    note = "" if covered_positions == count else f"at {covered_positions} of {count} positions"
    others = [s for s in (beam, estimate) if s is not None]
    if peaks.trusted:
        reason = f"converged {percent(peaks.check.change)}"
        higher = [s for s in others if s.value > fea.value]
        if higher:
            top = max(higher, key=lambda s: s.value)
            reason += f"; {higher_words(top)}"
        return VerdictRow(
            name, "fea-peaks", fea, yield_factor(material.yield_strength, fea.value, note),
            _fatigue(summary, note, peaks.fatigue_criterion), "FEA", reason,
        )
    change = f"{percent(max(peaks.check.change, peaks.check.previous_change))} over a mesh refinement (limit {percent(peaks.check.limit)})"
    best = max(others, key=lambda s: s.value)
    withheld = Factor(None, "withheld: FEA NOT converged")
    if fea.value >= best.value:
        return VerdictRow(name, "fea-peaks", fea, withheld, withheld, "NOT converged",
                          f"{change}: a lower bound, no safety factor; refine the mesh")
    return VerdictRow(
        name, "fea-peaks", best, yield_factor(material.yield_strength, best.value, "sections only" if best is beam else ""),
        withheld, "NOT converged", f"the FEA peak {mpa(fea.value)} MPa changed {change}; the {best.governing} governs",
    )


def peak_summaries_of(result: AnalysisResult, name: str) -> dict[str, object]:
    """Link ``name``'s FEA peak summary record (``peak_records``)."""
    return peak_summaries(result)[name]


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
    uncovered = [row.link for row in rows if row.uncovered and row.model != "fea-peaks"]
    if uncovered:
        parts.append(f"run `linkstress analyze {result.scene.path} --peaks` for the pin holes of {', '.join(uncovered)}")
    unsettled = [row.link for row in rows if row.trust == "NOT converged"]
    if unsettled:
        parts.append(
            f"the FEA peak of {', '.join(unsettled)} did not converge: round the sharp corner in the drawing or give a "
            "finer [analysis] mesh_size_m"
        )
    return "; ".join(parts)
