"""Models in: scene files (TOML/JSON, core only) and mesh files (through trimesh,
``pip install 'rigidrs[io]'``).

``scene.to_dict()`` / ``Scene.from_dict(d)``, ``scene.save(path)`` /
``load_scene(path)``, ``TriMesh.from_file``, ``ConvexHull.from_file`` and
``Compound.from_file`` (convex decomposition). The schema: ``docs/scene_format.md``.
"""
from __future__ import annotations

from .mesh import compound_from_file, convex_hull_from_file, decompose, load_mesh, trimesh_from_file
from .scene_dict import SceneDataError, from_dict, to_dict
from .scene_file import load_scene, save
from .schema import SCHEMA_VERSION

__all__ = [
    "SCHEMA_VERSION",
    "SceneDataError",
    "compound_from_file",
    "convex_hull_from_file",
    "decompose",
    "from_dict",
    "load_mesh",
    "load_scene",
    "save",
    "to_dict",
    "trimesh_from_file",
]
