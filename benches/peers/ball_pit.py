#!/usr/bin/env python
"""Scene 3 in rigidrs: N spheres dropped from a jittered grid into a box container (floor + 4 walls, z up).

The same scene and JSON fields as the peer-engine script of the same name (MuJoCo,
PyBullet, Rapier): spheres r 0.1 m, density 1000 kg/m³, from a jittered 10 × 10 × 10
grid (same seed, same positions) into a 2.5 × 2.5 m container of five fixed boxes
(floor slab with its top at z = 0, four walls 3 m high, 0.2 m thick), friction 0.5 on
every shape (geometric mean: 0.5), restitution 0, dt 1/60, 600 steps, sleeping off
unless `--sleep 1`. One `world.step()` call per step, as the peers are stepped.

Extra fields: `integrator`, `substeps`, `iterations`, `stages`, `step_wall_s`
(monotonic wall clock), `profile_s_per_step` / `profile_share` (`world.profile()`
over the timed loop, wall seconds per stage per step), `max_depth` (deepest
penetration in `world.contacts()["depth"]` after the last step; `max_depth_container`:
of the contacts with the floor and walls only), `peak_depth` (the
deepest seen every `--track` steps, read outside the timed region; 0 = off),
`n_contacts`, `asleep`, and `wall_penetrated` (centres closer than r − 1 cm to a wall).

    python benches/peers/ball_pit.py
    python benches/peers/ball_pit.py --sleep 1 --substeps 2
"""
import argparse
import time

import numpy as np

from common import emit

R = 0.1      # sphere radius (m)
HALF = 1.25  # inner half-width of the container (m)
WALL_H = 3.0  # wall height above the floor top (z = 0)
THICK = 0.2  # floor and wall thickness


def container():
    """Static boxes as (center, half extents): the floor (top face at z = 0) and 4 walls. As the peer script."""
    o, t = HALF + THICK / 2, THICK / 2
    outer = HALF + THICK
    return [((0, 0, -t), (outer, outer, t)),
            ((o, 0, WALL_H / 2), (t, outer, WALL_H / 2)), ((-o, 0, WALL_H / 2), (t, outer, WALL_H / 2)),
            ((0, o, WALL_H / 2), (HALF, t, WALL_H / 2)), ((0, -o, WALL_H / 2), (HALF, t, WALL_H / 2))]


def initial_positions(a):
    """Identical to the peer script."""
    per_side = 10
    rng = np.random.default_rng(a.seed)
    i = np.arange(a.n)
    g = np.stack([i % per_side, (i // per_side) % per_side, i // per_side ** 2], 1).astype(float)
    pos = np.empty((a.n, 3))
    pos[:, :2] = (g[:, :2] - (per_side - 1) / 2) * a.spacing + rng.uniform(-0.02, 0.02, (a.n, 2))
    pos[:, 2] = R + 0.2 + g[:, 2] * a.spacing
    return pos


def build_rigidrs(a, pos):
    import rigidrs as rr
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    walls = container()
    for c, h in walls:
        scene.add_body(rr.Box(h), fixed=True, position=c, friction=a.friction, restitution=0.0)
    ball = rr.Sphere(R)
    for x in pos:
        scene.add_body(ball, density=a.density, position=x, friction=a.friction, restitution=0.0)
    kw = {} if a.substeps is None else {"substeps": a.substeps}
    if a.threads is not None:
        kw["threads"] = a.threads
    world = scene.build(dt=a.dt, integrator=a.integrator, iterations=a.iterations, sleep=bool(a.sleep), **kw)
    bodies = world.bodies
    nw = len(walls)

    def read():
        return bodies.position[nw:].copy()

    def vel():
        return bodies.linear_velocity[nw:].copy()

    return world, read, vel, bodies.mass[nw:].copy(), nw


def max_depth(world, container=None):
    """Deepest penetration of this step's contacts; with `container` (the number of fixed
    boxes, bodies 0..container-1), only of the contacts with them."""
    c = world.contacts()
    d = c["depth"]
    if container is not None:
        d = d[(c["body_a"] < container) | (c["body_b"] < container)]
    return float(d.max()) if len(d) else 0.0


def variant(a, world):
    v = f"substeps={world.substeps},iterations={a.iterations}"
    if a.integrator != "strang":
        v += f",{a.integrator}"
    if a.threads is not None:
        v += f",threads={a.threads}"
    return v + (",sleep" if a.sleep else "")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=1000, help="spheres, 10x10 per layer")
    ap.add_argument("--steps", type=int, default=600)
    ap.add_argument("--dt", type=float, default=1 / 60)
    ap.add_argument("--spacing", type=float, default=0.25, help="grid spacing (m)")
    ap.add_argument("--friction", type=float, default=0.5, help="of every shape (geometric mean: the same)")
    ap.add_argument("--density", type=float, default=1000.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--sleep", type=int, default=0, help="allow bodies to sleep (off: same work in every engine)")
    ap.add_argument("--track", type=int, default=10,
                    help="read contact depths every TRACK steps, outside the timed region (peak_depth); 0: off")
    ap.add_argument("--substeps", type=int, default=None, help="substeps per step (rigidrs default with contacts: 4)")
    ap.add_argument("--iterations", type=int, default=1, help="contact-solver iterations per substep")
    ap.add_argument("--integrator", default="strang")
    ap.add_argument("--threads", type=int, default=None, help="the world's worker threads (default: every core)")
    a = ap.parse_args()

    pos0 = initial_positions(a)
    t0 = time.perf_counter()
    world, read, vel, mass, nw = build_rigidrs(a, pos0)
    build_s = time.perf_counter() - t0
    start = read()

    step = world.step
    chunk = a.track if a.track > 0 else a.steps
    world.profile(reset=True)
    step_s, wall_s, peak_depth = 0.0, 0.0, 0.0
    for k in range(0, a.steps, chunk):
        w0 = time.monotonic()
        t0 = time.perf_counter()
        for _ in range(min(chunk, a.steps - k)):
            step()
        step_s += time.perf_counter() - t0
        wall_s += time.monotonic() - w0
        if a.track > 0:
            peak_depth = max(peak_depth, max_depth(world))
    prof = world.profile(reset=True)
    nsteps = prof.pop("steps")
    total = sum(prof.values())
    t0 = time.perf_counter()
    end = read()
    read_s = time.perf_counter() - t0
    v = np.linalg.norm(vel(), axis=1)
    n_contacts = len(world.contacts()["depth"])

    x, y, z = end.T
    escaped = (np.abs(x) > HALF) | (np.abs(y) > HALF) | (z < -THICK) | (z > WALL_H)
    sunk = ~escaped & (z < R - 0.01)  # penetrates the floor by more than 1 cm
    in_wall = ~escaped & (np.maximum(np.abs(x), np.abs(y)) > HALF - R + 0.01)
    emit({
        "scene": "ball_pit", "engine": "rigidrs", "n": a.n, "steps": a.steps, "dt": a.dt,
        "variant": variant(a, world),
        "build_s": round(build_s, 4), "step_s": round(step_s, 4), "read_s": round(read_s, 5),
        "steps_per_s": a.steps / step_s,
        "escaped": int(escaped.sum()), "floor_penetrated": int(sunk.sum()), "bad": int((escaped | sunk).sum()),
        "min_z": float(z.min()), "max_z": float(z.max()), "mean_z": float(z.mean()),
        "max_speed_end": float(v.max()), "mean_speed_end": float(v.mean()),
        "start_offset": float(np.abs(start - pos0).max()),
        "mass_rel_err": float(np.max(np.abs(mass / (a.density * 4 / 3 * np.pi * R ** 3) - 1))),
        # rigidrs extras
        "integrator": a.integrator, "substeps": world.substeps, "iterations": a.iterations,
        "stages": world.stages, "step_wall_s": round(wall_s, 4),
        "profile_s_per_step": {k: v / nsteps for k, v in prof.items()},
        "profile_share": {k: v / total for k, v in prof.items()} if total > 0 else {},
        "max_depth": max_depth(world), "max_depth_container": max_depth(world, nw),
        "peak_depth": peak_depth, "n_contacts": n_contacts,
        "asleep": int(world.bodies.sleeping[nw:].sum()), "wall_penetrated": int(in_wall.sum()),
        "max_abs_xy": float(np.abs(end[:, :2]).max()),
    })


if __name__ == "__main__":
    main()
