"""What a reference problem of the work-precision report is made of.

A problem knows its scene, the methods it compares (an integrator, or a count of
solver iterations and substeps), the settings it sweeps for each method (a time
step or a substep count, over at least two decades of the substep ``h``), and how
to measure one run's error against its exact reference. The runner
(``runner.py``) does the timing.
"""
from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import Scene, World


@dataclass(frozen=True)
class Method:
    """One curve of a diagram: ``integrator`` with ``iterations`` solver passes and,
    for a sweep over dt, a fixed number of ``substeps`` (None: the engine's default).
    ``order``: the nominal order of convergence in h drawn as a reference slope.
    ``max_rotation_angle`` (rad): the limit of the automatic rotation substeps of fast
    spinners; the sweeps measure each method itself (``math.inf``: none), a curve
    that shows the engine's default sets None. ``articulation_integrator``: for a
    jointed scene, its joints form an articulation in reduced coordinates stepped by
    this method from ``ARTICULATION_INTEGRATORS``, ``substeps`` articulation substeps
    per step and nothing automatic; None: the joints are XPBD projections."""

    label: str
    integrator: str = "strang"
    iterations: int = 1
    substeps: int | None = None
    order: float | None = None
    max_rotation_angle: float | None = math.inf
    articulation_integrator: str | None = None

    @property
    def joint_solver(self) -> str:
        """``Scene.add_joint(solver=...)`` for this method's joints."""
        return "xpbd" if self.articulation_integrator is None else "articulation"


@dataclass(frozen=True)
class Point:
    """One run: ``steps`` steps of ``dt`` (s), each of ``substeps`` substeps."""

    steps: int
    dt: float
    substeps: int

    @property
    def h(self) -> float:
        """The substep (s)."""
        return self.dt / self.substeps


@dataclass(frozen=True)
class Config:
    """How much work the report does.

    ``points`` per sweep (log-spaced over its range), ``repeats`` timed runs per
    point (the median is kept), ``copies`` of a free-body problem stepped together
    in the timed runs (the cost is per copy: it leaves out the per-step overhead of
    a one-body world), ``full``: longer simulated times and every method."""

    full: bool = False
    points: int = 5
    repeats: int = 3
    copies: int = 16


Metrics = dict[str, float]


class Problem(ABC):
    """A reference problem. Subclasses set the class-level description and
    implement :meth:`methods`, :meth:`points`, :meth:`scene` and :meth:`measure`."""

    name: ClassVar[str]
    title: ClassVar[str]
    error_label: ClassVar[str]
    # The exact reference, in words (the report's legend).
    reference: ClassVar[str]
    # Errors for the "cost to reach" columns.
    targets: ClassVar[tuple[float, ...]]
    # Errors at or below this are round-off (left out of the fitted slopes).
    floor: ClassVar[float] = 1e-12
    # Errors at or above this are saturated or blown up (left out as well).
    ceiling: ClassVar[float] = 0.3
    # Extra metrics measured besides the error: key -> description.
    extras: ClassVar[dict[str, str]] = {}
    # Whether the world may sleep (a resting scene measured at rest must not).
    sleep: ClassVar[bool] = True

    @abstractmethod
    def methods(self, cfg: Config) -> list[Method]:
        """The curves to draw."""

    @abstractmethod
    def points(self, method: Method, cfg: Config) -> list[Point]:
        """The runs of one curve."""

    @abstractmethod
    def scene(self, copies: int) -> Scene:
        """The scene, with ``copies`` independent instances (copy 0 is measured)."""

    @abstractmethod
    def measure(self, world: World, point: Point) -> Metrics:
        """Steps a one-copy ``world`` through the run; returns ``"error"`` and extras."""

    def copies(self, cfg: Config) -> int:
        """Instances stepped together in a timed run."""
        return 1

    def scene_for(self, method: Method, copies: int) -> Scene:
        """The scene one method runs; jointed problems choose the joints' solver here."""
        return self.scene(copies)

    def build(self, method: Method, point: Point, copies: int = 1) -> World:
        articulated = method.articulation_integrator is not None
        world = self.scene_for(method, copies).build(
            dt=point.dt, integrator=method.integrator, substeps=1 if articulated else point.substeps,
            iterations=method.iterations, max_rotation_angle=method.max_rotation_angle,
            articulation_integrator=method.articulation_integrator or "leapfrog",
            articulation_substeps=point.substeps if articulated else None, sleep=self.sleep,
        )
        world.profiling = False
        return world


def log_counts(lo: int, hi: int, k: int) -> list[int]:
    """``k`` integers log-spaced from ``lo`` to ``hi`` (duplicates dropped)."""
    return sorted({int(round(x)) for x in np.geomspace(lo, hi, max(k, 2))})


def dt_sweep(duration: float, lo: int, hi: int, k: int, substeps: int = 1) -> list[Point]:
    """Runs of ``duration`` (s) in ``lo`` … ``hi`` steps (dt = duration/steps)."""
    return [Point(n, duration / n, substeps) for n in log_counts(lo, hi, k)]


def substep_sweep(duration: float, dt: float, lo: int, hi: int, k: int) -> list[Point]:
    """Runs of ``duration`` (s) at a fixed frame ``dt`` with ``lo`` … ``hi`` substeps."""
    n = int(round(duration / dt))
    return [Point(n, dt, s) for s in log_counts(lo, hi, k)]
