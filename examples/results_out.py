"""Results out: records a ball knocking over a pyramid of boxes next to a few other
shapes, saves the recording and an animated glTF (run.glb), and draws it without a display
(docs/results_out.png, and a GIF with --gif). Prints the files' sizes per simulated second.

    python examples/results_out.py [--out docs/results_out.png] [--gif run.gif]
"""
from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

import rigidrs as rr


def scene() -> rr.Scene:
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True, friction=0.6)
    for row in range(5):
        for j in range(5 - row):
            s.add_body(rr.Box((0.2, 0.2, 0.2)), density=300.0, friction=0.6,
                       position=((j - (4 - row) / 2) * 0.41, 0.0, 0.2 + 0.4 * row))
    s.add_body(rr.Sphere(0.3), density=1500.0, friction=0.6, position=(-0.1, 3.0, 0.3),
               linear_velocity=(0.0, -4.0, 0.0))
    s.add_body(rr.Capsule(0.12, 0.25), density=500.0, position=(1.7, -0.6, 0.3), orientation=(0.7071, 0, 0, 0.7071))
    s.add_body(rr.Cylinder(0.25, 0.3), density=500.0, position=(-1.7, 1.3, 0.3))
    s.add_body(rr.Cone(0.3, 0.35), density=500.0, position=(-1.6, -1.2, 0.35))
    return s


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="docs/results_out.png")
    ap.add_argument("--gif", default=None)
    ap.add_argument("--gltf", default=None, help="also keep the animated glTF here (.glb or .gltf)")
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--at", type=float, default=1.0, help="time of the picture (s)")
    args = ap.parse_args()
    dt = 1 / 120
    world = scene().build(dt=dt)
    rec = world.record(every=2)  # 60 frames per simulated second
    world.step(int(round(args.seconds / dt)))
    with tempfile.TemporaryDirectory() as tmp:
        for compress in (False, True):
            path = os.path.join(tmp, "run.npz")
            rec.save(path, compress=compress)
            print(f"{len(world.bodies)} bodies, 60 frames/s: {os.path.getsize(path) / args.seconds / 1e3:.1f} kB per "
                  f"simulated second ({'savez_compressed' if compress else 'savez'}); nbytes {rec.nbytes / args.seconds / 1e3:.1f} kB/s")
        one = rr.export_gltf(world, rec, os.path.join(tmp, "run.glb"))
        still = rr.export_gltf(world, os.path.join(tmp, "still.glb"))  # no animation: the fixed part
        size, fixed = os.path.getsize(one), os.path.getsize(still)
        print(f"glTF: {size / 1e3:.1f} kB for {args.seconds:g} s at 60 frames/s: {fixed / 1e3:.1f} kB of meshes and "
              f"nodes plus {(size - fixed) / args.seconds / 1e3:.1f} kB per simulated second")
    k = int(np.argmin(np.abs(rec.times - args.at)))
    camera = rr.Camera(eye=(4.6, 4.2, 2.3), target=(0.0, 0.2, 0.6))
    t0 = time.perf_counter()
    rr.render(world, rec, args.out, frame=k, camera=camera, antialias=2)
    print(f"wrote {args.out} (t = {rec.times[k]:.2f} s) in {time.perf_counter() - t0:.2f} s")
    if args.gltf:
        rr.export_gltf(world, rec, args.gltf)
        print(f"wrote {args.gltf}")
    if args.gif:
        rr.render(world, rec, args.gif, camera=camera, size=(480, 360), fps=30)
        print(f"wrote {args.gif}")


if __name__ == "__main__":
    main()
