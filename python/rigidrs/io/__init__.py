"""Models in: scene files (TOML/JSON, core only), mesh files (through trimesh,
``pip install 'rigidrs[io]'``), URDF (``rr.Scene.from_urdf``) and MJCF
(``rr.Scene.from_mjcf``) importers and the report of what they dropped or
approximated (``scene.import_report``).

``scene.to_dict()`` / ``Scene.from_dict(d)``, ``scene.save(path)`` /
``load_scene(path)``, ``TriMesh.from_file``, ``ConvexHull.from_file`` and
``Compound.from_file`` (convex decomposition). The schema: ``docs/scene_format.md``.
"""
from __future__ import annotations

from .. import _core
from .mesh import compound_from_file, convex_hull_from_file, decompose, load_mesh, trimesh_from_file
from .mjcf import from_mjcf
from .report import ImportReport, ReportEntry
from .robot import ModelError
from .scene_dict import SceneDataError, from_dict, to_dict
from .scene_file import load_scene, save
from .schema import SCHEMA_VERSION
from .urdf import from_urdf

setattr(_core.Scene, "from_urdf", classmethod(from_urdf))
setattr(_core.Scene, "from_mjcf", classmethod(from_mjcf))

__all__ = [
    "SCHEMA_VERSION",
    "ImportReport",
    "ModelError",
    "ReportEntry",
    "SceneDataError",
    "compound_from_file",
    "convex_hull_from_file",
    "decompose",
    "from_dict",
    "from_mjcf",
    "from_urdf",
    "load_mesh",
    "load_scene",
    "save",
    "to_dict",
    "trimesh_from_file",
]
