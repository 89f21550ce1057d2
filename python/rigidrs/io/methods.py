"""The file methods on the core's classes (set from here, so the core stays
free of file formats and of trimesh): ``Scene.to_dict``, ``Scene.from_dict``,
``Scene.save``, ``TriMesh.from_file``, ``ConvexHull.from_file``,
``Compound.from_file``."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from .. import _core
from . import mesh, scene_dict, scene_file


def to_dict(self: _core.Scene) -> dict[str, Any]:
    """The scene as plain JSON-able data (dicts, lists, str, float, int, bool) that
    ``Scene.from_dict`` rebuilds exactly; schema in ``docs/scene_format.md``."""
    return scene_dict.to_dict(self)


def from_dict(cls: type, data: Any, base_dir: str | os.PathLike[str] | None = None) -> _core.Scene:
    """A scene from ``to_dict`` data. ``base_dir``: folder that mesh ``file`` entries
    are relative to (default the current directory). Errors name the path inside
    the data (``bodies[3].density: ...``); nothing is built on error."""
    return scene_dict.from_dict(data, base_dir=Path(base_dir) if base_dir is not None else None)


def save(self: _core.Scene, path: str | os.PathLike[str]) -> None:
    """Writes the scene to ``path`` (``.toml`` or ``.json``) through a temporary
    file renamed over it; ``rigidrs.load_scene`` reads it back."""
    scene_file.save(self, path)


def trimesh_from_file(cls: type, path: str | os.PathLike[str], scale: float = 1.0, fix: bool = False) -> _core.TriMesh:
    """A ``TriMesh`` from an STL, OBJ, PLY, OFF or GLB/glTF file (needs
    ``rigidrs[io]``), vertices times ``scale`` (m per file unit, default 1).
    ``fix=True`` repairs winding, normals and holes first. A dynamic body needs
    the mesh closed and outward-oriented; else use ``ConvexHull.from_file`` or
    ``Compound.from_file``."""
    return mesh.trimesh_from_file(path, scale=scale, fix=fix)


def convex_hull_from_file(cls: type, path: str | os.PathLike[str], scale: float = 1.0) -> _core.ConvexHull:
    """The ``ConvexHull`` of the vertices of a mesh file (needs ``rigidrs[io]``),
    times ``scale`` (default 1). A flat mesh is a ``ShapeError``."""
    return mesh.convex_hull_from_file(path, scale=scale)


def compound_from_file(
    cls: type,
    path: str | os.PathLike[str],
    scale: float = 1.0,
    decompose: str = "coacd",
    threshold: float = 0.05,
    max_parts: int = -1,
) -> _core.Compound:
    """A ``Compound`` of convex parts of a mesh file for a dynamic body (needs
    ``rigidrs[io]``): ``decompose="coacd"`` (CoACD, ``threshold`` concavity per
    part, default 0.05; ``max_parts``, -1: no limit) or ``"hull"`` (its convex hull)."""
    return mesh.compound_from_file(path, scale=scale, decompose=decompose, threshold=threshold, max_parts=max_parts)


def install() -> None:
    targets: list[tuple[type, str, Any]] = [
        (_core.Scene, "to_dict", to_dict),
        (_core.Scene, "from_dict", classmethod(from_dict)),
        (_core.Scene, "save", save),
        (_core.TriMesh, "from_file", classmethod(trimesh_from_file)),
        (_core.ConvexHull, "from_file", classmethod(convex_hull_from_file)),
        (_core.Compound, "from_file", classmethod(compound_from_file)),
    ]
    for cls, name, fn in targets:
        setattr(cls, name, fn)
