"""``Scene.to_dict`` / ``Scene.from_dict``: a scene as plain data (dicts, lists, str,
float, int, bool), exactly.

What is written is what the scene was given, call by call (``Scene._recipe()``,
kept by the core as each ``add_*`` call succeeds), not the compiled bodies: the
principal frames, joint frames and particle rest values are derived from those
inputs, and deriving them again from the same bits gives the same bits. So
``from_dict`` replays the calls through the public methods (bodies, then joints,
then the particle-side calls in their order; no call depends on a later one), and a
rebuilt scene steps bit for bit like the original. Keys at their default are left
out. Floats are Python floats (repr round-trips exactly); the non-finite ones a
scene may hold (``max_force``, ``plastic_max``, build settings) are written as the
strings ``"inf"`` / ``"-inf"``, so the data is strict JSON; NaN is refused.
"""
from __future__ import annotations

import difflib
import inspect
import math
import re
import struct
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from .. import _core
from . import schema
from .schema import REQUIRED, Table

# Keys whose values are text: never decoded as "inf".
_TEXT_KEYS = {"name", "kind", "solver", "mode", "op", "file", "decompose", "format", "integrator", "articulation_integrator"}


class SceneDataError(_core.RigidError):
    """Scene data that does not follow the schema; the message names the path
    inside the data (``bodies[3].density``) and, for a file, the file and line."""


# ----------------------------------------------------------------------------- out


def _encode(v: Any, path: str) -> Any:
    if isinstance(v, bool) or v is None or isinstance(v, (int, str)):
        return v
    if isinstance(v, float):
        if math.isnan(v):
            raise SceneDataError(f"{path}: NaN cannot be written")
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return v
    if isinstance(v, dict):
        return {k: _encode(x, f"{path}.{k}") for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_encode(x, f"{path}[{i}]") for i, x in enumerate(v)]
    raise SceneDataError(f"{path}: cannot write a {type(v).__name__}")


def _same(a: Any, b: Any) -> bool:
    """Equal to the bit (-0.0 is not 0.0), lists element-wise."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    if isinstance(a, float) or isinstance(b, float):
        num = (int, float)
        return isinstance(a, num) and isinstance(b, num) and struct.pack("<d", a) == struct.pack("<d", b)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return type(a) is type(b) and a == b


def _trim(d: dict[str, Any], table: Table) -> dict[str, Any]:
    """`d`'s keys in schema order, those at their default left out."""
    return {k: d[k] for k, (default, _) in table.items() if k in d and (default is REQUIRED or not _same(d[k], default))}


def _shape_out(s: dict[str, Any]) -> dict[str, Any]:
    kind = s["kind"]
    out = {"kind": kind, **_trim(s, schema.SHAPES[kind])}
    if kind == "Compound":
        out["parts"] = [_trim({**p, "shape": _shape_out(p["shape"])}, schema.PART) for p in s["parts"]]
    return out


def _body_out(b: dict[str, Any]) -> dict[str, Any]:
    b = dict(b)
    if _same(b["static_friction"], b["friction"]):
        b["static_friction"] = None
    if b["shape"] is not None:
        b["shape"] = _shape_out(b["shape"])
    return _trim(b, schema.BODY)


def _joint_out(j: dict[str, Any]) -> dict[str, Any]:
    j = dict(j)
    if j["drive"] is not None:
        j["drive"] = _trim(j["drive"], schema.DRIVE)
    return _trim(j, schema.JOINT)


def _particle_out(c: dict[str, Any]) -> dict[str, Any]:
    op = c["op"]
    c = dict(c)
    if isinstance(c.get("shape"), dict):
        c["shape"] = _shape_out(c["shape"])
    return {"op": op, **_trim(c, schema.PARTICLE_OPS[op][1])}


def to_dict(scene: _core.Scene) -> dict[str, Any]:
    """The scene as plain, JSON-able data following ``docs/scene_format.md``."""
    r = scene._recipe()
    if (len(r["bodies"]), len(r["joints"])) != (len(scene), scene.joint_count):
        # Bodies or joints added by Rust code past the Python methods leave no record.
        raise SceneDataError(
            f"this scene has {len(scene)} bodies and {scene.joint_count} joints but a record of "
            f"{len(r['bodies'])} and {len(r['joints'])}: only scenes filled through the Python methods can be written"
        )
    out: dict[str, Any] = {"format": schema.FORMAT, "schema_version": schema.SCHEMA_VERSION, "gravity": r["gravity"]}
    parts = {
        "bodies": [_body_out(b) for b in r["bodies"]],
        "joints": [_joint_out(j) for j in r["joints"]],
        "particles": [_particle_out(c) for c in r["particles"]],
        "build": _build_settings(_encode(dict(scene.build_settings), "build")),  # what load would refuse, refused now
    }
    out.update({k: v for k, v in parts.items() if v})
    result: dict[str, Any] = _encode(out, "scene")
    return result


# ------------------------------------------------------------------------------ in

_PREFIX = re.compile(r"^(?:(?:body|joint|particle|cluster) \d+|constraint \d+ \([^)]*\)|particles): ")
_ARGUMENT = re.compile(r"^argument '(\w+)': ")


def _message(e: BaseException, path: str, keys: set[str]) -> str:
    """`e`'s message at `path`, the key it is about appended to the path when the
    message starts with one (``density must be positive`` -> ``….density: must be positive``)."""
    msg = str(e)
    msg = _PREFIX.sub("", msg, count=1)
    m = _ARGUMENT.match(msg)
    if m and m.group(1) in keys:
        return f"{_join(path, m.group(1))}: {msg[m.end():]}"
    for key in sorted(keys, key=len, reverse=True):
        for sep in (" ", ": ", ". "):
            if msg.startswith(key + sep):
                rest = msg[len(key) + len(sep):]
                return f"{_join(path, key)}: {rest}"
    return f"{path}: {msg}" if path else msg


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


@contextmanager
def _at(path: str, keys: set[str] | None = None) -> Iterator[None]:
    """Errors raised inside name `path` (and the key, when the message starts with it)."""
    try:
        yield
    except SceneDataError:
        raise
    except (ValueError, TypeError, OverflowError) as e:
        msg = _message(e, path, keys or set())
        cls = type(e)
        try:
            new = cls(msg)
        except Exception:
            new = SceneDataError(msg)
        raise new from e


def _decode(v: Any, key: str) -> Any:
    if isinstance(v, str) and key not in _TEXT_KEYS and v.strip().lower() in ("inf", "+inf", "-inf"):
        return float(v.strip().lower())
    if isinstance(v, list):
        return [_decode(x, key) for x in v]
    return v


class _Reader:
    def __init__(self, base_dir: Path) -> None:
        self.base_dir = base_dir

    def table(self, d: Any, table: Table, path: str, extra: tuple[str, ...] = ()) -> dict[str, Any]:
        """The keys of `d` checked against `table` (None values dropped, "inf" decoded)."""
        if not isinstance(d, dict):
            raise SceneDataError(f"{path}: must be a table (dict), got {type(d).__name__}")
        known = set(table) | set(extra)
        for k in d:
            if k not in known:
                near = difflib.get_close_matches(str(k), sorted(known), n=1)
                hint = f"; did you mean {near[0]!r}?" if near else f"; known keys: {', '.join(sorted(known))}"
                raise SceneDataError(f"{path}.{k}: unknown key{hint}")
        for k, (default, _) in table.items():
            if default is REQUIRED and d.get(k) is None:
                raise SceneDataError(f"{path}.{k}: missing (required)")
        return {k: _decode(v, k) for k, v in d.items() if v is not None and k not in extra}

    def shape(self, d: Any, path: str) -> _core.Shape:
        if not isinstance(d, dict):
            raise SceneDataError(f"{path}: must be a shape table with a `kind`, got {type(d).__name__}")
        kind = d.get("kind")
        if kind not in schema.SHAPES:
            raise SceneDataError(f"{path}.kind: unknown shape kind {kind!r}; choose one of {', '.join(schema.SHAPES)}")
        kw = self.table(d, schema.SHAPES[kind], path, extra=("kind",))
        keys = set(kw)
        with _at(path, keys):
            if "file" in kw:
                return self._from_file(kind, kw, path)
            for k in ("scale", "decompose", "threshold"):
                if k in kw:
                    raise SceneDataError(f"{path}.{k}: only with `file`")
            if kind == "Sphere":
                return _core.Sphere(kw["radius"])
            if kind == "Box":
                return _core.Box(kw["half_extents"])
            if kind in ("Capsule", "Cylinder", "Cone"):
                return getattr(_core, kind)(kw["radius"], kw["half_height"])
            if kind == "Plane":
                return _core.Plane(kw.get("normal"), kw.get("offset", 0.0))
            if kind == "ConvexHull":
                return _core.ConvexHull(self._need(kw, "points", path))
            if kind == "TriMesh":
                return _core.TriMesh(self._need(kw, "vertices", path), self._need(kw, "triangles", path))
            parts = self._need(kw, "parts", path)
            if not isinstance(parts, list):
                raise SceneDataError(f"{path}.parts: must be an array of part tables")
            built = []
            for n, p in enumerate(parts):
                pp = f"{path}.parts[{n}]"
                pk = self.table(p, schema.PART, pp)
                built.append((
                    self.shape(pk["shape"], f"{pp}.shape"),
                    pk.get("position", [0.0, 0.0, 0.0]),
                    pk.get("orientation", [0.0, 0.0, 0.0, 1.0]),
                ))
            return _core.Compound(built)

    @staticmethod
    def _need(kw: dict[str, Any], key: str, path: str) -> Any:
        if key not in kw:
            raise SceneDataError(f"{path}.{key}: missing (give it or `file`)")
        return kw[key]

    def _from_file(self, kind: str, kw: dict[str, Any], path: str) -> _core.Shape:
        from . import mesh

        inline = {"vertices", "triangles", "points", "parts"} & set(kw)
        if inline:
            raise SceneDataError(f"{path}: give `file` or {', '.join(sorted(inline))}, not both")
        if not isinstance(kw["file"], str):
            raise SceneDataError(f"{path}.file: must be a path (str)")
        file = self.base_dir / kw["file"]
        scale = kw.get("scale", 1.0)
        if kind == "TriMesh":
            return mesh.trimesh_from_file(file, scale=scale)
        if kind == "ConvexHull":
            return mesh.convex_hull_from_file(file, scale=scale)
        if kind == "Compound":
            return mesh.compound_from_file(file, scale=scale, decompose=kw.get("decompose", "coacd"),
                                           threshold=kw.get("threshold", 0.05))
        raise SceneDataError(f"{path}.file: a {kind} is not read from a file (TriMesh, ConvexHull, Compound are)")


def _bodies(scene: _core.Scene, items: Any, r: _Reader) -> None:
    for i, b in enumerate(_array(items, "bodies")):
        path = f"bodies[{i}]"
        kw = r.table(b, schema.BODY, path)
        if "shape" in kw:
            kw["shape"] = r.shape(kw["shape"], f"{path}.shape")
        if "mass_properties" in kw:
            mp = r.table(kw["mass_properties"], schema.MASS_PROPERTIES, f"{path}.mass_properties")
            with _at(f"{path}.mass_properties", set(mp)):
                kw["mass_properties"] = _core.MassProperties(mp["mass"], mp["center_of_mass"], mp["inertia"])
        shape = kw.pop("shape", None)
        with _at(path, set(schema.BODY)):
            scene.add_body(shape, **kw)


def _joints(scene: _core.Scene, items: Any, r: _Reader) -> None:
    for i, j in enumerate(_array(items, "joints")):
        path = f"joints[{i}]"
        kw = r.table(j, schema.JOINT, path)
        if "drive" in kw:
            dk = r.table(kw["drive"], schema.DRIVE, f"{path}.drive")
            with _at(f"{path}.drive", set(dk)):
                kw["drive"] = _core.Drive(**dk)
        kind, a = kw.pop("kind"), kw.pop("body_a")
        b = kw.pop("body_b", None)
        with _at(path, set(schema.JOINT)):
            scene.add_joint(kind, a, b, **kw)


def _particles(scene: _core.Scene, items: Any, r: _Reader) -> None:
    for i, c in enumerate(_array(items, "particles")):
        path = f"particles[{i}]"
        if not isinstance(c, dict) or c.get("op") not in schema.PARTICLE_OPS:
            op = c.get("op") if isinstance(c, dict) else None
            raise SceneDataError(f"{path}.op: unknown or missing op {op!r}; choose one of {', '.join(schema.PARTICLE_OPS)}")
        op = c["op"]
        method, table = schema.PARTICLE_OPS[op]
        kw = r.table(c, table, path, extra=("op",))
        args: list[Any] = []
        if op in ("distance", "bending"):
            args = list(kw.pop("particles"))
        elif op == "particle":
            args = [kw.pop("position")]
        elif op in ("rope", "cloth", "soft_box"):
            first = {"rope": ("start", "end", "segments"), "cloth": ("origin", "u", "v", "resolution"),
                     "soft_box": ("center", "half_extents", "cells")}[op]
            args = [kw.pop(k) for k in first]
            if op != "rope":
                args[-1] = tuple(args[-1]) if isinstance(args[-1], list) else args[-1]
        elif op == "mesh_volume":
            args = [kw.pop("triangles")]
        elif op == "attachment":
            args = [kw.pop("particle"), kw.pop("body")]
        elif op in ("volume", "shape_matching"):
            args = [kw.pop("particles")]
        elif op == "shape_matched_body":
            if ("shape" in kw) == ("points" in kw):
                raise SceneDataError(f"{path}: give exactly one of `shape` and `points`")
            args = [r.shape(kw.pop("shape"), f"{path}.shape") if "shape" in kw else kw.pop("points")]
        with _at(path, set(table)):
            getattr(scene, method)(*args, **kw)


def _array(items: Any, key: str) -> list[Any]:
    if not isinstance(items, list):
        raise SceneDataError(f"{key}: must be an array, got {type(items).__name__}")
    return items


def _build_settings(settings: Any) -> dict[str, Any]:
    if not isinstance(settings, dict):
        raise SceneDataError(f"build: must be a table, got {type(settings).__name__}")
    known = [p for p in inspect.signature(_core.Scene.build).parameters if p != "self"]
    out: dict[str, Any] = {}
    for k, v in settings.items():
        if k not in known:
            near = difflib.get_close_matches(str(k), known, n=1)
            hint = f"; did you mean {near[0]!r}?" if near else f"; known: {', '.join(known)}"
            raise SceneDataError(f"build.{k}: unknown build setting{hint}")
        if v is not None:
            out[k] = _decode(v, k)
    if out:
        # Checked now, on an empty scene (cheap), so that a bad setting is named with
        # its path rather than found at the first build.
        import warnings

        with _at("build", set(known)), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            _core.Scene().build(**{"dt": 0.01, **out})
    return out


def from_dict(data: Any, base_dir: str | Path | None = None) -> _core.Scene:
    """A new scene from ``to_dict`` data (or a file's tables). ``base_dir``: where
    mesh ``file`` paths are relative to (default the current directory). Errors
    name the path inside the data; nothing is returned on error."""
    r = _Reader(Path(base_dir) if base_dir is not None else Path.cwd())
    top = r.table(data, schema.TOP, "scene")
    fmt = top.get("format", schema.FORMAT)
    if fmt != schema.FORMAT:
        raise SceneDataError(f"format: expected {schema.FORMAT!r}, got {fmt!r}")
    version = top["schema_version"]
    if not isinstance(version, int) or isinstance(version, bool):
        raise SceneDataError(f"schema_version: must be an integer, got {version!r}")
    if version > schema.SCHEMA_VERSION or version < 1:
        raise SceneDataError(
            f"schema_version: {version} is not readable by this rigidrs ({_core.__version__}), which reads "
            f"schema version {schema.SCHEMA_VERSION}: load it with the version that wrote it"
        )
    with _at("", {"gravity"}):
        scene = _core.Scene(gravity=top.get("gravity", [0.0, 0.0, -9.81]))
    settings = _build_settings(top.get("build", {}))
    _bodies(scene, top.get("bodies", []), r)
    _joints(scene, top.get("joints", []), r)
    _particles(scene, top.get("particles", []), r)
    scene.build_settings = settings
    return scene
