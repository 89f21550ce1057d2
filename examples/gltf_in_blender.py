"""Opens a .glb written by rr.export_gltf in Blender (Blender as a Python module:
``pip install bpy`` for your Python, e.g. bpy 4.2 on Python 3.11) and renders one
frame with Cycles on the CPU: no display needed. docs/gltf_in_blender.png is

    python examples/results_out.py --gltf run.glb      # 20 bodies, 3 s at 60 frames/s
    python examples/gltf_in_blender.py run.glb --time 1.0 --out docs/gltf_in_blender.png

(about 10 s; the picture in docs/ was then reduced to 256 colours). The camera is the one of docs/results_out.png, in rigidrs's z-up
coordinates: Blender is z-up too, and its importer undoes the y-up of glTF.
"""
from __future__ import annotations

import argparse
import math

import bpy  # type: ignore[import-not-found]
from mathutils import Vector  # type: ignore[import-not-found]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("glb")
    ap.add_argument("--out", default="gltf_in_blender.png")
    ap.add_argument("--time", type=float, default=1.0, help="simulated time of the frame (s)")
    ap.add_argument("--size", type=int, nargs=2, default=(480, 360))
    args = ap.parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.fps = 60  # keys land on frame = time · fps
    bpy.ops.import_scene.gltf(filepath=args.glb)
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    sc.collection.objects.link(cam)
    cam.location = (4.6, 4.2, 2.3)
    cam.rotation_euler = (Vector((0.0, 0.2, 0.6)) - cam.location).to_track_quat("-Z", "Y").to_euler()
    cam.data.angle = math.radians(45)
    sc.camera = cam
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(30))
    sc.collection.objects.link(sun)
    sky = bpy.data.worlds.new("sky")
    sky.color = (0.6, 0.7, 0.9)
    sc.world = sky
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.samples = 16
    sc.render.resolution_x, sc.render.resolution_y = args.size
    sc.render.filepath = args.out
    sc.frame_set(round(args.time * sc.render.fps))
    bpy.ops.render.render(write_still=True)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
