#!/usr/bin/env python
"""Stepping throughput and per-call overhead through the Python bindings.

1. Body-steps per second for N free boxes (0.1 x 0.2 x 0.4 m, rho 1000, random
   orientations, |omega| = 5 rad/s, no gravity, dt 1/240; the initial state of
   benches/peers/free_bodies.py) for every integrator, two ways:
   `world.step(k)` (one call, GIL released once) and k calls of `world.step()`.
2. The cost of one `world.step()` call from Python on a 1-body world (a loop of
   calls, nothing subtracted), with stage profiling on (the default) and off, and
   for context the cost of one step inside a single `world.step(k)` call.

Every figure is the median of --repeats timed runs (after one warm-up run); the
machine is shared, so run it on a quiet machine and look at the spread (min, max)
printed next to each median. "CPU ns" is the thread's CPU time per body-step of
`world.step(k)` and of k x `world.step()`, which leaves out the time the process
waited for a core. Prints a table, then one JSON line (also written to
--json PATH if given).

    python benches/python/bench_bindings.py                 # ~1 min
    python benches/python/bench_bindings.py --n 2000 --k 50 --repeats 3
"""
import argparse
import json
import os
import platform
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "peers"))
from common import random_quats_xyzw  # noqa: E402  (the peer scenes' initial-state helpers)

import rigidrs as rr  # noqa: E402

SIZE = np.array([0.1, 0.2, 0.4])


def boxes_world(n, integrator, seed=0, spacing=1.0, omega=5.0, density=1000.0, dt=1 / 240):
    """The free_bodies scene with n boxes (same generator as benches/peers/free_bodies.py)."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(n ** (1 / 3)))
    i = np.arange(n)
    pos = spacing * np.stack([i % side, (i // side) % side, i // side ** 2], 1).astype(float)
    quat = random_quats_xyzw(rng, n)
    d = rng.normal(size=(n, 3))
    w = omega * d / np.linalg.norm(d, axis=1, keepdims=True)
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    box = rr.Box(half_extents=SIZE / 2)
    for x, q, om in zip(pos, quat, w):
        scene.add_body(box, density=density, position=x, orientation=q, angular_velocity=om)
    return scene.build(dt=dt, integrator=integrator)


def timed(fn, repeats, cpu=None):
    """Wall-clock seconds of each of `repeats` runs of fn(), after one warm-up run; if
    `cpu` is a list, the thread's CPU seconds of each run are appended to it (not
    counting time the thread waited for a core: the machine is shared)."""
    fn()
    out = []
    for _ in range(repeats):
        c0, t0 = time.thread_time(), time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
        if cpu is not None:
            cpu.append(time.thread_time() - c0)
    return out


def summary(samples, scale):
    """Median, min and max of samples * scale."""
    v = [s * scale for s in samples]
    return {"median": statistics.median(v), "min": min(v), "max": max(v)}


def throughput(a):
    rows = {}
    for name in rr.INTEGRATORS:
        world = boxes_world(a.n, name)
        step = world.step
        batch_cpu = []
        batch = timed(lambda: step(a.k), a.repeats, batch_cpu)

        def loop():
            for _ in range(a.k):
                step()

        looped_cpu = []
        looped = timed(loop, a.repeats, looped_cpu)
        body_steps = a.n * a.k
        rows[name] = {
            "stages": world.stages,
            # body-steps/s: invert each run's time, then take the median
            "batch_body_steps_per_s": summary([1 / t for t in batch], body_steps),
            "loop_body_steps_per_s": summary([1 / t for t in looped], body_steps),
            "batch_ns_per_body_step": summary(batch, 1e9 / body_steps),
            "batch_cpu_ns_per_body_step": summary(batch_cpu, 1e9 / body_steps),
            "loop_ns_per_body_step": summary(looped, 1e9 / body_steps),
            "loop_cpu_ns_per_body_step": summary(looped_cpu, 1e9 / body_steps),
        }
    return rows


def call_overhead(a):
    out = {}
    for profiling in (True, False):
        scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
        scene.add_body(rr.Box(half_extents=SIZE / 2), density=1000.0, angular_velocity=(0.1, 5.0, 0.1))
        world = scene.build(dt=1 / 240)
        world.profiling = profiling
        step = world.step

        def loop():
            for _ in range(a.calls):
                step()

        per_call_cpu, in_rust_cpu = [], []
        per_call = timed(loop, a.repeats, per_call_cpu)
        in_rust = timed(lambda: step(a.calls), a.repeats, in_rust_cpu)
        key = "profiling_on" if profiling else "profiling_off"
        out[key] = {
            "us_per_call": summary(per_call, 1e6 / a.calls),
            "us_per_step_in_one_call": summary(in_rust, 1e6 / a.calls),
            "cpu_us_per_call": summary(per_call_cpu, 1e6 / a.calls),
            "cpu_us_per_step_in_one_call": summary(in_rust_cpu, 1e6 / a.calls),
        }
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=10_000, help="boxes in the throughput scene")
    ap.add_argument("--k", type=int, default=100, help="steps per timed run")
    ap.add_argument("--calls", type=int, default=20_000, help="step() calls per timed run of the 1-body world")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--json", help="also write the JSON result to this file")
    a = ap.parse_args()

    rows = throughput(a)
    overhead = call_overhead(a)

    print(f"rigidrs {rr.__version__}: {a.n} free boxes, {a.k} steps per run, median of {a.repeats} (min-max)")
    print(f"{'integrator':18} {'world.step(k)':>26} {'k x world.step()':>26} {'ns/body-step (k)':>17}"
          f" {'CPU ns (k)':>11} {'CPU ns (k x 1)':>15}")
    for name, r in rows.items():
        b, l, ns = r["batch_body_steps_per_s"], r["loop_body_steps_per_s"], r["batch_ns_per_body_step"]
        cpu, cpu1 = r["batch_cpu_ns_per_body_step"], r["loop_cpu_ns_per_body_step"]
        print(f"{name:18} {b['median'] / 1e6:8.2f} M/s ({b['min'] / 1e6:5.2f}-{b['max'] / 1e6:5.2f})"
              f" {l['median'] / 1e6:8.2f} M/s ({l['min'] / 1e6:5.2f}-{l['max'] / 1e6:5.2f})"
              f" {ns['median']:17.1f} {cpu['median']:11.1f} {cpu1['median']:15.1f}")
    print(f"\none world.step() call on a 1-body world, {a.calls} calls per run, median of {a.repeats} (min-max)")
    for key, r in overhead.items():
        c, s = r["us_per_call"], r["us_per_step_in_one_call"]
        cc, cs = r["cpu_us_per_call"], r["cpu_us_per_step_in_one_call"]
        print(f"  {key:14} {c['median']:6.3f} us per call ({c['min']:.3f}-{c['max']:.3f}), CPU {cc['median']:6.3f};"
              f" inside one step(k): {s['median']:6.3f} us per step, CPU {cs['median']:6.3f}")

    result = {
        "bench": "bindings", "rigidrs": rr.__version__, "python": platform.python_version(),
        "machine": {"cpus": os.cpu_count(), "processor": platform.processor() or platform.machine()},
        "date": time.strftime("%Y-%m-%d"),
        "n": a.n, "k": a.k, "calls": a.calls, "repeats": a.repeats,
        "throughput": rows, "call_overhead": overhead,
    }
    line = json.dumps(result)
    print(line)
    if a.json:
        with open(a.json, "w") as f:
            f.write(line + "\n")


if __name__ == "__main__":
    main()
