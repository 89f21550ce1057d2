"""XPBD problems swept over substeps at a fixed frame, for a few iteration counts
(and, for the heavy top, integrators): the heavy symmetric top on a spherical joint,
the particle pendulum and the hanging chain (REFERENCES.md, "Under gravity and
torque" and "Position-based dynamics"). The heavy top's joint is also measured as
an articulation in reduced coordinates, over its articulation substeps."""
from __future__ import annotations

import math

import numpy as np

from .. import ARTICULATION_INTEGRATORS, INTEGRATORS, Scene, StateError, World
from . import exact
from .base import Config, Method, Metrics, Point, Problem, substep_sweep

G = 9.81


def iteration_methods(counts: list[int]) -> list[Method]:
    return [Method(f"{n} iteration{'s' if n > 1 else ''}", iterations=n, order=1.0) for n in counts]


class HeavyTop(Problem):
    name = "heavy_top"
    title = "Heavy symmetric top on a spherical joint"
    error_label = "precession-rate error |φ̇/φ̇_slow − 1|"
    reference = ("M = 1 kg, l = 0.1 m, I1 = 0.02 kg·m² about the pivot, I3 = 0.004 kg·m², ω3 = 200 rad/s, "
                 "θ = 30°, started in steady precession: slow root φ̇ = 1.26066 rad/s; frame 1/240 s, 2 s "
                 "(4 s full). The integrator curves pin the joint to XPBD (`solver=\"xpbd\"`) and sweep the "
                 "substeps; the articulation curves (the joint in reduced coordinates) sweep the articulation "
                 "substeps")
    targets = (1e-3, 1e-4)
    extras = {"tilt_drift": "largest change of the tilt (rad)", "stretch": "largest pivot gap (m)"}
    frame = 1 / 240
    m, l, i1, i3, w3, theta = 1.0, 0.1, 0.02, 0.004, 200.0, math.radians(30.0)

    def methods(self, cfg: Config) -> list[Method]:
        # XPBD costs 2–4 s per curve here (up to 1600 substeps per frame): the quick
        # report keeps the default integrator and the implicit one.
        names = list(INTEGRATORS) if cfg.full else ["strang", "implicit_gyro"]
        methods = [Method(f"{n} (XPBD joint)", integrator=n, order=1.0) for n in names]
        if cfg.full:
            methods.append(Method("strang (XPBD joint), 4 iterations", iterations=4, order=1.0))
        arts = [Method(f"articulation {n}", articulation_integrator=n, order=float(ARTICULATION_INTEGRATORS[n]))
                for n in (list(ARTICULATION_INTEGRATORS) if cfg.full else ["leapfrog", "rk4"])]
        return methods + arts

    def points(self, method: Method, cfg: Config) -> list[Point]:
        t = 4.0 if cfg.full else 2.0
        if method.articulation_integrator is not None:
            # From 0.06 (leapfrog, 2 substeps), 1e-2 (rk4, 1) and 4e-3 (euler, 32: measured, it
            # blows up at 2–7 and is off by 6× at 16 articulation substeps of 1/240 s).
            lo = {"leapfrog": 2, "euler": 32, "rk4": 1}[method.articulation_integrator]
            return substep_sweep(t, self.frame, lo, 128 * lo, cfg.points)
        # Below 16 substeps of 1/240 s the pivot's dissipation tilts the top by > 0.1 rad.
        return substep_sweep(t, self.frame, 16, 1600, cfg.points)

    def slow_root(self) -> float:
        return exact.heavy_top_slow_root(self.m, self.l, self.i1, self.i3, self.w3, self.theta, G)

    def scene_for(self, method: Method, copies: int) -> Scene:
        return self.scene(copies, method.joint_solver)

    def scene(self, copies: int, solver: str = "auto") -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        slow = self.slow_root()
        e3 = np.array([math.sin(self.theta), 0.0, math.cos(self.theta)])
        omega = slow * np.array([0.0, 0.0, 1.0]) + (self.w3 - slow * math.cos(self.theta)) * e3
        q = exact.matrix_to_quat(exact.expm_so3(np.array([0.0, self.theta, 0.0])))
        transverse = self.i1 - self.m * self.l**2  # about the centre of mass
        for k in range(copies):
            pivot = np.array([k, 0.0, 0.0])
            top = scene.add_body(mass=self.m, inertia=(transverse, transverse, self.i3), position=pivot + self.l * e3,
                                 orientation=q, angular_velocity=omega, linear_velocity=np.cross(omega, self.l * e3))
            scene.add_joint("spherical", top, None, anchor=pivot, solver=solver)
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        rot, pos = world.bodies.rotation, world.bodies.position
        phi, tilt, gap = np.empty(point.steps), np.empty(point.steps), 0.0
        for k in range(point.steps):
            try:
                world.step()
            except StateError:  # blew up: not finite any more
                return {"error": math.inf, "tilt_drift": math.inf, "stretch": math.inf}
            axis = rot[0][:, 2]
            phi[k], tilt[k] = math.atan2(axis[1], axis[0]), math.acos(axis[2])
            gap = max(gap, float(np.linalg.norm(pos[0] - self.l * axis)))
        t = point.dt * np.arange(1, point.steps + 1)
        rate = np.polyfit(t, np.unwrap(phi), 1)[0]
        return {"error": abs(rate / self.slow_root() - 1.0), "tilt_drift": float(np.abs(tilt - self.theta).max()),
                "stretch": gap}


class Pendulum(Problem):
    name = "pendulum"
    title = "XPBD particle pendulum"
    error_label = "period error |T/T_exact − 1|"
    reference = "L = 1 m, θ0 = 0.5 rad, frame 1/60 s: T = 4 K(sin²(θ0/2)) √(L/g), over the first two periods"
    targets = (1e-3, 1e-4)
    extras = {"stretch": "largest |length − L| (m)"}
    frame = 1 / 60
    theta0 = 0.5

    def methods(self, cfg: Config) -> list[Method]:
        return iteration_methods([1, 4])

    def period(self) -> float:
        return exact.pendulum_period(1.0, self.theta0, G)

    def points(self, method: Method, cfg: Config) -> list[Point]:
        return substep_sweep(2.2 * self.period(), self.frame, 1, 128, cfg.points)

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        for k in range(copies):
            pin = scene.add_particle((2.0 * k, 0, 0), fixed=True)
            bob = scene.add_particle((2.0 * k + math.sin(self.theta0), 0, -math.cos(self.theta0)), mass=1.0)
            scene.add_distance_constraint(pin, bob)
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        x, stretch = np.empty(point.steps), 0.0
        pos = world.particles.position
        for k in range(point.steps):
            world.step()
            x[k] = pos[1, 0]
            stretch = max(stretch, abs(float(np.linalg.norm(pos[1] - pos[0])) - 1.0))
        # Downward zero crossings, linear interpolation (x'' = −ω²x vanishes there: third order).
        i = np.nonzero((x[:-1] > 0) & (x[1:] <= 0))[0]
        crossings = (i + 1 + x[i] / (x[i] - x[i + 1])) * point.dt
        if len(crossings) < 2:
            return {"error": math.inf, "stretch": stretch}
        period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
        return {"error": abs(period / self.period() - 1.0), "stretch": stretch}


class HangingChain(Problem):
    name = "chain"
    title = "XPBD hanging chain, static elongation"
    error_label = "elongation error max_k |e_k − α W_k| / (α W_1)"
    reference = ("10 particles of 1 kg on links of 0.1 m, compliance α = 0.01 m/N, pinned at the top: link k "
                 "stretches by α × the weight it carries; started there at rest, frame 1/60 s, 2 s (10 s full)")
    targets = (1e-2, 1e-3)
    # Round-off: positions carry ~1e-16 m per substep against an elongation of 0.98 m.
    floor = 1e-8
    extras = {"force_error": "max_k |λ_k/h² + W_k| / W_1 at the end"}
    frame = 1 / 60
    links, mass, alpha, length = 10, 1.0, 1e-2, 0.1

    def methods(self, cfg: Config) -> list[Method]:
        return [Method(m.label, iterations=m.iterations, order=2.0) for m in iteration_methods([1, 4, 16])]

    def points(self, method: Method, cfg: Config) -> list[Point]:
        return substep_sweep(10.0 if cfg.full else 2.0, self.frame, 1, 128, cfg.points)

    def weights(self) -> np.ndarray:
        return self.mass * G * np.arange(self.links, 0, -1)

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        z = -np.cumsum(self.length + self.alpha * self.weights())
        for c in range(copies):
            ids = [scene.add_particle((float(c), 0, 0), fixed=True, mass=self.mass)]
            for k in range(self.links):
                ids.append(scene.add_particle((float(c), 0, z[k]), mass=self.mass))
                scene.add_distance_constraint(ids[-2], ids[-1], compliance=self.alpha, rest_length=self.length)
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        w = self.weights()
        target = self.alpha * w
        z = world.particles.position[:, 2]
        worst = 0.0
        for _ in range(point.steps):
            world.step()
            e = -np.diff(z[: self.links + 1]) - self.length
            worst = max(worst, float(np.abs(e - target).max()))
        force = float(np.abs(world.constraint_forces()[: self.links] + w).max())
        return {"error": worst / target[0], "force_error": force / w[0]}
