"""The model choice against FEA: on every shipped case and the README tutorial's scene, each link the
choice leaves on "beam" or "beam+Kt" gets the FEA peaks anyway, and its margin, FEA peak over the
governing stress its model reported minus 1, must stay within the accuracy
(``linkstress.model_choice``; ``tests/test_model_choice_cases.py`` holds it).

    python -m linkstress.validation.bench.model_choice [--accuracy 0.05 0.1] [--every]

prints a row per link: its model, the governing stress, the FEA peak and the margin; ``--every``
computes the FEA peaks of the links on "fea-peaks" too (what the beam would have missed there).
The FEA's unit-load solutions go to the disk cache (``LINKSTRESS_CACHE``, else the user's).
"""

from __future__ import annotations

import argparse
import tempfile
from dataclasses import dataclass, replace
from pathlib import Path

from linkstress.analysis import plan_for, run_analysis
from linkstress.model_choice import DEFAULT_ACCURACY, FEA_PEAKS
from linkstress.report.verdict import analysis_verdict
from linkstress.scene import load_scene
from linkstress.validation.fea.cache import CacheSettings, cache_settings
from linkstress.validation.peaks_scene import scene_peaks

CASES = Path(__file__).resolve().parents[1] / "cases"


@dataclass(frozen=True)
class Margin:
    """One link of ``case`` under ``accuracy``: its ``model`` and its reason, the ``governing``
    stress [Pa] the verdict reports without FEA, the converged or not FEA ``peak`` [Pa]."""

    case: str
    link: str
    accuracy: float
    model: str
    reason: str
    governing: float
    peak: float
    converged: bool

    @property
    def margin(self) -> float:
        """[-]: FEA peak / governing - 1 (within the accuracy where the model is "beam" or "beam+Kt")."""
        return self.peak / self.governing - 1.0


def case_scenes() -> list[Path]:
    """Every shipped case's scene that has section stresses to choose for."""
    return sorted(path for path in CASES.glob("*/scene.toml"))


def margins(path: Path, accuracy: float, cache: CacheSettings | None, every: bool = False) -> list[Margin]:
    """The margins of the links of scene ``path`` the choice leaves on the beam (all its links when
    ``every``), their FEA peaks from ``cache``."""
    scene = load_scene(path)
    plan = replace(plan_for(scene), accuracy=accuracy, peaks=())
    result = run_analysis(scene, plan)
    if result.forces is None or not result.stresses:
        return []
    chosen = [name for name, m in result.models.items() if every or m.model != FEA_PEAKS]
    if not chosen:
        return []
    rows = {row.link: row for row in analysis_verdict(result).rows}
    peaks = scene_peaks(scene, replace(plan, peaks=tuple(chosen)), result.forces, None, cache)
    case = path.parent.name if path.name == "scene.toml" else path.stem
    return [
        Margin(case, name, accuracy, result.models[name].model, result.models[name].reason, rows[name].stress.value,
               peaks[name].peak_max, peaks[name].trusted)
        for name in chosen if name in peaks
    ]


def table(rows: list[Margin]) -> str:
    """The margins as text, one line per link."""
    lines = [f"{'case':24s} {'link':15s} {'accuracy':>8s} {'model':9s} {'governing [MPa]':>15s} {'FEA peak [MPa]':>14s} "
             f"{'margin':>8s}"]
    for m in rows:
        flag = "" if m.converged else "  (FEA NOT converged)"
        lines.append(f"{m.case:24s} {m.link:15s} {100 * m.accuracy:7.3g}% {m.model:9s} {m.governing / 1e6:15.4g} "
                     f"{m.peak / 1e6:14.4g} {100 * m.margin:+7.2f}%{flag}")
    return "\n".join(lines)


def main() -> None:
    from linkstress.validation.bench.tutorial import tutorial_scene

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--accuracy", type=float, nargs="+", default=[DEFAULT_ACCURACY, 0.1])
    parser.add_argument("--every", action="store_true", help="the FEA peaks of the links on fea-peaks too")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        scenes = [*case_scenes(), tutorial_scene(Path(folder))]
        rows = [m for accuracy in args.accuracy for path in scenes
                for m in margins(path, accuracy, cache_settings(None), args.every)]
    print(table(rows))
    left = [m for m in rows if m.model != FEA_PEAKS]
    if left:
        worst = max(left, key=lambda m: m.margin - m.accuracy)
        print(f"links left on the beam: {len(left)}; the largest margin {100 * worst.margin:+.2f} % "
              f"({worst.case} {worst.link}, accuracy {100 * worst.accuracy:g} %)")


if __name__ == "__main__":
    main()
