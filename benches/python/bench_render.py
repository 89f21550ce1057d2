"""Frames per second of the NumPy software renderer (rigidrs.render) for a scene of
200 bodies (boxes, spheres, capsules, cylinders, cones on a ground plane) at
640 × 480, one core, shadows and fog on. A benchmark, not a test:

    python benches/python/bench_render.py [--bodies 200] [--frames 60] [--size 640 480]
"""
from __future__ import annotations

import argparse
import os
import time

# One core: NumPy's BLAS must not use more (set before NumPy loads).
for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402

import rigidrs as rr  # noqa: E402
from rigidrs.view.render import Renderer, _bounds, write_png  # noqa: E402


def scene(n: int) -> rr.Scene:
    rng = np.random.default_rng(1)
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True, friction=0.5)
    shapes = [rr.Box((0.15, 0.1, 0.2)), rr.Sphere(0.15), rr.Capsule(0.08, 0.15),
              rr.Cylinder(0.12, 0.12), rr.Cone(0.15, 0.15)]
    side = int(np.ceil(np.sqrt(n)))
    for i in range(n):
        q = rng.normal(size=4)
        s.add_body(shapes[i % len(shapes)], density=500.0, friction=0.5,
                   position=(0.5 * (i % side), 0.5 * (i // side), 0.3 + rng.uniform(0, 1.5)),
                   orientation=q / np.linalg.norm(q))
    return s


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bodies", type=int, default=200)
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--size", type=int, nargs=2, default=(640, 480))
    ap.add_argument("--save", default=None, help="also write the last frame as this PNG")
    args = ap.parse_args()
    world = scene(args.bodies).build(dt=1 / 60)
    rec = world.record()
    world.step(args.frames - 1)
    shapes = world.shapes()
    fixed = ~(np.asarray(world.bodies.inverse_mass) > 0)
    r = Renderer(shapes, fixed, bounds=_bounds(shapes, rec.position, rec.orientation, None), size=tuple(args.size))
    pos, quat = rec.position, rec.orientation
    r.frame(pos[0], quat[0])  # the background is drawn once per camera
    t0 = time.perf_counter()
    for k in range(len(pos)):
        img = r.frame(pos[k], quat[k])
    elapsed = time.perf_counter() - t0
    tris = len(r.scene.tris)
    print(f"{args.bodies} bodies ({tris} triangles) at {args.size[0]} x {args.size[1]}: "
          f"{len(pos) / elapsed:.1f} frames/s ({elapsed / len(pos) * 1e3:.1f} ms per frame, one core)")
    if args.save:
        write_png(args.save, img)


if __name__ == "__main__":
    main()
