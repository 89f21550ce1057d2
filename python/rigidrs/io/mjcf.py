"""MJCF in: ``rr.Scene.from_mjcf(path)``, through MuJoCo's own parser and compiler.

The file is read with ``mujoco.MjSpec`` and compiled by MuJoCo, so defaults, includes,
inertias inferred from geoms and mesh processing are MuJoCo's own; the compiled model
at its reference pose (``qpos0``) is then mapped onto bodies, shapes, articulation joints
and drives. ``scene.import_report`` lists what has no counterpart."""
from __future__ import annotations

import importlib
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from .. import _core as rr
from .report import APPROXIMATED, DROPPED, MAPPED, ImportReport
from .robot import Joint, Link, ModelError, Part, add_inertia, build_scene, hinge_limits, pick_drive, settle_mass

EXTRA = "pip install 'rigidrs[mjcf]'"
# mjtGeom, mjtJoint, mjtTrn, mjtGain, mjtBias values.
PLANE, HFIELD, SPHERE, CAPSULE, ELLIPSOID, CYLINDER, BOX, MESH = range(8)
FREE, BALL, SLIDE, HINGE = range(4)
TRN_JOINT = 0
GAIN_FIXED, BIAS_NONE, BIAS_AFFINE = 0, 0, 1
# Model parts with no counterpart: (count field, accessor, tag in the file, element, why).
UNSUPPORTED = (("ntendon", "tendon", "tendon", "tendon", "tendons are not modelled"),
               ("nsensor", "sensor", "sensor", "sensor", "sensors are not modelled (read the world's state instead)"),
               ("neq", "equality", "equality", "equality", "equality constraints are not modelled"),
               ("nexclude", "exclude", "exclude", "contact.exclude",
                "contact exclusions are not kept (the model's links do not touch each other by default)"),
               ("npair", "pair", "pair", "contact.pair", "explicit contact pairs are not kept"),
               ("nflex", "flex", "flex", "flex", "flexes are not modelled"),
               ("nskin", "skin", "skin", "skin", "skins are visual only"),
               ("nkey", "key", "key", "key", "keyframes are not read (use world.set_joint_positions)"))


def _mujoco() -> Any:
    try:
        return importlib.import_module("mujoco")
    except ImportError as e:
        raise ImportError(f"reading MJCF needs mujoco: {EXTRA}") from e


def _compile(path: Path) -> tuple[Any, Any]:
    mujoco = _mujoco()
    try:
        spec = mujoco.MjSpec.from_file(str(path))
        model = spec.compile()
    except ValueError as e:  # MuJoCo's messages name the element and the line
        raise ModelError(f"{path}: {' '.join(str(e).split())}") from e
    if model is None:
        raise ModelError(f"{path}: MuJoCo could not compile the model")
    return spec, model


def _lines(path: Path) -> dict[tuple[str, str], int]:
    """Line of each named element of the main file (includes are not followed)."""
    try:
        etree = importlib.import_module("lxml.etree")
        root = etree.parse(str(path)).getroot()
    except Exception:  # lines are a courtesy: MuJoCo already accepted the file
        return {}
    out: dict[tuple[str, str], int] = {}
    for el in root.iter():
        if isinstance(el.tag, str) and el.get("name") is not None:
            out.setdefault((el.tag, el.get("name")), el.sourceline)
    return out


def _name(model: Any, kind: str, i: int) -> str:
    n = getattr(model, kind)(i).name
    return n if n else f"{kind}{i}"


def _shape(model: Any, g: int, name: str, report: ImportReport, line: int | None) -> Any:
    t, size = int(model.geom_type[g]), model.geom_size[g]
    if t == SPHERE:
        return rr.Sphere(float(size[0]))
    if t == CAPSULE:
        return rr.Capsule(float(size[0]), float(size[1]))
    if t == CYLINDER:
        return rr.Cylinder(float(size[0]), float(size[1]))
    if t == BOX:
        return rr.Box(size.copy())
    if t == ELLIPSOID:
        u = np.random.default_rng(0).normal(size=(400, 3))
        u /= np.linalg.norm(u, axis=1, keepdims=True)
        report.add("geom", name, APPROXIMATED, "ellipsoid collided as a convex hull of 400 surface points", line)
        return rr.ConvexHull(u * size)
    if t == MESH:
        m = int(model.geom_dataid[g])
        a, n = int(model.mesh_vertadr[m]), int(model.mesh_vertnum[m])
        report.add("geom", name, MAPPED, "mesh collided as its convex hull (as MuJoCo does)", line)
        return rr.ConvexHull(np.array(model.mesh_vert[a:a + n], dtype=float))
    report.add("geom", name, DROPPED, {HFIELD: "height fields are not supported"}.get(t, f"geom type {t} not supported"), line)
    return None


def _local(body_pose: np.ndarray, pos: np.ndarray, mat: np.ndarray) -> np.ndarray:
    t = np.eye(4)
    r = body_pose[:3, :3]
    t[:3, :3] = r.T @ np.asarray(mat).reshape(3, 3)
    t[:3, 3] = r.T @ (np.asarray(pos) - body_pose[:3, 3])
    return t


def _pose(pos: np.ndarray, mat: np.ndarray) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = np.asarray(mat).reshape(3, 3), pos
    return t


def from_mjcf(cls: Any, path: str | os.PathLike[str], *, drives: Any = None, self_collision: bool = False) -> rr.Scene:
    """A Scene of the MJCF model at ``path``, at its reference pose (``qpos0``).

    Bodies with joints become articulation links (a body with several joints becomes a
    chain of massless-in-effect frames, one joint each), bodies without joints merge into
    their parent, world geoms become fixed bodies. Hinge and slide joints read back
    relative to their ``ref``. Position and velocity actuators on a joint become drives
    (stiffness ``kp·gear²``, damping ``kv·gear²``, target ``ctrl/gear − ref`` with ctrl 0,
    ``max_force`` from ``forcerange·gear``); a joint ``stiffness`` without an actuator
    becomes a position drive to ``springref``. ``drives``: an ``rr.Drive`` for every hinge
    and slide, a mapping joint name -> Drive (key ``"*"``: the others), or a callable name
    -> Drive or None; it replaces the file's drive on the joints it names (default none).
    ``self_collision`` (default False): the model's moving bodies collide with each other
    (never two a joint ties); they always collide with the world's geoms.
    Gravity is the file's. Raises ``FileNotFoundError`` for a missing file,
    ``rigidrs.io.ModelError`` (a ``rigidrs.RigidError``) with MuJoCo's message (element
    and line) for a bad one; nothing is built then."""
    mujoco = _mujoco()
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"MJCF file not found: {path}")
    spec, model = _compile(path)
    lines = _lines(path)
    report = ImportReport(source=str(path))
    _report_model(model, report, lines)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    bodies = [_pose(data.xpos[b], data.xmat[b]) for b in range(model.nbody)]
    links, joints, body_of = _links_and_joints(model, data, bodies, report, lines, drives)
    _geoms(model, data, bodies, links, body_of, report, lines, self_collision)
    heaviest = max([l.mass for l in links] + [1.0])
    for l in links:
        settle_mass(l, l.com, report, heaviest)
    flags = int(model.opt.disableflags)
    gravity = tuple(model.opt.gravity)
    if flags & int(mujoco.mjtDisableBit.mjDSBL_GRAVITY):
        gravity = (0.0, 0.0, 0.0)
        report.add("option.flag", "gravity", MAPPED, "gravity disabled in the file: the scene has none")
    if flags & int(mujoco.mjtDisableBit.mjDSBL_CONTACT):
        for l in links:
            l.filter = (0, 0)
        report.add("option.flag", "contact", MAPPED, "contacts disabled in the file: no shape collides")
    return build_scene(links, joints, gravity, report, self_collision)


def _report_model(model: Any, report: ImportReport, lines: dict) -> None:
    for count, accessor, tag, element, why in UNSUPPORTED:
        for i in range(int(getattr(model, count, 0))):
            name = getattr(model, accessor)(i).name if hasattr(model, accessor) else ""
            report.add(element, name or None, DROPPED, why, lines.get((tag, name)) if name else None)
    report.add("option.timestep", None, MAPPED, f"the file's timestep {model.opt.timestep:g} s is not a setting "
               "of the scene: pass dt= to build()")


def _links_and_joints(model: Any, data: Any, bodies: list, report: ImportReport, lines: dict,
                      drives: Any) -> tuple[list[Link], list[Joint], dict[int, int]]:
    """Links (one per body with joints, one frame per extra joint), joints and the link each
    MuJoCo body belongs to (-1: the world)."""
    links: list[Link] = []
    joints: list[Joint] = []
    body_of: dict[int, int] = {0: -1}
    actuated = _actuators(model, report, lines)
    for b in range(1, model.nbody):
        parent = body_of[int(model.body_parentid[b])]
        n, adr = int(model.body_jntnum[b]), int(model.body_jntadr[b])
        name = _name(model, "body", b)
        if n == 0:
            body_of[b] = parent
            if int(model.body_mocapid[b]) >= 0:
                report.add("body.mocap", name, APPROXIMATED, "mocap body: fixed at its pose", lines.get(("body", name)))
        elif int(model.jnt_type[adr]) == FREE:
            links.append(Link(name, bodies[b]))
            body_of[b] = len(links) - 1
        else:
            for k in range(n):
                j = adr + k
                last = k == n - 1
                links.append(Link(name if last else f"{name}/{_name(model, 'joint', j)}", bodies[b]))
                joints.append(_joint(model, data, j, len(links) - 1, parent, report, lines, actuated, drives))
                parent = len(links) - 1
            body_of[b] = parent
        if b in body_of and body_of[b] >= 0:
            _inertia(model, data, b, links[body_of[b]].pose, links[body_of[b]])
    return links, joints, body_of


def _inertia(model: Any, data: Any, b: int, pose: np.ndarray, link: Link) -> None:
    m = float(model.body_mass[b])
    if m <= 0:
        return
    r = pose[:3, :3]
    ri = np.asarray(data.ximat[b]).reshape(3, 3)
    com = r.T @ (data.xipos[b] - pose[:3, 3])
    tensor = r.T @ ri @ np.diag(model.body_inertia[b]) @ ri.T @ r
    add_inertia(link, m, com, tensor)


def _joint(model: Any, data: Any, j: int, a: int, b: int, report: ImportReport, lines: dict,
           actuated: dict, drives: Any) -> Joint:
    name = _name(model, "joint", j)
    line = lines.get(("joint", name))
    t = int(model.jnt_type[j])
    kind = {BALL: "spherical", SLIDE: "prismatic", HINGE: "hinge"}[t]
    d = int(model.jnt_dofadr[j])
    out = Joint(name, kind, a, None if b < 0 else b, np.array(data.xanchor[j]), np.array(data.xaxis[j]),
                damping=float(model.dof_damping[d]), armature=float(model.dof_armature[d]),
                friction=float(model.dof_frictionloss[d]))
    ref = float(model.qpos0[model.jnt_qposadr[j]]) if t in (SLIDE, HINGE) else 0.0
    if ref != 0.0:
        report.add("joint.ref", name, MAPPED, f"ref {ref:.4g}: the joint reads back q − ref (0 at the file's pose)", line)
    lo, hi = (float(x) - ref for x in model.jnt_range[j])
    if model.jnt_limited[j]:
        if t == BALL:
            out.cone_limit = min(float(model.jnt_range[j][1]), math.pi)
            report.add("joint.range", name, MAPPED, "ball range: a cone limit on the swing of the joint axis "
                       "(MuJoCo limits the total rotation angle)", line)
        elif t == HINGE:
            out.limits = hinge_limits(lo, hi, name, report, line)
        else:
            out.limits = (lo, hi)
    stiffness = float(model.jnt_stiffness[j])
    if t == BALL and j in actuated:
        report.add("actuator", name, DROPPED, "actuator on a ball joint (drives here are for hinges and slides)", line)
    elif j in actuated:
        out.drive, out.max_force = actuated[j](ref)
        if stiffness > 0:
            report.add("joint.stiffness", name, DROPPED, f"spring {stiffness:g}: the joint's actuator is its drive", line)
    elif stiffness > 0 and t != BALL:
        target = float(model.qpos_spring[model.jnt_qposadr[j]]) - ref
        out.drive = rr.Drive(mode="position", target=target, stiffness=stiffness)
        report.add("joint.stiffness", name, MAPPED, f"spring {stiffness:g} to springref: a position drive", line)
    elif stiffness > 0:
        report.add("joint.stiffness", name, DROPPED, "ball joint springs are not modelled", line)
    own = pick_drive(drives, name) if t != BALL else None
    if own is not None:
        if out.drive is not None:
            report.add("joint.drive", name, APPROXIMATED, "the file's drive (actuator or spring) replaced by drives=", line)
        out.drive = own
    return out


def _actuators(model: Any, report: ImportReport, lines: dict) -> dict[int, Any]:
    """{joint: ref -> (Drive, max_force)} for position and velocity actuators on one joint."""
    out: dict[int, Any] = {}
    for i in range(model.nu):
        name = _name(model, "actuator", i)
        line = lines.get(("position", name)) or lines.get(("velocity", name)) or lines.get(("motor", name)) \
            or lines.get(("general", name))
        gain, bias = int(model.actuator_gaintype[i]), int(model.actuator_biastype[i])
        kp, bp = model.actuator_gainprm[i], model.actuator_biasprm[i]
        if int(model.actuator_trntype[i]) != TRN_JOINT:
            report.add("actuator", name, DROPPED, "only actuators on a joint are read (tendon/site transmission)", line)
            continue
        j, gear = int(model.actuator_trnid[i][0]), float(model.actuator_gear[i][0])
        if int(model.actuator_dyntype[i]) != 0:
            report.add("actuator", name, DROPPED, "actuator with activation dynamics (intvelocity, muscle, filter)", line)
            continue
        if j in out:
            report.add("actuator", name, DROPPED, "a second actuator on the same joint", line)
            continue
        limit = None
        if model.actuator_forcelimited[i]:
            lo, hi = model.actuator_forcerange[i]
            limit = max(abs(lo), abs(hi)) * abs(gear)
            if abs(lo) != abs(hi):
                report.add("actuator.forcerange", name, APPROXIMATED, f"forcerange [{lo:g}, {hi:g}]: symmetric ±{limit:g}", line)
        ctrl0 = float(np.clip(0.0, *model.actuator_ctrlrange[i])) if model.actuator_ctrllimited[i] else 0.0
        if gain == GAIN_FIXED and bias == BIAS_AFFINE and bp[0] == 0 and np.isclose(bp[1], -kp[0]) and kp[0] > 0:
            k, c = kp[0] * gear * gear, -bp[2] * gear * gear
            out[j] = lambda ref, k=k, c=c, t=ctrl0 / gear, lim=limit: (
                rr.Drive(mode="position", target=t - ref, stiffness=k, damping=c), lim)
            report.add("actuator", name, MAPPED, f"position actuator: drive k = {k:g}, c = {c:g}; "
                       "world.joints.target = ctrl/gear − ref", line)
        elif gain == GAIN_FIXED and bias == BIAS_AFFINE and bp[0] == 0 and bp[1] == 0 and np.isclose(bp[2], -kp[0]) and kp[0] > 0:
            c = kp[0] * gear * gear
            out[j] = lambda ref, c=c, lim=limit: (rr.Drive(mode="velocity", target=0.0, damping=c), lim)
            report.add("actuator", name, MAPPED, f"velocity actuator: drive c = {c:g}", line)
        elif gain == GAIN_FIXED and bias == BIAS_NONE:
            report.add("actuator", name, DROPPED, "motor (force = gear·ctrl): no drive; apply torques "
                       "or give drives=", line)
        else:
            report.add("actuator", name, DROPPED, "general actuator without a drive counterpart", line)
    return out


def _geoms(model: Any, data: Any, bodies: list, links: list[Link], body_of: dict, report: ImportReport,
           lines: dict, self_collision: bool) -> None:
    """Collision geoms into their link (frame of that link); world geoms into fixed bodies."""
    frictions: dict[int, set] = {}
    for g in range(model.ngeom):
        name = _name(model, "geom", g)
        line = lines.get(("geom", name))
        link = body_of[int(model.geom_bodyid[g])]
        if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0:
            report.add("geom", name, DROPPED, "visual-only geom (contype = conaffinity = 0): mass kept, not collided", line)
            continue
        mu = float(model.geom_friction[g][0])
        if int(model.geom_type[g]) == PLANE:
            if link >= 0:
                report.add("geom", name, DROPPED, "a plane on a moving body (planes are fixed half-spaces)", line)
            else:
                _world_geom(model, data, g, name, None, mu, links)
            continue
        shape = _shape(model, g, name, report, line)
        if shape is None:
            continue
        if link < 0:
            _world_geom(model, data, g, name, shape, mu, links)
            continue
        links[link].parts.append(Part(shape, _local(links[link].pose, data.geom_xpos[g], data.geom_xmat[g])))
        frictions.setdefault(link, set()).add(mu)
        links[link].friction = mu
        if int(model.geom_condim[g]) > 3:
            report.add("geom.condim", name, APPROXIMATED, "torsional and rolling friction: the patch's own twist friction instead", line)
    for link, mus in frictions.items():
        if len(mus) > 1:
            report.add("geom.friction", links[link].name, APPROXIMATED, f"geoms of one body with frictions {sorted(mus)}: "
                       f"{links[link].friction:g} for all", None)


def _world_geom(model: Any, data: Any, g: int, name: str, shape: Any, mu: float, links: list[Link]) -> None:
    """A fixed body of its own for a geom of the world (planes cannot share a compound)."""
    pose = _pose(data.geom_xpos[g], data.geom_xmat[g])
    if int(model.geom_type[g]) == PLANE:
        n = pose[:3, 2]
        shape, pose = rr.Plane(n, float(n @ pose[:3, 3])), np.eye(4)
    link = Link(name, pose, fixed=True, friction=mu, filter=(1, 0xFFFFFFFF))
    link.parts.append(Part(shape, np.eye(4)))
    links.append(link)
