"""The bench scripts' arithmetic: `benches/peers/plot_scaling.py` reads a side-by-side
run's raw lines into µs per body-step by engine and thread count."""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benches" / "peers"))
import plot_scaling  # noqa: E402


def line(scene, engine, n, variant, sps):
    return {"scene": scene, "engine": engine, "n": n, "variant": variant, "steps_per_s": sps}


def test_scaling_plot_takes_medians_of_default_runs_per_thread_count():
    lines = [
        line("ball_pit", "rigidrs", 1000, "substeps=4,iterations=1,threads=1", 380.0),
        line("ball_pit", "rigidrs", 1000, "substeps=4,iterations=1,threads=1", 400.0),
        line("ball_pit", "rigidrs", 1000, "substeps=4,iterations=1,threads=1", 390.0),
        line("ball_pit", "rigidrs", 1000, "substeps=3,iterations=1,threads=1", 900.0),  # not the defaults
        line("ball_pit", "rigidrs", 1000, "substeps=4,iterations=1", 520.0),  # every core: no count
        line("ball_pit", "rapier3d", 1000, "threads=1", 450.0),
        line("pyramid", "rapier3d", 210, "threads=1,sleep", 9000.0),  # sleeping
        line("box_pile_4000", "rigidrs", 4000, "threads=2", 15.0),
        line("box_pile_4000", "rapier3d", 4000, "threads=2", 250.0),
        line("free_bodies", "rigidrs", 2000, "threads=1", 1e4),  # not a contact scene
    ]
    med = plot_scaling.medians(lines)
    assert med == {("ball_pit", 1000, "rigidrs", 1): 390.0, ("ball_pit", 1000, "rapier3d", 1): 450.0,
                   ("box_pile", 4000, "rigidrs", 2): 15.0, ("box_pile", 4000, "rapier3d", 2): 250.0}
    rows = plot_scaling.table(med)
    assert [(f, n) for f, n, _ in rows] == [("ball_pit", 1000), ("box_pile", 4000)]
    pit = rows[0][2]
    assert pit[("rigidrs", 1)] == pytest.approx(1e6 / (390.0 * 1000), rel=1e-12)
    assert pit[("rapier3d", 1)] / pit[("rigidrs", 1)] == pytest.approx(390.0 / 450.0, rel=1e-12)
