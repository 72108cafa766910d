"""``linkstress bench``: every measurement of speed against error in one run, and the checks on it.

The run measures (``speed_error``) the beam engine, the original program's strip sums and P1/P2
FEA along every member of the links of the shipped cases (``CASES``: the seed's ANSYS four-bar,
the banana-coupler and arc-coupler four-bars, whose couplers are curved, and the two-loop machine
whose rocker is an L-shaped bell crank of two members), the throughput of each analysis stage and
the FEA's peak memory (``throughput``), the hard cases (``stability``), and the FEA peaks by
superposition of unit loads against direct FEA on the seed, the banana coupler and the bell crank
(``bench_peaks``). The checks are on errors only, never on times (machines are shared and noisy):

- the beam engine at the default station count within its case's bound of the reference on every
  member of every studied link that has a station away from the holes (NOMINAL_BOUND; CURVED_BOUND
  on the curved couplers), and the curved links found curved;
- validate's default FEA (the finest mesh of its three-level study) within CONVERGED_BOUND, and the
  reference's own Richardson estimate within it too;
- on the hard cases, the beam within STABILITY_BOUND wherever the engine raises no flag, and the
  flags each case must raise;
- every superposed link's peak within PEAK_BOUND and its von Mises field within FIELD_BOUND (rms)
  of the direct FEA on the same mesh.

The must-show figures are ratios of times, reported with whether they meet their target, not
checked: the beam's speed-up over the converged FEA at nominal error under NOMINAL_BOUND, and the
seed's 360-position sweep with FEA peaks against one validate at one position (RATIO_TARGET), its
superposition per link and position within SUPERPOSITION_TARGET. ``analyze`` of the README
tutorial's scene and of the seed runs as a whole process, first on an empty disk cache and again on
the warm one, with the models it chose (``model_bounds``).
"""

from __future__ import annotations

import os
import platform
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

from linkstress.analysis import DEFAULT_STATIONS
from linkstress.validation.bench.model_bounds import AnalyzeRun, analyze_runs
from linkstress.validation.bench.peaks import FIELD_BOUND, PEAK_BOUND, PeaksSpeed, PeaksStudy, peaks_speed, peaks_study
from linkstress.validation.bench.speed_error import RATIO, VALIDATE_LEVELS, CaseStudy, StudySettings, case_study
from linkstress.validation.bench.stability import HardCaseResult, hard_cases
from linkstress.validation.bench.throughput import MemoryUse, StageRate, fea_sweep_rate, memory_use, sweep_rates

CASES = Path(__file__).resolve().parents[1] / "cases"
SEED = CASES / "seed_ansys_fourbar" / "scene.toml"
CURVED_CASE = CASES / "banana_coupler" / "scene.toml"
BELL_CRANK = CASES / "bell_crank" / "scene.toml"
NOMINAL_BOUND = 0.02
"""Nominal error the beam engine must stay under against converged FEA (a must-show figure), on
every member of a link unless its case bounds it otherwise."""
CURVED_BOUND = 0.03
"""Nominal error bound of the beam's curved (Winkler-Bach) sections on the curved couplers."""
CONVERGED_BOUND = 0.005
"""validate's convergence criterion: a converged FEA is within 0.5 % of the reference."""
STABILITY_BOUND = 0.05
"""On the hard cases, where the engine raises no flag, its nominal error stays under this."""
SPEEDUP = 1000.0
"""The must-show speed-up of the beam engine over the converged FEA."""


@dataclass(frozen=True)
class BenchCase:
    """One case of the speed-against-error study: its scene ``path``, the ``links`` studied (None:
    every link its plan validates), the beam's nominal error ``bounds`` per link (on every member;
    NOMINAL_BOUND where a link is not named), the links that must be found ``curved``, and the
    ``study`` settings where they are not the run's."""

    path: Path
    bounds: dict[str, float] = field(default_factory=dict)
    curved: tuple[str, ...] = ()
    links: tuple[str, ...] | None = None
    study: StudySettings | None = None

    @property
    def name(self) -> str:
        return self.path.parent.name


@dataclass(frozen=True)
class BenchSettings:
    """What one run measures: the speed/error ``study``, sweeps of ``sweep_positions`` (best of
    ``sweep_repeat``), an FEA sweep of ``fea_sweep_positions``, the FEA memory at the refinement
    levels ``memory_levels`` (k, order) and the hard cases at level ``stability_level``; the
    speed/error ``cases``, the seed first (the must-show is measured on it); the superposed FEA
    peaks against direct FEA at ``peak_positions`` of each sweep, on the seed's whole turn (timed
    against one validate, best of ``peak_repeat``) and on the scenes ``peak_cases``; ``analyze`` of the
    README tutorial's scene and the seed as whole processes, best of ``analyze_repeat``."""

    name: str
    study: StudySettings
    cases: tuple[BenchCase, ...]
    sweep_positions: int
    sweep_repeat: int
    fea_sweep_positions: int
    memory_levels: tuple[tuple[int, int], ...]
    stability_level: int
    peak_positions: int
    peak_repeat: int
    peak_cases: tuple[Path, ...]
    analyze_repeat: int = 1


SEED_CASE = BenchCase(SEED)
BANANA_CASE = BenchCase(CURVED_CASE, {"coupler": CURVED_BOUND}, ("coupler",))
ARC_CASE = BenchCase(CASES / "arc_coupler" / "scene.toml", {"coupler": CURVED_BOUND}, ("coupler",))
BELL_CRANK_CASE = BenchCase(BELL_CRANK)
QUICK_STUDY = StudySettings(
    positions=2, station_counts=(5, 21, DEFAULT_STATIONS), strip_steps=(1e-2, 1e-3),
    p2_levels=VALIDATE_LEVELS, p1_levels=(0, 1), repeat=3, cheap=0.2,
)
FULL_STUDY = StudySettings(
    positions=12, station_counts=(3, 5, 11, 21, 51, 101, 201, 501, 1001), strip_steps=(1e-2, 1e-3, 1e-4),
    p2_levels=(-2, -1, 0, 1, 2, 3, 4), p1_levels=(-1, 0, 1, 2, 3, 4, 5), repeat=5,
)
FULL = BenchSettings(
    "full",
    FULL_STUDY,
    # The bell-crank machine's coupler has a 6.5 mm ligament beside its pin hole, which the mesh 2.25 x
    # coarser than the default cannot span with two elements: its P2 levels start at 1.5 x coarser.
    (SEED_CASE, BANANA_CASE, ARC_CASE, replace(BELL_CRANK_CASE, study=replace(FULL_STUDY, p2_levels=FULL_STUDY.p2_levels[1:]))),
    sweep_positions=3600, sweep_repeat=5, fea_sweep_positions=360,
    memory_levels=((2, 2), (4, 2), (5, 1)), stability_level=2,
    peak_positions=36, peak_repeat=3, peak_cases=(CURVED_CASE, BELL_CRANK), analyze_repeat=3,
)
# CI's run keeps within about a minute: the two new cases study only the link they were shipped for,
# without P1 (measured on the other two); the superposed peaks only on the seed, at 6 positions.
QUICK = BenchSettings(
    "quick",
    QUICK_STUDY,
    (
        SEED_CASE, BANANA_CASE, replace(ARC_CASE, links=("coupler",), study=replace(QUICK_STUDY, p1_levels=())),
        replace(BELL_CRANK_CASE, links=("bellcrank",), study=replace(QUICK_STUDY, p1_levels=())),
    ),
    sweep_positions=360, sweep_repeat=3, fea_sweep_positions=12,
    memory_levels=((0, 2),), stability_level=1,
    peak_positions=6, peak_repeat=1, peak_cases=(),
)


@dataclass(frozen=True)
class Check:
    """One bound on an error: ``value`` [-] against ``bound`` [-] (None: a flag that must be raised)."""

    name: str
    passed: bool
    value: float | None = None
    bound: float | None = None


@dataclass(frozen=True)
class MustShow:
    """The beam engine at the default stations against validate's converged FEA on the seed case."""

    beam_error: float
    beam_seconds: float
    fea_error: float
    fea_seconds: float
    study_seconds: float

    @property
    def speedup(self) -> float:
        """Over the one solve on the converged mesh."""
        return self.fea_seconds / self.beam_seconds

    @property
    def study_speedup(self) -> float:
        """Over validate's three-level study, which is what establishes convergence."""
        return self.study_seconds / self.beam_seconds

    @property
    def met(self) -> bool:
        return self.beam_error < NOMINAL_BOUND and self.speedup >= SPEEDUP


@dataclass(frozen=True)
class BenchResult:
    settings: BenchSettings
    machine: dict[str, str]
    cases: tuple[CaseStudy, ...]
    rates: tuple[StageRate, ...]
    memory: tuple[MemoryUse, ...]
    stability: tuple[HardCaseResult, ...]
    must_show: MustShow
    peaks: tuple[PeaksStudy, ...]
    """The superposed FEA peaks against direct FEA, the seed's (its timed sweep's) first."""
    peaks_speed: PeaksSpeed
    checks: tuple[Check, ...]
    seconds: float
    notes: tuple[str, ...] = field(default_factory=tuple)
    analyze_runs: tuple[AnalyzeRun, ...] = ()
    """``analyze`` of the README tutorial's scene and of the seed as whole processes: first and cached runs."""

    def failures(self) -> list[str]:
        return [c.name for c in self.checks if not c.passed]


def machine() -> dict[str, str]:
    """What the figures were measured on."""
    cpu = platform.processor() or platform.machine()
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.is_file():
        names = [line.split(":", 1)[1].strip() for line in cpuinfo.read_text().splitlines() if line.startswith("model name")]
        cpu = names[0] if names else cpu
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return {
        "cpu": cpu,
        "cores": str(os.cpu_count()),
        "system": f"{platform.system()} {platform.release()}",
        "python": platform.python_version(),
        "load average at start (1 min)": f"{load:.2f}",
    }


def run_bench(settings: BenchSettings, progress=lambda message: None) -> BenchResult:
    """Measure everything ``settings`` asks for; ``progress(message)`` hears of each part."""
    start = time.perf_counter()
    info = machine()
    cases = []
    for case in settings.cases:
        progress(f"speed against error: {case.name}")
        cases.append(case_study(case.path, case.study or settings.study, case.links))
    progress("superposed FEA peaks: the seed's whole turn against one validate")
    speed = peaks_speed(SEED, settings.peak_positions, settings.peak_repeat)
    peaks = [speed.study]
    for path in settings.peak_cases:
        progress(f"superposed FEA peaks: {path.parent.name}")
        peaks.append(peaks_study(path, settings.peak_positions))
    progress("throughput and memory")
    rates = [r for path in (SEED, CURVED_CASE) for r in sweep_rates(path, settings.sweep_positions, settings.sweep_repeat)]
    rates.append(fea_sweep_rate(SEED, "crank", settings.fea_sweep_positions, RATIO ** VALIDATE_LEVELS[-1]))
    memory = [memory_use(SEED, "crank", RATIO**k, order) for k, order in settings.memory_levels]
    progress("hard cases")
    stability = hard_cases(settings.stability_level)
    progress("analyze as a whole process: the tutorial and the seed, first and cached runs")
    runs = analyze_runs(settings.analyze_repeat)
    must_show = _must_show(cases[0])
    return BenchResult(
        settings, info, tuple(cases), tuple(rates), tuple(memory), tuple(stability), must_show, tuple(peaks), speed,
        tuple(_checks(settings.cases, cases, stability, must_show) + _peak_checks(peaks)), time.perf_counter() - start,
        analyze_runs=tuple(runs),
    )


def converged_setting() -> str:
    return f"k = {VALIDATE_LEVELS[-1]}"


def _must_show(seed: CaseStudy) -> MustShow:
    beam = seed.find("beam", f"{DEFAULT_STATIONS} stations")
    fea = seed.find("FEA P2", converged_setting())
    study = sum(seed.find("FEA P2", f"k = {k}").seconds for k in VALIDATE_LEVELS)
    return MustShow(beam.nominal_error, beam.seconds, fea.nominal_error, fea.seconds, study)


def _checks(
    bench_cases: tuple[BenchCase, ...], cases: list[CaseStudy], stability: list[HardCaseResult], must_show: MustShow,
) -> list[Check]:
    checks = [Check("seed: beam engine at the default stations within 2 % of converged FEA",
                    must_show.beam_error < NOMINAL_BOUND, must_show.beam_error, NOMINAL_BOUND)]
    for bench_case, case in zip(bench_cases, cases):
        checks += _member_checks(bench_case, case)
        found = sorted(case.curved)
        checks.append(Check(f"{case.name}: the curved links are {sorted(bench_case.curved)} (found {found})",
                            found == sorted(bench_case.curved)))
        fea = case.find("FEA P2", converged_setting())
        checks.append(Check(f"{case.name}: validate's converged FEA against the reference", fea.nominal_error < CONVERGED_BOUND,
                            fea.nominal_error, CONVERGED_BOUND))
        worst = max(e for e in case.reference_error.values() if e is not None)
        checks.append(Check(f"{case.name}: Richardson estimate of the reference's own error", worst < CONVERGED_BOUND,
                            worst, CONVERGED_BOUND))
        checks += [Check(f"{case.name}: {failure}", False) for failure in case.failures]
    for result in stability:
        trusted = [row.nominal for row in result.rows if row.trusted]
        worst = max(trusted, default=0.0)
        checks.append(Check(f"{result.name}: beam nominal error where nothing is flagged", worst < STABILITY_BOUND,
                            worst, STABILITY_BOUND))
    expected = {
        "near toggle": "infeasible", "change point": "change point", "stubby link": "no station is a section depth",
        "hole close to the edge": "within a section depth of a hole",
    }
    for result in stability:
        if result.name in expected:
            raised = any(expected[result.name] in flag for flag in result.flags)
            checks.append(Check(f"{result.name}: the engine says so ({expected[result.name]})", raised))
    return checks


def _peak_checks(studies: list[PeaksStudy]) -> list[Check]:
    """Every superposed link's peak and field against the direct FEA on the same mesh."""
    checks = []
    for study in studies:
        for link in study.links:
            checks.append(Check(f"{study.name}: superposed FEA peak of {link.name} against direct FEA",
                                link.peak_error <= PEAK_BOUND, link.peak_error, PEAK_BOUND))
            checks.append(Check(f"{study.name}: superposed FEA field of {link.name} against direct FEA (rms)",
                                link.field_error <= FIELD_BOUND, link.field_error, FIELD_BOUND))
    return checks


def _member_checks(bench_case: BenchCase, case: CaseStudy) -> list[Check]:
    """The beam at the default stations within the case's bound on every member that has a station
    away from the holes (a member whose every station is nominal has no nominal error to bound)."""
    beam = case.find("beam", f"{DEFAULT_STATIONS} stations")
    checks = []
    for link, members in beam.member_errors.items():
        bound = bench_case.bounds.get(link, NOMINAL_BOUND)
        for member, (nominal, _) in members.items():
            if nominal is not None:
                name = f"{case.name}: beam nominal error of {link} member {member}"
                checks.append(Check(name, nominal < bound, nominal, bound))
    return checks
