"""URDF in: ``rr.Scene.from_urdf(path, package_map=..., fixed_base=True)``, through yourdfpy.

Links become bodies (links tied by fixed joints merge into one body), joints become
articulation joints, collision geometry becomes shapes (a mesh: its convex hull), and
``scene.import_report`` lists what the file had that the scene does not hold exactly."""
from __future__ import annotations

import importlib
import math
import os
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from .. import _core as rr
from .report import APPROXIMATED, DROPPED, MAPPED, ImportReport
from .robot import Joint, Link, ModelError, Part, add_inertia, build_scene, hinge_limits, moved, pick_drive, settle_mass, where

EXTRA = "pip install 'rigidrs[io]'"
# Top-level tags the importer reads; anything else is reported.
KNOWN_TOP = {"link", "joint", "material"}
JOINT_KINDS = {"revolute": "hinge", "continuous": "hinge", "prismatic": "prismatic", "fixed": "fixed"}


def _need(module: str) -> Any:
    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise ImportError(f"reading URDF needs {module}: {EXTRA}") from e


def _xml_tree(path: Path) -> Any:
    """The file parsed by lxml (kept for line numbers); malformed XML names the line."""
    etree = _need("lxml.etree")
    try:
        return etree.parse(str(path))
    except etree.XMLSyntaxError as e:
        line = e.lineno if e.lineno else (e.position[0] if e.position else None)
        raise ModelError(f"{path}, line {line}: malformed XML: {e.msg}") from e


def _lines(root: Any) -> dict[tuple[str, str], int]:
    """Line of each named link and joint: {(tag, name): line}."""
    out: dict[tuple[str, str], int] = {}
    for el in root:
        if isinstance(el.tag, str) and el.get("name") is not None:
            out.setdefault((el.tag, el.get("name")), el.sourceline)
    return out


def _check_names(root: Any, path: Path) -> None:
    """The attributes yourdfpy needs, checked first so that the error names the line."""
    if root.tag != "robot":
        raise ModelError(f"{path}, line {root.sourceline}: the root element is <{root.tag}>, not <robot>")
    needs = {"robot": ("name",), "link": ("name",), "joint": ("name", "type")}
    for el in [root, *root]:
        for attr in needs.get(el.tag, ()) if isinstance(el.tag, str) else ():
            if el.get(attr) is None:
                raise ModelError(f"{path}, line {el.sourceline}: <{el.tag}> has no {attr!r} attribute")
        if el.tag == "joint":
            for part in ("parent", "child"):
                sub = el.find(part)
                if sub is None or sub.get("link") is None:
                    raise ModelError(f"{where(str(path), 'joint', el.get('name'), el.sourceline)}: no <{part} link=...>")


def _report_tags(root: Any, path: Path, report: ImportReport) -> None:
    """Everything outside links, joints and materials; visuals; joint parts without a counterpart."""
    for el in root:
        if not isinstance(el.tag, str):
            continue
        if el.tag not in KNOWN_TOP:
            why = {"transmission": "transmissions (actuator gearing) have no counterpart; use drives=",
                   "gazebo": "Gazebo simulator settings are not read",
                   "ros2_control": "ros2_control hardware interfaces are not read"}.get(el.tag, "unsupported tag")
            report.add(el.tag, el.get("name"), DROPPED, why, el.sourceline)
        elif el.tag == "link":
            for v in el.findall("visual"):
                report.add("visual", el.get("name"), DROPPED, "visual-only geometry (not collided, no mass)", v.sourceline)
        elif el.tag == "joint":
            for dyn in el.findall("dynamics"):
                extra = sorted(set(dyn.keys()) - {"damping", "friction"})
                if extra:
                    report.add("joint.dynamics", el.get("name"), DROPPED,
                               f"attributes {', '.join(extra)} are not URDF and are not read", dyn.sourceline)
            for tag, why in (("calibration", "calibration is not read"),
                             ("safety_controller", "soft limits and safety gains are not read")):
                for sub in el.findall(tag):
                    report.add(f"joint.{tag}", el.get("name"), DROPPED, why, sub.sourceline)


def resolve(filename: str, urdf: Path, package_map: Mapping[str, str | os.PathLike[str]] | None) -> Path:
    """The file a mesh reference names: ``package://pkg/rest`` through ``package_map``, then
    ``ROS_PACKAGE_PATH`` (a directory named pkg, or holding one), then the directories
    around the URDF (an ancestor named pkg, or one holding pkg/); ``file://`` and plain
    paths relative to the URDF's directory."""
    if filename.startswith("file://"):
        p = Path(filename[len("file://"):])
        return p if p.is_absolute() else urdf.parent / p
    if not filename.startswith("package://"):
        p = Path(filename)
        return p if p.is_absolute() else urdf.parent / p
    pkg, _, rest = filename[len("package://"):].partition("/")
    candidates: list[Path] = []
    if package_map and pkg in package_map:
        candidates.append(Path(package_map[pkg]) / rest)
    for d in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep):
        if d:
            root = Path(d)
            candidates += [root / rest] if root.name == pkg else [root / pkg / rest]
    for a in urdf.resolve().parents:
        candidates.append(a / rest if a.name == pkg else a / pkg / rest)
    for c in candidates:
        if c.is_file():
            return c
    return candidates[0] if package_map and pkg in package_map else Path(filename)


def _origin(o: Any) -> np.ndarray:
    return np.eye(4) if o is None else np.asarray(o, dtype=float)


def _mesh_hull(file: Path, scale: Any, link: str, what: str, report: ImportReport, line: int | None) -> Any:
    trimesh = _need("trimesh")
    if not file.is_file():
        raise ModelError(f"{what}: mesh file not found: {file}")
    try:
        mesh = trimesh.load(str(file), force="mesh")
    except Exception as e:  # trimesh raises many kinds for a bad file
        raise ModelError(f"{what}: cannot read mesh {file}: {e}") from e
    v = np.asarray(mesh.vertices, dtype=float) * (1.0 if scale is None else np.asarray(scale, dtype=float))
    hull = None
    try:  # qhull's hull first (fewer points; parry's own can fail on large scans)
        hull = rr.ConvexHull(np.asarray(trimesh.convex.convex_hull(v).vertices, dtype=float))
    except Exception:  # no scipy, or a flat mesh: parry on the raw points decides
        pass
    if hull is None:
        try:
            hull = rr.ConvexHull(v)
        except ValueError as e:
            raise ModelError(f"{what}: mesh {file} has no volume for a convex hull: {e}") from e
    report.add("collision.mesh", link, APPROXIMATED, "mesh collided as its convex hull", line)
    return hull


def _shape(geom: Any, link: str, what: str, urdf: Path, package_map: Any, report: ImportReport,
           line: int | None) -> Any:
    if geom is None:
        raise ModelError(f"{what}: collision without geometry")
    if geom.box is not None:
        return rr.Box(np.asarray(geom.box.size, dtype=float) / 2)
    if geom.sphere is not None:
        return rr.Sphere(float(geom.sphere.radius))
    if geom.cylinder is not None:
        return rr.Cylinder(float(geom.cylinder.radius), float(geom.cylinder.length) / 2)
    if geom.mesh is not None:
        return _mesh_hull(resolve(geom.mesh.filename, urdf, package_map), geom.mesh.scale, link, what, report, line)
    raise ModelError(f"{what}: unknown geometry")


def _check_tree(robot: Any, path: Path, lines: dict) -> tuple[str, dict[str, Any]]:
    """The root link and each child's joint; errors for a joint naming a missing link,
    a link with two parents (a loop), no root or several."""
    names = [l.name for l in robot.links]
    if not names:
        raise ModelError(f"{path}: <robot> has no <link>")
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ModelError(f"{where(str(path), 'link', n, lines.get(('link', n)))}: two links have this name")
        seen.add(n)
    parent_joint: dict[str, Any] = {}
    for j in robot.joints:
        at = where(str(path), "joint", j.name, lines.get(("joint", j.name)))
        for role in ("parent", "child"):
            if getattr(j, role) not in seen:
                raise ModelError(f"{at}: {role} link {getattr(j, role)!r} is not a <link> of the file")
        if j.child in parent_joint:
            raise ModelError(f"{at}: link {j.child!r} already has parent joint {parent_joint[j.child].name!r}: "
                             "a URDF must be a tree (a loop or a link with two parents)")
        parent_joint[j.child] = j
    roots = [n for n in names if n not in parent_joint]
    if len(roots) != 1:
        raise ModelError(f"{path}: the links must form one tree; roots found: {roots} "
                         "(none: every link has a parent, a loop)")
    return roots[0], parent_joint


def _order(root: str, robot: Any) -> list[Any]:
    """Joints parent before child (breadth first from the root); a loop leaves some out."""
    children: dict[str, list[Any]] = {}
    for j in robot.joints:
        children.setdefault(j.parent, []).append(j)
    order, todo = [], [root]
    while todo:
        n = todo.pop(0)
        for j in children.get(n, []):
            order.append(j)
            todo.append(j.child)
    return order


def from_urdf(cls: Any, path: str | os.PathLike[str], package_map: Mapping[str, str | os.PathLike[str]] | None = None,
              fixed_base: bool = True, *, drives: Any = None, self_collision: bool = False,
              friction: float = 0.5, gravity: Any = None) -> rr.Scene:
    """A Scene of the robot in the URDF file at ``path``, at its zero joint configuration.

    ``package_map``: {package name: directory} for ``package://`` mesh references (default
    none; then ``ROS_PACKAGE_PATH`` and the directories around the file are searched).
    ``fixed_base`` (default True): the root link is fixed to the world; False makes it a
    free floating base (a root named ``world`` without mass is the world either way).
    ``drives``: an ``rr.Drive`` for every revolute, continuous and prismatic joint, a
    mapping joint name -> Drive (key ``"*"``: the others), or a callable name -> Drive or
    None; default none. A drive without ``max_force`` takes the joint's ``limit effort``.
    ``self_collision`` (default False): links of the robot collide with each other
    (never two links a joint ties); they always collide with other bodies.
    ``friction``: contact friction of the links (default 0.5; URDF has none).
    ``gravity`` (3,) m/s², default (0, 0, −9.81).
    Raises ``FileNotFoundError`` for a missing file, ``rigidrs.io.ModelError`` (a
    ``rigidrs.RigidError``) naming the file, element and line for a bad one; nothing is
    built then."""
    path = Path(path)
    robot, tree, lines = _read(path)
    report = ImportReport(source=str(path))
    _report_tags(tree.getroot(), path, report)
    root, _ = _check_tree(robot, path, lines)
    order = _order(root, robot)
    if len(order) != len(robot.joints):
        raise ModelError(f"{path}: some links are not reachable from the root {root!r} (a loop)")
    # World pose of every link frame at q = 0.
    pose = {root: np.eye(4)}
    for j in order:
        pose[j.child] = pose[j.parent] @ _origin(j.origin)
    links, joints, body_of = _bodies(robot, root, order, pose, fixed_base, friction, drives, report, lines)
    _fill_links(robot, body_of, links, pose, path, package_map, report, lines)
    heaviest = max([l.mass for l in links] + [1.0])
    for l in links:
        settle_mass(l, np.zeros(3), report, heaviest)
    return build_scene(links, joints, gravity, report, self_collision)


def _read(path: Path) -> tuple[Any, Any, dict]:
    """The robot as yourdfpy reads it, the lxml tree and the lines of named elements."""
    yourdfpy = _need("yourdfpy")
    if not path.is_file():
        raise FileNotFoundError(f"URDF file not found: {path}")
    tree = _xml_tree(path)
    _check_names(tree.getroot(), path)
    try:
        urdf = yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False,
                                  build_collision_scene_graph=False, load_collision_meshes=False)
    except Exception as e:  # yourdfpy's parse errors for missing attributes and values
        raise ModelError(f"{path}: not a valid URDF: {e}") from e
    return urdf.robot, tree, _lines(tree.getroot())


def _bodies(robot: Any, root: str, order: list[Any], pose: dict, fixed_base: bool, friction: float,
            drives: Any, report: ImportReport, lines: dict) -> tuple[list[Link], list[Joint], dict[str, int]]:
    """One body per link moved by a joint (links tied by a fixed or unsupported joint merge
    into their parent's body), the joints between them, and the body of every link."""
    by_name = {l.name: l for l in robot.links}
    root_massless = by_name[root].inertial is None or not (by_name[root].inertial.mass or 0) > 0
    fixed_root = fixed_base or (root == "world" and root_massless)
    if not fixed_base and fixed_root:
        report.add("link", root, MAPPED, "a massless root named 'world' is the world: the base is fixed",
                   lines.get(("link", root)))
    links = [Link(root, pose[root], fixed=fixed_root, friction=friction)]
    body_of = {root: 0}
    joints: list[Joint] = []
    for j in order:
        line = lines.get(("joint", j.name))
        kind = JOINT_KINDS.get(j.type)
        if j.type == "floating":
            if body_of[j.parent] != 0 or not links[0].fixed:
                report.add("joint", j.name, APPROXIMATED, "floating joint below another link: the child is a free body", line)
            links.append(Link(j.child, pose[j.child], friction=friction))
            body_of[j.child] = len(links) - 1
            continue
        if kind is None:
            report.add("joint", j.name, APPROXIMATED, f"{j.type} joint has no counterpart: taken as fixed", line)
            kind = "fixed"
        if kind == "fixed":
            body_of[j.child] = body_of[j.parent]
            if j.type == "fixed":
                report.add("joint", j.name, MAPPED, f"fixed joint: link {j.child!r} merged into body "
                           f"{links[body_of[j.parent]].name!r}", line)
            continue
        links.append(Link(j.child, pose[j.child], friction=friction))
        body_of[j.child] = len(links) - 1
        joints.append(_joint(j, kind, body_of, pose, report, line, drives))
    return links, joints, body_of


def _joint(j: Any, kind: str, body_of: dict, pose: dict, report: ImportReport,
           line: int | None, drives: Any) -> Joint:
    t = pose[j.child]
    axis = np.asarray(j.axis if j.axis is not None else (1.0, 0.0, 0.0), dtype=float)
    if not np.linalg.norm(axis) > 0:
        raise ModelError(f"joint {j.name!r} (line {line}): zero axis")
    out = Joint(j.name, kind, body_of[j.child], body_of[j.parent], t[:3, 3].copy(), t[:3, :3] @ axis)
    lim = j.limit
    if j.type in ("revolute", "prismatic") and lim is not None and lim.lower is not None and lim.upper is not None:
        lo, hi = float(lim.lower), float(lim.upper)
        if kind == "hinge":
            out.limits = hinge_limits(lo, hi, j.name, report, line)
        elif lo > hi:
            raise ModelError(f"joint {j.name!r} (line {line}): limit lower {lo} > upper {hi}")
        else:
            out.limits = (lo, hi)
    if lim is not None and lim.velocity is not None and lim.velocity > 0:
        report.add("joint.limit.velocity", j.name, DROPPED, "velocity limits are not enforced", line)
    if j.dynamics is not None:
        out.damping = float(j.dynamics.damping or 0.0)
        out.friction = float(j.dynamics.friction or 0.0)
    if j.mimic is not None:
        report.add("joint.mimic", j.name, DROPPED, f"mimics {j.mimic.joint!r}: no coupling, the joint moves "
                   "on its own (drive it to follow)", line)
    out.drive = pick_drive(drives, j.name)
    if out.drive is not None and lim is not None and lim.effort is not None and lim.effort > 0:
        out.max_force = float(lim.effort)
        if math.isinf(out.drive.max_force):
            report.add("joint.limit.effort", j.name, MAPPED, f"effort {lim.effort:.4g} is the drive's max_force", line)
    return out


def _fill_links(robot: Any, body_of: dict, links: list[Link], pose: dict, path: Path,
                package_map: Any, report: ImportReport, lines: dict) -> None:
    """Mass and collision parts of every link, into the body it belongs to (frame of that body)."""
    by_name = {l.name: l for l in robot.links}
    for name, b in body_of.items():
        link, body = by_name[name], links[b]
        rel = np.linalg.inv(body.pose) @ pose[name]
        line = lines.get(("link", name))
        ine = link.inertial
        if ine is not None and ine.mass is not None and ine.mass > 0:
            o = _origin(ine.origin)
            inertia = np.asarray(ine.inertia if ine.inertia is not None else np.zeros((3, 3)), dtype=float)
            com, tensor = moved(rel @ o, float(ine.mass), np.zeros(3), inertia)
            add_inertia(body, float(ine.mass), com, tensor)
        elif ine is not None and ine.mass is not None and ine.mass < 0:
            raise ModelError(f"{where(str(path), 'link', name, line)}: negative mass {ine.mass}")
        for k, c in enumerate(link.collisions):
            what = where(str(path), "link", name, line) + f" <collision> {k}"
            shape = _shape(c.geometry, name, what, path, package_map, report, line)
            body.parts.append(Part(shape, rel @ _origin(c.origin)))
        if len(link.collisions) > 1:
            report.add("collision", name, MAPPED, f"{len(link.collisions)} collision elements: one Compound", line)
