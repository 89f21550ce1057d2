"""Results out: pictures, meshes and glTF files of a world or a recording (no display needed), and a viewer in the browser."""
from .gltf import export_gltf
from .render import Camera, render
from .viewer import Viewer, view

__all__ = ["Camera", "Viewer", "export_gltf", "render", "view"]
