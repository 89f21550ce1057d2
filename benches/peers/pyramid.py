#!/usr/bin/env python
"""Scene 2 in rigidrs: a 2D-like pyramid of 1 m boxes (base B) standing on a ground plane (z up).

The same scene and JSON fields as the peer-engine script of the same name (MuJoCo,
PyBullet, Rapier): boxes of edge 1 m, density 1000 kg/m³, rows 2 cm apart, a fixed
half-space `Plane` as ground, friction 0.5 on both (rigidrs combines by the geometric
mean: 0.5), restitution 0, dt 1/60, 600 steps, sleeping off unless `--sleep 1`. One
`world.step()` call per step, as the peers are stepped; positions are read every
`--track` steps outside the timed region (peak displacement).

Extra fields: `integrator`, `substeps`, `iterations`, `stages`, `step_wall_s` (the same
loop by the monotonic wall clock, which `cpu_clock.py` leaves alone),
`profile_s_per_step` (`world.profile()` over the timed loop: wall seconds per stage
per step), `profile_share` (each stage's fraction of the profiled total),
`max_horiz_disp` (largest horizontal displacement at the end),
`max_depth` (deepest penetration in `world.contacts()` at the end), `peak_depth`
(deepest seen at the tracked steps) and `asleep` (bodies asleep at the end).

    python benches/peers/pyramid.py
    python benches/peers/pyramid.py --sleep 1 --substeps 2 --iterations 2
"""
import argparse
import time

import numpy as np

from common import emit

EDGE = 1.0


def initial_positions(a):
    """Identical to the peer script."""
    pos = []
    for i in range(a.base):  # row i has base - i boxes, each resting on two below
        k = a.base - i
        for j in range(k):
            pos.append(((j - (k - 1) / 2) * (EDGE + a.gap), 0.0, EDGE / 2 + i * EDGE))
    return np.array(pos)


def build_rigidrs(a, pos):
    import rigidrs as rr
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True, friction=a.friction, restitution=0.0)  # body 0: the ground
    h = EDGE / 2
    box = rr.Box((h, h, h))
    for x in pos:
        scene.add_body(box, density=a.density, position=x, friction=a.friction, restitution=0.0)
    kw = {} if a.substeps is None else {"substeps": a.substeps}
    if a.threads is not None:
        kw["threads"] = a.threads
    world = scene.build(dt=a.dt, integrator=a.integrator, iterations=a.iterations, sleep=bool(a.sleep), **kw)
    bodies = world.bodies

    def read():
        return bodies.position[1:].copy()

    return world, read, bodies.mass[1:].copy()


def max_depth(world):
    d = world.contacts()["depth"]
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
    ap.add_argument("--base", type=int, default=20)
    ap.add_argument("--steps", type=int, default=600)
    ap.add_argument("--dt", type=float, default=1 / 60)
    ap.add_argument("--friction", type=float, default=0.5, help="of every shape (geometric mean: the same)")
    ap.add_argument("--density", type=float, default=1000.0)
    ap.add_argument("--gap", type=float, default=0.02, help="horizontal gap between boxes of a row (m)")
    ap.add_argument("--track", type=int, default=10, help="read positions every TRACK steps (peak displacement)")
    ap.add_argument("--sleep", type=int, default=0, help="allow bodies to sleep (off: same work in every engine)")
    ap.add_argument("--substeps", type=int, default=None, help="substeps per step (rigidrs default with contacts: 4)")
    ap.add_argument("--iterations", type=int, default=1, help="contact-solver iterations per substep")
    ap.add_argument("--integrator", default="strang")
    ap.add_argument("--threads", type=int, default=None, help="the world's worker threads (default: every core)")
    a = ap.parse_args()

    pos0 = initial_positions(a)
    t0 = time.perf_counter()
    world, read, mass = build_rigidrs(a, pos0)
    build_s = time.perf_counter() - t0
    start = read()

    step = world.step
    world.profile(reset=True)
    step_s, wall_s, read_s, peak, peak_depth = 0.0, 0.0, 0.0, 0.0, 0.0
    for k in range(0, a.steps, a.track):  # only the stepping is timed; positions are read every `track` steps
        w0 = time.monotonic()
        t0 = time.perf_counter()
        for _ in range(min(a.track, a.steps - k)):
            step()
        t1 = time.perf_counter()
        wall_s += time.monotonic() - w0
        end = read()
        read_s += time.perf_counter() - t1
        step_s += t1 - t0
        peak = max(peak, float(np.linalg.norm(end - pos0, axis=1).max()))
        peak_depth = max(peak_depth, max_depth(world))
    prof = world.profile(reset=True)
    nsteps = prof.pop("steps")
    total = sum(prof.values())

    disp = np.linalg.norm(end - pos0, axis=1)
    bottom = pos0[:, 2] < EDGE
    emit({
        "scene": "pyramid", "engine": "rigidrs", "n": len(pos0), "steps": a.steps, "dt": a.dt,
        "variant": variant(a, world),
        "build_s": round(build_s, 4), "step_s": round(step_s, 4), "read_s": round(read_s, 5),
        "steps_per_s": a.steps / step_s,
        "max_disp": float(disp.max()), "mean_disp": float(disp.mean()), "collapsed": bool(disp.max() > 0.5),
        "n_moved": int((disp > 0.5).sum()), "peak_disp": peak,  # largest displacement seen during the run
        "start_offset": float(np.abs(start - pos0).max()),
        "top_dz": float(end[-1, 2] - pos0[-1, 2]),  # sink of the apex box (compression of the stack)
        "bottom_row_min_z": float(end[bottom, 2].min()),  # < 0.5: boxes sunk into the ground
        "min_z": float(end[:, 2].min()),  # << 0: broken ground (free fall)
        "mass_rel_err": float(np.max(np.abs(mass / (a.density * EDGE ** 3) - 1))),
        # rigidrs extras
        "integrator": a.integrator, "substeps": world.substeps, "iterations": a.iterations,
        "stages": world.stages, "step_wall_s": round(wall_s, 4),
        "profile_s_per_step": {k: v / nsteps for k, v in prof.items()},
        "profile_share": {k: v / total for k, v in prof.items()} if total > 0 else {},
        "max_horiz_disp": float(np.linalg.norm(end[:, :2] - pos0[:, :2], axis=1).max()),
        "max_depth": max_depth(world), "peak_depth": peak_depth,
        "asleep": int(world.bodies.sleeping[1:].sum()),
    })


if __name__ == "__main__":
    main()
