"""USD export: ``export_usd(world, rec, "run.usd")`` (``pip install "rigidrs[usd]"``: usd-core).

What is in the file (z-up, metres: ``upAxis = "Z"``, ``metersPerUnit = 1``, so no root
rotation is needed, unlike glTF):

* ``/World`` (the default prim), and under it one Xform per body, named after
  ``world.bodies.names`` (made a valid identifier; ``body_<i>`` when unnamed or taken),
  with the custom attribute ``rigidrs:body`` (its index). Its ops are ``translate``
  (double3) then ``orient`` (quatd), both double precision: the body's centre of mass
  and principal-frame orientation. With a recording they are time-sampled at every
  frame (a body that never moves: one value); without one they hold the current pose.
* Under each body Xform a Mesh ``shape`` in the body frame: primitives tessellated by
  :mod:`rigidrs.view.mesh` (as the renderer and glTF export draw them), hulls and
  triangle meshes as they are, compound parts merged, a Plane as a square of ground
  (``ground_size``); ``displayColor`` its colour (linear, from the sRGB palette or
  ``colors``), double-sided for planes and triangle meshes.
* Particles: a ``Points`` prim ``/World/particles`` with time-sampled ``points`` and
  ``widths`` (2 × radius; 1 % of the scene's size where the radius is 0).
* Time: ``timeCodesPerSecond`` = ``framesPerSecond`` = 1 / (the recording's frame
  interval); frame k is at time code ``times[k] × timeCodesPerSecond`` (snapped to a
  whole number within 1e-6), so a time code is simulated seconds × that rate. ``startTimeCode``/``endTimeCode`` span the frames.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from .gltf import _export_args, _ground, _linear, _poses
from .mesh import quat_matrix, shape_mesh
from .render import _atomic, _bounds, _source, body_colors

FORMATS = (".usd", ".usda", ".usdc")


def _pxr() -> Any:
    try:
        from pxr import Gf, Sdf, Tf, Usd, UsdGeom, Vt  # type: ignore[import-untyped, import-not-found, unused-ignore]
    except ImportError as e:
        raise ImportError('export_usd needs usd-core: pip install "rigidrs[usd]"') from e
    return Gf, Sdf, Tf, Usd, UsdGeom, Vt


def time_codes_per_second(times: Any) -> float:
    """The recording's frame rate (1 / median frame interval, frames per second); 60
    for a single frame."""
    t = np.asarray(times, float)
    if len(t) < 2:
        return 60.0
    return float(1.0 / np.median(np.diff(t)))


def time_codes(times: Any, tcps: float) -> list[float]:
    """Each frame's time code, ``times × tcps``, snapped to the nearest integer when within
    1e-6 of it (a recording's frames are whole frames apart; the product's rounding would
    otherwise write codes like 8.000000000000002)."""
    codes = np.asarray(times, float) * tcps
    near = np.round(codes)
    return [float(x) for x in np.where(np.abs(codes - near) < 1e-6, near, codes)]


def export_usd(source: Any, rec: Any = None, path: str | os.PathLike[str] | None = None, *,
               colors: Any = None, detail: int = 2, ground_size: float | None = None,
               particles: bool = True) -> Path:
    """Writes ``source`` (a World or Scene) as a USD stage, animated over the frames of
    ``rec`` (a Recording), or at its current pose (a Scene: its initial pose).

    ``path``: ``.usd`` or ``.usdc`` (binary crate) or ``.usda`` (text); written to a
    temporary name then renamed: on failure (missing or unwritable directory, unknown
    extension, a recording of another scene) a clear error and no file left.
    ``export_usd(world, "x.usd")`` also works. ``colors``, ``detail`` (0..3),
    ``ground_size`` (m) and ``particles`` as in :func:`rigidrs.export_gltf`. Poses are
    stored in double precision (module doc for the layout). Returns the path written.
    """
    rec, path = _export_args(rec, path, FORMATS, detail, ground_size, "export_usd")
    Gf, Sdf, Tf, Usd, UsdGeom, Vt = _pxr()
    world, shapes = _source(source)
    times, pos, quat, parts = _poses(world, len(shapes), rec)
    if rec is not None and len(times) > 1 and not np.all(np.diff(times) > 0):
        raise ValueError("the recording's times are not strictly increasing")
    has_particles = particles and parts.shape[1] > 0
    lo, hi = _bounds(shapes, pos, quat, parts if has_particles else None)
    size = ground_size if ground_size is not None else max(4.0, 4.0 * float(np.max(hi - lo)))
    color = _linear(body_colors(~(np.asarray(world.bodies.inverse_mass) > 0), colors))

    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    root = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(root.GetPrim())
    animated = rec is not None
    tcps = time_codes_per_second(times)
    codes = [Usd.TimeCode(c) for c in time_codes(times, tcps)] if animated else [Usd.TimeCode.Default()]
    if animated:
        stage.SetTimeCodesPerSecond(tcps)
        stage.SetFramesPerSecond(tcps)
        stage.SetStartTimeCode(codes[0].GetValue())
        stage.SetEndTimeCode(codes[-1].GetValue())

    taken: set[str] = set()
    names = list(world.bodies.names)
    centre = (lo + hi) / 2
    for i, d in enumerate(shapes):
        name = Tf.MakeValidIdentifier(names[i]) if names[i] else f"body_{i}"
        if name in taken or name == "particles":
            name = f"{name}_{i}"
        taken.add(name)
        xf = UsdGeom.Xform.Define(stage, f"/World/{name}")
        prim = xf.GetPrim()
        if names[i]:
            prim.SetDisplayName(names[i])
        prim.CreateAttribute("rigidrs:body", Sdf.ValueTypeNames.Int, custom=True).Set(i)
        translate = xf.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble)
        orient = xf.AddOrientOp(UsdGeom.XformOp.PrecisionDouble)
        # A body that never moves (fixed, or asleep throughout) holds one value, not samples.
        still = bool(np.all(pos[:, i] == pos[0, i]) and np.all(quat[:, i] == quat[0, i]))
        for k, code in enumerate([Usd.TimeCode.Default()] if still else codes):
            p, q = pos[k, i], quat[k, i]
            translate.Set(Gf.Vec3d(float(p[0]), float(p[1]), float(p[2])), code)
            orient.Set(Gf.Quatd(float(q[3]), float(q[0]), float(q[1]), float(q[2])), code)
        if d is None:
            continue
        if d["kind"] == "Plane":
            v, t = _ground(d, quat_matrix(quat[0, i]).T @ (centre - pos[0, i]), size)
        else:
            v, t = shape_mesh(d, detail)
        if not len(t):
            continue
        mesh = UsdGeom.Mesh.Define(stage, f"/World/{name}/shape")
        mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(np.asarray(v, np.float32)))
        mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(t), 3, np.int32)))
        mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(np.asarray(t, np.int32).reshape(-1)))
        mesh.CreateExtentAttr(Vt.Vec3fArray.FromNumpy(np.array([v.min(0), v.max(0)], np.float32)))
        mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        mesh.CreateDoubleSidedAttr(d["kind"] in ("Plane", "TriMesh"))
        mesh.CreateDisplayColorAttr(Vt.Vec3fArray.FromNumpy(np.asarray(color[i:i + 1], np.float32)))
    if has_particles:
        pts = UsdGeom.Points.Define(stage, "/World/particles")
        radius = np.asarray(world.particles.radius, float)
        # Points of radius 0 (no collision radius) are drawn 1 % of the scene's size wide.
        radius = np.where(radius > 0, radius, max(0.005 * float(np.max(hi - lo)), 1e-3))
        widths = Vt.FloatArray.FromNumpy((2.0 * radius).astype(np.float32))
        pts.CreateWidthsAttr(widths)
        attr = pts.CreatePointsAttr()
        for k, code in enumerate(codes):
            attr.Set(Vt.Vec3fArray.FromNumpy(np.asarray(parts[k], np.float32)), code)

    def save(tmp: Path) -> None:
        if not stage.GetRootLayer().Export(str(tmp)):
            raise OSError(f"cannot write {path}: USD could not export the stage")

    _atomic(path, save)
    return path
