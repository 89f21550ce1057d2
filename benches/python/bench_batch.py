#!/usr/bin/env python
"""A batch of worlds against the same worlds stepped one after another.

Scene: 20 boxes and spheres dropped in two jittered layers on the ground (the
contact scene of tests/test_batch.py), dt 1/120, sleep off (so every step does
the same work). B copies (default 256) are warmed up for --warm steps, then
timed over --steps steps three ways, taking turns (--repeats rounds):

- sequential: B worlds (`threads=1`), `world.step(steps)` on each in turn;
- `rr.Batch(scene, copies=B, threads=1).step(steps)` (the batch's own overhead);
- `rr.Batch(scene, copies=B, threads=T).step(steps)` for T = 2 (or --threads).

Reported per way: the median wall time of --repeats runs, the process CPU time
(all threads) and the load average when it ran; the speed-up is sequential wall /
batch wall of the medians, and of the minima (the least disturbed runs). The machine may be shared: the load average and CPU/wall show it
(CPU/wall near T on a quiet machine). The batch's copies are checked bitwise
against the sequential worlds at the end.

    python benches/python/bench_batch.py                    # ~1 min
    python benches/python/bench_batch.py --copies 64 --steps 30
"""
import argparse
import json
import os
import statistics
import time

import numpy as np

import rigidrs as rr

G = 9.81
DT = 1 / 120


def pile():
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    rng = np.random.default_rng(7)
    for k in range(20):
        x, y = 0.3 * (k % 5 - 2) + rng.uniform(-0.03, 0.03), 0.3 * (k // 5 % 2) + rng.uniform(-0.03, 0.03)
        shape = rr.Box((0.1, 0.08, 0.09)) if k % 2 else rr.Sphere(0.1)
        scene.add_body(shape, density=500.0, position=(x, y, 0.15 + 0.25 * (k // 10)), linear_velocity=(0.5, 0, 0))
    return scene


def timed(fn):
    load = os.getloadavg()[0]
    c0, t0 = time.process_time(), time.perf_counter()
    fn()
    return time.perf_counter() - t0, time.process_time() - c0, load


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--copies", type=int, default=256)
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--warm", type=int, default=30)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    scene = pile()

    def sequential():
        worlds = [scene.build(DT, sleep=False, threads=1) for _ in range(a.copies)]
        for w in worlds:
            w.step(a.warm)
        return lambda: [w.step(a.steps) for w in worlds], lambda: worlds[0].bodies.position

    def batched(threads):
        b = rr.Batch(scene, copies=a.copies, dt=DT, sleep=False, threads=threads)
        b.step(a.warm)
        return lambda: b.step(a.steps), lambda: b.bodies.position[0]

    # The ways take turns, each from a fresh warm-up every repeat, so that a
    # burst of load elsewhere on a shared machine hits them alike; the minimum
    # over repeats is the least disturbed run.
    ways = {"sequential": sequential, **{f"batch threads={t}": (lambda t=t: batched(t)) for t in sorted({1, a.threads})}}
    rows = {name: [] for name in ways}
    for _ in range(a.repeats):
        ends = {}
        for name, make in ways.items():
            run, end = make()
            rows[name].append(timed(run))
            ends[name] = end().copy()
        first = ends["sequential"]
        assert all(np.array_equal(e.view(np.uint8), first.view(np.uint8)) for e in ends.values())
    base = statistics.median(r[0] for r in rows["sequential"])
    best = min(r[0] for r in rows["sequential"])
    body_steps = a.copies * a.steps * 21
    print(f"{a.copies} copies x {a.steps} steps of a 21-body contact scene; cores: {os.cpu_count()}")
    print(f"{'way':<20} {'wall s':>8} {'(min-max)':>15} {'CPU/wall':>9} {'load':>6} {'Mbody-steps/s':>14} "
          f"{'speed-up':>9} {'of mins':>8}")
    summary = {}
    for name, runs in rows.items():
        wall = statistics.median(r[0] for r in runs)
        cpu = statistics.median(r[1] for r in runs)
        load = statistics.median(r[2] for r in runs)
        lo, hi = min(r[0] for r in runs), max(r[0] for r in runs)
        summary[name] = {"wall": wall, "cpu": cpu, "load": load, "ratio": base / wall, "ratio_of_mins": best / lo}
        print(f"{name:<20} {wall:8.3f} {f'({lo:.3f}-{hi:.3f})':>15} {cpu / wall:9.2f} {load:6.2f} "
              f"{body_steps / wall / 1e6:14.2f} {base / wall:9.2f} {best / lo:8.2f}")
    line = json.dumps({"copies": a.copies, "steps": a.steps, "rows": summary})
    print(line)
    if a.json:
        with open(a.json, "w") as f:
            f.write(line + "\n")


if __name__ == "__main__":
    main()
