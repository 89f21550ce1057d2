#!/usr/bin/env python
"""Box pile: N cubes dropped in a loose lattice onto a ground plane, in rigidrs or Rapier.

A scene of the issue "Scale": n×n×layers cubes of edge 0.5 m, density 1000 kg/m³, 5 cm
apart at their widest, each turned by a small random angle (seeded, the same in both engines) so that
they land on edges and corners and pile up; friction 0.5, restitution 0, dt 1/60,
sleeping off (the same work in both engines). Only the stepping is timed. One JSON line
as the peer scripts print (fields: scene, engine, n, steps, steps_per_s, ...).

    python benches/peers/box_pile.py --engine rigidrs --side 20 --layers 10      # 4000
    python benches/peers/box_pile.py --engine rapier3d --side 40 --layers 10     # 16000
"""
import argparse
import json
import time

import numpy as np

HALF = 0.25
GAP = 0.05


def initial_poses(a):
    rng = np.random.default_rng(a.seed)
    # A turned cube reaches at most √3 half edges along any axis: no two start
    # overlapping, whatever their tilt.
    pitch = 2 * HALF * np.sqrt(3) + GAP
    pos, quat = [], []
    for k in range(a.layers):
        for i in range(a.side):
            for j in range(a.side):
                pos.append(((i - (a.side - 1) / 2) * pitch, (j - (a.side - 1) / 2) * pitch, HALF + GAP + k * pitch))
                axis = rng.normal(size=3)
                axis /= np.linalg.norm(axis)
                angle = rng.uniform(0.05, 0.3)
                quat.append((*(axis * np.sin(angle / 2)), np.cos(angle / 2)))  # x, y, z, w
    return np.array(pos), np.array(quat)


def build_rigidrs(a, pos, quat):
    import rigidrs as rr
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True, friction=a.friction, restitution=0.0)
    box = rr.Box((HALF, HALF, HALF))
    for x, q in zip(pos, quat):
        scene.add_body(box, density=1000.0, position=x, orientation=q, friction=a.friction, restitution=0.0)
    kw = {} if a.threads is None else {"threads": a.threads}
    if a.substeps is not None:
        kw["substeps"] = a.substeps
    world = scene.build(dt=a.dt, sleep=False, **kw)
    return world.step, lambda: world.bodies.position[1:].copy()


def build_rapier3d(a, pos, quat):
    import rapier3d as r
    w = r.PhysicsWorld(gravity=(0, 0, -9.81))
    w.integration_parameters.dt = a.dt
    w.set_num_threads(a.threads or 1)
    w.add_collider(r.Collider.halfspace((0, 0, 1)).friction(a.friction))
    handles = []
    for x, q in zip(pos, quat):
        angle = 2 * np.arctan2(np.linalg.norm(q[:3]), q[3])  # Rapier takes a scaled axis
        axis = q[:3] / max(np.linalg.norm(q[:3]), 1e-300)
        body = r.RigidBody.dynamic().translation(x.tolist()).rotation((axis * angle).tolist()).can_sleep(False)
        handles.append(w.add_body(body, [r.Collider.cuboid(HALF, HALF, HALF).density(1000.0).friction(a.friction)]))
    bodies = w.rigid_bodies
    return w.step, lambda: np.array([bodies[h].translation.to_tuple() for h in handles])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--engine", choices=["rigidrs", "rapier3d"], required=True)
    ap.add_argument("--side", type=int, default=20)
    ap.add_argument("--layers", type=int, default=10)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--dt", type=float, default=1 / 60)
    ap.add_argument("--friction", type=float, default=0.5)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--substeps", type=int, default=None, help="rigidrs: substeps per step (default: chosen, 4 or 16)")
    ap.add_argument("--threads", type=int, default=None, help="worker threads (rigidrs: build's threads=; rapier: 1 if unset)")
    a = ap.parse_args()
    pos, quat = initial_poses(a)
    t0 = time.perf_counter()
    step, read = globals()["build_" + a.engine](a, pos, quat)
    build_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    for _ in range(a.steps):
        step()
    step_s = time.perf_counter() - t0
    end = read()
    print(json.dumps({
        "scene": f"box_pile_{len(pos)}", "engine": a.engine, "n": len(pos), "steps": a.steps, "dt": a.dt,
        "variant": f"threads={a.threads}" + (f",substeps={a.substeps}" if a.substeps else ""), "build_s": round(build_s, 4), "step_s": round(step_s, 4),
        "steps_per_s": a.steps / step_s, "us_per_body_step": 1e6 * step_s / (a.steps * len(pos)),
        "min_z": float(end[:, 2].min()),  # < 0: a box fell through the ground
        "mean_z": float(end[:, 2].mean()),
    }), flush=True)


if __name__ == "__main__":
    main()
