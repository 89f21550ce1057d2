"""Results out: pictures, meshes, glTF and USD files of a world or a recording (no display needed), and a viewer in the browser."""
from .extras import Capture, Extras
from .gltf import export_gltf
from .render import Camera, render
from .usd import export_usd
from .viewer import Viewer, view

__all__ = ["Camera", "Capture", "Extras", "Viewer", "export_gltf", "export_usd", "render", "view"]
