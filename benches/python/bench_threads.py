#!/usr/bin/env python
"""One world on 1 and 2 threads (`threads=`): steps per second and the ratio.

Scenes:
- `stacks`: 64 separate stacks of 4 boxes on the ground (64 islands), sleep off;
- `free`: N free boxes 0.1 x 0.2 x 0.4 m (asymmetric), |omega| = 5 rad/s, no
  gravity, no colliders (default N = 20 000);
- `free_colliding`: the same boxes with colliders, 1 m apart (nothing touches);
- `pyramid_820`: the pyramid of base 40 of `benches/peers/pyramid.py` (1600
  contact pairs: its narrow phase and constraint build run on both threads);
- `ball_pit`: 1000 balls of 0.1 m in a 2 m box, 10 layers, sleep off (2900 pairs).

Per scene and thread count: the median wall time of --repeats runs of --steps
steps after a warm-up, the process CPU time over wall (near the thread count on a
quiet machine) and the load average, then the ratio 1-thread wall / 2-thread wall
(of the medians, and of the minima: the two take turns, so a burst of load
elsewhere hits both).
The end states are checked bitwise equal.

    python benches/python/bench_threads.py          # ~45 s
"""
import argparse
import json
import os
import statistics
import time

import numpy as np

import rigidrs as rr


def stacks(threads):
    scene = rr.Scene(gravity=(0, 0, -9.81))
    scene.add_body(rr.Plane(), fixed=True)
    for s in range(64):
        for k in range(4):
            scene.add_body(rr.Box((0.1, 0.1, 0.1)), density=500.0, position=(0.5 * (s % 8), 0.5 * (s // 8), 0.1 + 0.21 * k))
    return scene.build(dt=1 / 60, sleep=False, threads=threads)


def free(threads, n=20_000, colliders=False):
    rng = np.random.default_rng(0)
    scene = rr.Scene(gravity=(0, 0, 0))
    box = rr.Box((0.05, 0.1, 0.2))
    for k in range(n):
        d = rng.normal(size=3)
        w = 5.0 * d / np.linalg.norm(d)
        if colliders:
            scene.add_body(box, density=1000.0, position=(k % 100, k // 100, 0), angular_velocity=w)
        else:
            scene.add_body(None, mass=1.0, inertia=(0.0042, 0.0033, 0.0017), position=(k % 100, k // 100, 0), angular_velocity=w)
    return scene.build(dt=1 / 240, threads=threads)


def pyramid_820(threads, base=40):
    scene = rr.Scene(gravity=(0, 0, -9.81))
    scene.add_body(rr.Plane(), fixed=True, friction=0.5)
    for i in range(base):
        for j in range(base - i):
            x = (j - (base - i - 1) / 2) * 1.02
            scene.add_body(rr.Box((0.5, 0.5, 0.5)), density=1000.0, position=(x, 0, 0.5 + i), friction=0.5)
    return scene.build(dt=1 / 60, sleep=False, threads=threads)


def ball_pit(threads, n=1000):
    scene = rr.Scene(gravity=(0, 0, -9.81))
    scene.add_body(rr.Plane(), fixed=True)
    for x, y in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        scene.add_body(rr.Plane(normal=(-x, -y, 0), offset=-1.0), fixed=True)
    rng = np.random.default_rng(2)
    for k in range(n):
        jx, jy = rng.uniform(-0.005, 0.005, size=2)
        scene.add_body(rr.Sphere(0.1), density=1000.0, position=((k % 10 - 4.5) * 0.2 + jx, (k // 10 % 10 - 4.5) * 0.2 + jy, 0.1 + 0.199 * (k // 100)))
    return scene.build(dt=1 / 60, sleep=False, threads=threads)


SCENES = {"stacks": (stacks, 200), "free": (free, 100), "free_colliding": (lambda t: free(t, colliders=True), 50),
          "pyramid_820": (pyramid_820, 200), "ball_pit": (ball_pit, 100)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--scenes", nargs="*", default=list(SCENES))
    a = ap.parse_args()
    out = {}
    print(f"{'scene':<16} {'threads':>7} {'wall s':>8} {'CPU/wall':>9} {'load':>6} {'ratio':>6}")
    for name in a.scenes:
        make, steps = SCENES[name]
        runs, ends = {1: [], 2: []}, {}
        for _ in range(a.repeats):  # 1 and 2 threads take turns: load bursts hit both
            for t in (1, 2):
                w = make(t)
                w.profiling = False
                w.step(10)
                load = os.getloadavg()[0]
                c0, t0 = time.process_time(), time.perf_counter()
                w.step(steps)
                runs[t].append((time.perf_counter() - t0, time.process_time() - c0, load))
                ends[t] = w.bodies.position.copy()
        res = {t: [statistics.median(r[i] for r in runs[t]) for i in range(3)] for t in (1, 2)}
        mins = {t: min(r[0] for r in runs[t]) for t in (1, 2)}
        assert np.array_equal(ends[1].view(np.uint8), ends[2].view(np.uint8)), name
        ratio = res[1][0] / res[2][0]
        for t in (1, 2):
            wall, cpu, load = res[t]
            print(f"{name:<16} {t:>7} {wall:8.3f} {cpu / wall:9.2f} {load:6.2f} {ratio if t == 2 else 1.0:6.2f}")
        out[name] = {"wall_1": res[1][0], "wall_2": res[2][0], "ratio": ratio, "ratio_of_mins": mins[1] / mins[2], "load": res[2][2]}
        print(f"{'':<16} ratio of minima {mins[1] / mins[2]:.2f}")
    print(json.dumps(out))


if __name__ == "__main__":
    main()
