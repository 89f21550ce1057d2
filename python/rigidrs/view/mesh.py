"""Triangle meshes of the shapes ``World.shapes()`` describes, for drawing.

Every mesh is (vertices (V, 3) float64, triangles (F, 3) int64), counter-clockwise
seen from outside. Primitives are tessellated with ``detail`` (0 coarse, 2 default,
3 fine); hulls and meshes are used as they are. Planes are infinite and have no
mesh (the renderer draws them per pixel).
"""
from __future__ import annotations

from functools import lru_cache
from typing import Any, Mapping

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
I64 = npt.NDArray[np.int64]
Mesh = tuple[F64, I64]


def quat_rotate(q: npt.ArrayLike, v: npt.ArrayLike) -> F64:
    """Rotates vectors ``v`` (..., 3) by unit quaternions ``q`` (..., 4) (x, y, z, w), broadcasting."""
    q = np.asarray(q, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    u, w = q[..., :3], q[..., 3:4]
    t = 2.0 * np.cross(u, v)
    return np.asarray(v + w * t + np.cross(u, t))


def quat_matrix(q: npt.ArrayLike) -> F64:
    """Rotation matrices (..., 3, 3) of unit quaternions (..., 4) (x, y, z, w)."""
    q = np.asarray(q, dtype=np.float64)
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    r = np.empty(q.shape[:-1] + (3, 3))
    r[..., 0, 0] = 1 - 2 * (y * y + z * z)
    r[..., 0, 1] = 2 * (x * y - z * w)
    r[..., 0, 2] = 2 * (x * z + y * w)
    r[..., 1, 0] = 2 * (x * y + z * w)
    r[..., 1, 1] = 1 - 2 * (x * x + z * z)
    r[..., 1, 2] = 2 * (y * z - x * w)
    r[..., 2, 0] = 2 * (x * z - y * w)
    r[..., 2, 1] = 2 * (y * z + x * w)
    r[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return r


def _outward(v: F64, t: I64) -> I64:
    """Flips triangles of a convex (star-shaped about its centroid) mesh that face inward."""
    c = v.mean(axis=0)
    a, b, d = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    n = np.cross(b - a, d - a)
    inward = np.einsum("ij,ij->i", n, (a + b + d) / 3 - c) < 0
    t = t.copy()
    t[inward] = t[inward][:, [0, 2, 1]]
    return t


@lru_cache(maxsize=8)
def unit_sphere(level: int) -> Mesh:
    """An icosphere of radius 1: 20·4^level triangles."""
    p = (1 + 5**0.5) / 2
    v = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0), (0, -1, p), (0, 1, p),
         (0, -1, -p), (0, 1, -p), (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(x, dtype=float) / np.linalg.norm(x) for x in v]
    faces = list(f)
    for _ in range(level):
        mid: dict[tuple[int, int], int] = {}

        def middle(a: int, b: int) -> int:
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                mid[key] = len(verts) - 1
            return mid[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    vv = np.array(verts)
    return vv, _outward(vv, np.array(faces, dtype=np.int64))


def _ring(n: int) -> F64:
    a = 2 * np.pi * np.arange(n) / n
    return np.stack([np.cos(a), np.sin(a)], axis=1)


def _lathe(profile: list[tuple[float, float]], n: int) -> Mesh:
    """A surface of revolution about z from (radius, z) points, bottom to top; a point of
    radius 0 is a single vertex (a pole), others are rings of n vertices."""
    ring = _ring(n)
    verts: list[F64] = []
    rows: list[list[int]] = []
    for r, z in profile:
        start = sum(len(x) for x in verts)
        if r == 0:
            verts.append(np.array([[0.0, 0.0, z]]))
            rows.append([start] * n)
        else:
            verts.append(np.column_stack([r * ring, np.full(n, z)]))
            rows.append(list(range(start, start + n)))
    tris = []
    for lo, hi in zip(rows[:-1], rows[1:]):
        for k in range(n):
            k1 = (k + 1) % n
            if lo[k] != lo[k1]:
                tris.append((lo[k], lo[k1], hi[k1]))
            if hi[k] != hi[k1]:
                tris.append((lo[k], hi[k1], hi[k]))
    v = np.concatenate(verts)
    return v, _outward(v, np.array(tris, dtype=np.int64))


def _segments(detail: int) -> int:
    return 4 * 2 ** max(detail, 0)


def primitive(d: Mapping[str, Any], detail: int = 2) -> Mesh:
    """The mesh of one shape dict (as in ``World.shapes()``) in the shape's own frame;
    raises ``ValueError`` for a Plane or an unknown kind."""
    kind = d["kind"]
    if kind == "Sphere":
        v, t = unit_sphere(max(detail, 0))
        return v * float(d["radius"]), t
    if kind == "Box":
        half = np.asarray(d["half_extents"], dtype=float)
        c = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * half
        f = np.array([(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                      (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)], dtype=np.int64)
        return c, _outward(c, f)
    n = _segments(detail)
    if kind in ("Cylinder", "Cone", "Capsule"):
        r, h = float(d["radius"]), float(d["half_height"])
        if kind == "Cylinder":
            return _lathe([(0.0, -h), (r, -h), (r, h), (0.0, h)], n)
        if kind == "Cone":
            return _lathe([(0.0, -h), (r, -h), (0.0, h)], n)
        k = max(n // 4, 2)
        a = np.linspace(-np.pi / 2, 0, k + 1)
        lower = [(r * float(np.cos(x)), -h + r * float(np.sin(x))) for x in a]
        upper = [(r * float(np.cos(-x)), h + r * float(np.sin(-x))) for x in a[::-1]]
        prof = [(0.0, z) if i in (0, len(lower) + len(upper) - 1) else (rr, z)
                for i, (rr, z) in enumerate(lower + upper)]
        return _lathe(prof, n)
    if kind in ("ConvexHull", "TriMesh"):
        v = np.asarray(d["vertices"], dtype=float)
        t = np.asarray(d["triangles"], dtype=np.int64)
        return (v, _outward(v, t)) if kind == "ConvexHull" else (v, t)
    raise ValueError(f"no mesh for a {kind} shape")


def shape_mesh(d: Mapping[str, Any], detail: int = 2) -> Mesh:
    """The mesh of a shape dict in the frame its pose refers to (a body's frame), with
    compound parts merged."""
    if d["kind"] == "Compound":
        parts = [shape_mesh(p, detail) for p in d["parts"]]
        v, t = _merge(parts)
    else:
        v, t = primitive(d, detail)
    return quat_rotate(d["orientation"], v) + np.asarray(d["position"], dtype=float), t


def _merge(meshes: list[Mesh]) -> Mesh:
    offsets = np.cumsum([0] + [len(v) for v, _ in meshes[:-1]])
    v = np.concatenate([m[0] for m in meshes]) if meshes else np.zeros((0, 3))
    t = np.concatenate([m[1] + o for m, o in zip(meshes, offsets)]) if meshes else np.zeros((0, 3), np.int64)
    return v, t
