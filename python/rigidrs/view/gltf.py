"""Animated glTF 2.0 export: ``export_gltf(world, rec, "run.glb")``.

The file is written by hand with NumPy and ``json`` (no dependency): glTF is a JSON
document plus one binary buffer, and the part of it used here (meshes, materials,
nodes, one animation) is small and fully specified, so an extra would only add an
install step. Independent readers (pygltflib, trimesh) check the files in the tests.

What is in the file:

* A root node ``rigidrs (z-up)`` rotated −90° about x, quaternion (−√½, 0, 0, √½):
  glTF is y-up, rigidrs is z-up, and this rotation takes rigidrs's z to glTF's y
  (a point (x, y, z) of the world is at (x, z, −y) in the file). Everything else is
  a child of it, in rigidrs coordinates, metres.
* One node per body (named ``world.bodies.names``), translation and rotation = the
  body's position and orientation (centre of mass, principal frame; glTF quaternions
  are x, y, z, w like ours), carrying its shape as a mesh in the body frame:
  primitives tessellated by :mod:`rigidrs.view.mesh` (as the renderer draws them),
  hulls and triangle meshes as they are, compound parts merged, a Plane as a finite
  square of ground (``ground_size``) around the bodies. A body without a shape has a
  node and no mesh. No normals are written: glTF readers then shade flat, which is
  right for boxes and hulls (and keeps the file small).
* One material per colour (``colors`` as in :func:`rigidrs.render`, sRGB: a palette by
  default, fixed bodies grey), stored linear as glTF's ``baseColorFactor`` wants it, so
  viewers show the renderer's colours; triangle meshes and the ground are double-sided.
* With a recording, one animation: per body a translation and a rotation channel,
  LINEAR, sampled at ``rec.times`` (s, float32, as recorded). Consecutive quaternions
  are sign-aligned so that interpolation takes the short way. Without a recording
  the nodes hold the current pose (a Scene: its initial pose).
* Particles (``particles=True``, default): a POINTS primitive per frame, shown only at
  its frame (scale 1 at its time and 0 at the others, STEP), under a node
  ``particles``; cloth or soft bodies are not exported as a deforming surface.

Geometry and samplers are float32, indices uint16 or uint32; identical geometry
(equal bodies) is stored once.
"""
from __future__ import annotations

import base64
import json
import os
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import numpy.typing as npt

from .mesh import F64, I64, quat_matrix, shape_mesh
from .render import PARTICLE, _atomic, _bounds, _source, _writable_folder, body_colors

FORMATS = (".glb", ".gltf")
ROOT_ROTATION = (-0.5**0.5, 0.0, 0.0, 0.5**0.5)
"""The root node's quaternion (x, y, z, w): −90° about x, rigidrs z-up to glTF y-up."""

_FLOAT, _U16, _U32 = 5126, 5123, 5125
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963
_POINTS, _TRIANGLES = 0, 4


class _Builder:
    """Accumulates the binary buffer (4-byte aligned views) and the JSON arrays."""

    def __init__(self) -> None:
        self.chunks: list[bytes] = []
        self.size = 0
        self.doc: dict[str, Any] = {"bufferViews": [], "accessors": []}
        self._geometry: dict[bytes, tuple[int, int]] = {}

    def accessor(self, data: npt.NDArray[Any], kind: str, target: int | None = None,
                 bounds: bool = False) -> int:
        data = np.ascontiguousarray(data)
        raw = data.tobytes()
        view: dict[str, Any] = {"buffer": 0, "byteOffset": self.size, "byteLength": len(raw)}
        if target is not None:
            view["target"] = target
        self.chunks.append(raw + b"\0" * (-len(raw) % 4))
        self.size += len(raw) + (-len(raw) % 4)
        self.doc["bufferViews"].append(view)
        ctype = {np.dtype(np.float32): _FLOAT, np.dtype(np.uint16): _U16, np.dtype(np.uint32): _U32}[data.dtype]
        acc: dict[str, Any] = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": ctype,
                               "count": int(data.shape[0]), "type": kind}
        if bounds and data.shape[0]:
            flat = data.reshape(data.shape[0], -1)
            acc["min"] = [float(x) for x in flat.min(0)]
            acc["max"] = [float(x) for x in flat.max(0)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def geometry(self, v: F64, t: I64) -> tuple[int, int]:
        """(POSITION accessor, indices accessor) of a triangle mesh, shared when identical."""
        v32 = np.asarray(v, np.float32)
        idx = np.asarray(t, np.uint16 if len(v) <= 0xFFFF else np.uint32).reshape(-1)
        key = v32.tobytes() + b"|" + idx.tobytes()
        if key not in self._geometry:
            self._geometry[key] = (self.accessor(v32, "VEC3", _ARRAY_BUFFER, bounds=True),
                                   self.accessor(idx, "SCALAR", _ELEMENT_ARRAY_BUFFER, bounds=True))
        return self._geometry[key]

    def binary(self) -> bytes:
        return b"".join(self.chunks)


def _ground(d: Mapping[str, Any], centre_body: F64, size: float) -> tuple[F64, I64]:
    """A square of side ``size`` (m) on the plane of shape dict ``d``, in the body frame,
    centred at the point of the plane nearest ``centre_body``; it faces the normal."""
    rot, origin = quat_matrix(d["orientation"]), np.asarray(d["position"], float)
    n = np.asarray(d["normal"], float)
    n = n / np.linalg.norm(n)
    local = rot.T @ (centre_body - origin)               # centre in the shape frame
    c = local - (local @ n - float(d["offset"])) * n     # onto the plane n·x = offset
    u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(n, u)                                   # (u, w, n) right-handed: CCW seen from +n
    h = size / 2
    quad = c + h * np.array([-u - w, u - w, u + w, -u + w])
    return quad @ rot.T + origin, np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)


def _poses(world: Any, n: int, rec: Any) -> tuple[F64, F64, F64, F64]:
    """(times (T,), positions (T, N, 3), orientations (T, N, 4), particles (T, P, 3))."""
    if rec is None:
        return (np.zeros(1), np.array(world.bodies.position)[None], np.array(world.bodies.orientation)[None],
                np.array(world.particles.position)[None])
    from .. import Recording

    if not isinstance(rec, Recording):
        raise TypeError(f"rec must be a rigidrs Recording or None, got {type(rec).__name__}")
    times, pos, quat, parts = rec.times, rec.position, rec.orientation, rec.particle_position
    m = len(world.particles.position)
    if pos.shape[1] != n or parts.shape[1] != m:
        raise ValueError(f"the recording does not match the scene: {pos.shape[1]} bodies and "
                         f"{parts.shape[1]} particles recorded, the scene has {n} and {m}")
    if len(times) == 0:
        raise ValueError("the recording has no frames")
    if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(quat)) and np.all(np.isfinite(parts))):
        raise ValueError("the recording holds non-finite positions or orientations")
    t32 = times.astype(np.float32)
    if len(t32) > 1 and not np.all(np.diff(t32) > 0):
        raise ValueError("the recording's times are not strictly increasing in float32 (glTF stores "
                         "times as float32): record with a larger `every`, or from an earlier time")
    return times, pos, quat, parts


def _export_args(rec: Any, path: Any, formats: Sequence[str], detail: int,
                 ground_size: float | None, name: str) -> tuple[Any, Path]:
    """The recording and path of an exporter called as ``f(source, rec, path)`` or
    ``f(source, path)``, checked before anything is built: a known suffix, a writable
    folder, ``detail`` in 0..3 and a positive ``ground_size``."""
    if isinstance(rec, (str, os.PathLike)) and path is None:
        rec, path = None, rec
    if path is None:
        raise TypeError(f"{name} needs a path ending in {', '.join(formats[:-1])} or {formats[-1]}")
    path = Path(path)
    if path.suffix.lower() not in formats:
        raise ValueError(f"cannot write {path}: unknown format {path.suffix!r}; use one of {', '.join(formats)}")
    _writable_folder(path)
    if detail not in (0, 1, 2, 3):
        raise ValueError(f"detail must be 0, 1, 2 or 3, got {detail!r}")
    if ground_size is not None and not (np.isfinite(ground_size) and ground_size > 0):
        raise ValueError(f"ground_size must be a positive length (m), got {ground_size!r}")
    return rec, path


def export_gltf(source: Any, rec: Any = None, path: str | os.PathLike[str] | None = None, *,
                colors: Any = None, detail: int = 2, ground_size: float | None = None,
                particles: bool = True) -> Path:
    """Writes ``source`` (a World or Scene) as glTF 2.0, animated over the frames of ``rec``
    (a Recording), or at its current pose without one (a Scene: its initial pose).

    ``path``: ``.glb`` (binary glTF, one file) or ``.gltf`` (JSON with the buffer embedded
    as base64, one file, a third bigger); written to a temporary name then renamed: on any
    failure (missing or unwritable directory, unknown extension, a recording that does not
    match the scene) a clear error and no file left. ``export_gltf(world, "x.glb")`` also works.
    ``colors``: (3,), (N, 3) or {body: (3,)}, RGB in 0..1 or 0..255, as :func:`rigidrs.render`;
    default a palette, fixed bodies grey. ``detail`` (0..3, default 2) subdivides spheres,
    cylinders, cones and capsules as the renderer does. ``ground_size`` (m): side of the
    square drawn for each Plane (default: 4 × the extent of the bodies over the recording,
    at least 4 m). ``particles`` (default True): particles as a POINTS primitive per frame.
    Units metres; z-up converted to glTF's y-up by the root node's rotation (module doc).
    Returns the path written.
    """
    rec, path = _export_args(rec, path, FORMATS, detail, ground_size, "export_gltf")
    suffix = path.suffix.lower()

    world, shapes = _source(source)
    n = len(shapes)
    times, pos, quat, parts = _poses(world, n, rec)
    fixed = ~(np.asarray(world.bodies.inverse_mass) > 0)
    # The palette and ``colors`` are sRGB (as the renderer shows them); glTF's
    # baseColorFactor is linear: convert, so that viewers show the same colours.
    srgb = body_colors(fixed, colors)
    color = _linear(srgb)
    names = list(world.bodies.names)
    has_particles = particles and parts.shape[1] > 0
    lo, hi = _bounds(shapes, pos, quat, parts if has_particles else None)
    if ground_size is None:
        ground_size = max(4.0, 4.0 * float(np.max(hi - lo)))

    # Rotations: unit length, sign-aligned frame to frame (the short way between keys).
    quat = quat / np.linalg.norm(quat, axis=-1, keepdims=True)
    if len(quat) > 1:
        flip = np.cumprod(np.where(np.einsum("tnk,tnk->tn", quat[1:], quat[:-1]) < 0, -1.0, 1.0), axis=0)
        quat = quat.copy()
        quat[1:] *= flip[..., None]

    b = _Builder()
    materials: list[dict[str, Any]] = []
    material_index: dict[tuple[Any, ...], int] = {}

    def material(rgb: Sequence[float] | F64, double: bool, name: str) -> int:
        key = (*(round(float(x), 6) for x in rgb), double)
        if key not in material_index:
            materials.append({"name": f"{name} {len(materials)}", "doubleSided": double, "pbrMetallicRoughness": {
                "baseColorFactor": [*(float(x) for x in rgb), 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8}})
            material_index[key] = len(materials) - 1
        return material_index[key]

    meshes: list[dict[str, Any]] = []
    mesh_index: dict[tuple[int, ...], int] = {}
    centre = (lo + hi) / 2
    nodes: list[dict[str, Any]] = [{"name": "rigidrs (z-up)", "rotation": list(ROOT_ROTATION), "children": []}]
    for i, d in enumerate(shapes):
        node: dict[str, Any] = {"name": names[i] or f"body {i}",
                                "translation": [float(x) for x in pos[0, i]],
                                "rotation": [float(x) for x in quat[0, i]]}
        if d is not None:
            if d["kind"] == "Plane":
                centre_body = quat_matrix(quat[0, i]).T @ (centre - pos[0, i])
                v, t = _ground(d, centre_body, ground_size)
            else:
                v, t = shape_mesh(d, detail)
            double = d["kind"] in ("Plane", "TriMesh")
            if len(t):
                geo = b.geometry(v, t)
                mat = material(color[i], double, "colour")
                if (*geo, mat) not in mesh_index:
                    meshes.append({"name": d["kind"], "primitives": [{
                        "attributes": {"POSITION": geo[0]}, "indices": geo[1], "material": mat, "mode": _TRIANGLES}]})
                    mesh_index[(*geo, mat)] = len(meshes) - 1
                node["mesh"] = mesh_index[(*geo, mat)]
        nodes[0]["children"].append(len(nodes))
        nodes.append(node)

    doc = b.doc
    doc["asset"] = {"version": "2.0", "generator": f"rigidrs {_version()} export_gltf"}
    doc["scene"] = 0
    doc["scenes"] = [{"name": "rigidrs", "nodes": [0]}]
    doc["extras"] = {"up": "z-up world under a root rotation of -90 deg about x", "units": "m"}

    channels: list[dict[str, Any]] = []
    samplers: list[dict[str, Any]] = []
    animated = rec is not None
    if animated:
        t_in = b.accessor(times.astype(np.float32), "SCALAR", bounds=True)
        for i in range(n):
            for prop, data, kind in (("translation", pos[:, i], "VEC3"), ("rotation", quat[:, i], "VEC4")):
                out = b.accessor(data.astype(np.float32), kind)
                samplers.append({"input": t_in, "output": out, "interpolation": "LINEAR"})
                channels.append({"sampler": len(samplers) - 1, "target": {"node": 1 + i, "path": prop}})

    if has_particles:
        group: dict[str, Any] = {"name": "particles", "children": []}
        nodes[0]["children"].append(len(nodes))
        nodes.append(group)
        pmat = material(_linear(PARTICLE), False, "particles")
        frames = len(parts)
        for k in range(frames):
            acc = b.accessor(parts[k].astype(np.float32), "VEC3", _ARRAY_BUFFER, bounds=True)
            meshes.append({"name": f"particles {k}", "primitives": [{
                "attributes": {"POSITION": acc}, "material": pmat, "mode": _POINTS}]})
            node = {"name": f"particles {k}", "mesh": len(meshes) - 1}
            if animated and frames > 1:
                # Shown at its own frame only: scale 1 from times[k] to times[k + 1], else 0.
                keys = sorted({0, k, min(k + 1, frames - 1)})
                scale = np.array([[1.0] * 3 if j == k else [0.0] * 3 for j in keys], np.float32)
                if k != 0:
                    node["scale"] = [0.0, 0.0, 0.0]
                s_in = b.accessor(times[keys].astype(np.float32), "SCALAR", bounds=True)
                samplers.append({"input": s_in, "output": b.accessor(scale, "VEC3"), "interpolation": "STEP"})
                channels.append({"sampler": len(samplers) - 1, "target": {"node": len(nodes), "path": "scale"}})
            group["children"].append(len(nodes))
            nodes.append(node)

    doc["nodes"] = nodes
    if meshes:
        doc["meshes"] = meshes
    if materials:
        doc["materials"] = materials
    if channels:
        doc["animations"] = [{"name": "rigidrs recording", "channels": channels, "samplers": samplers}]
    for key in ("bufferViews", "accessors"):
        if not doc[key]:
            del doc[key]
    blob = b.binary()
    if blob:
        doc["buffers"] = [{"byteLength": len(blob)}]

    if suffix == ".glb":
        data = _glb(doc, blob)
    else:
        if blob:
            doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
        data = json.dumps(doc, separators=(",", ":")).encode()
    _atomic(path, lambda tmp: tmp.write_bytes(data))
    return path


def _linear(srgb: F64) -> F64:
    """sRGB (0..1) to linear RGB, the sRGB transfer function inverted."""
    c = np.asarray(srgb, dtype=float)
    return np.asarray(np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4))


def _glb(doc: Mapping[str, Any], blob: bytes) -> bytes:
    """The GLB container: 12-byte header, JSON chunk (space-padded), BIN chunk (zero-padded)."""
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    out = [len(text).to_bytes(4, "little"), b"JSON", text]
    if blob:
        blob += b"\0" * (-len(blob) % 4)
        out += [len(blob).to_bytes(4, "little"), b"BIN\0", blob]
    body = b"".join(out)
    return b"glTF" + (2).to_bytes(4, "little") + (12 + len(body)).to_bytes(4, "little") + body


def _version() -> str:
    from .. import __version__

    return str(__version__)
