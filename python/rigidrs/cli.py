"""Command line: ``rigidrs demo`` simulates built-in scenes and prints what it measured;
``rigidrs accuracy`` writes the work-precision report."""
from __future__ import annotations

import argparse
import sys

from . import demo


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="rigidrs", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    p_demo = sub.add_parser("demo", help="simulate built-in scenes and print measurements")
    p_demo.add_argument("--seconds", type=float, default=60.0, help="simulated time per scene (s)")
    p_demo.add_argument("--integrator", default="strang", help="integrator name (see rigidrs.INTEGRATORS)")
    p_acc = sub.add_parser("accuracy", help="work-precision report: error against cost for every method")
    p_acc.add_argument("--quick", action="store_true", help="fewer points and shorter runs (under two minutes)")
    p_acc.add_argument("--out", default="accuracy-report", help="output directory (default: accuracy-report)")
    p_acc.add_argument("--problems", nargs="+", metavar="NAME", help="a subset of the problems (default: all)")
    p_acc.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    if args.command == "demo":
        return demo.run(seconds=args.seconds, integrator=args.integrator, out=sys.stdout)
    if args.command == "accuracy":
        return run_accuracy(args.quick, args.out, args.problems, not args.no_progress)
    return 2


def run_accuracy(quick: bool, out: str, problems: list[str] | None, progress: bool) -> int:
    from .work_precision import PROBLEMS, accuracy

    if problems and any(p not in PROBLEMS for p in problems):
        print(f"unknown problem in {problems}; choose from {', '.join(PROBLEMS)}", file=sys.stderr)
        return 2
    report = accuracy(quick=quick, out=out, problems=problems, progress=progress)
    print(f"work-precision report ({'quick' if quick else 'full'}) in {report.seconds:.0f} s: {out}/report.md")
    if not report.plots:
        print("plots skipped: matplotlib is not installed (pip install rigidrs[plots])")
    for path in report.files:
        print(f"  {path}")
    return 0
