"""Benchmark (not a test): XPBD cost per substep and per constraint.

Two scenes, each stepped for a fixed simulated time after a short warm-up:

* a 100 × 100 cloth (10 000 particles; stretch/shear distance constraints on every
  triangle edge plus dihedral bending on every interior edge), pinned at two
  corners, falling onto a sphere: with and without particle–particle collisions;
* a 100-link chain (pinned at the top, compliance 0) swinging under gravity.

Reports the wall time per substep, per substep per constraint (and per
constraint pass), and the share of the `xpbd` stage from `world.profile()`.

    python benches/python/bench_xpbd.py [--quick]
"""
from __future__ import annotations

import argparse
import time

import numpy as np

import rigidrs as rr


def cloth(n: int, radius: float, substeps: int, iterations: int):
    scene = rr.Scene()
    scene.add_body(rr.Sphere(0.3), fixed=True, position=(0, 0, 0))
    scene.add_cloth((-0.5, -0.5, 0.5), (1, 0, 0), (0, 1, 0), (n, n), mass=0.5, radius=radius,
                    compliance=1e-7, bending_compliance=10.0, pinned=[0, n - 1])
    return scene, scene.build(dt=1 / 60, substeps=substeps, iterations=iterations)


def chain(links: int, substeps: int, iterations: int):
    scene = rr.Scene()
    scene.add_rope((0, 0, 0), (links * 0.02, 0, 0), links, mass=links * 0.01, pinned=[0])
    return scene, scene.build(dt=1 / 60, substeps=substeps, iterations=iterations)


def measure(name: str, scene, world, steps: int) -> dict:
    world.step(5)  # warm-up: contacts, caches
    world.profile()
    t0 = time.perf_counter()
    world.step(steps)
    wall = time.perf_counter() - t0
    prof = world.profile()
    sub = steps * world.substeps
    c = scene.constraint_count
    it = world_iterations[name]
    row = {
        "scene": name,
        "particles": scene.particle_count,
        "constraints": c,
        "substeps x iterations": f"{world.substeps} x {it}",
        "ms / step": 1e3 * wall / steps,
        "us / substep": 1e6 * wall / sub,
        "ns / substep / constraint": 1e9 * wall / sub / c,
        "ns / constraint pass": 1e9 * wall / sub / c / it,
        "xpbd share": prof.get("xpbd", 0.0) / wall,
    }
    assert np.isfinite(world.particles.position).all()
    return row


world_iterations: dict[str, int] = {}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer steps")
    args = ap.parse_args()
    steps = 20 if args.quick else 60
    rows = []
    for name, (scene, world), it in [
        ("cloth 100x100", cloth(100, 0.0, 4, 2), 2),
        ("cloth 100x100 + self-collision", cloth(100, 0.004, 4, 2), 2),
        ("chain 100 links", chain(100, 20, 1), 1),
        ("chain 100 links (1 x 20)", chain(100, 1, 20), 20),
    ]:
        world_iterations[name] = it
        rows.append(measure(name, scene, world, steps if "cloth" in name else 10 * steps))
    keys = list(rows[0])
    print(" | ".join(keys))
    for r in rows:
        print(" | ".join(f"{r[k]:.3g}" if isinstance(r[k], float) else str(r[k]) for k in keys))


if __name__ == "__main__":
    main()
