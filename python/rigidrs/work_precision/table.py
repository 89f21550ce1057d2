"""Numbers read off the curves (convergence slopes, cost to reach an error) and the
markdown report."""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .base import Problem
from .runner import Result, Run


def usable(problem: Problem, runs: Sequence[Run]) -> list[Run]:
    """Runs whose error is above round-off and below saturation."""
    return [r for r in runs if problem.floor < r.error < problem.ceiling]


def slope(problem: Problem, runs: Sequence[Run]) -> float | None:
    """Least-squares slope of log(error) against log(h) over the usable runs."""
    pts = usable(problem, runs)
    if len({r.h for r in pts}) < 2:
        return None
    return float(np.polyfit(np.log([r.h for r in pts]), np.log([r.error for r in pts]), 1)[0])


def cost_to_reach(runs: Sequence[Run], target: float) -> tuple[float | None, str]:
    """The cost at which a curve first gets to ``target``: log-log interpolation
    between the last run above it and the first at or below it, in order of cost.
    Returns ``(cost, note)``: note ``"≤"`` if the cheapest run already reaches it,
    ``"never"`` (cost None) if no run does."""
    pts = sorted((r.cost, r.error) for r in runs if math.isfinite(r.error) and r.cost > 0)
    for k, (c, e) in enumerate(pts):
        if e <= target:
            if k == 0:
                return c, "≤"
            c0, e0 = pts[k - 1]
            f = (math.log(e0) - math.log(target)) / (math.log(e0) - math.log(max(e, 1e-300)))
            return math.exp(math.log(c0) + f * (math.log(c) - math.log(c0))), ""
    return None, "never"


def fmt_cost(seconds: float) -> str:
    """A cost in seconds per simulated second, 3 digits in the largest unit that keeps
    the number below 1000 after rounding."""
    for unit, scale in (("ns", 1e-9), ("µs", 1e-6), ("ms", 1e-3)):
        text = f"{seconds / scale:.3g}"
        if float(text) < 1000:
            return f"{text} {unit}/s"
    return f"{seconds:.3g} s/s"


def fmt_err(e: float) -> str:
    return "∞ (blew up)" if math.isinf(e) else f"{e:.2e}"


def reach_cell(runs: Sequence[Run], target: float) -> str:
    cost, note = cost_to_reach(runs, target)
    if cost is None:
        best = min((r.error for r in runs), default=math.inf)
        return f"never (best {fmt_err(best)})"
    return f"{note} {fmt_cost(cost)}".strip()


def summary_rows(result: Result) -> list[list[str]]:
    rows = []
    for label, runs in result.curves().items():
        s = slope(result.problem, runs)
        nominal = "—" if runs[0].order is None else f"{runs[0].order:g}"
        rows.append([
            label, nominal, "—" if s is None else f"{s:.2f}",
            f"{fmt_err(runs[0].error)} → {fmt_err(runs[-1].error)}",
            f"{fmt_cost(runs[0].cost)} → {fmt_cost(runs[-1].cost)}",
            *[reach_cell(runs, t) for t in result.problem.targets],
        ])
    return rows


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def cheapest(result: Result, target: float) -> str:
    """"method (cost), …" in order of the cost to reach ``target``."""
    found = []
    for label, runs in result.curves().items():
        cost, _ = cost_to_reach(runs, target)
        if cost is not None:
            found.append((cost, label))
    if not found:
        return "no method reaches it"
    return ", ".join(f"{label} ({fmt_cost(c)})" for c, label in sorted(found)[:3])


def problem_section(result: Result) -> str:
    p = result.problem
    header = ["method", "nominal order", "measured slope", "error, coarse → fine h", "cost, coarse → fine h",
              *[f"cost to reach {t:g}" for t in p.targets]]
    parts = [f"## {p.title} (`{p.name}`)", "", f"Error: {p.error_label}. Reference: {p.reference}.", "",
             markdown_table(header, summary_rows(result)), ""]
    parts += [f"- cheapest to reach {t:g}: {cheapest(result, t)}" for t in p.targets]
    parts += ["", "<details><summary>every run</summary>", "", runs_table(result), "", "</details>", ""]
    return "\n".join(parts)


def runs_table(result: Result) -> str:
    extras = list(result.problem.extras)
    header = ["method", "dt (s)", "substeps", "h (s)", "error", "cost", "timing spread", *extras]
    rows = []
    for label, runs in result.curves().items():
        for r in runs:
            rows.append([label, f"{r.dt:.3g}", str(r.substeps), f"{r.h:.3g}", fmt_err(r.error), fmt_cost(r.cost),
                         f"{100 * r.cost_spread:.0f} %", *[f"{r.metrics.get(k, math.nan):.2e}" for k in extras]])
    legend = "; ".join(f"{k}: {v}" for k, v in result.problem.extras.items())
    return markdown_table(header, rows) + (f"\n\n{legend}." if legend else "")


def report_markdown(results: Sequence[Result], intro: str) -> str:
    return "\n".join([intro, "", *[problem_section(r) for r in results]])
