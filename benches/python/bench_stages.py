#!/usr/bin/env python
"""Benchmark (not a test): a stage a scene does not need costs nothing, and the
ones it does need show their cost in ``world.profile()``.

Scenes of N boxes 0.1 x 0.2 x 0.4 m (rho 1000, random orientations, |omega| = 5
rad/s, dt 1/240 s, strang; the initial state of benches/peers/free_bodies.py):

* ``free``: bodies given by mass and inertia (no shape), no gravity: the pipeline is
  ``translate`` + ``rotate_asymmetric``, the bare integrator kernel;
* ``masked colliders``: the same bodies with their box shapes, every pair filtered
  out (``collision_mask=0``); ``masked ground``: plus a ground plane, restitution,
  friction and sleeping on, still no pair that can touch; ``forces cleared``: a force
  and a torque applied to every body, then ``world.clear_forces()``. None of these
  may add a stage or change the time;
* effects switched on: ``gravity`` (``forces``), ``contacts`` (the boxes resting
  upright on a ground plane, sleeping off, so every contact stage runs every step),
  ``contacts asleep`` (the same after the boxes fell asleep), ``joints`` (each box
  hung from a spherical joint to the world, in gravity) and ``shape matching`` (the
  free bodies plus N/8 linear clusters of 8 particles).

For each scene: the CPU time (``time.thread_time``: time waiting for a shared core
left out) of one ``world.step(k)`` call with profiling off, and, from a second call
with profiling on, each stage's share of that call's wall time (``world.profile()``
times stages by wall clock; within one call a uniform slowdown of the shared
machine cancels). What is outside every stage is the pipeline's own cost (state
check, normalisation, planning, the loop). The *bare kernel* is the ``translate``
and ``rotate_asymmetric`` stages of the ``free`` scene: the kernels
``benches/free_bodies.rs`` calls directly in ``pipeline/bare_kernel``. Medians of
--repeats, repetitions outermost (every scene once per round), after one warm-up
call. Prints a markdown table and one JSON line.

    python benches/python/bench_stages.py                    # ~1 min
    python benches/python/bench_stages.py --n 2000 --repeats 3
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from collections.abc import Callable

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "peers"))
from common import random_quats_xyzw  # noqa: E402  (the peer scenes' initial-state helpers)

import rigidrs as rr  # noqa: E402

HALF = np.array([0.05, 0.1, 0.2])
DENSITY = 1000.0
G = (0.0, 0.0, -9.81)
KERNEL = ("translate", "rotate_asymmetric")


def initial_state(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions on a 1 m grid in a square, random orientations and spin directions."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n)))
    i = np.arange(n)
    pos = np.stack([i % side, i // side, np.zeros(n)], 1).astype(float)
    quat = random_quats_xyzw(rng, n)
    d = rng.normal(size=(n, 3))
    return pos, quat, 5.0 * d / np.linalg.norm(d, axis=1, keepdims=True)


def boxes(scene: rr.Scene, n: int, shape: bool, **kw: object) -> None:
    box = rr.Box(HALF)
    props = box.mass_properties(DENSITY)
    for p, q, w in zip(*initial_state(n)):
        if shape:
            scene.add_body(box, density=DENSITY, position=p, orientation=q, angular_velocity=w, **kw)
        else:
            scene.add_body(mass=props.mass, inertia=props.principal_moments, position=p, orientation=q,
                           angular_velocity=w)


def free(n: int) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    boxes(scene, n, shape=False)
    return scene.build(dt=1 / 240)


def masked_colliders(n: int) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    boxes(scene, n, shape=True, collision_mask=0)
    return scene.build(dt=1 / 240)


def masked_ground(n: int) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(rr.Plane(offset=-10.0), fixed=True, friction=0.5, restitution=0.5)
    boxes(scene, n, shape=True, collision_mask=0, friction=0.5, restitution=0.5)
    return scene.build(dt=1 / 240, sleep=True)


def forces_cleared(n: int) -> rr.World:
    world = free(n)
    for i in range(n):
        world.apply_force(i, (1.0, 0.0, 0.0), point=world.bodies.position[i] + HALF)
        world.apply_torque(i, (0.0, 0.1, 0.0))
    world.clear_forces()
    return world


def gravity(n: int) -> rr.World:
    scene = rr.Scene(gravity=G)
    boxes(scene, n, shape=False)
    return scene.build(dt=1 / 240)


def resting(n: int, sleep: bool) -> rr.World:
    scene = rr.Scene(gravity=G)
    scene.add_body(rr.Plane(), fixed=True)
    pos, _, _ = initial_state(n)
    for p in pos:
        scene.add_body(rr.Box(HALF), density=DENSITY, position=p + (0.0, 0.0, HALF[2]))
    world = scene.build(dt=1 / 240, sleep=sleep)
    world.step(480)  # settle (and fall asleep: 0.5 s at rest)
    assert not sleep or world.bodies.sleeping[1:].all()
    return world


def joints(n: int) -> rr.World:
    scene = rr.Scene(gravity=G)
    boxes(scene, n, shape=False)
    pos, _, _ = initial_state(n)
    for i, p in enumerate(pos):
        scene.add_joint("spherical", i, None, anchor=p + (0.0, 0.0, 0.3))
    return scene.build(dt=1 / 240)


def shape_matching(n: int) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    boxes(scene, n, shape=False)
    corners = 0.05 * np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    pos, _, _ = initial_state(n // 8, seed=1)
    for p in pos:
        ids = [scene.add_particle(p + (0.5, 0.5, 1.0) + c, mass=0.1, velocity=(0.0, 0.0, 0.1)) for c in corners]
        scene.add_shape_matching(ids, mode="linear")
    return scene.build(dt=1 / 240)


SCENES: dict[str, tuple[str, Callable[[int], rr.World]]] = {
    "free": ("free bodies (mass + inertia, no shape)", free),
    "masked colliders": ("+ box colliders, every pair filtered (collision_mask=0)", masked_colliders),
    "masked ground": ("+ ground plane, friction, restitution, sleep on; every pair filtered", masked_ground),
    "forces cleared": ("+ a force and torque on every body, then clear_forces()", forces_cleared),
    "gravity": ("gravity on", gravity),
    "contacts": ("boxes resting on a ground plane, sleep off", lambda n: resting(n, False)),
    "contacts asleep": ("the same, every box asleep", lambda n: resting(n, True)),
    "joints": ("each box on a spherical joint to the world, gravity", joints),
    "shape matching": ("free bodies + N/8 linear clusters of 8 particles", shape_matching),
}


def measure(world: rr.World, k: int) -> tuple[float, float, dict[str, float]]:
    """CPU seconds of one world.step(k) with profiling off; then, for another call
    with profiling on, its wall seconds and world.profile()'s (wall) seconds per stage."""
    world.profiling = False
    c0 = time.thread_time()
    world.step(k)
    cpu = time.thread_time() - c0
    world.profiling = True
    world.profile(reset=True)
    t0 = time.perf_counter()
    world.step(k)
    wall = time.perf_counter() - t0
    prof = world.profile()
    return cpu, wall, {name: s for name, s in prof.items() if name != "steps"}


def run(n: int, k: int, repeats: int) -> dict[str, dict]:
    """Per scene: medians over the rounds of the CPU time per step and of each stage's
    share of the profiled call (the shares compare like with like: wall against wall
    within one call, so a uniform slowdown of a shared machine cancels)."""
    worlds = {name: make(n) for name, (_, make) in SCENES.items()}
    cpu: dict[str, list[float]] = {name: [] for name in SCENES}
    shares: dict[str, list[dict[str, float]]] = {name: [] for name in SCENES}
    for world in worlds.values():
        measure(world, k)  # warm-up
    for _ in range(repeats):
        for name, world in worlds.items():
            seconds, wall, prof = measure(world, k)
            cpu[name].append(seconds / k)
            shares[name].append({s: v / wall for s, v in prof.items()})
    out = {}
    for name in SCENES:
        share = {s: statistics.median(p.get(s, 0.0) for p in shares[name]) for s in shares[name][0]}
        out[name] = {
            "stages": worlds[name].stages,
            "step_s": statistics.median(cpu[name]),
            "step_s_min": min(cpu[name]),
            "step_s_max": max(cpu[name]),
            "stage_share": share,
            "outside_stages": statistics.median(1.0 - sum(p.values()) for p in shares[name]),
        }
    return out


def table(rows: dict[str, dict], n: int) -> str:
    free = rows["free"]
    kernel_share = sum(free["stage_share"].get(s, 0.0) for s in KERNEL)
    kernel = free["step_s"] * kernel_share
    lines = ["| scene | stages | CPU ms per step (median, min–max) | ÷ bare kernel | ÷ free | outside the stages | "
             "per stage (µs per step) |", "|---|---|---|---|---|---|---|"]
    for name, r in rows.items():
        per_stage = ", ".join(f"{s} {1e6 * v * r['step_s']:.0f}" for s, v in r["stage_share"].items())
        lines.append(
            f"| {name}: {SCENES[name][0]} | {len(r['stages'])} | {1e3 * r['step_s']:.3f} "
            f"({1e3 * r['step_s_min']:.3f}–{1e3 * r['step_s_max']:.3f}) | {r['step_s'] / kernel:.3f} | "
            f"{r['step_s'] / free['step_s']:.3f} | {100 * r['outside_stages']:.1f} % | {per_stage} |")
    lines.append(f"\nBare kernel: the translate + rotate_asymmetric stages of `free` ({100 * kernel_share:.1f} % of "
                 f"its step): {1e3 * kernel:.3f} ms per step, {1e9 * kernel / n:.1f} ns per body-step. Per-stage "
                 "times: each stage's share of a profiled call times the CPU time per step.")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=10_000, help="boxes per scene")
    ap.add_argument("--k", type=int, default=100, help="steps per timed call")
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--json", help="also write the JSON result to this file")
    a = ap.parse_args()
    rows = run(a.n, a.k, a.repeats)
    print(f"rigidrs {rr.__version__}: N = {a.n}, world.step({a.k}), CPU time, median of {a.repeats}\n")
    print(table(rows, a.n))
    for name, r in rows.items():
        print(f"  {name}: {', '.join(r['stages'])}")
    result = {"bench": "stages", "rigidrs": rr.__version__, "python": platform.python_version(),
              "machine": {"cpus": os.cpu_count(), "processor": platform.processor() or platform.machine()},
              "date": time.strftime("%Y-%m-%d"), "n": a.n, "k": a.k, "repeats": a.repeats, "scenes": rows}
    line = json.dumps(result)
    print(line)
    if a.json:
        with open(a.json, "w") as f:
            f.write(line + "\n")


if __name__ == "__main__":
    main()
