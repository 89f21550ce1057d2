"""The scene-file schema: every key a scene file may hold, with its default and
unit. One table drives writing (keys at their default are left out), reading
(unknown keys are errors naming their path) and ``docs/scene_format.md``.

A key's entry is ``(default, doc)``; ``REQUIRED`` marks keys without a default.
"""
from __future__ import annotations

from typing import Any

FORMAT = "rigidrs.scene"
SCHEMA_VERSION = 1


class _Required:
    def __repr__(self) -> str:
        return "required"


REQUIRED: Any = _Required()
ALL_BITS = 4294967295

Table = dict[str, tuple[Any, str]]

TOP: Table = {
    "format": (FORMAT, f'"{FORMAT}": what the file is'),
    "schema_version": (REQUIRED, f"integer, {SCHEMA_VERSION} for this schema; a newer one is refused"),
    "gravity": ([0.0, 0.0, -9.81], "(3,) m/s²"),
    "bodies": ([], "array of body tables, in index order"),
    "joints": ([], "array of joint tables, in index order"),
    "particles": ([], "array of particle-side calls, in the order made (see `op`)"),
    "build": ({}, "`Scene.build` keyword arguments kept with the scene (`Scene.build_settings`)"),
}

_FILTER: Table = {
    "collision_group": (1, "32-bit group bits"),
    "collision_mask": (ALL_BITS, "32-bit mask bits; touch iff group_a & mask_b and group_b & mask_a"),
}

BODY: Table = {
    "name": (None, "str, unique among bodies"),
    "shape": (None, "shape table (see Shapes)"),
    "density": (None, "kg/m³, > 0, with a shape"),
    "mass": (None, "kg, > 0; with a shape (uniform density) or with `inertia`"),
    "inertia": (None, "(3,) principal moments or (3, 3) tensor about the centre of mass, kg·m²"),
    "mass_properties": (None, "table {mass (kg), center_of_mass (3,) m, inertia (3, 3) kg·m²}"),
    "position": ([0.0, 0.0, 0.0], "(3,) m, of the shape's frame"),
    "orientation": ([0.0, 0.0, 0.0, 1.0], "(4,) quaternion (x, y, z, w) of the shape's frame"),
    "linear_velocity": ([0.0, 0.0, 0.0], "(3,) m/s, of the centre of mass, world"),
    "angular_velocity": ([0.0, 0.0, 0.0], "(3,) rad/s, world"),
    "fixed": (False, "bool: never moves"),
    "kinematic": (False, "bool: moves with its given velocities, infinite mass"),
    "friction": (0.5, "μk, ≥ 0"),
    "static_friction": (None, "μs ≥ μk; default `friction`"),
    "restitution": (0.0, "e in [0, 1]"),
    "ccd": (False, "bool: continuous collision detection"),
    **_FILTER,
}

MASS_PROPERTIES: Table = {
    "mass": (REQUIRED, "kg"),
    "center_of_mass": (REQUIRED, "(3,) m, in the body's given frame"),
    "inertia": (REQUIRED, "(3, 3) kg·m² about the centre of mass"),
}

DRIVE: Table = {
    "mode": ("position", '"position" or "velocity"'),
    "target": (None, "list: [angle rad | slide m] or its rate; spherical: (x, y, z, w) or (3,) rad/s"),
    "stiffness": (0.0, "N·m/rad or N/m"),
    "damping": (0.0, "N·m·s/rad or N·s/m"),
    "max_force": (float("inf"), 'N·m or N; "inf": no limit'),
}

JOINT: Table = {
    "kind": (REQUIRED, '"spherical", "hinge", "fixed", "prismatic" or "distance"'),
    "body_a": (REQUIRED, "body index"),
    "body_b": (None, "body index; absent: the world"),
    "name": (None, "str, unique among joints"),
    "anchor": (None, "(3,) m, world at build; default a's centre of mass"),
    "anchor_b": (None, "(3,) m, world at build; default `anchor`"),
    "axis": ([0.0, 0.0, 1.0], "(3,) hinge or slide axis, any non-zero length"),
    "compliance": (0.0, "m/N"),
    "angular_compliance": (0.0, "rad/(N·m)"),
    "limits": (None, "[lo, hi]: rad (hinge), m (prismatic, distance)"),
    "rest_length": (None, "m (distance joints); default the anchors' distance"),
    "solver": ("auto", '"auto", "xpbd" or "articulation"'),
    "drive": (None, "drive table (see Drives)"),
    "damping": (0.0, "N·m·s/rad or N·s/m"),
    "armature": (0.0, "kg·m² or kg"),
    "friction": (0.0, "N·m or N (Coulomb)"),
    "cone_limit": (None, "rad in (0, π], spherical"),
    "twist_limits": (None, "[lo, hi] rad, spherical"),
}

_COMPLIANCE: Table = {
    "compliance": (0.0, "α: m/N (lengths), rad/(N·m) (angles), m³/Pa (volumes)"),
    "damping": (0.0, "β: N·s/m, N·m·s/rad, Pa·s/m³"),
}
_MATERIAL: Table = {
    "mass": (1.0, "kg, total, shared equally"),
    "radius": (0.0, "m, each particle"),
    "friction": (0.5, "μ"),
    **_FILTER,
}
_CLUSTER: Table = {
    "mode": ("linear", '"rigid", "linear" or "quadratic"'),
    "stiffness": (1.0, "in [0, 1]"),
    "beta": (0.5, "in [0, 1]"),
    "preserve_volume": (True, "bool"),
    "plastic_yield": (None, "‖S − I‖_F; absent: elastic"),
    "plastic_creep": (0.0, "1/s"),
    "plastic_max": (float("inf"), "‖Sp − I‖_F"),
}

# One table per `op` of the `particles` array: the Scene method it calls, its keys.
PARTICLE_OPS: dict[str, tuple[str, Table]] = {
    "particle": ("add_particle", {
        "position": (REQUIRED, "(3,) m"),
        "velocity": ([0.0, 0.0, 0.0], "(3,) m/s"),
        "mass": (1.0, "kg"),
        "radius": (0.0, "m"),
        "fixed": (False, "bool: pinned"),
        "friction": (0.5, "μ"),
        **_FILTER,
    }),
    "distance": ("add_distance_constraint", {
        "particles": (REQUIRED, "[p, q] particle indices"),
        **_COMPLIANCE,
        "rest_length": (None, "m; default the current distance"),
    }),
    "bending": ("add_bending_constraint", {"particles": (REQUIRED, "[p0, p1, p2, p3]"), **_COMPLIANCE}),
    "volume": ("add_volume_constraint", {"particles": (REQUIRED, "4 particle indices"), **_COMPLIANCE}),
    "mesh_volume": ("add_mesh_volume_constraint", {
        "triangles": (REQUIRED, "(T, 3) particle indices, counter-clockwise from outside"),
        "pressure": (1.0, "–, times the rest volume"),
        **_COMPLIANCE,
    }),
    "attachment": ("add_attachment", {
        "particle": (REQUIRED, "particle index"),
        "body": (REQUIRED, "body index"),
        "point": (None, "(3,) m, world at build; default the particle's position"),
        "rest_length": (0.0, "m"),
        **_COMPLIANCE,
    }),
    "shape_matching": ("add_shape_matching", {"particles": (REQUIRED, "particle indices"), **_CLUSTER}),
    "rope": ("add_rope", {
        "start": (REQUIRED, "(3,) m"),
        "end": (REQUIRED, "(3,) m"),
        "segments": (REQUIRED, "integer ≥ 1"),
        **_MATERIAL,
        **_COMPLIANCE,
        "pinned": ([], "local particle indices"),
    }),
    "cloth": ("add_cloth", {
        "origin": (REQUIRED, "(3,) m"),
        "u": (REQUIRED, "(3,) m"),
        "v": (REQUIRED, "(3,) m"),
        "resolution": (REQUIRED, "[nu, nv] particles"),
        **_MATERIAL,
        **_COMPLIANCE,
        "bending_compliance": (None, "rad/(N·m); absent: no bending constraints"),
        "bending_damping": (None, "N·m·s/rad; default 0.05 s / bending_compliance"),
        "pinned": ([], "local particle indices"),
    }),
    "soft_box": ("add_soft_box", {
        "center": (REQUIRED, "(3,) m"),
        "half_extents": (REQUIRED, "(3,) m"),
        "cells": (REQUIRED, "[nx, ny, nz]"),
        **_MATERIAL,
        **_COMPLIANCE,
        "volume_compliance": (None, "m³/Pa; absent: no volume constraints"),
    }),
    "shape_matched_body": ("add_shape_matched_body", {
        "shape": (None, "shape table to fill (with `spacing`); or `points`"),
        "points": (None, "(N, 3) m"),
        "spacing": (None, "m, grid spacing filling `shape`"),
        "position": (None, "(3,) m"),
        "orientation": (None, "(4,) (x, y, z, w)"),
        **_MATERIAL,
        **_CLUSTER,
        "cluster_size": (None, "m; absent: one cluster"),
    }),
}

_FILE: Table = {
    "file": (None, "mesh file, relative to the scene file (STL, OBJ, PLY, GLB/glTF; needs rigidrs[io])"),
    "scale": (1.0, "factor from file units to m, with `file`"),
}

SHAPES: dict[str, Table] = {
    "Sphere": {"radius": (REQUIRED, "m")},
    "Box": {"half_extents": (REQUIRED, "(3,) m")},
    "Capsule": {"radius": (REQUIRED, "m"), "half_height": (REQUIRED, "m, along z")},
    "Cylinder": {"radius": (REQUIRED, "m"), "half_height": (REQUIRED, "m, along z")},
    "Cone": {"radius": (REQUIRED, "m"), "half_height": (REQUIRED, "m, along z")},
    "ConvexHull": {"points": (None, "(N, 3) m; or `file`"), **_FILE},
    "TriMesh": {
        "vertices": (None, "(V, 3) m; or `file`"),
        "triangles": (None, "(T, 3) vertex indices, counter-clockwise from outside"),
        **_FILE,
    },
    "Plane": {"normal": ([0.0, 0.0, 1.0], "(3,), any non-zero length"), "offset": (0.0, "m: the half-space normal·x ≤ offset")},
    "Compound": {
        "parts": (None, "array of part tables {shape, position, orientation}; or `file`"),
        **_FILE,
        "decompose": ("coacd", 'with `file`: "coacd" (convex decomposition) or "hull" (one convex hull)'),
        "threshold": (0.05, "with decompose = \"coacd\": concavity threshold (–, CoACD's)"),
    },
}

PART: Table = {
    "shape": (REQUIRED, "shape table: Sphere, Box, Capsule, Cylinder, Cone or ConvexHull"),
    "position": ([0.0, 0.0, 0.0], "(3,) m, in the compound's frame"),
    "orientation": ([0.0, 0.0, 0.0, 1.0], "(4,) (x, y, z, w)"),
}


def _default(v: Any) -> str:
    if v is REQUIRED:
        return "required"
    if v is None:
        return "absent"
    if isinstance(v, float) and v == float("inf"):
        return '`"inf"`'
    if isinstance(v, bool):
        return f"`{str(v).lower()}`"
    if isinstance(v, str):
        return f'`"{v}"`'
    return f"`{v}`"


def _rows(table: Table) -> list[str]:
    out = ["| key | default | unit / meaning |", "|---|---|---|"]
    out += [f"| `{k}` | {_default(d)} | {doc} |" for k, (d, doc) in table.items()]
    return out


def reference_markdown() -> str:
    """The key tables of ``docs/scene_format.md`` (a test keeps the page in step)."""
    lines = ["### Top level", "", *_rows(TOP), "", "### Bodies (`[[bodies]]`)", "", *_rows(BODY), "",
             "`mass_properties` table:", "", *_rows(MASS_PROPERTIES), "", "### Shapes (`shape`, a table with `kind`)", ""]
    for kind, table in SHAPES.items():
        lines += [f"`kind = \"{kind}\"`:", "", *_rows(table), ""]
    lines += ["Compound part (`[[bodies.shape.parts]]`):", "", *_rows(PART), "",
              "### Joints (`[[joints]]`)", "", *_rows(JOINT), "", "Drive table (`[joints.drive]`):", "", *_rows(DRIVE), "",
              "### Particle-side calls (`[[particles]]`, each with `op`)", ""]
    for op, (method, table) in PARTICLE_OPS.items():
        lines += [f"`op = \"{op}\"` (`Scene.{method}`):", "", *_rows(table), ""]
    return "\n".join(lines).rstrip("\n") + "\n"
