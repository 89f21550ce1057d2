"""Plot a side-by-side run's contact scenes, rigidrs against Rapier, on one and two threads.

    python benches/peers/plot_scaling.py OUT_DIR/results.jsonl -o docs/scaling.png

Reads the raw lines `run_side_by_side.sh` writes (run it with `SCENES="pyramid ball_pit
large_pyramids two_threads box_pile"`) and draws, per scene (ordered by body count): the
time per body-step (µs, the median over repetitions) of each engine on one and two threads,
and rigidrs's speed over Rapier's on the same thread count, with the issue "Scale"'s bar at
1.0. Sleeping variants and rigidrs's non-default settings are left out. Needs matplotlib
(`pip install rigidrs[plots]`).
"""
from __future__ import annotations

import argparse
import json
import re
import statistics
from collections import defaultdict
from pathlib import Path

CONTACT_SCENES = ("pyramid", "ball_pit", "box_pile")


def threads_of(row: dict) -> int | None:
    """The thread count a line ran on (rigidrs's default, every core, counts as none)."""
    m = re.search(r"threads=(\d+)", row.get("variant") or "")
    return int(m.group(1)) if m else None


def medians(lines: list[dict]) -> dict[tuple[str, int, str, int], float]:
    """Median steps/s per (scene, bodies, engine, threads), default settings, sleeping off."""
    runs: dict[tuple[str, int, str, int], list[float]] = defaultdict(list)
    for row in lines:
        scene = str(row.get("scene", ""))
        family = next((s for s in CONTACT_SCENES if scene.startswith(s)), None)
        variant = row.get("variant") or ""
        t = threads_of(row)
        if family is None or t is None or "sleep" in variant:
            continue
        sub, it = re.search(r"substeps=(\d+)", variant), re.search(r"iterations=(\d+)", variant)
        if (sub and sub.group(1) != "4") or (it and it.group(1) != "1"):
            continue
        runs[(family, int(row["n"]), row["engine"], t)].append(float(row["steps_per_s"]))
    return {k: statistics.median(v) for k, v in runs.items()}


def table(med: dict) -> list[tuple[str, int, dict[tuple[str, int], float]]]:
    """Per scene with both engines on some thread count: its µs per body-step by (engine, threads)."""
    scenes = sorted({(f, n) for f, n, _, _ in med}, key=lambda s: s[1])
    out = []
    for f, n in scenes:
        cell = {(e, t): 1e6 / (sps * n) for (f2, n2, e, t), sps in med.items() if (f2, n2) == (f, n)}
        if any(("rigidrs", t) in cell and ("rapier3d", t) in cell for t in (1, 2)):
            out.append((f, n, cell))
    return out


def plot(rows, out: Path, title: str) -> None:
    try:
        import matplotlib
    except ImportError as e:
        raise SystemExit("plot_scaling.py needs matplotlib: pip install rigidrs[plots]") from e
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.ticker import FormatStrFormatter, LogLocator, NullFormatter

    labels = [f"{f.replace('_', ' ')}\n{n} bodies" for f, n, _ in rows]
    x = np.arange(len(rows))
    fig, (a, b) = plt.subplots(1, 2, figsize=(13, 4.8))
    series = [("rigidrs", 1, "#1f77b4", None), ("rigidrs", 2, "#1f77b4", "//"),
              ("rapier3d", 1, "#ff7f0e", None), ("rapier3d", 2, "#ff7f0e", "//")]
    w = 0.2
    for k, (e, t, colour, hatch) in enumerate(series):
        ys = [cell.get((e, t), np.nan) for _, _, cell in rows]
        a.bar(x + (k - 1.5) * w, ys, w, color=colour, hatch=hatch, edgecolor="white",
              label=f"{'Rapier' if e == 'rapier3d' else e}, {t} thread{'s' if t > 1 else ''}")
    a.set_yscale("log")
    a.set_xticks(x, labels, fontsize=8)
    a.set_ylabel("µs per body-step (lower is faster)")
    a.set_title("Time per body and step")
    a.legend(fontsize=8)
    a.grid(axis="y", which="both", alpha=0.3)
    for k, t in enumerate((1, 2)):
        ys = [cell[("rapier3d", t)] / cell[("rigidrs", t)] if ("rigidrs", t) in cell and ("rapier3d", t) in cell
              else np.nan for _, _, cell in rows]
        # From 1.0, up where rigidrs is faster and down where it is slower.
        bars = b.bar(x + (k - 0.5) * 0.35, [y - 1.0 for y in ys], 0.35, bottom=1.0, hatch="//" if t == 2 else None,
                     color=["#2ca02c" if y >= 1.0 else "#d62728" for y in ys], edgecolor="white",
                     label=f"{t} thread{'s' if t > 1 else ''} against Rapier's {t}")
        for r, y in zip(bars, ys):
            if np.isfinite(y):
                b.annotate(f"{y:.2f}" if y >= 0.1 else f"{y:.2g}", (r.get_x() + r.get_width() / 2, y), ha="center",
                           va="bottom" if y >= 1.0 else "top", fontsize=7)
    b.axhline(1.0, color="black", lw=1, ls="--", label="the bar: 1.0")
    b.set_yscale("log")
    b.set_xticks(x, labels, fontsize=8)
    b.set_ylabel("rigidrs steps/s ÷ Rapier's (higher is faster)")
    b.set_title("rigidrs over Rapier")
    b.legend(fontsize=8, loc="lower left")
    b.grid(axis="y", which="both", alpha=0.3)
    for axis in (a.yaxis, b.yaxis):
        axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(FormatStrFormatter("%g"))
        axis.set_minor_formatter(NullFormatter())
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", type=Path, help="results.jsonl of run_side_by_side.sh")
    ap.add_argument("-o", "--out", type=Path, default=Path("scaling.png"))
    ap.add_argument("--title", default="Contact scenes side by side (dt 1/60 s, sleeping off, wall clock, medians)")
    a = ap.parse_args()
    lines = [json.loads(s) for s in a.results.read_text().splitlines() if s.startswith("{")]
    rows = table(medians(lines))
    if not rows:
        raise SystemExit(f"no contact scene with both engines in {a.results}")
    for f, n, cell in rows:
        print(f, n, {f"{e}/{t}": round(v, 3) for (e, t), v in sorted(cell.items())})
    plot(rows, a.out, a.title)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
