#!/usr/bin/env python
"""Medians and ratios of the JSON lines written by run_side_by_side.sh, as Markdown.

    python benches/peers/compare.py results.jsonl > COMPARISON.md
"""
import argparse
import datetime
import json
import os
from collections import defaultdict

import numpy as np

from common import versions

PEER_ORDER = [("mujoco", "Euler/Newton"), ("mujoco", "RK4/Newton"), ("pybullet", "maximal"), ("rapier3d", "threads=1")]
BASELINES = {"MuJoCo Euler": ("mujoco", "Euler/Newton"), "PyBullet": ("pybullet", "maximal"),
             "Rapier": ("rapier3d", "threads=1")}


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def med(runs, key):
    vals = [r[key] for r in runs if r.get(key) is not None]
    return float(np.median(vals)) if vals else float("nan")


def rng(runs, key, scale=1.0):
    vals = [r[key] * scale for r in runs if r.get(key) is not None]
    return f"{min(vals):.2f}–{max(vals):.2f}" if len(vals) > 1 else ""


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("results")
    ap.add_argument("--clock", default="wall", help="wall or cpu: how the runs were timed (for the heading)")
    ap.add_argument("--peer-versions", help="JSON of the peer environment's versions (run_side_by_side.sh writes it)")
    a = ap.parse_args()
    vers = {k: v for k, v in versions().items() if v}
    if a.peer_versions:
        with open(a.peer_versions) as f:
            vers.update({k: v for k, v in json.load(f).items() if v and k not in ("python", "numpy", "scipy")})
    groups = defaultdict(list)
    with open(a.results) as f:
        for line in f:
            if line.startswith("{"):
                d = json.loads(line)
                groups[(d["scene"], d["engine"], d["variant"])].append(d)

    reps = max((len(v) for v in groups.values()), default=0)
    print(f"# rigidrs against peer engines, same scenes\n")
    print(f"{datetime.date.today()}, {os.cpu_count()} cores ({cpu_name()}), shared with other jobs; "
          f"medians of {reps} runs, run sequentially, timed by "
          + ("wall clock" if a.clock == "wall" else "process CPU time (waiting for a core not counted)")
          + ". Versions: "
          + ", ".join(f"{k} {v}" for k, v in vers.items()) + ".\n")

    fb = {k[1:]: v for k, v in groups.items() if k[0] == "free_bodies"}
    rig = [(v, runs) for (e, v), runs in fb.items() if e == "rigidrs"]
    if fb:
        n, steps = next(iter(fb.values()))[0]["n"], next(iter(fb.values()))[0]["steps"]
        base = {name: med(fb[key], "body_steps_per_s") for name, key in BASELINES.items() if key in fb}
        print(f"## free_bodies: {n} boxes, {steps} steps, stepped one call per step\n")
        cols = " | ".join(f"÷ {b}" for b in base)
        print(f"| engine | variant | M body-steps/s (min–max) | {cols} | KE drift | Σ\\|L\\| drift |")
        print("|---|---|---|" + "---|" * len(base) + "---|---|")
        rows = [(e, v) for e, v in PEER_ORDER if (e, v) in fb] + [("rigidrs", v) for v, _ in rig]
        for e, v in rows:
            runs = fb[(e, v)]
            s = med(runs, "body_steps_per_s")
            ratios = " | ".join(f"{s / b:.2f}" for b in base.values())
            print(f"| {e} | {v} | {s / 1e6:.2f} ({rng(runs, 'body_steps_per_s', 1e-6)}) | {ratios} | "
                  f"{med(runs, 'ke_rel_drift'):+.1e} | {med(runs, 'L_rel_drift'):+.1e} |")
        if rig:
            print("\nrigidrs with all steps in one `world.step(steps)` call:\n")
            print(f"| variant | M body-steps/s | {cols} |")
            print("|---|---|" + "---|" * len(base))
            for v, runs in rig:
                s = med(runs, "body_steps_per_s_batch")
                print(f"| {v} | {s / 1e6:.2f} | " + " | ".join(f"{s / b:.2f}" for b in base.values()) + " |")

    dz = {k[1:]: v for k, v in groups.items() if k[0] == "dzhanibekov"}
    if dz:
        first = next(iter(dz.values()))[0]
        print(f"\n## dzhanibekov: inertia (1, 2, 3), ω0 = (0.01, 5, 0), {first['steps']} steps of "
              f"{first['dt']:.6g} s, against DOP853 (flip period {first['flip_period_ref']:.4f} s, "
              f"{first['n_flips_ref']} flips)\n")
        print("| engine | variant | energy drift | \\|L\\| drift | max \\|energy drift\\| | flip-period error | flips | s (steps + reads) |")
        print("|---|---|---|---|---|---|---|---|")
        order = sorted(dz, key=lambda k: (k[0] == "rigidrs", k[0]))
        for e, v in order:
            runs = dz[(e, v)]
            print(f"| {e} | {v} | {med(runs, 'E_rel_drift'):+.1e} | {med(runs, 'L_rel_drift'):+.1e} | "
                  f"{med(runs, 'E_max_abs_drift'):.1e} | {med(runs, 'flip_period_rel_err'):+.1e} | "
                  f"{med(runs, 'n_flips'):.0f} | {med(runs, 'wall_s'):.2f} |")


if __name__ == "__main__":
    main()
