"""Command line: ``rigidrs demo`` simulates built-in scenes and prints what it measured."""
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
    args = parser.parse_args(argv)
    if args.command == "demo":
        return demo.run(seconds=args.seconds, integrator=args.integrator, out=sys.stdout)
    return 2
