"""Contact problems swept over dt for a few substep and iteration counts: the
bouncing ball, the block on an incline and the sphere launched sliding
(REFERENCES.md, "Contact"), and at the default contact settings the tall tower of
equal cubes and the spinning plate ("Contacts and joints at default settings"),
the box sliding over a triangulated floor, and the kicked column of cubes at
fixed and chosen substeps."""
from __future__ import annotations

import math

import numpy as np

from .. import Box, Plane, Scene, Sphere, TriMesh, World
from .base import Config, Method, Metrics, Point, Problem, dt_sweep

G = 9.81


def contact_methods(cfg: Config, order: float | None = 1.0) -> list[Method]:
    """Substeps × iterations of the contact solver (the engine's default is 4 × 1)."""
    splits = [(1, 1), (4, 1), (16, 1), (4, 4)] + ([(1, 4), (16, 4)] if cfg.full else [])
    return [Method(f"{s} substep{'s' if s > 1 else ''} × {i}", substeps=s, iterations=i, order=order)
            for s, i in splits]


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
                 "12v0²/(49μg). The sphere rests at the rest depth δ = 1 µm whatever its load, the contact point "
                 "midway, so the lever arm is r − δ/2 and the measured slip v − ωr reaches 0 a fraction "
                 "(5/7)·δ/(2r) = 3.6e-6 early: t* and v* are within 4e-6 at every h (no slope above that floor, "
                 "set at 1e-5); the slip distance converges at first order in h")
    targets = (1e-2, 1e-3)
    floor = 1e-5
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


class Tower(ContactProblem):
    """REFERENCES.md "Tall tower of equal boxes" at the default contact settings."""

    name = "tower"
    title = "Tower of 30 cubes at rest"
    error_label = "load error max |F_k / W_k − 1| over the last 0.3 s"
    reference = ("30 cubes of 0.2 m (8 kg) stacked on a plane, placed touching, sleep off, T = 0.6 s: contact k "
                 "carries W_k = the weight of the cubes above it; measured after 0.3 s (the first steps sink "
                 "each contact to the 1 µm rest depth, a transient of a step or two); every point is exact or "
                 "within round-off, so no slope is fitted")
    targets = (1e-2, 1e-6)
    floor = 1e-3
    extras = {"sag": "|top − N a| at the end (m)", "tilt": "largest tilt (rad)",
              "settling": "worst load error of the first 0.3 s"}
    duration = 0.6
    sleep = False
    cubes, side = 30, 0.2

    def methods(self, cfg: Config) -> list[Method]:
        return [m for m in contact_methods(cfg, order=None) if cfg.full or m.substeps in (1, 4) and m.iterations == 1]

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        scene.add_body(Plane(), fixed=True)
        for c in range(copies):
            for i in range(self.cubes):
                scene.add_body(Box((self.side / 2,) * 3), density=1000.0,
                               position=(2.0 * c, 0.0, self.side / 2 + i * self.side))
        return scene

    def load_error(self, world: World, dt: float) -> float:
        c = world.contacts()
        loads = np.zeros(self.cubes + 1)
        np.add.at(loads, np.maximum(c["body_a"], c["body_b"]), c["normal_impulse"] / dt)
        weight = world.bodies.mass[1] * G * np.arange(self.cubes, 0, -1)
        return float(np.abs(loads[1:] / weight - 1.0).max())

    def measure(self, world: World, point: Point) -> Metrics:
        half = point.steps // 2
        every = max(1, half // 50)  # ~100 samples of the loads over the run
        worst, settling, done = 0.0, 0.0, 0
        while done < point.steps:
            n = 1 if done < 2 else min(every, point.steps - done)
            world.step(n)
            done += n
            e = self.load_error(world, point.dt)
            if done <= half:
                settling = max(settling, e)
            else:
                worst = max(worst, e)
        top = float(world.bodies.position[-1, 2]) + self.side / 2
        tilt = float(np.arccos(np.clip(world.bodies.rotation[1:, 2, 2], -1.0, 1.0)).max())
        return {"error": worst, "sag": abs(top - self.cubes * self.side), "tilt": tilt, "settling": settling}


class SpinningPlate(ContactProblem):
    """REFERENCES.md "Spinning plate (torsional friction)" at the default contact
    settings: the twist's lever is the patch's mean distance from its centre."""

    name = "spinning_plate"
    title = "Spinning plate stopped by torsional friction"
    error_label = "stop-time error |t_stop / t_exact − 1|"
    reference = ("square plate 0.4 × 0.4 × 0.04 m, μ = 0.4, spun at ω0 = 8 rad/s on a plane: friction over the "
                 "patch gives the torque μ m g r̄, r̄ = a (√2 + ln(1 + √2))/3 = 0.7652 a the mean distance of a "
                 "square of side 2a from its centre, so t_stop = I_z ω0 / (μ m g r̄) = 0.3551 s; the stop is "
                 "placed inside its step by the deceleration of the steps before (as in "
                 "tests/test_patch_friction.py); T = 0.5 s")
    targets = (1e-2, 1e-6)
    sleep = False
    floor = 1e-9
    extras = {"drift": "distance the centre moved (m)"}
    duration = 0.5
    half, mu, omega0 = 0.2, 0.4, 8.0

    def methods(self, cfg: Config) -> list[Method]:
        return [m for m in contact_methods(cfg, order=None) if cfg.full or m.substeps in (1, 4) and m.iterations == 1]

    def r_bar(self) -> float:
        return self.half * (math.sqrt(2.0) + math.log(1.0 + math.sqrt(2.0))) / 3.0

    def stop_time(self, mass: float, inertia: float) -> float:
        return inertia * self.omega0 / (self.mu * mass * G * self.r_bar())

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        scene.add_body(Plane(), fixed=True, friction=self.mu)
        thick = self.half / 10
        for k in range(copies):
            scene.add_body(Box((self.half, self.half, thick)), density=500.0, position=(2.0 * k, 0.0, thick),
                           friction=self.mu, angular_velocity=(0.0, 0.0, self.omega0))
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        p0 = world.bodies.position[1].copy()
        w = np.empty(point.steps + 1)
        w[0] = self.omega0
        for k in range(1, point.steps + 1):
            world.step()
            w[k] = world.bodies.angular_velocity[1, 2]
        drift = float(np.linalg.norm(world.bodies.position[1] - p0))
        stopped = np.nonzero(w <= 1e-9 * self.omega0)[0]
        if len(stopped) == 0 or stopped[0] < 3:
            return {"error": math.inf, "drift": drift}
        k = int(stopped[0])
        # Inside step k: the rate before it over the deceleration of the steps before that.
        rate = (w[k - 3] - w[k - 1]) / (2 * point.dt)
        t_stop = (k - 1) * point.dt + w[k - 1] / rate
        t_ref = self.stop_time(float(world.bodies.mass[1]), float(world.bodies.inertia[1][2]))
        return {"error": abs(t_stop / t_ref - 1.0), "drift": drift}


def triangulated_floor(cells: int, size: float) -> TriMesh:
    """A flat square floor of side ``size`` (m) about the origin, of ``cells`` ×
    ``cells`` squares each cut along a diagonal."""
    xs = np.linspace(-size / 2, size / 2, cells + 1)
    vertices = np.array([[x, y, 0.0] for y in xs for x in xs])
    corner = np.arange(cells * (cells + 1)).reshape(cells, cells + 1)[:, :cells].ravel()
    faces = np.concatenate([np.stack([corner, corner + 1, corner + cells + 2], axis=1),
                            np.stack([corner, corner + cells + 2, corner + cells + 1], axis=1)])
    return TriMesh(vertices, faces)


class MeshSlide(ContactProblem):
    """A box sliding over a floor given as triangles: its face rests on several at
    a time, whose manifolds share one friction patch (rust/solve/coplanar.rs)."""

    name = "mesh_slide"
    title = "Box sliding straight over a triangulated floor"
    error_label = "stop-distance error |d / (v0²/2μg) − 1|"
    reference = ("0.2 m cube launched at v0 = 3 m/s along x, μ = 0.3, over a flat TriMesh of 0.5 m squares cut along "
                 "their diagonals (the face on two to eight triangles at a time), its path 0.13 m off a row of "
                 "vertices: Coulomb friction stops it after v0²/(2 μ g) = 1.529 m without turning it; T = 1.2 s")
    targets = (1e-2, 1e-3)
    extras = {"yaw": "largest yaw rate (rad/s)", "drift": "sideways drift (m)"}
    duration = 1.2
    half, mu, v0 = 0.1, 0.3, 3.0

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        scene.add_body(triangulated_floor(16, 8.0), fixed=True, friction=self.mu)
        for k in range(copies):
            scene.add_body(Box((self.half,) * 3), density=1000.0, position=(-2.0, 0.13 + 0.5 * k, self.half),
                           linear_velocity=(self.v0, 0.0, 0.0), friction=self.mu)
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        p0 = world.bodies.position[1].copy()
        yaw = 0.0
        for _ in range(point.steps):
            world.step()
            yaw = max(yaw, abs(float(world.bodies.angular_velocity[1, 2])))
        d = world.bodies.position[1] - p0
        exact = self.v0**2 / (2 * self.mu * G)
        return {"error": abs(float(d[0]) / exact - 1.0), "yaw": yaw, "drift": abs(float(d[1]))}


class KickedColumn(ContactProblem):
    """Our case "kicked column" (tests/test_kicked_column.py) at a fixed 4 and 16
    substeps and at the default, which takes substeps of at most 1/960 s (16 at
    60 Hz) while a slow body rocks on its supports in a settling scene
    (``World.last_substeps``)."""

    name = "kicked_column"
    title = "Column of ten cubes kicked, coming to rest"
    error_label = "fastest cube at T over the kick's speed, max |v| / 0.1 m/s"
    reference = ("ten cubes of 0.5 m (μ 0.5) resting on each other 5 cm off each other's axis, kicked sideways "
                 "(seeded, σ 0.1 m/s and 0.1 rad/s): the kick's energy is a third of the least that tips a "
                 "cube over an edge, and inelastic contacts that rub only take energy out, so the column comes "
                 "to rest standing; T = 4 s. Errors of 0.3 and more are columns still moving or toppled")
    targets = (1e-2, 1e-6)
    floor = 1e-9
    extras = {"top": "|top − its resting height| (m)", "substeps_taken": "mean contact substeps a step took"}
    duration = 4.0
    sleep = False
    cubes, half, kick, seed = 10, 0.25, 0.1, 3

    def methods(self, cfg: Config) -> list[Method]:
        return [Method("4 substeps × 1", substeps=4), Method("default (4; substeps ≤ 1/960 s while rocking)"),
                Method("16 substeps × 1", substeps=16)]

    def build(self, method: Method, point: Point, copies: int = 1) -> World:
        world = self.scene(copies).build(dt=point.dt, substeps=method.substeps and point.substeps, sleep=False)
        world.profiling = False
        return world

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=(0.0, 0.0, -G))
        scene.add_body(Plane(), fixed=True, friction=0.5, restitution=0.0)
        for c in range(copies):
            rng = np.random.default_rng(self.seed)
            for k in range(self.cubes):
                x = 0.0 if k == 0 else 0.05 * (1 if k % 2 else -1)
                v = rng.normal(size=3) * self.kick * np.array([1.0, 1.0, 0.0])
                w = rng.normal(size=3) * self.kick
                scene.add_body(Box((self.half,) * 3), density=1000.0, position=(5.0 * c + x, 0.0, self.half * (1 + 2 * k)),
                               linear_velocity=tuple(v), angular_velocity=tuple(w), friction=0.5, restitution=0.0)
        return scene

    def measure(self, world: World, point: Point) -> Metrics:
        taken = 0
        for _ in range(point.steps):
            world.step()
            taken += world.last_substeps
        column = slice(1, 1 + self.cubes)
        speed = float(np.linalg.norm(world.bodies.linear_velocity[column], axis=1).max())
        top = abs(float(world.bodies.position[self.cubes, 2]) - self.half * (2 * self.cubes - 1))
        return {"error": speed / self.kick, "top": top, "substeps_taken": taken / point.steps}
