"""Results out: pictures, meshes and glTF files of a world or a recording (no display needed)."""
from .gltf import export_gltf
from .render import Camera, render

__all__ = ["Camera", "export_gltf", "render"]
