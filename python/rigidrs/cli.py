"""Command line: ``rigidrs demo`` simulates built-in scenes and prints what it measured;
``rigidrs run SCENE`` simulates a scene file and writes a recording, video, glTF or USD;
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
    p_demo.add_argument("--video", metavar="PATH", default=None,
                        help="also draw a ball knocking over a pyramid into PATH (.mp4 or .gif: pip install "
                             "\"rigidrs[video]\"; .png: the last frame)")
    p_demo.add_argument("--only-video", action="store_true", help="with --video: skip the measured scenes")
    p_acc = sub.add_parser("accuracy", help="work-precision report: error against cost for every method")
    p_acc.add_argument("--quick", action="store_true", help="fewer points and shorter runs (under two minutes)")
    p_acc.add_argument("--out", default="accuracy-report", help="output directory (default: accuracy-report)")
    p_acc.add_argument("--problems", nargs="+", metavar="NAME", help="a subset of the problems (default: all)")
    p_acc.add_argument("--no-progress", action="store_true", help="no progress bar")
    p_run = sub.add_parser("run", help="simulate a scene file; write a recording, video, glTF or USD; view it")
    p_run.add_argument("scene", help="a Python file defining `scene` or `make_scene()`, or a scene file (.toml, .json)")
    p_run.add_argument("--seconds", type=float, default=5.0, help="simulated time (s, default 5)")
    p_run.add_argument("--dt", type=float, default=None, help="time step (s; default the file's `dt`, else 1/120)")
    p_run.add_argument("--every", type=int, default=None, help="steps between recorded frames (default: 60 frames/s)")
    for flag, kinds in OUTPUT_FLAGS.items():
        p_run.add_argument(f"--{flag}", metavar="PATH", help=f"write {OUTPUT_WHAT[flag]} ({', '.join(kinds)})")
    p_run.add_argument("-o", "--out", action="append", default=[], metavar="PATH",
                       help="another output, chosen by its extension (.npz .png .gif .mp4 .glb .gltf .usd .usda "
                            ".usdc); repeat for more")
    p_run.add_argument("--energies", action="store_true", help="also record kinetic and potential energy per frame (in the .npz)")
    p_run.add_argument("--contacts", action="store_true", help="also record the contact points per frame (in the .npz)")
    p_run.add_argument("--view", action="store_true", help="then play the recording in the browser viewer (Ctrl-C to stop)")
    p_run.add_argument("--port", type=int, default=8080, help="viewer port (default 8080)")
    p_run.add_argument("--no-progress", action="store_true", help="no progress bar")
    p_view = sub.add_parser("view", help="open the browser viewer on a scene (stepped live) or a recording of it")
    p_view.add_argument("scene", help="as for `run`: a Python file defining `scene` or `make_scene()`, or a scene file")
    p_view.add_argument("recording", nargs="?", help="a recording of that scene (.npz, from `run --record`) to play back")
    p_view.add_argument("--dt", type=float, default=None, help="time step (s; default the file's `dt`, else 1/120)")
    p_view.add_argument("--speed", type=float, default=1.0, help="simulated seconds per second (default 1)")
    p_view.add_argument("--paused", action="store_true", help="start paused")
    p_view.add_argument("--host", default="127.0.0.1", help="address to serve on (default 127.0.0.1; 0.0.0.0: all)")
    p_view.add_argument("--port", type=int, default=8080, help="port (default 8080; the next free one if taken)")
    args = parser.parse_args(argv)
    if args.command == "run":
        return _run(args)
    if args.command == "view":
        return _view(args)
    if args.command == "demo":
        code = 0 if args.only_video else demo.run(seconds=args.seconds, integrator=args.integrator, out=sys.stdout)
        if code == 0 and args.video:
            if not args.only_video:
                print()
            code = demo.video(args.video, integrator=args.integrator, out=sys.stdout)
        return code
    if args.command == "accuracy":
        return run_accuracy(args.quick, args.out, args.problems, not args.no_progress)
    return 2


OUTPUT_FLAGS = {"record": (".npz",), "video": (".mp4", ".gif", ".png"), "gltf": (".glb", ".gltf"),
                "usd": (".usd", ".usda", ".usdc")}
"""``rigidrs run`` output flags and the extensions each takes (``--out`` takes any of them)."""
OUTPUT_WHAT = {"record": "the recording", "video": "a video, or a picture of the last frame",
               "gltf": "an animated glTF", "usd": "an animated USD stage"}


def _run(args: argparse.Namespace) -> int:
    from .run import run

    outputs = list(args.out)
    for flag, kinds in OUTPUT_FLAGS.items():
        path = getattr(args, flag)
        if path is not None:
            if not path.lower().endswith(kinds):
                print(f"rigidrs run: --{flag} {path}: the file name must end in {' or '.join(kinds)}", file=sys.stderr)
                return 2
            outputs.append(path)
    return run(args.scene, seconds=args.seconds, dt=args.dt, every=args.every, outputs=outputs,
               view=args.view, port=args.port, progress=not args.no_progress,
               energies=args.energies, contacts=args.contacts)


def _view(args: argparse.Namespace) -> int:
    from . import Recording
    from .run import RunError, load
    from .view import viewer as viewer_module

    try:
        world = load(args.scene, args.dt)
        rec = Recording.load(args.recording) if args.recording else None
        viewer_module.view(world, rec, host=args.host, port=args.port, speed=args.speed, playing=not args.paused)
    except (RunError, OSError, ValueError, TypeError, ImportError) as e:
        print(f"rigidrs view: {e}", file=sys.stderr)
        return 2
    return 0


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
