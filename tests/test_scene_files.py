"""Scene files: ``to_dict``/``from_dict`` and ``save``/``load_scene`` round-trip every
input a scene holds exactly (a rebuilt scene pickles to the same bytes and steps bit
for bit like the original), and bad data is refused with the path inside it, the
file and the line."""
from __future__ import annotations

import copy
import json
import pickle
import re
from pathlib import Path
from typing import Any

import pytest

import rigidrs as rr
from rigidrs.io import schema
from io_scenes import SCENES
from snapshot_scenes import assert_same, state

STEPS = 40


def stepped(scene: rr.Scene, settings: dict[str, Any]) -> dict[str, Any]:
    world = scene.build(**settings)
    world.step(STEPS)
    return state(world)


def walk_kinds(d: dict[str, Any]) -> dict[str, set[str]]:
    """Which shape kinds, joint kinds, drive modes and particle ops the data holds."""
    kinds: dict[str, set[str]] = {"shapes": set(), "joints": set(), "drives": set(), "ops": set(), "mass": set()}

    def shape(s: dict[str, Any]) -> None:
        kinds["shapes"].add(s["kind"])
        for p in s.get("parts", []):
            shape(p["shape"])

    for b in d.get("bodies", []):
        if "shape" in b:
            shape(b["shape"])
        kinds["mass"].update(k for k in ("density", "mass", "inertia", "mass_properties", "fixed", "kinematic") if k in b)
    for j in d.get("joints", []):
        kinds["joints"].add(j["kind"])
        if "drive" in j:
            kinds["drives"].add(j["drive"].get("mode", "position"))
    for c in d.get("particles", []):
        kinds["ops"].add(c["op"])
        if "shape" in c:
            shape(c["shape"])
    return kinds


def test_the_scenes_use_every_kind_of_input() -> None:
    """The round-trip tests below are only as good as what these scenes hold."""
    seen: dict[str, set[str]] = {}
    for make in SCENES.values():
        for k, v in walk_kinds(make()[0].to_dict()).items():
            seen.setdefault(k, set()).update(v)
    assert seen["shapes"] == set(schema.SHAPES)
    assert seen["joints"] == {"spherical", "hinge", "fixed", "prismatic", "distance"}
    assert seen["drives"] == {"position", "velocity"}
    assert seen["ops"] == set(schema.PARTICLE_OPS)
    assert seen["mass"] == {"density", "mass", "inertia", "mass_properties", "fixed", "kinematic"}


@pytest.mark.parametrize("name", SCENES)
def test_dict_round_trip_is_exact_and_steps_bitwise(name: str) -> None:
    scene, settings = SCENES[name]()
    d = scene.to_dict()
    text = json.dumps(d, allow_nan=False)  # strict JSON: no NaN/Infinity tokens
    again = rr.Scene.from_dict(json.loads(text))
    assert again.to_dict() == d
    # The compiled scene (bodies, joints, particle model) and the recipe, to the byte.
    assert pickle.dumps(again) == pickle.dumps(scene)
    assert_same(stepped(again, settings), stepped(scene, settings))


@pytest.mark.parametrize("suffix", [".toml", ".json"])
@pytest.mark.parametrize("name", SCENES)
def test_file_round_trip_keeps_scene_and_build_settings(name: str, suffix: str, tmp_path: Path) -> None:
    scene, settings = SCENES[name]()
    scene.build_settings = settings
    path = tmp_path / f"{name}{suffix}"
    scene.save(path)
    loaded = rr.load_scene(path)
    assert pickle.dumps(loaded) == pickle.dumps(scene)
    assert loaded.build_settings == settings
    assert_same(stepped(loaded, loaded.build_settings), stepped(scene, settings))
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary left behind


def test_round_trip_counts() -> None:
    """Entry by entry, every body, shape, joint and particle-side call comes back as it
    was given (the closing note quotes the totals: 3 scenes, 22 bodies with 24 shapes
    counting compound parts, 8 joints, 29 particle-side calls)."""
    totals = {"bodies": 0, "shapes": 0, "joints": 0, "particles": 0}
    same = dict.fromkeys(totals, 0)
    for make in SCENES.values():
        scene = make()[0]
        before, after = scene._recipe(), rr.Scene.from_dict(scene.to_dict())._recipe()
        for key in ("bodies", "joints", "particles"):
            totals[key] += len(before[key])
            same[key] += sum(x == y for x, y in zip(before[key], after[key], strict=True))
        shapes = [(b["shape"], c["shape"]) for b, c in zip(before["bodies"], after["bodies"]) if b["shape"]]
        totals["shapes"] += sum(1 + len(x.get("parts", [])) for x, _ in shapes)
        same["shapes"] += sum((1 + len(x.get("parts", []))) * (x == y) for x, y in shapes)
    print("round-tripped:", same)
    assert same == totals
    assert totals["bodies"] >= 22 and totals["shapes"] >= 24 and totals["joints"] >= 8 and totals["particles"] >= 29


def test_defaults_are_left_out_and_a_minimal_dict_loads() -> None:
    scene = rr.Scene()
    scene.add_body(rr.Sphere(0.5), density=2.0)
    d = scene.to_dict()
    assert d == {"format": "rigidrs.scene", "schema_version": 1, "gravity": [0.0, 0.0, -9.81],
                 "bodies": [{"shape": {"kind": "Sphere", "radius": 0.5}, "density": 2.0}]}
    minimal = {"schema_version": 1, "bodies": [{"shape": {"kind": "Sphere", "radius": 0.5}, "density": 2.0}]}
    assert pickle.dumps(rr.Scene.from_dict(minimal)) == pickle.dumps(scene)


def test_infinities_are_strings_and_nan_build_settings_are_refused() -> None:
    scene = rr.Scene()
    a = scene.add_body(rr.Sphere(0.1), mass=1.0)
    scene.add_joint("hinge", a, None, drive=rr.Drive("velocity", target=1.0, damping=1.0, max_force=float("inf")))
    scene.build_settings = {"dt": 0.01, "max_rotation_angle": float("inf")}
    d = scene.to_dict()
    assert d["build"]["max_rotation_angle"] == "inf"
    assert rr.Scene.from_dict(d).build_settings["max_rotation_angle"] == float("inf")
    scene.build_settings = {"dt": float("nan")}
    with pytest.raises(rr.RigidError, match=r"build\.dt: NaN cannot be written"):
        scene.to_dict()


def test_the_docs_list_every_key_and_their_example_loads(tmp_path: Path) -> None:
    page = (Path(__file__).resolve().parents[1] / "docs" / "scene_format.md").read_text(encoding="utf-8")
    assert page.endswith(schema.reference_markdown())
    example = re.search(r"```toml\n(.*?)```", page, flags=re.S)
    assert example is not None
    (tmp_path / "example.toml").write_text(example.group(1), encoding="utf-8")
    scene = rr.load_scene(tmp_path / "example.toml")
    assert (len(scene), scene.joint_count) == (2, 1)
    world = scene.build(**scene.build_settings)
    assert world.bodies.names == ["floor", "ball"]


# ------------------------------------------------------------------------- errors


def base() -> dict[str, Any]:
    scene = rr.Scene()
    scene.add_body(rr.Plane(), fixed=True)
    for k in range(4):
        scene.add_body(rr.Box((0.1, 0.1, 0.1)), density=500.0, position=(0, 0, 0.2 + 0.3 * k))
    scene.add_joint("hinge", 1, 2, anchor=(0, 0, 0.35))
    return scene.to_dict()


@pytest.mark.parametrize("change,error,message", [
    (lambda d: d["bodies"][3].update(density=-1), rr.RigidError, "bodies[3].density: must be positive and finite, got -1"),
    (lambda d: d["bodies"][2].update(densty=5.0), rr.RigidError, "bodies[2].densty: unknown key; did you mean 'density'?"),
    (lambda d: d["bodies"][1]["shape"].update(half_extents=[0.1, -0.1, 0.1]), rr.RigidError,
     "bodies[1].shape: Box half_extents.y must be positive and finite, got -0.1"),
    (lambda d: d["bodies"][1]["shape"].update(kind="Blob"), rr.RigidError, "bodies[1].shape.kind: unknown shape kind 'Blob'"),
    (lambda d: d["joints"][0].update(body_b=9), rr.RigidError, "joints[0].body_b: body index 9 is out of range: the scene has 5 bodies"),
    (lambda d: d["joints"][0].pop("kind"), rr.RigidError, "joints[0].kind: missing (required)"),
    (lambda d: d["joints"][0].update(drive={"mode": "torque"}), rr.RigidError, "joints[0].drive: Drive mode: unknown mode"),
    (lambda d: d.update(particles=[{"op": "particle", "position": [0, 0, 1], "mass": -2.0}]), rr.RigidError,
     "particles[0].mass: must be positive"),
    (lambda d: d.update(particles=[{"op": "glue"}]), rr.RigidError, "particles[0].op: unknown or missing op 'glue'"),
    (lambda d: d.update(gravity=[0, 0, float("nan")]), rr.RigidError, "gravity: must be finite"),
    (lambda d: d.update(build={"dt": -1.0}), rr.RigidError, "build"),
    (lambda d: d.update(build={"time_step": 0.1}), rr.RigidError, "build.time_step: unknown build setting"),
    (lambda d: d.update(schema_version=2), rr.RigidError, "schema_version: 2 is not readable"),
    (lambda d: d.update(extra=1), rr.RigidError, "scene.extra: unknown key"),
])
def test_bad_data_names_the_path_and_builds_nothing(change: Any, error: type, message: str) -> None:
    d = base()
    change(d)
    with pytest.raises(error) as info:
        rr.Scene.from_dict(d)
    assert message in str(info.value)


def test_file_errors_name_the_file_and_the_line(tmp_path: Path) -> None:
    scene = rr.Scene.from_dict(base())
    path = tmp_path / "s.toml"
    scene.save(path)
    lines = path.read_text().splitlines()
    starts = [n for n, line in enumerate(lines) if line == "[[bodies]]"]
    at = next(n for n in range(starts[3], len(lines)) if lines[n].startswith("density"))
    lines[at] = "density = -1.0"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(rr.RigidError) as info:
        rr.load_scene(path)
    assert str(info.value).startswith(f"{path}, line {at + 1}: bodies[3].density: must be positive and finite, got -1")

    path.write_text('schema_version = 1\ngravity = [0, 0,\n[[bodies]]\nmass = 1\n')
    with pytest.raises(rr.RigidError, match=r"s\.toml: malformed TOML: .*line 3"):
        rr.load_scene(path)
    bad_json = tmp_path / "s.json"
    bad_json.write_text('{\n  "schema_version": 1,\n  "bodies": [\n    {"mass": 1.0,}\n  ]\n}\n')
    with pytest.raises(rr.RigidError, match=r"s\.json: malformed JSON: .*\(at line 4, column"):
        rr.load_scene(bad_json)
    with pytest.raises(FileNotFoundError):
        rr.load_scene(tmp_path / "missing.toml")
    with pytest.raises(ValueError, match=r"unknown scene file extension '\.yaml'; supported: \.toml, \.json"):
        rr.load_scene(tmp_path / "s.yaml")
    with pytest.raises(ValueError, match=r"supported: \.toml, \.json"):
        scene.save(tmp_path / "s.xml")


def test_a_failed_save_leaves_the_old_file(tmp_path: Path) -> None:
    path = tmp_path / "s.json"
    scene = rr.Scene.from_dict(base())
    scene.save(path)
    before = path.read_bytes()
    scene.build_settings = {"dt": float("nan")}
    with pytest.raises(rr.RigidError):
        scene.save(path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["s.json"]


def test_from_dict_does_not_modify_its_input() -> None:
    d = base()
    kept = copy.deepcopy(d)
    rr.Scene.from_dict(d)
    assert d == kept


def test_nested_errors_point_at_their_line_and_toml_inf_reads(tmp_path: Path) -> None:
    text = (
        "schema_version = 1\n\n[build]\ndt = 0.01\nmax_rotation_angle = inf\n\n"
        '[[bodies]]\nmass = 1.0\nshape = {kind = "Sphere", radius = 0.1}\n\n'
        "[[bodies]]\nmass = 1.0\n\n[bodies.shape]\nkind = \"Box\"\nhalf_extent = [0.1, 0.1, 0.1]\n"
    )
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(rr.RigidError) as info:
        rr.load_scene(path)
    line = text.splitlines().index("half_extent = [0.1, 0.1, 0.1]") + 1
    assert str(info.value) == f"{path}, line {line}: bodies[1].shape.half_extent: unknown key; did you mean 'half_extents'?"
    path.write_text(text.replace("half_extent =", "half_extents ="))
    assert rr.load_scene(path).build_settings == {"dt": 0.01, "max_rotation_angle": float("inf")}


def test_unknown_build_settings_are_refused_when_written() -> None:
    scene = rr.Scene()
    scene.build_settings = {"dt": 0.01, "substep": 4}
    with pytest.raises(rr.RigidError, match=r"build\.substep: unknown build setting; did you mean 'substeps'\?"):
        scene.to_dict()
    scene.build_settings = {"dt": 0.01, "integrator": "leapfrog"}
    with pytest.raises(rr.RigidError, match=r"build\.integrator: unknown name \"leapfrog\"; choose one of euler"):
        scene.to_dict()
    with pytest.raises(TypeError, match=r'build_settings\["dt"\] must be None, a bool, int, float or str, got list'):
        scene.build_settings = {"dt": [0.01]}


def test_normals_and_part_orientations_are_kept_as_given() -> None:
    """A plane's normal and a compound part's orientation are written as given, not
    in the normalised form the shape holds: normalising (0, 0.3, 1.1) twice moves a
    bit, so a scene rebuilt from the normalised values would not be the same."""
    import numpy as np

    def make(normal: Any, q: Any) -> rr.Scene:
        scene = rr.Scene()
        scene.add_body(rr.Plane(normal), fixed=True)
        scene.add_body(rr.Compound([(rr.Box((0.1, 0.1, 0.1)), (0, 0, 0), q)]), density=1.0, position=(0, 0, 1))
        return scene

    given = make((0.0, 0.3, 1.1), (0.0, 0.0, 0.3, 1.1))
    shapes = given.shapes()
    assert shapes[0] is not None and shapes[1] is not None
    normal, q = shapes[0]["normal"], shapes[1]["parts"][0]["orientation"]
    again = make(normal, q).shapes()
    assert again[0] is not None and again[1] is not None
    assert not np.array_equal(again[0]["normal"], normal)
    assert not np.array_equal(again[1]["parts"][0]["orientation"], q)
    d = given.to_dict()
    assert d["bodies"][0]["shape"]["normal"] == [0.0, 0.3, 1.1]
    assert d["bodies"][1]["shape"]["parts"][0]["orientation"] == [0.0, 0.0, 0.3, 1.1]
    assert pickle.dumps(rr.Scene.from_dict(d)) == pickle.dumps(given)
