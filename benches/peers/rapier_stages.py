"""Where Rapier's step goes, by its own counters, window by window: the yardstick for
`world.profile()`'s stages of the same scene.

    python benches/peers/rapier_stages.py --scene ball_pit --window 200 --steps 600
    python benches/peers/rapier_stages.py --scene box_pile --window 40 --steps 120

Builds the scene as `ball_pit.py` (the peer scripts' builder, `PEERS_DIR` or
`../shared/bench/peers`) or `box_pile.py` does, on one thread, and prints one JSON
line per window: µs a step of wall clock and of each of Rapier's counters
(`PhysicsPipeline.counters`: broad and narrow phase, the solver's velocity assembly, i.e.
its constraint build, and its resolution, the position update). Counting, and reading the
counters after each step, costs the step about 13 % (the 1000-ball pit: 2.50 ms a step here
against 2.20 in `ball_pit.py`, 2026-12-06): compare stages, not whole steps, with it.
Needs the `rapier3d` Python package.
"""
import argparse
import json
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
COUNTERS = {
    "stages": ("collision_detection_time_ms", "solver_time_ms", "update_time_ms", "island_construction_time_ms"),
    "cd": ("broad_phase_time_ms", "final_broad_phase_time_ms", "narrow_phase_time_ms"),
    "solver": ("velocity_assembly_time_ms", "velocity_resolution_time_ms", "velocity_update_time_ms", "nconstraints"),
}


def build(a):
    """Rapier's step function for the scene, from the scripts that time it."""
    if a.scene == "ball_pit":
        sys.path.insert(0, os.environ.get("PEERS_DIR", str(HERE.parents[2] / "shared" / "bench" / "peers")))
        import ball_pit
        args = argparse.Namespace(n=1000, dt=1 / 60, spacing=0.25, friction=0.5, density=1000.0, seed=0, sleep=0, threads=1)
        step, *_ = ball_pit.build_rapier3d(args, ball_pit.initial_positions(args))
        return step
    sys.path.insert(0, str(HERE))
    import box_pile
    args = argparse.Namespace(side=a.side, layers=10, dt=1 / 60, friction=0.5, seed=0, threads=1, substeps=None)
    pos, quat = box_pile.initial_poses(args)
    step, _ = box_pile.build_rapier3d(args, pos, quat)
    return step


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", choices=["ball_pit", "box_pile"], default="ball_pit")
    ap.add_argument("--side", type=int, default=20, help="box pile: cubes a side (20: 4000 in ten layers)")
    ap.add_argument("--steps", type=int, default=600)
    ap.add_argument("--window", type=int, default=200)
    a = ap.parse_args()
    step = build(a)
    counters = step.__self__.physics_pipeline.counters
    counters.enable()
    done = 0
    while done < a.steps:
        n = min(a.window, a.steps - done)
        acc = {}
        t0 = time.perf_counter()
        for _ in range(n):
            step()
            for group, names in COUNTERS.items():
                obj = getattr(counters, group)
                for name in names:
                    acc[name] = acc.get(name, 0.0) + float(getattr(obj, name))
        wall = time.perf_counter() - t0
        done += n
        row = {"scene": a.scene, "steps_to": done, "wall_us": round(wall / n * 1e6)}
        row.update({k.replace("_time_ms", "_us"): round(v / n * (1 if k == "nconstraints" else 1e3)) for k, v in acc.items()})
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
