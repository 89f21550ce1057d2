"""A robot's tree as importers read it (links with mass and collision parts, joints
between them), checked in full, then turned into a Scene in one go: an error leaves
no partial scene behind."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from .. import _core as rr
from .report import APPROXIMATED, DROPPED, ImportReport

# Collision bit of a model's own links when they must not touch each other: links get
# this group and a mask without it, so they still collide with everything else.
MODEL_BIT = 1 << 30
ALL_BITS = 0xFFFFFFFF

class ModelError(rr.RigidError):
    """A model file that cannot be imported: the message names the file, the element
    and the line where the format gives one."""


def where(path: str, element: str, name: str | None = None, line: int | None = None) -> str:
    who = f" {name!r}" if name is not None else ""
    at = f", line {line}" if line is not None else ""
    return f"{path}{at}: <{element}>{who}"


@dataclass
class Part:
    """A collision shape and its pose (4, 4) in its link's frame."""
    shape: Any
    pose: np.ndarray


@dataclass
class Link:
    """A body to be: world pose (4, 4) of its frame at build, mass (kg), centre of mass
    (3,) and inertia (3, 3) about it in that frame, collision parts; ``fixed`` pins it."""
    name: str
    pose: np.ndarray
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    parts: list[Part] = field(default_factory=list)
    fixed: bool = False
    friction: float = 0.5
    # Collision filter of this link's shapes (None: decided at build).
    filter: tuple[int, int] | None = None


@dataclass
class Joint:
    """A joint to be, world-frame at build: child link ``a`` moves relative to ``b``
    (None: the world). ``kind`` is a rigidrs joint kind."""
    name: str
    kind: str
    a: int
    b: int | None
    anchor: np.ndarray
    axis: np.ndarray
    limits: tuple[float, float] | None = None
    damping: float = 0.0
    friction: float = 0.0
    armature: float = 0.0
    cone_limit: float | None = None
    drive: Any = None
    max_force: float | None = None


def add_inertia(link: Link, mass: float, com: np.ndarray, inertia: np.ndarray) -> None:
    """Adds a mass (kg) at ``com`` with ``inertia`` about it (link frame) to ``link``:
    the combined centre of mass and the parallel-axis sum."""
    if mass <= 0.0:
        return
    total = link.mass + mass
    c = (link.mass * link.com + mass * com) / total

    def shifted(m: float, at: np.ndarray, i: np.ndarray) -> np.ndarray:
        d = at - c
        return i + m * (float(d @ d) * np.eye(3) - np.outer(d, d))

    link.inertia = shifted(link.mass, link.com, link.inertia) + shifted(mass, com, inertia)
    link.mass, link.com = total, c


def moved(pose: np.ndarray, mass: float, com: np.ndarray, inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre of mass and inertia given in a frame at ``pose`` re-expressed in the outer frame."""
    r = pose[:3, :3]
    return pose[:3, :3] @ com + pose[:3, 3], r @ inertia @ r.T


def quat_xyzw(r: np.ndarray) -> np.ndarray:
    """Quaternion (x, y, z, w) of a rotation matrix (Shepperd's method)."""
    t = np.trace(r)
    if t > 0:
        s = 2.0 * math.sqrt(t + 1.0)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, 0.25 * s]
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = [0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s, (r[2, 1] - r[1, 2]) / s]
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        q = [(r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s, (r[0, 2] - r[2, 0]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        q = [(r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s, (r[1, 0] - r[0, 1]) / s]
    out = np.array(q, dtype=float)
    return out / np.linalg.norm(out)


def rotation_of_quat(q_wxyz: np.ndarray) -> np.ndarray:
    """Rotation matrix of a quaternion in MuJoCo's (w, x, y, z) order."""
    w, x, y, z = np.asarray(q_wxyz, dtype=float) / np.linalg.norm(q_wxyz)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def transform(r: np.ndarray, p: np.ndarray) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = r, p
    return t


def hinge_limits(lo: float, hi: float, name: str, report: ImportReport, line: int | None) -> tuple[float, float] | None:
    """Hinge limits as the core takes them (angles within [-pi, pi]): a range of a full
    turn or more is no limit; a range past +-pi is clipped. Both reported."""
    if lo > hi:
        raise ModelError(f"joint {name!r}" + (f" (line {line})" if line else "") + f": lower limit {lo} > upper {hi}")
    if hi - lo >= 2 * math.pi:
        report.add("joint.limit", name, DROPPED, f"range [{lo:.4g}, {hi:.4g}] rad spans a full turn: "
                   "the hinge turns freely", line)
        return None
    if lo > 0 or hi < 0:
        report.add("joint.limit", name, APPROXIMATED, f"the file's pose (0) is outside the range [{lo:.4g}, {hi:.4g}]: "
                   "the limit pushes the joint in at the first step; pose it inside with world.set_joint_positions", line)
    if lo < -math.pi or hi > math.pi:
        report.add("joint.limit", name, APPROXIMATED, f"range [{lo:.4g}, {hi:.4g}] rad clipped to "
                   "[-pi, pi] (hinge limits are angles within a turn)", line)
        return (max(lo, -math.pi), min(hi, math.pi))
    return (lo, hi)


def pick_drive(drives: Any, name: str) -> Any:
    """The drive asked for joint ``name``: one ``rr.Drive`` for every joint, a mapping by
    name (key ``"*"``: the rest), or a callable name -> Drive or None."""
    if drives is None:
        return None
    if isinstance(drives, rr.Drive):
        return drives
    if isinstance(drives, Mapping):
        return drives.get(name, drives.get("*"))
    if callable(drives):
        return drives(name)
    raise TypeError(f"drives must be an rr.Drive, a mapping joint name -> Drive, or a callable, got {type(drives).__name__}")


def with_max_force(drive: Any, max_force: float | None) -> Any:
    """``drive`` limited to the file's effort where the drive itself sets no limit."""
    if drive is None or max_force is None or not math.isinf(drive.max_force):
        return drive
    target = drive.target
    return rr.Drive(mode=drive.mode, target=target if len(target) != 1 else target[0],
                    stiffness=drive.stiffness, damping=drive.damping, max_force=max_force)


def body_shape(link: Link) -> Any:
    """One shape for the link's parts: the part itself at an identity pose, else a Compound."""
    if not link.parts:
        return None
    if len(link.parts) == 1 and np.allclose(link.parts[0].pose, np.eye(4), atol=1e-15):
        return link.parts[0].shape
    return rr.Compound([(p.shape, p.pose[:3, 3], quat_xyzw(p.pose[:3, :3])) for p in link.parts])


def settle_mass(link: Link, anchor_local: np.ndarray, report: ImportReport, reference_mass: float) -> None:
    """A moving link needs positive mass and a positive-definite inertia: a massless one
    (a frame between two joints) gets a small mass at its joint; a degenerate tensor
    (a point mass, a rod) the smallest moments floored. Both reported."""
    if link.fixed:
        return
    if link.mass <= 0.0:
        m = 1e-6 * reference_mass
        link.mass, link.com = m, np.array(anchor_local, dtype=float)
        link.inertia = np.eye(3) * m * 1e-4
        report.add("inertial", link.name, APPROXIMATED,
                   f"moving link without mass: given {m:.3g} kg at its joint (1e-6 of the heaviest link)")
        return
    w, v = np.linalg.eigh(0.5 * (link.inertia + link.inertia.T))
    floor = max(1e-9 * max(w.max(), 0.0), link.mass * 1e-10)
    fixed = np.maximum(w, floor)
    # A rigid body's moments obey I_k <= I_i + I_j (the sum of the other two): a file that
    # breaks it gets its largest moment lowered to that sum.
    if fixed[2] > (fixed[0] + fixed[1]) * (1 + 1e-9):
        fixed[2] = fixed[0] + fixed[1]
    if np.any(fixed != w):
        link.inertia = v @ np.diag(fixed) @ v.T
        report.add("inertial", link.name, APPROXIMATED,
                   f"inertia not physical (principal moments {np.round(w, 12).tolist()} kg m^2: not positive, or "
                   f"one above the sum of the other two): taken as {np.round(fixed, 12).tolist()}")


def build_scene(links: list[Link], joints: list[Joint], gravity: Any, report: ImportReport,
                self_collision: bool) -> rr.Scene:
    """The scene of ``links`` (added in order: a parent before its children) and ``joints``.
    Raises ``ModelError`` naming the link or joint a check of the core refused."""
    scene = rr.Scene(gravity=gravity)
    for i, link in enumerate(links):
        shape = body_shape(link)
        group, mask = link.filter if link.filter else (
            (1, ALL_BITS) if self_collision else (MODEL_BIT, ALL_BITS & ~MODEL_BIT))
        kw: dict[str, Any] = dict(position=link.pose[:3, 3], orientation=quat_xyzw(link.pose[:3, :3]),
                                  fixed=link.fixed, friction=link.friction, name=link.name,
                                  collision_group=group, collision_mask=mask)
        if shape is None:
            kw["collision_mask"] = 0
        if not link.fixed:
            kw["mass_properties"] = rr.MassProperties(link.mass, link.com, link.inertia)
        try:
            index = scene.add_body(shape, **kw)
        except (ValueError, TypeError) as e:
            raise ModelError(f"link {link.name!r}: {e}") from e
        assert index == i
    for j in joints:
        kw = dict(anchor=j.anchor, name=j.name)
        if j.kind in ("hinge", "prismatic"):
            kw["axis"] = j.axis
            if j.limits is not None:
                kw["limits"] = j.limits
        if j.kind != "fixed":
            kw.update(damping=j.damping, friction=j.friction, armature=j.armature)
            drive = with_max_force(j.drive, j.max_force)
            if drive is not None:
                kw["drive"] = drive
        if j.cone_limit is not None:
            kw["cone_limit"] = j.cone_limit
        try:
            scene.add_joint(j.kind, j.a, j.b, **kw)
        except (ValueError, TypeError) as e:
            raise ModelError(f"joint {j.name!r}: {e}") from e
    scene.import_report = report
    return scene
