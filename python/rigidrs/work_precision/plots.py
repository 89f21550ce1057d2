"""Work-precision and convergence diagrams (matplotlib, an optional extra:
``pip install rigidrs[plots]``)."""
from __future__ import annotations

import importlib
import io
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .. import ARTICULATION_INTEGRATORS, INTEGRATORS
from .runner import Result, Run
from .table import usable

TINY = 1e-17  # an exact zero error is drawn here


def pyplot() -> Any | None:
    """matplotlib.pyplot on the Agg backend, or None if matplotlib is not installed."""
    try:
        matplotlib = importlib.import_module("matplotlib")
    except ImportError:
        return None
    matplotlib.use("Agg")
    return importlib.import_module("matplotlib.pyplot")


def finite(runs: Sequence[Run]) -> list[Run]:
    return [r for r in runs if math.isfinite(r.error)]


def styles(result: Result) -> dict[str, dict[str, Any]]:
    """Line style per method: an integrator keeps its colour across problems (dashed
    with more than one iteration; an articulation integrator takes the colours after
    the body integrators', square markers); curves of one integrator take the colour
    cycle. A further curve of the same integrator and iterations (the bare method
    beside its default substeps) is dash-dotted."""
    curves = result.curves()
    seen: set[tuple[str, str | None, int]] = set()
    by_integrator = len({(runs[0].integrator, runs[0].articulation_integrator) for runs in curves.values()}) > 1
    names, arts = list(INTEGRATORS), list(ARTICULATION_INTEGRATORS)
    out = {}
    for k, (label, runs) in enumerate(curves.items()):
        r = runs[0]
        art = r.articulation_integrator
        index = len(names) + arts.index(art) if art else names.index(r.integrator)
        color = f"C{index % 10}" if by_integrator else f"C{k}"
        dashed = by_integrator and r.iterations > 1
        key = (r.integrator, art, r.iterations)
        ls = "-." if by_integrator and key in seen else "--" if dashed else "-"
        seen.add(key)
        out[label] = {"color": color, "ls": ls, "marker": "s" if art else "o", "ms": 3, "lw": 1.2, "label": label}
    return out


def work_precision(ax: Any, result: Result, small: bool = False) -> None:
    """Error against cost, one curve per method, the targets as dotted lines."""
    style = styles(result)
    for label, runs in result.curves().items():
        pts = sorted(finite(runs), key=lambda r: r.cost)
        ax.loglog([r.cost for r in pts], [max(r.error, TINY) for r in pts], **style[label])
    for t in result.problem.targets:
        ax.axhline(t, color="0.6", lw=0.6, ls=":")
    ax.set_xlabel("CPU time per simulated second (s/s)")
    ax.set_ylabel("error" if small else result.problem.error_label)
    ax.set_title(result.problem.title, fontsize=9 if small else 11)


def convergence(ax: Any, result: Result, small: bool = False) -> None:
    """Error against the substep h, with a dashed reference slope per nominal order."""
    slopes_drawn: set[float] = set()
    style = styles(result)
    for label, runs in result.curves().items():
        pts = finite(runs)
        ax.loglog([r.h for r in pts], [max(r.error, TINY) for r in pts], **style[label])
        order = runs[0].order
        good = usable(result.problem, pts)
        if order is None or order in slopes_drawn or len(good) < 2:
            continue
        slopes_drawn.add(order)
        h = np.array([good[0].h, good[-1].h])
        anchor = good[len(good) // 2]
        ax.loglog(h, anchor.error * (h / anchor.h) ** order, "--", color="0.4", lw=0.8)
        ax.annotate(f"slope {order:g}", (h[0], anchor.error * (h[0] / anchor.h) ** order), fontsize=7, color="0.3")
    ax.set_xlabel("substep h (s)")
    ax.set_ylabel("error" if small else result.problem.error_label)
    ax.set_title(result.problem.title, fontsize=9 if small else 11)


def save(fig: Any, path: Path, dpi: int) -> Path:
    """Writes ``fig`` as a PNG of 64 colours (a quarter of the bytes; Pillow comes
    with matplotlib), or as matplotlib writes it if Pillow is missing."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    try:
        image = importlib.import_module("PIL.Image")
    except ImportError:
        path.write_bytes(buf.getvalue())
        return path
    buf.seek(0)
    image.open(buf).convert("RGB").quantize(colors=64).save(path, optimize=True)
    return path


def single(plt: Any, result: Result, kind: str, path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(6.0, 4.5))
    (work_precision if kind == "work_precision" else convergence)(ax, result)
    ax.grid(True, which="major", lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save(fig, path, dpi=100)
    plt.close(fig)
    return path


def overview(plt: Any, results: Sequence[Result], kind: str, path: Path) -> Path:
    """Every problem's diagram of one kind in a grid of small panels."""
    cols = 3
    rows = math.ceil(len(results) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.0 * cols, 3.1 * rows), squeeze=False)
    for ax, result in zip(axes.flat, results):
        (work_precision if kind == "work_precision" else convergence)(ax, result, small=True)
        ax.tick_params(labelsize=7)
        ax.xaxis.label.set_size(7)
        ax.yaxis.label.set_size(7)
        ax.legend(fontsize=5.5, loc="best")
    for ax in list(axes.flat)[len(results):]:
        ax.axis("off")
    fig.tight_layout()
    save(fig, path, dpi=72)
    plt.close(fig)
    return path


def write_plots(results: Sequence[Result], out: Path) -> list[Path] | None:
    """Writes every PNG into ``out``; None if matplotlib is missing."""
    plt = pyplot()
    if plt is None:
        return None
    files = []
    for result in results:
        for kind in ("work_precision", "convergence"):
            files.append(single(plt, result, kind, out / f"{result.problem.name}_{kind}.png"))
    for kind in ("work_precision", "convergence"):
        files.append(overview(plt, results, kind, out / f"{kind}.png"))
    return files
