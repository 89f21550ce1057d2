"""Rigid-body problems swept over dt for every integrator: the torque-free
asymmetric top, the Dzhanibekov flip, the symmetric disc, the fast thin rod and the
projectile (REFERENCES.md, "Free rigid body" and "Under gravity and torque"), and
the fast spinner at coarse steps ("Contacts and joints at default settings"), with
and without the automatic rotation substeps."""
from __future__ import annotations

import math

import numpy as np

from .. import INTEGRATORS, Box, Scene, StateError, World
from . import exact
from .base import Config, Method, Metrics, Point, Problem, dt_sweep

# Step counts (coarsest, finest) per integrator for the smooth tops: two decades
# each, the coarse end still asymptotic, the fine end still above round-off
# (the ranges of tests/test_convergence.py, where both ends are checked).
TOP_STEPS = {
    "euler": (100, 10_000),
    "symplectic_euler": (100, 10_000),
    "implicit_gyro": (100, 10_000),
    "strang": (20, 2_000),
    "rk4": (10, 1_000),
    "yoshida4": (7, 700),
    "suzuki4": (4, 400),
}


# Steps per simulated second (coarsest, finest) for the Dzhanibekov flip: the error
# of a near-separatrix flip grows fast with h (rk4 is pre-asymptotic below 40
# steps/s, suzuki4 below 10), and the round-off of E and |L| (~1e-13 after 10⁴
# steps) moves the flip times by 1e-10 to 1e-9 of themselves (the half-period goes
# as log(1/(M² − 2EI2)), and M² − 2EI2 is 2e-5 of M² here).
FLIP_RATES = {
    "euler": (60, 6_000),
    "symplectic_euler": (60, 6_000),
    "implicit_gyro": (60, 6_000),
    "strang": (15, 1_500),
    "rk4": (40, 4_000),
    "yoshida4": (10, 1_000),
    "suzuki4": (10, 1_000),
}


def every_integrator() -> list[Method]:
    return [Method(name, integrator=name, order=order) for name, order in INTEGRATORS.items()]


def box_moments(mass: float, size: tuple[float, float, float]) -> tuple[float, float, float]:
    """Principal moments of a solid box of edges ``size`` (m)."""
    a, b, c = size
    return (mass / 12 * (b * b + c * c), mass / 12 * (a * a + c * c), mass / 12 * (a * a + b * b))


def body_omega(world: World, i: int = 0) -> np.ndarray:
    """Body-frame angular velocity of body ``i``."""
    return np.asarray(world.bodies.rotation[i].T @ world.bodies.angular_velocity[i])


def drifts(world: World, e0: float, l0: float) -> Metrics:
    """Relative change of the kinetic energy and of |L| of body 0."""
    l1 = float(np.linalg.norm(world.bodies.angular_momentum[0]))
    e1 = 0.5 * float(np.sum(world.bodies.inertia[0] * body_omega(world) ** 2))
    return {"energy_drift": abs(e1 / e0 - 1.0), "L_drift": abs(l1 / l0 - 1.0)}


class FreeBody(Problem):
    """A body without torque (or in gravity), stepped in one call; ``copies`` bodies
    side by side in the timed runs."""

    duration: float = 1.0
    inertia: tuple[float, float, float] = (1.0, 1.0, 1.0)
    w0_body: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotvec0: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gravity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    extras = {"energy_drift": "|E/E0 − 1| at the end", "L_drift": "||L|/|L0| − 1| at the end"}

    def methods(self, cfg: Config) -> list[Method]:
        return every_integrator()

    def copies(self, cfg: Config) -> int:
        return cfg.copies

    @property
    def r0(self) -> np.ndarray:
        return np.asarray(exact.expm_so3(np.array(self.rotvec0)))

    def scene(self, copies: int) -> Scene:
        scene = Scene(gravity=self.gravity)
        q = exact.matrix_to_quat(self.r0)
        w = self.r0 @ np.array(self.w0_body)
        for k in range(copies):
            self.add(scene, (2.0 * k, 0.0, 0.0), q, w)
        return scene

    def add(self, scene: Scene, position: tuple[float, float, float], q: np.ndarray, w: np.ndarray) -> None:
        scene.add_body(mass=1.0, inertia=self.inertia, position=position, orientation=q, angular_velocity=w)

    def invariants(self) -> tuple[float, float]:
        i, w = np.array(self.inertia), np.array(self.w0_body)
        return 0.5 * float(np.sum(i * w * w)), float(np.linalg.norm(i * w))


class AsymmetricTop(FreeBody):
    name = "top"
    title = "Torque-free asymmetric top"
    error_label = "orientation error ‖log(R_refᵀR)‖ at T (rad)"
    reference = ("I = (1, 1.6, 2.1) kg·m², body ω0 = (1, 0.5, 1.5) rad/s, T = 4 s; Landau–Lifshitz elliptic "
                 "solution, orientation by quadrature (checked against DOP853 to 1e-12 rad)")
    targets = (1e-3, 1e-6, 1e-9)
    duration = 4.0
    inertia = (1.0, 1.6, 2.1)
    w0_body = (1.0, 0.5, 1.5)
    rotvec0 = (0.3, -0.5, 0.8)

    def points(self, method: Method, cfg: Config) -> list[Point]:
        lo, hi = TOP_STEPS[method.integrator]
        return dt_sweep(self.duration, lo, hi, cfg.points)

    def measure(self, world: World, point: Point) -> Metrics:
        e0, l0 = self.invariants()
        world.step(point.steps)
        top = exact.EllipticTop.from_initial(self.inertia, self.w0_body, self.r0)
        r_ref = top.rotation([world.time])[0]
        return {"error": float(exact.rotation_angle(r_ref, world.bodies.rotation[0])), **drifts(world, e0, l0)}


class Disc(FreeBody):
    name = "disc"
    title = "Symmetric disc wobble"
    error_label = "orientation error ‖log(R_refᵀR)‖ at T (rad)"
    reference = ("thin disc I = (0.25, 0.25, 0.5) kg·m², spin 4 rad/s, wobble at |L|/I1, T = 10 s; closed form "
                 "R(t) = exp(t L̂/I1) R0 exp(t (I1 − I3)/I1 ω3 ê3)")
    targets = (1e-3, 1e-6, 1e-9)
    # strang and its compositions are exact here: their error is round-off, ~1e-16
    # rad per stage, up to 2e-12 after 10⁴ steps of suzuki4.
    floor = 1e-10
    duration = 10.0
    inertia = (0.25, 0.25, 0.5)
    w0_body = (0.3, 0.2, 4.0)
    rotvec0 = (0.4, 0.2, -0.7)

    def points(self, method: Method, cfg: Config) -> list[Point]:
        # First-order methods turn the disc by more than a radian wrong below 1000 steps.
        lo = 1_000 if INTEGRATORS[method.integrator] == 1 else 100
        return dt_sweep(self.duration, lo, 100 * lo, cfg.points)

    def measure(self, world: World, point: Point) -> Metrics:
        e0, l0 = self.invariants()
        world.step(point.steps)
        r_ref = exact.symmetric_top(self.inertia, self.r0, self.r0 @ np.array(self.w0_body), [world.time])[0]
        return {"error": float(exact.rotation_angle(r_ref, world.bodies.rotation[0])), **drifts(world, e0, l0)}


class FastRod(FreeBody):
    name = "rod"
    title = "Fast thin rod"
    error_label = "energy error max |E/E0 − 1| over T"
    reference = ("I = (1, 1.005, 0.01) kg·m², |ω| = 50 rad/s at 10° from the long axis; E is conserved, "
                 "orientation against the elliptic solution")
    targets = (1e-2, 1e-4, 1e-6)
    floor = 1e-11
    extras = {"angle": "orientation error at T (rad)", "L_drift": "||L|/|L0| − 1| at the end"}
    inertia = (1.0, 1.005, 0.01)
    w0_body = (50.0 * math.sin(math.radians(10.0)), 0.0, 50.0 * math.cos(math.radians(10.0)))

    def duration_for(self, cfg: Config) -> float:
        return 10.0 if cfg.full else 2.0

    def points(self, method: Method, cfg: Config) -> list[Point]:
        t = self.duration_for(cfg)
        return dt_sweep(t, int(100 * t), int(10_000 * t), cfg.points)

    def measure(self, world: World, point: Point) -> Metrics:
        e0, l0 = self.invariants()
        every = max(1, point.steps // 2000)
        worst = 0.0
        for _ in range(point.steps // every):
            try:
                world.step(every)
            except StateError:  # blew up: not finite any more
                return {"error": math.inf, "angle": math.pi, "L_drift": math.inf}
            worst = max(worst, abs(world.kinetic_energy() / e0 - 1.0))
        world.step(point.steps % every)
        top = exact.EllipticTop.from_initial(self.inertia, self.w0_body)
        r_ref = top.rotation([world.time])[0]
        angle = float(exact.rotation_angle(r_ref, world.bodies.rotation[0]))
        l_drift = abs(float(np.linalg.norm(world.bodies.angular_momentum[0])) / l0 - 1.0)
        return {"error": worst, "angle": angle, "L_drift": l_drift}


class Projectile(FreeBody):
    name = "projectile"
    title = "Projectile (spinning box in gravity)"
    error_label = "position error |p − p_exact| at T (m)"
    reference = "p(t) = p0 + v0 t + g t²/2, T = 2 s; a box 0.1 × 0.4 × 0.9 m spinning near its intermediate axis"
    targets = (1e-2, 1e-4, 1e-6)
    # The second-order splittings and RK4 are exact for a constant force: round-off,
    # ~1 ulp of |p| ≈ 10 m per step, up to 3e-12 m after 6000 steps.
    floor = 1e-10
    duration = 2.0
    gravity = (0.0, 0.0, -9.81)
    extras = {"velocity_error": "|v − v_exact| at T (m/s)"}
    v0 = np.array([3.0, -1.0, 8.0])

    def add(self, scene: Scene, position: tuple[float, float, float], q: np.ndarray, w: np.ndarray) -> None:
        scene.add_body(Box(half_extents=(0.05, 0.2, 0.45)), mass=10.0, position=position, orientation=q,
                       linear_velocity=self.v0, angular_velocity=(0.1, 5.0, 0.1))

    def points(self, method: Method, cfg: Config) -> list[Point]:
        return dt_sweep(self.duration, 60, 6_000, cfg.points)

    def measure(self, world: World, point: Point) -> Metrics:
        world.step(point.steps)
        t, g = world.time, np.array(self.gravity)
        p = self.v0 * t + 0.5 * g * t * t
        return {"error": float(np.linalg.norm(world.bodies.position[0] - p)),
                "velocity_error": float(np.linalg.norm(world.bodies.linear_velocity[0] - (self.v0 + g * t)))}


class Dzhanibekov(FreeBody):
    name = "flip"
    title = "Dzhanibekov flip times"
    error_label = "flip-time error max |t_k − t_k,exact| / t_k"
    reference = ("box 0.1 × 0.4 × 0.9 m, 10 kg, body ω0 = (0.1, 5, 0.1) rad/s: zeros of sn in the elliptic "
                 "solution (first flip 1.16596 s, half-period 3.02842 s); 4 flips (10 in the full report)")
    targets = (1e-2, 1e-4, 1e-6)
    floor = 2e-9
    extras = {"energy_drift": "|E/E0 − 1| at the end", "L_drift": "||L|/|L0| − 1| at the end"}
    w0_body = (0.1, 5.0, 0.1)
    inertia = box_moments(10.0, (0.1, 0.4, 0.9))

    def add(self, scene: Scene, position: tuple[float, float, float], q: np.ndarray, w: np.ndarray) -> None:
        scene.add_body(Box(half_extents=(0.05, 0.2, 0.45)), mass=10.0, position=position, orientation=q,
                       angular_velocity=w)

    def flips(self, count: int) -> np.ndarray:
        return exact.EllipticTop.from_initial(self.inertia, self.w0_body).flip_times(count)

    def points(self, method: Method, cfg: Config) -> list[Point]:
        flips = self.flips(10 if cfg.full else 4)
        t = flips[-1] + 0.25 * (flips[1] - flips[0])
        lo, hi = FLIP_RATES[method.integrator]
        return dt_sweep(t, round(lo * t), round(hi * t), cfg.points)

    def measure(self, world: World, point: Point) -> Metrics:
        e0, l0 = self.invariants()
        w = np.empty((point.steps + 1, 3))
        rot, omega = world.bodies.rotation, world.bodies.angular_velocity
        w[0] = rot[0].T @ omega[0]
        for k in range(1, point.steps + 1):
            world.step()
            w[k] = rot[0].T @ omega[0]
        exact_flips = self.flips(20)
        exact_flips = exact_flips[exact_flips < point.steps * point.dt]
        found = flip_times(w, point.dt, np.array(self.inertia))
        out = drifts(world, e0, l0)
        if len(found) < len(exact_flips):
            return {"error": math.inf, **out}
        return {"error": float(np.max(np.abs(found[: len(exact_flips)] / exact_flips - 1.0))), **out}


def flip_times(w: np.ndarray, dt: float, inertia: np.ndarray, axis: int = 1) -> np.ndarray:
    """Sign changes of ``w[:, axis]`` (body ω sampled every ``dt``), located by the cubic
    Hermite interpolant with the slopes of Euler's equations, ``I ω̇ = (Iω) × ω``:
    fourth-order accurate, so it does not hide the error of a fourth-order method."""
    y = w[:, axis]
    slope = (np.cross(inertia * w, w) / inertia)[:, axis] * dt
    out = []
    for k in np.nonzero(np.signbit(y[1:]) != np.signbit(y[:-1]))[0]:
        y0, y1, d0, d1 = y[k], y[k + 1], slope[k], slope[k + 1]
        # p(s) = y0 + d0 s + (3(y1 − y0) − 2d0 − d1) s² + (2(y0 − y1) + d0 + d1) s³
        roots = np.roots([2 * (y0 - y1) + d0 + d1, 3 * (y1 - y0) - 2 * d0 - d1, d0, y0])
        real = roots[np.abs(roots.imag) < 1e-9].real
        guess = y0 / (y0 - y1)
        s = real[np.argmin(np.abs(real - guess))] if len(real) else guess
        out.append((k + s) * dt)
    return np.array(out)


class FastSpinner(FreeBody):
    """The fast spinner of REFERENCES.md over dt, where the other problems are not:
    at 480 rad/s a step of 1/30 s turns the box by 16 rad. The curves with the
    engine's default rotation substeps (``max_rotation_angle=None``) keep the error
    of a step of ``max_rotation_angle`` at every dt, for a cost that does not depend
    on dt while the substeps are on; ``strang, no substeps`` shows the split alone."""

    name = "spinner"
    title = "Fast spinner at a coarse step"
    error_label = "energy error max |E/E0 − 1| over T"
    reference = ("box 0.1 × 0.4 × 0.9 m, 10 kg, body ω0 = 96 (0.1, 5, 0.1) rad/s (|ω| = 480 rad/s, near the "
                 "intermediate axis; 8 rad per step at dt = 1/60 s); E and |L| are conserved, T = 1 s (5 s in "
                 "the full report), dt from 1/30 to 1/3000 s")
    targets = (1e-2, 1e-3, 1e-4)
    floor = 1e-11
    ceiling = 1.0
    extras = {"L_drift": "||L|/|L0| − 1| at the end"}
    inertia = box_moments(10.0, (0.1, 0.4, 0.9))
    w0_body = (9.6, 480.0, 9.6)

    def methods(self, cfg: Config) -> list[Method]:
        auto = [Method(f"{name} (default substeps)", integrator=name, max_rotation_angle=None)
                for name in ("strang", "yoshida4", "suzuki4", "rk4")]
        return auto + [Method("strang, no substeps", integrator="strang", order=2.0),
                       Method("rk4, no substeps", integrator="rk4", order=4.0)]

    def duration_for(self, cfg: Config) -> float:
        return 5.0 if cfg.full else 1.0

    def points(self, method: Method, cfg: Config) -> list[Point]:
        t = self.duration_for(cfg)
        return dt_sweep(t, round(30 * t), round(3000 * t), cfg.points)

    def measure(self, world: World, point: Point) -> Metrics:
        e0, l0 = self.invariants()
        worst = 0.0
        for _ in range(point.steps):
            world.step()
            worst = max(worst, abs(world.kinetic_energy() / e0 - 1.0))
        l_drift = abs(float(np.linalg.norm(world.bodies.angular_momentum[0])) / l0 - 1.0)
        return {"error": worst, "L_drift": l_drift}
