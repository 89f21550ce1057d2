"""rigidrs: rigid bodies and position-based bodies, with measured accuracy.

Describe what to simulate in a :class:`Scene`, compile it with
:meth:`Scene.build` into a :class:`World`, step it, and read its state through
NumPy views (``world.bodies.position``, ``world.particles.position`` and
friends). SI units, z up, quaternions
in (x, y, z, w) order. :func:`accuracy` runs the work-precision report.
"""
from ._core import (
    ARTICULATION_INTEGRATORS,
    INTEGRATORS,
    Batch,
    BatchBodies,
    Bodies,
    Box,
    Capsule,
    Compound,
    Cone,
    ConvexHull,
    Cylinder,
    Drive,
    Joints,
    MassProperties,
    Particles,
    Plane,
    Recording,
    RigidError,
    Scene,
    Shape,
    ShapeError,
    SimulationError,
    Snapshot,
    Sphere,
    StateError,
    TriMesh,
    World,
    __version__,
    load,
    mass_properties,
    polar_decomposition,
)
from . import io
from .io import load_scene
from .io.methods import install as _install_file_methods
from .scale import SweepError, SweepFailure, sweep
from .view import Camera, Capture, Extras, Viewer, export_gltf, export_usd, render, view
from .work_precision import accuracy

__all__ = [
    "ARTICULATION_INTEGRATORS",
    "INTEGRATORS",
    "Batch",
    "BatchBodies",
    "Bodies",
    "Camera",
    "Capture",
    "Box",
    "Capsule",
    "Compound",
    "Cone",
    "ConvexHull",
    "Cylinder",
    "Drive",
    "Extras",
    "Joints",
    "MassProperties",
    "Particles",
    "Plane",
    "Recording",
    "RigidError",
    "Scene",
    "Shape",
    "ShapeError",
    "SimulationError",
    "Snapshot",
    "Sphere",
    "StateError",
    "SweepError",
    "SweepFailure",
    "TriMesh",
    "Viewer",
    "World",
    "__version__",
    "accuracy",
    "export_gltf",
    "export_usd",
    "io",
    "load",
    "load_scene",
    "mass_properties",
    "polar_decomposition",
    "render",
    "sweep",
    "view",
]

_install_file_methods()
