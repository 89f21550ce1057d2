"""Joint problems: the same hinged pendulum and chain as an articulation in reduced
coordinates (every ``ARTICULATION_INTEGRATORS`` entry over dt, one articulation
substep per step, nothing automatic) and as XPBD joints (over substeps at a fixed
frame): the 1 m pendulum from 0.5 rad of REFERENCES.md ("Pendulum") against its
elliptic-integral period, and a chain released from horizontal ("Jointed chain
released horizontally") against its exact initial energy."""
from __future__ import annotations

import math
from abc import abstractmethod

import numpy as np

from .. import ARTICULATION_INTEGRATORS, Box, Scene, Sphere, StateError, World
from . import exact
from .base import Config, Method, Metrics, Point, Problem, dt_sweep, substep_sweep

G = 9.81
FRAME = 1 / 60


def hermite_falls(t0: float, dt: float, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Times where ``x`` (sampled every ``dt`` from ``t0``, rate ``v``) falls through 0,
    located on the cubic Hermite interpolant: fourth-order accurate, so it does not
    hide the error of a fourth-order method."""
    out = []
    for k in np.nonzero((x[:-1] > 0) & (x[1:] <= 0))[0]:
        y0, y1, d0, d1 = x[k], x[k + 1], v[k] * dt, v[k + 1] * dt
        roots = np.roots([2 * (y0 - y1) + d0 + d1, 3 * (y1 - y0) - 2 * d0 - d1, d0, y0])
        real = roots[np.abs(roots.imag) < 1e-9].real
        guess = y0 / (y0 - y1)
        s = real[np.argmin(np.abs(real - guess))] if len(real) else guess
        out.append(t0 + (k + s) * dt)
    return np.array(out)


def articulation_methods(orders: dict[str, float] | None = None) -> list[Method]:
    """One curve per articulation integrator (nominal order from ``orders``, else
    ``ARTICULATION_INTEGRATORS``)."""
    return [Method(f"articulation {name}", articulation_integrator=name,
                   order=float((orders or {}).get(name, order)))
            for name, order in ARTICULATION_INTEGRATORS.items()]


class JointProblem(Problem):
    """A jointed scene, built with its joints as one method asks (``scene(copies,
    solver)``); articulation curves sweep dt over ``rates`` (steps per simulated
    second, per integrator), the XPBD curve the substeps of ``FRAME``."""

    duration: float = 2.0
    rates: dict[str, tuple[int, int]] = {}
    xpbd_substeps: tuple[int, int] = (1, 128)

    @abstractmethod
    def scene(self, copies: int, solver: str = "auto") -> Scene:
        """The scene with ``copies`` instances, its joints built with ``solver``."""

    def scene_for(self, method: Method, copies: int) -> Scene:
        return self.scene(copies, method.joint_solver)

    def xpbd_method(self) -> Method:
        return Method("XPBD joints, 1 iteration", order=1.0)

    def methods(self, cfg: Config) -> list[Method]:
        return articulation_methods() + [self.xpbd_method()]

    def duration_for(self, cfg: Config) -> float:
        return self.duration

    def points(self, method: Method, cfg: Config) -> list[Point]:
        t = self.duration_for(cfg)
        if method.articulation_integrator is None:
            return substep_sweep(t, FRAME, *self.xpbd_substeps, cfg.points)
        lo, hi = self.rates[method.articulation_integrator]
        return dt_sweep(t, round(lo * t), round(hi * t), cfg.points)


class HingePendulum(JointProblem):
    name = "hinge_pendulum"
    title = "Hinged pendulum: articulation vs XPBD"
    error_label = "period error |T/T_exact − 1|"
    reference = ("ball r = 5 cm, 1 kg, on a hinge 1 m from the pivot, released at rest from θ0 = 0.5 rad: "
                 "T = 4 K(sin²(θ0/2)) √(L_eq/g), L_eq = L + (2/5) r²/L (the ball turns with the rod), over "
                 "the first two periods; articulations over dt (one articulation substep per step), XPBD over "
                 "substeps of 1/60 s. The symplectic `euler` keeps the period to second order (its phase is "
                 "first order: `phase_error`)")
    targets = (1e-3, 1e-6)
    extras = {"phase_error": "|θ(T) − θ_exact(T)| at the end (rad)", "stretch": "largest pivot gap (m)"}
    length, radius, mass, theta0 = 1.0, 0.05, 1.0, 0.5
    rates = {"leapfrog": (15, 1500), "euler": (15, 1500), "rk4": (5, 500)}

    def methods(self, cfg: Config) -> list[Method]:
        # The period of a symplectic method is second order: euler's is (its phase is not).
        return articulation_methods({"euler": 2.0}) + [self.xpbd_method()]

    @property
    def equivalent_length(self) -> float:
        return self.length + 0.4 * self.radius**2 / self.length

    def period(self) -> float:
        return exact.pendulum_period(self.equivalent_length, self.theta0, G)

    def angle(self, t: float) -> float:
        """θ(t) from rest at θ0: sin(θ/2) = k sn(K − ω0 t | k²), k = sin(θ0/2)."""
        k = math.sin(self.theta0 / 2)
        w0 = math.sqrt(G / self.equivalent_length)
        sn, _, _ = exact.ellipj(exact.ellipk(k * k) - w0 * t, k * k)
        return 2.0 * math.asin(k * float(sn))

    def duration_for(self, cfg: Config) -> float:
        return 2.2 * self.period()

    def copies(self, cfg: Config) -> int:
        return cfg.copies

    def scene(self, copies: int, solver: str = "auto") -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        s, c = math.sin(self.theta0), math.cos(self.theta0)
        for k in range(copies):
            pivot = (2.0 * k, 0.0, 0.0)
            ball = scene.add_body(Sphere(self.radius), mass=self.mass,
                                  position=(2.0 * k + self.length * s, 0.0, -self.length * c))
            scene.add_joint("hinge", ball, None, anchor=pivot, axis=(0.0, 1.0, 0.0), solver=solver)
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        pos, vel = world.bodies.position, world.bodies.linear_velocity
        x, v, gap = np.empty(point.steps), np.empty(point.steps), 0.0
        for k in range(point.steps):
            try:
                world.step()
            except StateError:  # blew up: not finite any more
                return {"error": math.inf, "phase_error": math.inf, "stretch": math.inf}
            p, u = pos[0], vel[0]
            r2 = p[0] ** 2 + p[2] ** 2
            x[k], v[k] = math.atan2(p[0], -p[2]), (-p[2] * u[0] + p[0] * u[2]) / r2
            gap = max(gap, abs(math.sqrt(r2 + p[1] ** 2) - self.length))
        falls = hermite_falls(point.dt, point.dt, x, v)
        phase = abs(x[-1] - self.angle(point.steps * point.dt))
        if len(falls) < 2:
            return {"error": math.inf, "phase_error": phase, "stretch": gap}
        period = (falls[-1] - falls[0]) / (len(falls) - 1)
        return {"error": abs(period / self.period() - 1.0), "phase_error": phase, "stretch": gap}


class ChainEnergy(JointProblem):
    name = "chain_energy"
    title = "Chain released from horizontal: energy"
    error_label = "energy error max_t |E(t) − E0| / (M g L/2), 2 s"
    reference = ("10 boxes of 0.1 × 0.02 × 0.02 m, 0.1 kg in all (L = 1 m), hinged end to end about y, the first "
                 "to the world, released at rest from horizontal at the pivot's height: E0 = 0 exactly; "
                 "E = kinetic + potential energy sampled ~1000 times over 2 s (every step at the coarse end); "
                 "articulations over dt (one articulation substep per step, nothing automatic), XPBD joints over "
                 "substeps of 1/60 s")
    targets = (1e-2, 1e-4)
    ceiling = 1.0
    extras = {"gap": "largest joint gap (m)"}
    links, length, mass = 10, 1.0, 0.1
    rates = {"leapfrog": (120, 12_000), "euler": (120, 12_000), "rk4": (120, 12_000)}
    xpbd_substeps = (2, 256)

    def scene(self, copies: int, solver: str = "auto") -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        l = self.length / self.links
        half = (l / 2, 0.1 * l, 0.1 * l)  # along x
        for c in range(copies):
            y = 2.0 * c
            prev = None
            for k in range(self.links):
                body = scene.add_body(Box(half), mass=self.mass / self.links, position=((k + 0.5) * l, y, 0.0),
                                      collision_mask=0)
                scene.add_joint("hinge", body, prev, anchor=(k * l, y, 0.0), axis=(0.0, 1.0, 0.0), solver=solver)
                prev = body
        return scene

    def methods(self, cfg: Config) -> list[Method]:
        # euler (first order) only in the full report: it needs 10⁴ steps per second to get below 1e-2.
        arts = [m for m in articulation_methods() if cfg.full or m.articulation_integrator != "euler"]
        return arts + [self.xpbd_method()]

    def measure(self, world: World, point: Point) -> Metrics:
        scale = self.mass * G * self.length / 2
        half = np.array([self.length / self.links / 2, 0.0, 0.0])
        pos, rot = world.bodies.position, world.bodies.rotation
        worst, gap, e0 = 0.0, 0.0, 0.0  # e0: at rest, every link at the pivot's height
        # Sampled about 1000 times over the run (every step at the coarse end).
        every = max(1, point.steps // 1000)
        done = 0
        while done < point.steps:
            n = min(every, point.steps - done)
            try:
                world.step(n)
            except StateError:
                return {"error": math.inf, "gap": math.inf}
            done += n
            e = world.kinetic_energy() + world.potential_energy()
            if not math.isfinite(e):
                return {"error": math.inf, "gap": math.inf}
            worst = max(worst, abs(e - e0) / scale)
            ends, starts = pos[: self.links] + rot[: self.links] @ half, pos[: self.links] - rot[: self.links] @ half
            gap = max(gap, float(np.linalg.norm(starts[0])), float(np.linalg.norm(starts[1:] - ends[:-1], axis=1).max()))
        return {"error": worst, "gap": gap}
