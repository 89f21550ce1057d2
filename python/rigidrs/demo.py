"""The built-in demo: a box tumbling near its intermediate axis (the Dzhanibekov
effect), bodies under gravity and applied forces, a pyramid of boxes standing on
the ground, and a crowd of free bodies for speed. Prints what it measured; with
``--video`` also draws a ball knocking over a pyramid into a video file."""
from __future__ import annotations

import time
from typing import TextIO

import numpy as np

from . import INTEGRATORS, Box, Capsule, Cylinder, Plane, Scene, Sphere, World


def _body_frame_omega(world: World, i: int) -> np.ndarray:
    r = world.bodies.rotation[i]
    return r.T @ world.bodies.angular_velocity[i]


def _tumbling_box(seconds: float, integrator: str, out: TextIO) -> None:
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(Box(half_extents=(0.05, 0.2, 0.45)), mass=10.0, angular_velocity=(0.1, 5.0, 0.1))
    dt = 1.0 / 240.0
    world = scene.build(dt=dt, integrator=integrator)
    e0, l0 = world.kinetic_energy(), np.linalg.norm(world.angular_momentum())
    flips: list[float] = []
    prev = _body_frame_omega(world, 0)[1]
    n = int(round(seconds / dt))
    elapsed = 0.0
    for _ in range(n):
        t0 = time.perf_counter()
        world.step()
        elapsed += time.perf_counter() - t0
        wy = _body_frame_omega(world, 0)[1]
        if np.sign(wy) != np.sign(prev):
            flips.append(world.time - dt * wy / (wy - prev))
        prev = wy
    e1, l1 = world.kinetic_energy(), np.linalg.norm(world.angular_momentum())
    out.write(f"tumbling box 0.1 x 0.4 x 0.9 m, 10 kg, w0 = (0.1, 5, 0.1) rad/s, dt = 1/240 s, {seconds:g} s:\n")
    out.write(f"  energy drift {e1 / e0 - 1:+.2e}, |L| drift {l1 / l0 - 1:+.2e}\n")
    if len(flips) >= 2:
        intervals = np.diff(flips)
        out.write(f"  {len(flips)} flips of w_y, first at {flips[0]:.5f} s (exact 1.16596), "
                  f"half-period {intervals.mean():.5f} s (exact 3.02842), spread {np.ptp(intervals):.1e} s\n")
    out.write(f"  stages: {', '.join(world.stages)}; {n / elapsed:,.0f} steps/s through Python\n")


def _forces(seconds: float, integrator: str, out: TextIO) -> None:
    scene = Scene()
    ball = scene.add_body(Sphere(radius=0.1), density=1000.0, position=(0, 0, 10), linear_velocity=(3, 0, 5))
    rod = scene.add_body(Cylinder(radius=0.02, half_height=0.5), density=2700.0, position=(2, 0, 10))
    pill = scene.add_body(Capsule(radius=0.1, half_height=0.2), density=500.0, position=(4, 0, 10))
    dt = 1.0 / 240.0
    world = scene.build(dt=dt, integrator=integrator)
    m = world.bodies.mass
    world.apply_force(rod, (0.0, 0.0, 9.81 * m[rod]))  # holds it up
    world.apply_force(rod, (0.5, 0.0, 0.0), point=(2.0, 0.0, 10.5))  # pushes its top sideways
    world.apply_force(pill, (0.0, 0.0, 9.81 * m[pill]))
    world.apply_torque(pill, (0.0, 0.01, 0.0))
    n = int(round(seconds / dt))
    world.step(n)
    t = world.time
    exact = np.array([3.0 * t, 0.0, 10.0 + 5.0 * t - 0.5 * 9.81 * t * t])
    err = np.linalg.norm(world.bodies.position[ball] - exact)
    out.write(f"bodies under gravity and applied forces, {seconds:g} s:\n")
    out.write(f"  projectile position error {err:.1e} m after {t:g} s (exact parabola)\n")
    out.write(f"  rod held up, pushed at its top: |w| = {np.linalg.norm(world.bodies.angular_velocity[rod]):.3g} rad/s; "
              f"capsule spun by a torque: |w| = {np.linalg.norm(world.bodies.angular_velocity[pill]):.3g} rad/s\n")
    out.write(f"  stages: {', '.join(world.stages)}\n")


def _crowd(integrator: str, out: TextIO, n: int = 10_000, steps: int = 240) -> None:
    rng = np.random.default_rng(0)
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    shape = Box(half_extents=(0.05, 0.1, 0.2))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w = rng.normal(size=(n, 3))
    w *= 5.0 / np.linalg.norm(w, axis=1, keepdims=True)
    for i in range(n):
        scene.add_body(shape, density=1000.0, position=(i % 100, i // 100, 0.0), orientation=q[i], angular_velocity=w[i])
    world = scene.build(dt=1.0 / 240.0, integrator=integrator)
    e0 = world.kinetic_energy()
    best = float("inf")
    for _ in range(3):
        world.profile(reset=True)
        t0 = time.perf_counter()
        world.step(steps)
        elapsed = time.perf_counter() - t0
        if elapsed < best:
            best, profile = elapsed, world.profile()
    per_stage = {k: v for k, v in profile.items() if k != "steps"}
    out.write(f"{n} free boxes spinning at 5 rad/s, {steps} steps: {n * steps / best / 1e6:.1f} M body-steps/s "
              f"(one core), energy drift {world.kinetic_energy() / e0 - 1:+.1e}\n")
    out.write("  time per body-step by stage: "
              + ", ".join(f"{k} {v / (n * steps) * 1e9:.1f} ns" for k, v in per_stage.items()) + "\n")


def _pyramid(integrator: str, out: TextIO, base: int = 10, seconds: float = 10.0) -> None:
    scene = Scene()
    scene.add_body(Plane(), fixed=True, friction=0.5)
    start = []
    for row in range(base):
        k = base - row
        for j in range(k):
            start.append(((j - (k - 1) / 2) * 1.02, 0.0, 0.5 + row))
            scene.add_body(Box(half_extents=(0.5, 0.5, 0.5)), density=1000.0, position=start[-1], friction=0.5)
    dt = 1.0 / 60.0
    world = scene.build(dt=dt, integrator=integrator, sleep=False)
    n = int(round(seconds / dt))
    deepest = 0.0
    t0 = time.perf_counter()
    for _ in range(n):
        world.step()
        deepest = max(deepest, float(world.contacts()["depth"].max(initial=0.0)))
    elapsed = time.perf_counter() - t0
    moved = np.linalg.norm(world.bodies.position[1:] - np.array(start), axis=1).max()
    out.write(f"pyramid of {len(start)} boxes on the ground at 60 Hz, {seconds:g} s: largest displacement "
              f"{moved * 1000:.1f} mm, deepest penetration {deepest * 1000:.2f} mm (slop 5 mm), "
              f"{n / elapsed:,.0f} steps/s with contacts read every step\n")
    out.write(f"  stages: {', '.join(world.stages)}\n")


def knockdown_scene() -> Scene:
    """The video's scene: a heavy ball rolls into a pyramid of 15 boxes."""
    s = Scene()
    s.add_body(Plane(), fixed=True, friction=0.6)
    for row in range(5):
        for j in range(5 - row):
            s.add_body(Box(half_extents=(0.2, 0.2, 0.2)), density=300.0, friction=0.6,
                       position=((j - (4 - row) / 2) * 0.41, 0.0, 0.2 + 0.4 * row))
    s.add_body(Sphere(radius=0.3), density=1500.0, friction=0.6, position=(-0.1, 3.0, 0.3),
               linear_velocity=(0.0, -4.0, 0.0))
    return s


def video(path: str, integrator: str = "strang", seconds: float = 3.0, out: TextIO | None = None) -> int:
    """Simulates :func:`knockdown_scene` for ``seconds`` (s) and draws it into ``path``
    (.mp4, .gif or .png: the last frame) with :func:`rigidrs.render`; says where."""
    import sys

    from .view import render
    from .view.render import Camera

    out = out or sys.stdout
    dt = 1.0 / 120.0
    world = knockdown_scene().build(dt=dt, integrator=integrator)
    rec = world.record(every=4)  # 30 frames per simulated second, the video's rate
    t0 = time.perf_counter()
    world.step(int(round(seconds / dt)))
    stepped = time.perf_counter() - t0
    camera = Camera(eye=(4.6, 4.2, 2.3), target=(0.0, 0.2, 0.6))
    t0 = time.perf_counter()
    try:
        render(world, rec, path, camera=camera, fps=30.0)
    except (OSError, ValueError, ImportError) as e:
        out.write(f"cannot write the video: {e}\n")
        return 2
    drawn = time.perf_counter() - t0
    frames = 1 if str(path).lower().endswith(".png") else len(rec)
    out.write(f"video: a ball rolls into a pyramid of 15 boxes, {seconds:g} s simulated in {stepped:.2f} s, "
              f"{frames} frame{'s' if frames > 1 else ''} drawn in {drawn:.1f} s without a display: {path}\n")
    return 0


def run(seconds: float = 60.0, integrator: str = "strang", out: TextIO | None = None) -> int:
    import sys

    out = out or sys.stdout
    if integrator not in INTEGRATORS:
        out.write(f"unknown integrator {integrator!r}; choose one of {', '.join(INTEGRATORS)}\n")
        return 2
    out.write(f"rigidrs demo, integrator {integrator!r} (order {INTEGRATORS[integrator]})\n\n")
    _tumbling_box(seconds, integrator, out)
    _forces(min(seconds, 1.0), integrator, out)
    _pyramid(integrator, out, seconds=min(seconds, 10.0))
    _crowd(integrator, out)
    return 0
