"""Runs the sweeps: one measured run per point (its error against the exact
reference), and ``repeats`` timed runs whose median gives the cost."""
from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from .. import StateError, World
from .base import Config, Method, Point, Problem


@dataclass
class Run:
    """One point of one curve: settings, error, cost and extra metrics."""

    method: str
    integrator: str
    iterations: int
    order: float | None
    steps: int
    dt: float
    substeps: int
    error: float
    # CPU seconds of the core per simulated second, per copy: median of the repeats.
    cost: float
    # (max − min) / median of the timed repeats.
    cost_spread: float
    metrics: dict[str, float] = field(default_factory=dict)
    # The joints' articulation integrator (None: no articulation, or XPBD joints).
    articulation_integrator: str | None = None

    @property
    def h(self) -> float:
        return self.dt / self.substeps


@dataclass
class Result:
    """All runs of one problem."""

    problem: Problem
    runs: list[Run]

    def curves(self) -> dict[str, list[Run]]:
        """Runs by method, in method order, each sorted from the coarsest h."""
        out: dict[str, list[Run]] = {}
        for run in self.runs:
            out.setdefault(run.method, []).append(run)
        return {k: sorted(v, key=lambda r: -r.h) for k, v in out.items()}


# A timed sample shorter than this steps several fresh worlds in a row (the clock's
# granularity and the call's fixed cost would otherwise dominate a run of a few µs).
MIN_SAMPLE = 2e-3  # s


def step_all(worlds: list[World], steps: int) -> float:
    """CPU time of the calling thread (which runs the core, GIL released) for one
    ``world.step(steps)`` call on each world in turn: no Python inside the calls."""
    t0 = time.thread_time()
    for world in worlds:
        try:
            world.step(steps)
        except StateError:  # a method that blows up still took this long
            pass
    return time.thread_time() - t0


def core_seconds(problem: Problem, method: Method, point: Point, copies: int, repeats: int) -> list[float]:
    """``repeats`` samples of the time of one run on a freshly built world. The first
    sample is a warm-up; if it is shorter than MIN_SAMPLE, each sample steps enough
    worlds (built beforehand, outside the timing) to last that long, and is divided
    by their number."""
    first = step_all([problem.build(method, point, copies)], point.steps)
    batch = min(100, math.ceil(MIN_SAMPLE / first)) if first < MIN_SAMPLE else 1
    times = []
    for _ in range(repeats):
        worlds = [problem.build(method, point, copies) for _ in range(batch)]
        times.append(step_all(worlds, point.steps) / batch)
    return times


def run_point(problem: Problem, method: Method, point: Point, cfg: Config) -> Run:
    metrics = problem.measure(problem.build(method, point), point)
    copies = problem.copies(cfg)
    times = core_seconds(problem, method, point, copies, cfg.repeats)
    median = statistics.median(times)
    simulated = point.steps * point.dt * copies
    error = metrics.pop("error")
    return Run(method.label, method.integrator, method.iterations, method.order, point.steps, point.dt,
               point.substeps, error if math.isfinite(error) else math.inf, median / simulated,
               (max(times) - min(times)) / median if median > 0 else 0.0, metrics, method.articulation_integrator)


def run_problem(problem: Problem, cfg: Config, tick: Callable[[str], None]) -> Result:
    runs = []
    for method in problem.methods(cfg):
        for point in problem.points(method, cfg):
            tick(f"{problem.name}: {method.label}, h = {point.h:.2g} s")
            runs.append(run_point(problem, method, point, cfg))
    return Result(problem, runs)


def count_points(problem: Problem, cfg: Config) -> int:
    return sum(len(problem.points(m, cfg)) for m in problem.methods(cfg))
