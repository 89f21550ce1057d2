"""Benchmark (not a test): XPBD cost per substep and per constraint.

Scenes, each stepped for a fixed simulated time after a short warm-up:

* a 100 × 100 cloth (10 000 particles; stretch/shear distance constraints on every
  triangle edge plus dihedral bending on every interior edge), pinned at two
  corners, falling onto a sphere: with and without particle–particle collisions;
* a 100-link particle chain (`add_rope`, pinned at the top, compliance 0) swinging
  under gravity, 20 substeps × 1 iteration and 1 × 20;
* a 100-link rigid chain: 100 rigid links (2 cm, 10 g, no collider) joined by XPBD
  joints (`add_joint`, compliance 0), the first to the world, starting horizontal
  and swinging under gravity; spherical and hinge joints, 20 × 1 and 1 × 20. Its
  "constraints" are the joints (a spherical joint is one 3×3 point block; a hinge
  adds the axis alignment).

Reports the time per substep, per substep per constraint (and per constraint pass,
i.e. divided by the iterations), and the share of the `xpbd` (particles) or
`joints` (rigid) stage in `world.profile()`. Every figure is the median of
`--repeats` runs, each on a freshly built world, timed by the thread's CPU time
(`time.thread_time`: the stepping runs on the calling thread with the GIL released,
and CPU time leaves out waiting for a core on a shared machine); wall-clock
medians are in the JSON. `max_stretch` is the largest relative error of a link's
length at the end (particle chains), or the largest distance between the two sides
of a joint over the link length (rigid chains).

    python benches/python/bench_xpbd.py [--quick] [--repeats 3] [--json PATH]
"""
from __future__ import annotations

import argparse
import json
import statistics
import time

import numpy as np

import rigidrs as rr

LINK = 0.02  # chain link length (m)
LINK_MASS = 0.01  # kg


def cloth(n: int, radius: float, substeps: int, iterations: int):
    scene = rr.Scene()
    scene.add_body(rr.Sphere(0.3), fixed=True, position=(0, 0, 0))
    scene.add_cloth((-0.5, -0.5, 0.5), (1, 0, 0), (0, 1, 0), (n, n), mass=0.5, radius=radius,
                    compliance=1e-7, bending_compliance=10.0, pinned=[0, n - 1])
    return scene, scene.build(dt=1 / 60, substeps=substeps, iterations=iterations)


def chain(links: int, substeps: int, iterations: int):
    scene = rr.Scene()
    scene.add_rope((0, 0, 0), (links * LINK, 0, 0), links, mass=links * LINK_MASS, pinned=[0])
    return scene, scene.build(dt=1 / 60, substeps=substeps, iterations=iterations)


def rigid_chain(links: int, kind: str, substeps: int, iterations: int):
    """`links` rigid links along +x, joined end to end; link 0 hinged/pinned to the world at the origin."""
    scene = rr.Scene()
    t = 0.2 * LINK  # link cross-section (m)
    inertia = LINK_MASS / 12 * np.array([2 * t * t, LINK ** 2 + t * t, LINK ** 2 + t * t])
    bodies = [scene.add_body(mass=LINK_MASS, inertia=inertia, position=((i + 0.5) * LINK, 0, 0))
              for i in range(links)]
    scene.add_joint(kind, bodies[0], None, anchor=(0, 0, 0), axis=(0, 1, 0))
    for i in range(1, links):
        scene.add_joint(kind, bodies[i], bodies[i - 1], anchor=(i * LINK, 0, 0), axis=(0, 1, 0))
    world = scene.build(dt=1 / 60, substeps=substeps, iterations=iterations)
    assert np.allclose(np.abs(world.bodies.orientation[:, 3]), 1.0)  # principal frame = world frame at build
    return scene, world


def stretch(points: np.ndarray) -> float:
    return float(np.abs(np.linalg.norm(np.diff(points, axis=0), axis=1) / LINK - 1).max())


def joint_gap(world) -> float:
    """Rigid chain: the largest distance between the two sides of a joint, over the link length."""
    c, rot = world.bodies.position, world.bodies.rotation
    assert np.isfinite(c).all()
    half = np.array([0.5 * LINK, 0.0, 0.0])
    near = c + rot @ -half  # each link's end towards the world anchor
    far = c + rot @ half
    gaps = np.linalg.norm(near - np.vstack([[0.0, 0.0, 0.0], far[:-1]]), axis=1)
    return float(gaps.max() / LINK)


def run_once(build, steps: int) -> dict:
    scene, world = build()
    world.step(5)  # warm-up: contacts, caches
    world.profile()
    c0, t0 = time.thread_time(), time.perf_counter()
    world.step(steps)
    wall = time.perf_counter() - t0
    cpu = time.thread_time() - c0
    prof = world.profile()
    rigid = scene.joint_count > 0
    stage = "joints" if rigid else "xpbd"
    if rigid:
        max_stretch = joint_gap(world)
    else:
        pos = world.particles.position
        assert np.isfinite(pos).all()
        max_stretch = stretch(pos) if scene.constraint_count == scene.particle_count - 1 else None
    return {"wall": wall, "cpu": cpu, "stage": prof.get(stage, 0.0), "profiled": sum(v for k, v in prof.items() if k != "steps"),
            "substeps": world.substeps, "max_stretch": max_stretch,
            "particles": scene.particle_count, "bodies": len(world.bodies),
            "constraints": scene.joint_count if rigid else scene.constraint_count, "stage_name": stage,
            "stages": world.stages}


def measure(name: str, build, iterations: int, steps: int, repeats: int) -> dict:
    runs = [run_once(build, steps) for _ in range(repeats)]
    r0 = runs[0]
    sub = steps * r0["substeps"]
    c = r0["constraints"]
    cpu = statistics.median(r["cpu"] for r in runs)
    wall = statistics.median(r["wall"] for r in runs)
    row = {
        "scene": name,
        "particles": r0["particles"],
        "bodies": r0["bodies"],
        "constraints": c,
        "substeps x iterations": f"{r0['substeps']} x {iterations}",
        "ms / step": 1e3 * cpu / steps,
        "us / substep": 1e6 * cpu / sub,
        "ns / substep / constraint": 1e9 * cpu / sub / c,
        "ns / constraint pass": 1e9 * cpu / sub / c / iterations,
        "stage share": statistics.median(r["stage"] / r["profiled"] for r in runs),
        "max stretch": r0["max_stretch"],
        # JSON only
        "stage": r0["stage_name"], "stages": r0["stages"], "steps": steps, "repeats": repeats,
        "cpu_s": [r["cpu"] for r in runs], "wall_s": [r["wall"] for r in runs],
        "ns / substep / constraint (wall)": 1e9 * wall / sub / c,
    }
    return row


TABLE = ["scene", "particles", "bodies", "constraints", "substeps x iterations", "ms / step", "us / substep",
         "ns / substep / constraint", "ns / constraint pass", "stage share", "max stretch"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="fewer steps")
    ap.add_argument("--repeats", type=int, default=3, help="runs per scene (median)")
    ap.add_argument("--json", help="also write the rows as JSON lines to this file")
    args = ap.parse_args()
    steps = 20 if args.quick else 60
    scenes = [
        ("cloth 100x100", lambda: cloth(100, 0.0, 4, 2), 2, steps),
        ("cloth 100x100 + self-collision", lambda: cloth(100, 0.004, 4, 2), 2, steps),
        ("chain 100 links", lambda: chain(100, 20, 1), 1, 10 * steps),
        ("chain 100 links (1 x 20)", lambda: chain(100, 1, 20), 20, 10 * steps),
        ("rigid chain 100 spherical", lambda: rigid_chain(100, "spherical", 20, 1), 1, 10 * steps),
        ("rigid chain 100 spherical (1 x 20)", lambda: rigid_chain(100, "spherical", 1, 20), 20, 10 * steps),
        ("rigid chain 100 hinge", lambda: rigid_chain(100, "hinge", 20, 1), 1, 10 * steps),
        ("rigid chain 100 hinge (1 x 20)", lambda: rigid_chain(100, "hinge", 1, 20), 20, 10 * steps),
    ]
    rows = [measure(name, build, it, n, args.repeats) for name, build, it, n in scenes]
    print(f"CPU time (thread), medians of {args.repeats} runs")
    print(" | ".join(TABLE))
    for r in rows:
        print(" | ".join("—" if r[k] is None else f"{r[k]:.3g}" if isinstance(r[k], float) else str(r[k])
                         for k in TABLE))
    if args.json:
        with open(args.json, "w") as f:
            for r in rows:
                f.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
