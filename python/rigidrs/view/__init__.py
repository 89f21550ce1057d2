"""Results out: pictures and meshes of a world or a recording (no display needed)."""
from .render import Camera, render

__all__ = ["Camera", "render"]
