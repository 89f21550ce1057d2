"""Contact problems swept over dt for a few substep and iteration counts: the
bouncing ball, the block on an incline and the sphere launched sliding
(REFERENCES.md, "Contact")."""
from __future__ import annotations

import math

import numpy as np

from .. import Box, Plane, Scene, Sphere, World
from .base import Config, Method, Metrics, Point, Problem, dt_sweep

G = 9.81


def contact_methods(cfg: Config) -> list[Method]:
    """Substeps × iterations of the contact solver (the engine's default is 4 × 1)."""
    splits = [(1, 1), (4, 1), (16, 1), (4, 4)] + ([(1, 4), (16, 4)] if cfg.full else [])
    return [Method(f"{s} substep{'s' if s > 1 else ''} × {i}", substeps=s, iterations=i, order=1.0) for s, i in splits]


class ContactProblem(Problem):
    duration: float = 1.0

    def methods(self, cfg: Config) -> list[Method]:
        return contact_methods(cfg)

    def points(self, method: Method, cfg: Config) -> list[Point]:
        n = round(30 * self.duration)
        return dt_sweep(self.duration, n, 100 * n, cfg.points, substeps=method.substeps or 4)


def deepest(world: World) -> float:
    depth = world.contacts()["depth"]
    return float(depth.max()) if len(depth) else 0.0


class BouncingBall(ContactProblem):
    name = "bounce"
    title = "Bouncing ball"
    error_label = "apex-height error max_n |h_n / (e^2n h0) − 1|, 3 bounces"
    reference = "ball r = 0.1 m dropped from h0 = 1 m, e = 0.75: apex heights h_n = e^2n h0, first impact at √(2h0/g)"
    targets = (1e-2, 1e-3, 1e-4)
    extras = {"penetration": "deepest contact (m)", "impact_time": "|t_1 − √(2h0/g)| (s)"}
    duration = 1.9
    radius, h0, e = 0.1, 1.0, 0.75

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        scene.add_body(Plane(), fixed=True, restitution=self.e)
        for k in range(copies):
            scene.add_body(Sphere(self.radius), density=1000.0, position=(k, 0.0, self.h0 + self.radius),
                           restitution=self.e)
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        z, vz = np.empty(point.steps + 1), np.empty(point.steps + 1)
        pos, vel = world.bodies.position, world.bodies.linear_velocity
        z[0], vz[0], depth = pos[1, 2], vel[1, 2], 0.0
        for k in range(1, point.steps + 1):
            world.step()
            z[k], vz[k] = pos[1, 2], vel[1, 2]
            depth = max(depth, deepest(world))
        # The last sample of each rise is in free flight: its apex is z + vz²/2g exactly.
        rising = np.nonzero((vz[:-1] > 0) & (vz[1:] <= 0))[0]
        apex = z[rising] - self.radius + vz[rising] ** 2 / (2 * G)
        exact = self.h0 * self.e ** (2 * np.arange(1, 4))
        # The sample before the first bounce is in free flight: its parabola gives the impact time.
        k = int(np.argmax(vz > 0)) - 1
        fall = vz[k] + math.sqrt(vz[k] ** 2 + 2 * G * (z[k] - self.radius))
        impact = abs(k * point.dt + fall / G - math.sqrt(2 * self.h0 / G))
        if len(apex) < 3:
            return {"error": math.inf, "penetration": depth, "impact_time": impact}
        return {"error": float(np.abs(apex[:3] / exact - 1).max()), "penetration": depth, "impact_time": impact}


class Incline(ContactProblem):
    name = "incline"
    title = "Block on an incline (Coulomb)"
    error_label = "slide error |x(T) / (a T²/2) − 1|"
    reference = ("30° plane; a block with μ = 0.3 slides from rest with a = g (sin θ − μ cos θ), one with "
                 "μ = 0.8 > tan θ must not creep; T = 1 s")
    targets = (1e-2, 1e-3)
    extras = {"accel_error": "|v(T)/(a T) − 1| (the solver's convergence)", "creep": "held block's travel (m)",
              "penetration": "deepest contact (m)"}
    theta = math.radians(30.0)
    half = (0.2, 0.15, 0.1)

    def scene(self, copies: int) -> Scene:
        n = np.array([math.sin(self.theta), 0.0, math.cos(self.theta)])
        scene = Scene(gravity=(0.0, 0.0, -G))
        # Friction combines by the geometric mean: √(1 · 0.09) = 0.3, √(1 · 0.64) = 0.8.
        scene.add_body(Plane(normal=n, offset=0.0), fixed=True, friction=1.0)
        q = (0.0, math.sin(self.theta / 2), 0.0, math.cos(self.theta / 2))
        for k in range(copies):
            for j, mu in enumerate((0.09, 0.64)):
                pos = n * self.half[2] + np.array([0.0, 2.0 * (2 * k + j), 0.0])
                scene.add_body(Box(self.half), density=500.0, position=pos, orientation=q, friction=mu)
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        down = np.array([math.cos(self.theta), 0.0, -math.sin(self.theta)])
        p0 = world.bodies.position[1:3].copy()
        depth = 0.0
        for _ in range(point.steps):
            world.step()
            depth = max(depth, deepest(world))
        t = world.time
        a = G * (math.sin(self.theta) - 0.3 * math.cos(self.theta))
        x = float((world.bodies.position[1] - p0[0]) @ down)
        v = float(world.bodies.linear_velocity[1] @ down)
        creep = float(np.linalg.norm(world.bodies.position[2] - p0[1]))
        return {"error": abs(x / (0.5 * a * t * t) - 1), "accel_error": abs(v / (a * t) - 1), "creep": creep,
                "penetration": depth}


class SlipToRoll(ContactProblem):
    name = "slip_roll"
    title = "Sphere launched sliding, slip to roll"
    error_label = "rolling-onset error |t*/t*_exact − 1|"
    reference = ("r = 0.1 m, v0 = 3 m/s, μ = 0.5: rolls from t* = 2v0/(7μg) at v* = 5v0/7 after slipping "
                 "12v0²/(49μg). The soft contact (contact_hertz 30 Hz) sags by δ ≈ g/(2π·30 Hz)² = 0.28 mm, which "
                 "shortens the lever arm by δ/2: t* and v* keep an error of ~4e-4 that substeps do not remove "
                 "(the slope is fitted above 5e-4)")
    targets = (1e-2, 1e-3)
    floor = 5e-4
    extras = {"speed_error": "|v(T)/v* − 1|", "slip_error": "|s/s* − 1| (slip distance)"}
    duration = 0.5
    radius, v0, mu = 0.1, 3.0, 0.5

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        scene.add_body(Plane(), fixed=True, friction=self.mu)
        for k in range(copies):
            scene.add_body(Sphere(self.radius), density=500.0, position=(0.0, k, self.radius), friction=self.mu,
                           linear_velocity=(self.v0, 0.0, 0.0))
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        slip = np.empty(point.steps + 1)
        vel, omega = world.bodies.linear_velocity, world.bodies.angular_velocity
        slip[0] = vel[1, 0] - omega[1, 1] * self.radius
        x0 = world.bodies.position[1, 0]
        for k in range(1, point.steps + 1):
            world.step()
            slip[k] = vel[1, 0] - omega[1, 1] * self.radius
        t_star, v_star = 2 * self.v0 / (7 * self.mu * G), 5 * self.v0 / 7
        s_star = 12 * self.v0**2 / (49 * self.mu * G)
        # The slip falls linearly while it slides: extrapolate its last two sliding samples to zero.
        k = int(np.argmax(slip <= 1e-6 * self.v0)) - 1
        onset = (k + slip[k] / (slip[k - 1] - slip[k])) * point.dt if k >= 1 else math.inf
        v = vel[1, 0]
        s = world.bodies.position[1, 0] - x0 - v * (world.time - t_star)
        return {"error": abs(onset / t_star - 1), "speed_error": abs(v / v_star - 1), "slip_error": abs(s / s_star - 1)}
