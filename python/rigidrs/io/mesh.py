"""Mesh files (STL, OBJ, PLY, OFF, GLB/glTF) through trimesh, an optional
dependency (``pip install 'rigidrs[io]'``): ``TriMesh.from_file``,
``ConvexHull.from_file`` and ``Compound.from_file`` (a convex decomposition by
CoACD for a non-convex mesh on a dynamic body).

A file holding a scene of several meshes (glTF, multi-object OBJ) is flattened
into one mesh with each node's transform applied. Duplicate vertices are merged
(an STL stores each triangle's corners apart), so a closed surface reads as closed.
"""
from __future__ import annotations

import errno
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core

MESH_SUFFIXES = (".stl", ".obj", ".ply", ".off", ".glb", ".gltf")
DECOMPOSITIONS = ("coacd", "hull")


def _trimesh() -> Any:
    try:
        import trimesh
    except ImportError as e:
        raise ImportError("reading mesh files needs trimesh: pip install 'rigidrs[io]'") from e
    return trimesh


def _check_scale(scale: float, path: Path) -> float:
    s = float(scale)
    if not (math.isfinite(s) and s > 0.0):
        raise ValueError(f"{path}: scale must be positive and finite, got {scale}")
    return s


def load_mesh(
    path: str | os.PathLike[str], scale: float = 1.0, fix: bool = False
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Vertices (V, 3) (file units × ``scale``, m) and triangles (T, 3) of the mesh in
    ``path``. ``fix``: repair with trimesh (consistent winding, outward normals,
    holes filled) before returning. Raises ``FileNotFoundError``, ``ValueError``
    for an unknown extension or a file that does not parse, ``ShapeError`` for a
    file without triangles; each names the file."""
    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(errno.ENOENT, "mesh file not found", str(p))
    if p.suffix.lower() not in MESH_SUFFIXES:
        raise ValueError(f"{p}: unknown mesh file extension {p.suffix!r}; supported: {', '.join(MESH_SUFFIXES)}")
    s = _check_scale(scale, p)
    trimesh = _trimesh()
    try:
        # Geometry only: materials and textures (which would need Pillow) are skipped.
        extra = {"skip_materials": True} if p.suffix.lower() == ".obj" else {}
        mesh = trimesh.load(str(p), force="mesh", process=True, **extra)
    except Exception as e:  # trimesh raises many kinds for a bad file
        raise ValueError(f"{p}: could not be read as a {p.suffix.lower()[1:].upper()} mesh: {e}") from e
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise _core.ShapeError(f"{p}: holds no triangles")
    # By position only: corners split for texture seams or hard normals would leave
    # a closed surface looking open.
    mesh.merge_vertices(merge_tex=True, merge_norm=True)
    if fix:
        trimesh.repair.fix_winding(mesh)
        trimesh.repair.fix_inversion(mesh)
        trimesh.repair.fill_holes(mesh)
    vertices = np.asarray(mesh.vertices, dtype=np.float64) * s
    return vertices, np.asarray(mesh.faces, dtype=np.int64)


def _named(path: Path, make: Any) -> Any:
    try:
        return make()
    except (ValueError, TypeError) as e:
        raise type(e)(f"{path}: {e}") from e


def trimesh_from_file(path: str | os.PathLike[str], scale: float = 1.0, fix: bool = False) -> _core.TriMesh:
    """A ``TriMesh`` from a mesh file (see ``load_mesh``). A dynamic body needs it
    closed and outward-oriented (``fix=True`` repairs what trimesh can); otherwise
    use ``ConvexHull.from_file`` or ``Compound.from_file``."""
    v, t = load_mesh(path, scale, fix)
    return _named(Path(path), lambda: _core.TriMesh(v, t))


def convex_hull_from_file(path: str | os.PathLike[str], scale: float = 1.0) -> _core.ConvexHull:
    """The ``ConvexHull`` of a mesh file's vertices; a flat mesh (no volume) is an error."""
    v, _ = load_mesh(path, scale)
    return _named(Path(path), lambda: _core.ConvexHull(v))


def decompose(
    vertices: npt.ArrayLike, triangles: npt.ArrayLike, threshold: float = 0.05, max_parts: int = -1, seed: int = 0
) -> list[npt.NDArray[np.float64]]:
    """Convex parts of a mesh by CoACD (Wei et al. 2022; ``pip install 'rigidrs[io]'``):
    one (K, 3) point array per part. ``threshold``: concavity allowed per part (–,
    smaller: more parts, default 0.05); ``max_parts`` (-1: no limit); ``seed`` of
    its search (same seed, same parts)."""
    try:
        import coacd  # type: ignore[import-untyped,import-not-found,unused-ignore]
    except ImportError as e:
        raise ImportError("convex decomposition needs coacd: pip install 'rigidrs[io]'") from e
    if hasattr(coacd, "set_log_level"):
        coacd.set_log_level("error")
    mesh = coacd.Mesh(np.asarray(vertices, dtype=np.float64), np.asarray(triangles, dtype=np.int64))
    parts = coacd.run_coacd(mesh, threshold=threshold, max_convex_hull=max_parts, seed=seed)
    return [np.asarray(p[0], dtype=np.float64) for p in parts]


def compound_from_file(
    path: str | os.PathLike[str], scale: float = 1.0, decompose: str = "coacd", threshold: float = 0.05, max_parts: int = -1
) -> _core.Compound:
    """A ``Compound`` of convex parts of a (non-convex) mesh file, for a dynamic body.
    ``decompose``: ``"coacd"`` (CoACD convex decomposition, ``threshold`` and
    ``max_parts`` as in ``rigidrs.io.decompose``) or ``"hull"`` (one part: the
    convex hull). The parts sit at the file's coordinates (position 0)."""
    p = Path(path)
    if decompose not in DECOMPOSITIONS:
        raise ValueError(f"{p}: decompose must be one of {', '.join(DECOMPOSITIONS)}, got {decompose!r}")
    v, t = load_mesh(p, scale)
    if decompose == "hull":
        pieces = [v]
    else:
        pieces = [x for x in _decompose(v, t, threshold, max_parts) if len(x) >= 4]
    return _named(p, lambda: _core.Compound([(_core.ConvexHull(x), (0.0, 0.0, 0.0)) for x in pieces]))


_decompose = decompose
