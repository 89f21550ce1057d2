"""The rim depth of Euler's disk over 2 s at the defaults (`docs/eulers_disk.png`).

    python docs/eulers_disk.py series > now.json        # with the build to measure
    python docs/eulers_disk.py plot before.json now.json docs/eulers_disk.png

The disk of `tests/test_rolling.py` (r 0.2 m, 4 cm thick, on its rim tilted 57°),
spun about its axis at 5, 10 and 30 rad/s, without friction and with μ = 0.5; the
depth is its lowest point below the floor, from its pose.
"""
import json
import sys
from pathlib import Path

import numpy as np

SPINS = (5.0, 10.0, 30.0)
FRICTIONS = (0.0, 0.5)


def series(spin, friction, seconds=2.0):
    """The rim depth (m) after each step of the disk of `tests/test_rolling.py`."""
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    from test_rolling import DT, rim_depth, wobbling_disk

    world, disk, (r, half) = wobbling_disk(spin, friction)
    depths = []
    for _ in range(round(seconds / DT)):
        world.step(1)
        depths.append(rim_depth(world, disk, r, half))
    return depths


def plot(before, now, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    colors = dict(zip(SPINS, ("tab:blue", "tab:orange", "tab:green")))
    for ax, mu in zip(axes, FRICTIONS):
        for spin in SPINS:
            key = f"{spin}/{mu}"
            t = np.arange(1, len(now[key]) + 1) / 60.0
            mm = lambda d: np.maximum(np.asarray(d) * 1e3, 1e-4)  # lifted: at the axis' floor
            ax.semilogy(t, mm(before[key]), color=colors[spin], ls="--", lw=1.2, label=f"{spin:.0f} rad/s, before")
            ax.semilogy(t, mm(now[key]), color=colors[spin], lw=1.8, label=f"{spin:.0f} rad/s, now")
        ax.axhline(5.0, color="k", lw=0.8, ls=":")
        ax.text(0.02, 5.6, "slop 5 mm", fontsize=8)
        ax.axhline(2e-3, color="gray", lw=0.8, ls=":")
        ax.text(0.02, 2.3e-3, "rest depth 2 µm", fontsize=8, color="gray")
        ax.set_title(f"Euler's disk (r 0.2 m, tilted 57°), {'frictionless' if mu == 0 else f'friction μ = {mu}'}")
        ax.set_xlabel("time (s), dt 1/60, defaults")
        ax.set_ylim(1e-4, 30)
    axes[0].set_ylabel("rim depth below the floor (mm)")
    axes[1].legend(fontsize=7, ncol=2, loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if sys.argv[1:2] == ["series"]:
        print(json.dumps({f"{s}/{m}": series(s, m) for s in SPINS for m in FRICTIONS}))
    elif sys.argv[1:2] == ["plot"] and len(sys.argv) == 5:
        plot(json.load(open(sys.argv[2])), json.load(open(sys.argv[3])), sys.argv[4])
    else:
        sys.exit(__doc__)
