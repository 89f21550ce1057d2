"""The work-precision report: what accuracy costs in time.

``rigidrs.accuracy()`` (or ``rigidrs accuracy`` on the command line) runs reference
problems with exact solutions for every integrator over at least two decades of
dt, jointed problems as articulations (every articulation integrator) and as XPBD
joints, and the contact and XPBD problems over solver iterations and substeps. For
each run it measures the error against the exact reference and the cost: CPU
time of the core per simulated second (one ``world.step(n)`` call, no Python in
it, median of repeats). It writes a markdown table (``report.md``, with the cost
to reach given errors), the raw runs (``results.json``) and, with matplotlib,
log-log work-precision and convergence diagrams (PNG).
"""
from __future__ import annotations

import json
import math
import os
import platform
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, TextIO

from .. import __version__
from .base import Config, Method, Point, Problem
from .articulation import ChainEnergy, HingePendulum
from .contact import BouncingBall, Incline, KickedColumn, MeshSlide, SlipToRoll, SpinningPlate, Tower
from .plots import write_plots
from .progress import Progress
from .rigid import AsymmetricTop, Disc, Dzhanibekov, FastRod, FastSpinner, Projectile
from .runner import Result, Run, count_points, run_problem
from .table import cost_to_reach, report_markdown, slope
from .xpbd import HangingChain, HeavyTop, Pendulum

__all__ = ["PROBLEMS", "Config", "Method", "Point", "Problem", "Report", "Result", "Run", "accuracy", "cost_to_reach",
           "slope"]

ALL: tuple[type[Problem], ...] = (AsymmetricTop, Dzhanibekov, Disc, FastRod, FastSpinner, HeavyTop, Projectile,
                                  BouncingBall, Incline, SlipToRoll, Tower, SpinningPlate, MeshSlide, KickedColumn, Pendulum,
                                  HangingChain, HingePendulum, ChainEnergy)
PROBLEMS: dict[str, type[Problem]] = {cls.name: cls for cls in ALL}

QUICK = Config(full=False, points=5, repeats=3, copies=16)
FULL = Config(full=True, points=9, repeats=5, copies=16)


@dataclass
class Report:
    """What :func:`accuracy` measured, and the files it wrote."""

    config: Config
    results: list[Result]
    seconds: float
    files: list[Path] = field(default_factory=list)
    plots: bool = False

    def result(self, name: str) -> Result:
        return next(r for r in self.results if r.problem.name == name)

    def slopes(self, name: str) -> dict[str, float | None]:
        """Measured convergence slope of each method of problem ``name``."""
        result = self.result(name)
        return {label: slope(result.problem, runs) for label, runs in result.curves().items()}

    def markdown(self) -> str:
        return report_markdown(self.results, intro(self))


def intro(report: Report) -> str:
    cfg = report.config
    plots = ("Diagrams: `<problem>_work_precision.png` (error against cost), `<problem>_convergence.png` "
             "(error against the substep h, dashed: the nominal slope), `work_precision.png` and "
             "`convergence.png` (all problems)." if report.plots else
             "Plots skipped: matplotlib is not installed (`pip install rigidrs[plots]`).")
    return "\n".join([
        "# rigidrs work-precision report", "",
        f"rigidrs {__version__}, Python {platform.python_version()}, {platform.machine()}, "
        f"{os.cpu_count()} CPUs; {'full' if cfg.full else 'quick'} mode: {cfg.points} points per sweep, "
        f"median of {cfg.repeats} timed runs, {report.seconds:.0f} s in all.", "",
        "**Cost** is the CPU time of the thread running the core (`time.thread_time`, so waiting for a "
        "shared core is left out) for one `world.step(n)` call over the whole run (profiling off, no Python "
        f"in it), per simulated second; free-body problems step {cfg.copies} copies together and report the "
        "cost per copy. **Error** is measured on a separate run against the exact reference. "
        "**Measured slope**: least-squares slope of log(error) against log(h) over the runs above round-off "
        "and below saturation (see each problem's floor). **Cost to reach** an error: log-log interpolation "
        "along the work-precision curve; `≤` means the cheapest run already reaches it, `never` that no run "
        "of the sweep does.", "", plots, "",
    ])


def finite_or_none(x: float) -> float | None:
    return x if math.isfinite(x) else None


def results_json(report: Report) -> dict[str, Any]:
    def run_dict(run: Run) -> dict[str, Any]:
        d = asdict(run)
        d["error"] = finite_or_none(run.error)
        d["metrics"] = {k: finite_or_none(v) for k, v in run.metrics.items()}
        return d

    return {
        "rigidrs": __version__, "config": asdict(report.config), "seconds": report.seconds,
        "problems": {
            r.problem.name: {"title": r.problem.title, "error": r.problem.error_label, "reference": r.problem.reference,
                             "extras": r.problem.extras, "runs": [run_dict(x) for x in r.runs]}
            for r in report.results
        },
    }


def write(report: Report, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    files = write_plots(report.results, out)
    report.plots = files is not None
    (out / "report.md").write_text(report.markdown() + "\n", encoding="utf-8")
    (out / "results.json").write_text(json.dumps(results_json(report), indent=1) + "\n", encoding="utf-8")
    report.files = [out / "report.md", out / "results.json", *(files or [])]


def accuracy(
    quick: bool = False,
    out: str | os.PathLike[str] | None = None,
    problems: list[str] | None = None,
    *,
    config: Config | None = None,
    progress: bool = True,
    stream: TextIO | None = None,
) -> Report:
    """Runs the work-precision report and returns what it measured.

    ``quick``: fewer points, shorter runs, fewer methods (under two minutes); the
    default is the full report. ``out``: a directory for ``report.md``,
    ``results.json`` and the PNG diagrams (nothing is written if None).
    ``problems``: names from ``PROBLEMS`` (default all). ``config`` overrides the
    mode's :class:`Config`. ``progress``: a progress bar on ``stream`` (stderr)."""
    cfg = config or (QUICK if quick else FULL)
    names = list(PROBLEMS) if problems is None else problems
    unknown = [n for n in names if n not in PROBLEMS]
    if unknown:
        raise ValueError(f"unknown problem(s) {unknown}; choose from {list(PROBLEMS)}")
    chosen = [PROBLEMS[n]() for n in names]
    bar = Progress(sum(count_points(p, cfg) for p in chosen), progress, stream or sys.stderr)
    start = time.perf_counter()
    results = [run_problem(p, cfg, bar.tick) for p in chosen]
    bar.close()
    report = Report(cfg, results, time.perf_counter() - start)
    if out is not None:
        write(report, Path(out))
    return report
