"""A ball spinning on flush tiles, against the Hertz patch's rate (`docs/ball_spin_tiles.png`).

    python docs/ball_spin_tiles.py series > now.json        # with the build to measure
    python docs/ball_spin_tiles.py plot before.json now.json docs/ball_spin_tiles.png

The ball of `tests/test_ball_spin.py` (r 0.1 m, 1000 kg/m³, μ 0.5) spun about the
vertical at 5 rad/s, at rest on a plane, on the seam between two of four box tiles
(0.5 m, flush) and on the corner where the four meet. On the floor it slows at
`α = (3π/16) √(R δ) μ g / (2/5 R)` (`δ` the 1 µm resting depth): the line drawn.
"""
import json
import sys
from pathlib import Path

import numpy as np

RADIUS, MU, SPIN, G, DT, SECONDS = 0.1, 0.5, 5.0, 9.81, 1.0 / 60.0, 3.0
PLACES = {"on a plane": None, "on a seam of two tiles": (0.0, 0.13), "where four tiles meet": (0.0, 0.0)}


def world_at(place):
    import rigidrs as rr

    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    x, y = place or (0.0, 0.0)
    if place is None:
        scene.add_body(rr.Plane(), fixed=True, friction=MU)
    else:
        for i in (-1, 0):
            for j in (-1, 0):
                scene.add_body(rr.Box((0.25, 0.25, 0.25)), fixed=True, friction=MU,
                               position=(0.5 * i + 0.25, 0.5 * j + 0.25, -0.25))
    scene.add_body(rr.Sphere(RADIUS), density=1000.0, friction=MU, position=(x, y, RADIUS),
                   angular_velocity=(0.0, 0.0, SPIN))
    return scene.build(dt=DT, sleep=False)


def series(place):
    """The ball's spin (rad/s) after each step."""
    world = world_at(place)
    ball = len(world.bodies) - 1
    out = []
    for _ in range(round(SECONDS / DT)):
        world.step(1)
        out.append(float(world.bodies.angular_velocity[ball, 2]))
    return out


def hertz_rate():
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    from test_ball_spin import hertz_spin_deceleration

    return hertz_spin_deceleration(RADIUS, MU)


def plot(before, now, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    t = np.arange(1, round(SECONDS / DT) + 1) * DT
    formula = np.maximum(SPIN - hertz_rate() * t, 0.0)
    for ax, (title, data) in zip(axes, [("before", before), ("now", now)]):
        ax.plot(t, formula, color="black", lw=3, alpha=0.25, label="Hertz patch: 5 − αt")
        for (name, w), style in zip(data.items(), ("-", "--", ":")):
            ax.plot(t, w, style, lw=1.8, label=name)
        ax.set_title(f"{title}: ball (r 0.1 m, μ 0.5) spun at 5 rad/s")
        ax.set_xlabel("time (s)")
        ax.grid(alpha=0.3)
        ax.legend(loc="lower left", fontsize=8)
    axes[0].set_ylabel("spin about the vertical (rad/s)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if sys.argv[1] == "series":
        print(json.dumps({name: series(place) for name, place in PLACES.items()}))
    else:
        before, now = (json.loads(Path(f).read_text()) for f in sys.argv[2:4])
        plot(before, now, sys.argv[4])
