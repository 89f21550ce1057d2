#!/usr/bin/env python
"""Medians and ratios of the JSON lines written by run_side_by_side.sh, as Markdown.

    python benches/peers/compare.py results.jsonl > COMPARISON.md

Sections for whichever scenes the file holds: free_bodies, dzhanibekov, and the
contact scenes pyramid (sleep off and on) and ball_pit, each with every engine's
steps/s and its ratio to MuJoCo, PyBullet and Rapier (1 thread) run with the same
sleep setting, the physics outcome, and rigidrs's `world.profile()` per stage.
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


def rng(runs, key, scale=1.0, digits=2):
    vals = [r[key] * scale for r in runs if r.get(key) is not None]
    return f"{min(vals):.{digits}f}–{max(vals):.{digits}f}" if len(vals) > 1 else ""


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
                if d["scene"] == "pyramid" and d["n"] != 210:  # the larger bases are scenes of their own
                    d["scene"] = f"pyramid_{d['n']}"
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

    scenes = sorted({k[0] for k in groups}, key=lambda s: (s.split("_")[0], len(s), s))
    for scene in scenes:
        if scene.startswith(("pyramid", "ball_pit")):
            contact_scene(scene, {k[1:]: v for k, v in groups.items() if k[0] == scene})
        elif scene.startswith("box_pile"):
            box_pile(scene, {k[1:]: v for k, v in groups.items() if k[0] == scene})


CONTACT_BASELINES = {"MuJoCo": ("mujoco", "Euler/"), "PyBullet": ("pybullet", "maximal"),
                     "Rapier": ("rapier3d", "threads=1"), "Rapier 2 threads": ("rapier3d", "threads=2")}  # variant without ",sleep": a prefix for MuJoCo, exact otherwise


def is_sleep(variant):
    return variant.endswith(",sleep")


def baseline(runs, engine, variant, sleep):
    """Median steps/s of the peer's default run with the given sleep setting, or None."""
    for (e, v), r in runs.items():
        base = v.removesuffix(",sleep")
        if e == engine and is_sleep(v) == sleep and (base.startswith(variant) if engine == "mujoco" else base == variant):
            return med(r, "steps_per_s")
    return None


def outcome(scene, runs):
    m = lambda k: med(runs, k)  # noqa: E731
    has = lambda k: runs[0].get(k) is not None  # noqa: E731  (rigidrs's extra fields)
    depth = ""
    if has("peak_depth"):
        depth = f"; penetration {1e3 * m('max_depth'):.1f} mm at the end"
        if has("max_depth_container"):
            depth += f" ({1e3 * m('max_depth_container'):.1f} against the container)"
        depth += f", peak {1e3 * m('peak_depth'):.1f}"
    if scene.startswith("pyramid"):
        state = "**collapsed**" if m("collapsed") >= 0.5 else ("stands" if m("max_disp") < 0.03 else "stands, > 3 cm")
        horiz = f", horizontal {100 * m('max_horiz_disp'):.1f} cm" if has("max_horiz_disp") else ""
        asleep = f"; {m('asleep'):.0f} asleep at the end" if has("asleep") and is_sleep(runs[0]["variant"]) else ""
        return (f"{state}: max disp {100 * m('max_disp'):.1f} cm{horiz} (peak {100 * m('peak_disp'):.1f}, "
                f"{m('n_moved'):.0f} moved > 0.5 m), apex sinks {100 * -m('top_dz'):.1f} cm" + depth + asleep)
    bad = m("escaped") + m("floor_penetrated") + (m("wall_penetrated") if has("wall_penetrated") else 0)
    state = "all in the box" if bad == 0 else "**balls out of the box or sunk**"
    return (f"{state}: escaped {m('escaped'):.0f}, floor-penetrated {m('floor_penetrated'):.0f}, lowest centre "
            f"{1e3 * m('min_z'):.1f} mm (r = 100), max speed at the end {m('max_speed_end'):.3f} m/s" + depth)


def contact_scene(scene, runs):
    first = next(iter(runs.values()))[0]
    title = f"pyramid of {first['n']} boxes" if scene.startswith("pyramid") else f"ball pit, {first['n']} spheres"
    print(f"\n## {title}: {first['steps']} steps of {first['dt']:.6g} s, stepped one call per step\n")
    print("Ratios: steps/s of the row ÷ steps/s of the peer run with the same sleep setting (> 1: the row is faster).\n")
    print("| engine | variant | steps/s (min–max) | " + " | ".join(f"÷ {b}" for b in CONTACT_BASELINES) + " | outcome |")
    print("|---|---|---|" + "---|" * len(CONTACT_BASELINES) + "---|")
    order = sorted(runs, key=lambda k: (is_sleep(k[1]), k[0] == "rigidrs", k[0], k[1]))
    for e, v in order:
        r = runs[(e, v)]
        s = med(r, "steps_per_s")
        ratios = []
        for eng, prefix in CONTACT_BASELINES.values():
            b = baseline(runs, eng, prefix, is_sleep(v))
            ratios.append(f"{s / b:.2f}" if b else "—")
        print(f"| {e} | {v} | {s:.0f} ({rng(r, 'steps_per_s', digits=0)}) | " + " | ".join(ratios)
              + f" | {outcome(scene, r)} |")
    rig = [(v, r) for (e, v), r in runs.items() if e == "rigidrs" and r[0].get("profile_s_per_step")]
    if rig:
        print(f"\nrigidrs `world.profile()` over the timed loop ({scene}): µs per step per stage (wall clock, "
              "median), its share of the profiled total, and that share of the median CPU time per step:\n")
        stages = []
        for _, r in rig:
            for k in r[0]["profile_s_per_step"]:
                if k not in stages:
                    stages.append(k)
        print("| variant | " + " | ".join(stages) + " | profiled total | CPU time per step |")
        print("|---|" + "---|" * (len(stages) + 2))
        for v, r in sorted(rig):
            cpu = med(r, "step_s") / r[0]["steps"]
            cells = []
            for k in stages:
                us = float(np.median([x["profile_s_per_step"].get(k, 0.0) for x in r])) * 1e6
                share = float(np.median([x["profile_share"].get(k, 0.0) for x in r]))
                cells.append(f"{us:.0f} ({share:.0%}; {share * cpu * 1e6:.0f})" if us >= 0.5 else "0")
            tot = float(np.median([sum(x["profile_s_per_step"].values()) for x in r])) * 1e6
            print(f"| {v} | " + " | ".join(cells) + f" | {tot:.0f} | {cpu * 1e6:.0f} |")


def box_pile(scene, runs):
    first = next(iter(runs.values()))[0]
    print(f"\n## box pile, {first['n']} cubes dropped: {first['steps']} steps of {first['dt']:.6g} s, sleep off\n")
    print("| engine | variant | steps/s (min–max) | µs per body-step | ÷ Rapier 1 thread | ÷ Rapier 2 threads | lowest centre |")
    print("|---|---|---|---|---|---|---|")
    base = {t: med(runs[("rapier3d", f"threads={t}")], "steps_per_s") if ("rapier3d", f"threads={t}") in runs else None
            for t in (1, 2)}
    for e, v in sorted(runs, key=lambda k: (k[0] == "rigidrs", k[1])):
        r = runs[(e, v)]
        s = med(r, "steps_per_s")
        ratios = " | ".join(f"{s / b:.3f}" if b else "—" for b in base.values())
        print(f"| {e} | {v} | {s:.2f} ({rng(r, 'steps_per_s')}) | {med(r, 'us_per_body_step'):.2f} | {ratios} | "
              f"{med(r, 'min_z'):.3f} m |")


if __name__ == "__main__":
    main()
