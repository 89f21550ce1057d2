"""rr.export_gltf: files read back by independent readers (pygltflib for the document and
its accessors, trimesh for the scene graph and geometry, scipy for the root rotation),
checked against the recording and the shapes' dimensions; clean failures."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import rigidrs as rr

pygltflib = pytest.importorskip("pygltflib", reason="install the test extra: pip install '.[test]'")
trimesh = pytest.importorskip("trimesh", reason="install the test extra: pip install '.[test]'")
Rotation = pytest.importorskip("scipy.spatial.transform").Rotation

HALF = (0.1, 0.2, 0.3)
TYPES = {5126: np.float32, 5125: np.uint32, 5123: np.uint16}
WIDTH = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}


def scene() -> rr.Scene:
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True, name="ground")
    s.add_body(rr.Box(HALF), density=500.0, position=(0.1, 0.2, 1.0), angular_velocity=(1, 2, 0), name="box")
    s.add_body(rr.Sphere(0.15), density=500.0, position=(0.6, -0.3, 0.5), linear_velocity=(1, 0.5, 2))
    s.add_body(rr.Capsule(0.1, 0.2), density=500.0, position=(-0.6, 0, 0.5), angular_velocity=(0, 0, 3))
    return s


def recorded(steps: int = 90, every: int = 3) -> tuple[rr.World, rr.Recording]:
    world = scene().build(dt=1 / 120)
    rec = world.record(every=every)
    world.step(steps)
    return world, rec


def read(g: Any, index: int) -> np.ndarray:
    """An accessor's data, decoded from the GLB's binary chunk or the .gltf's data URI."""
    acc = g.accessors[index]
    view = g.bufferViews[acc.bufferView]
    blob = g.binary_blob()
    if blob is None:  # .gltf: the buffer is a data URI
        blob = g.get_data_from_buffer_uri(g.buffers[view.buffer].uri)
    start = (view.byteOffset or 0) + (acc.byteOffset or 0)
    dtype = TYPES[acc.componentType]
    width = WIDTH[acc.type]
    assert view.byteStride in (None, 0)
    data = np.frombuffer(blob, dtype=dtype, count=acc.count * width, offset=start)
    return data.reshape(acc.count, width) if width > 1 else data


def body_nodes(g: Any) -> list[Any]:
    root = g.nodes[g.scenes[g.scene].nodes[0]]
    return [g.nodes[i] for i in root.children if g.nodes[i].name != "particles"]


def to_y_up(p: np.ndarray) -> np.ndarray:
    """rigidrs z-up (x, y, z) is glTF y-up (x, z, -y)."""
    return np.stack([p[..., 0], p[..., 2], -p[..., 1]], axis=-1)


def test_glb_animation_matches_the_recording(tmp_path: Path) -> None:
    world, rec = recorded()
    path = tmp_path / "run.glb"
    assert rr.export_gltf(world, rec, path) == path
    assert os.listdir(tmp_path) == ["run.glb"]
    data = path.read_bytes()
    assert data[:4] == b"glTF" and int.from_bytes(data[4:8], "little") == 2
    assert int.from_bytes(data[8:12], "little") == len(data)
    g = pygltflib.GLTF2().load(str(path))
    assert g.asset.version == "2.0"
    n = len(world.bodies.position)
    nodes = body_nodes(g)
    assert len(nodes) == n
    assert [x.name for x in nodes[:2]] == ["ground", "box"]
    # The root's rotation takes z-up to y-up: rigidrs's z axis is glTF's y axis.
    root = g.nodes[g.scenes[g.scene].nodes[0]]
    r = Rotation.from_quat(root.rotation)
    assert np.allclose(r.apply([0, 0, 1]), [0, 1, 0], atol=1e-12)
    assert np.allclose(r.apply([0, 1, 0]), [0, 0, -1], atol=1e-12)
    (anim,) = g.animations
    assert len(anim.channels) == 2 * n
    index = {id(x): i for i, x in enumerate(g.nodes)}
    times32 = rec.times.astype(np.float32)
    pos, quat = rec.position, rec.orientation
    for ch in anim.channels:
        sampler = anim.samplers[ch.sampler]
        assert sampler.interpolation == "LINEAR"
        assert np.array_equal(read(g, sampler.input), times32)
        body = [index[id(x)] for x in nodes].index(ch.target.node)
        out = read(g, sampler.output)
        if ch.target.path == "translation":
            assert np.array_equal(out, pos[:, body].astype(np.float32))
            # In the file's (y-up) world: the root rotation applied.
            assert np.allclose(r.apply(out), to_y_up(pos[:, body]), atol=1e-6 * (1 + np.abs(pos).max()))
        else:
            assert ch.target.path == "rotation"
            # Unit quaternions, equal to the recorded ones up to sign, to float32 precision.
            same = np.abs(np.einsum("tk,tk->t", out.astype(float), quat[:, body]))
            assert np.allclose(same, 1.0, atol=1e-6)
            assert np.all(np.einsum("tk,tk->t", out[1:], out[:-1]) >= 0)  # the short way
    # The box moved and spun: its keys are not all equal.
    assert np.ptp(pos[:, 1], axis=0).max() > 0.1


def test_meshes_span_the_shape_dimensions(tmp_path: Path) -> None:
    world = scene().build(dt=1 / 120)
    path = rr.export_gltf(world, tmp_path / "still.glb")
    g = pygltflib.GLTF2().load(str(path))
    assert not g.animations
    nodes = body_nodes(g)
    # The node poses are the world's (no recording).
    for i, node in enumerate(nodes):
        assert np.allclose(node.translation, world.bodies.position[i])
        assert np.allclose(np.abs(np.dot(node.rotation, world.bodies.orientation[i])), 1.0)

    def verts(i: int) -> np.ndarray:
        prim = g.meshes[nodes[i].mesh].primitives[0]
        assert prim.mode == 4 and prim.material is not None
        v = read(g, prim.attributes.POSITION).astype(float)
        acc = g.accessors[prim.attributes.POSITION]
        assert np.allclose(acc.min, v.min(0)) and np.allclose(acc.max, v.max(0))
        idx = read(g, prim.indices)
        assert idx.max() < len(v) and len(idx) % 3 == 0
        return v

    # Box of half extents (a, b, c): in the body frame a box spanning 2a, 2b, 2c (the
    # principal frame may order the axes differently: compare in the world frame too).
    v = verts(1)
    world_v = v @ Rotation.from_quat(world.bodies.orientation[1]).as_matrix().T
    assert np.allclose(np.ptp(world_v, axis=0), 2 * np.array(HALF), atol=1e-6)
    assert np.allclose(world_v.mean(0), 0.0, atol=1e-6)
    # Sphere radius 0.15: every vertex on the sphere, spanning 0.3 along each axis.
    v = verts(2)
    assert np.allclose(np.linalg.norm(v, axis=1), 0.15, atol=1e-6)
    assert np.allclose(np.ptp(v, axis=0), 0.3, atol=1e-6)
    # Capsule radius 0.1, half height 0.2: 0.2 across, 2 (0.2 + 0.1) long.
    v = verts_world(world, 3, verts(3))
    assert np.allclose(np.sort(np.ptp(v, axis=0)), [0.2, 0.2, 0.6], atol=1e-6)
    # Ground: a finite square on z = 0 (all four corners), facing +z.
    v = verts(0)
    assert v.shape == (4, 3) and np.allclose(v[:, 2], 0.0)
    assert np.ptp(v[:, 0]) >= 4.0 and np.ptp(v[:, 1]) >= 4.0
    idx = read(g, g.meshes[nodes[0].mesh].primitives[0].indices).reshape(-1, 3)
    a, b, c = v[idx[:, 0]], v[idx[:, 1]], v[idx[:, 2]]
    assert (np.cross(b - a, c - a)[:, 2] > 0).all()
    # Materials: the ground grey, the others coloured, one per colour.
    colours = [tuple(g.materials[g.meshes[x.mesh].primitives[0].material].pbrMetallicRoughness.baseColorFactor)
               for x in nodes]
    assert len(set(colours)) == 4 and np.ptp(colours[0][:3]) == 0


def verts_world(world: rr.World, i: int, v: np.ndarray) -> np.ndarray:
    return v @ Rotation.from_quat(world.bodies.orientation[i]).as_matrix().T


def test_trimesh_loads_the_scene_in_y_up(tmp_path: Path) -> None:
    world, rec = recorded()
    path = rr.export_gltf(world, rec, tmp_path / "run.glb")
    sc = trimesh.load(path)
    assert isinstance(sc, trimesh.Scene)
    assert len(sc.geometry) == 4
    # trimesh shows the nodes' rest pose (the first frame), through the root rotation.
    for i, name in enumerate(["ground", "box"]):
        transform, geometry = sc.graph[name]
        assert np.allclose(transform[:3, 3], to_y_up(rec.position[0, i]), atol=1e-6)
    # The box stands 2c = 0.6 tall along y (up) at the start (identity orientation).
    transform, geometry = sc.graph["box"]
    box = sc.geometry[geometry].copy()
    box.apply_transform(transform)
    assert np.allclose(box.extents, [2 * HALF[0], 2 * HALF[2], 2 * HALF[1]], atol=1e-6)
    assert box.is_watertight
    # The ground lies at y = 0.
    transform, geometry = sc.graph["ground"]
    ground = sc.geometry[geometry].copy()
    ground.apply_transform(transform)
    assert np.allclose(ground.vertices[:, 1], 0.0, atol=1e-9)
    assert sc.bounds[0, 1] == pytest.approx(0.0, abs=1e-9)


def test_gltf_text_has_the_same_content(tmp_path: Path) -> None:
    world, rec = recorded(steps=30)
    glb = rr.export_gltf(world, rec, tmp_path / "run.glb")
    text = rr.export_gltf(world, rec, tmp_path / "run.gltf")
    a, b = pygltflib.GLTF2().load(str(glb)), pygltflib.GLTF2().load(str(text))
    assert len(a.accessors) == len(b.accessors)
    for i in range(len(a.accessors)):
        assert np.array_equal(read(a, i), read(b, i))
    assert len(trimesh.load(text).geometry) == 4


def test_equal_bodies_share_geometry_and_size(tmp_path: Path) -> None:
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True)
    for i in range(20):
        s.add_body(rr.Box((0.1, 0.1, 0.1)), density=500.0, position=(0.3 * (i % 5), 0.3 * (i // 5), 0.5))
    world = s.build(dt=1 / 60)
    rec = world.record(every=1)
    world.step(60)
    path = rr.export_gltf(world, rec, tmp_path / "boxes.glb")
    g = pygltflib.GLTF2().load(str(path))
    assert len(body_nodes(g)) == 21
    # One cube geometry (8 colours of the palette: 8 meshes) and one ground.
    positions = {p.attributes.POSITION for m in g.meshes for p in m.primitives}
    assert len(positions) == 2 and len(g.meshes) == 9
    # Sampled data: 61 frames × 21 bodies × 7 float32 + times; meshes and JSON are small.
    assert path.stat().st_size < 61 * 21 * 7 * 4 + 61 * 4 + 30_000


def test_particles_are_points_shown_at_their_frame(tmp_path: Path) -> None:
    s = rr.Scene()
    s.add_body(rr.Sphere(0.1), density=500.0, position=(0, 0, 1))
    for k in range(3):
        s.add_particle((0.2 * k, 0.0, 1.0), mass=0.1, radius=0.02)
    world = s.build(dt=1 / 60)
    rec = world.record(every=2)
    world.step(10)
    path = rr.export_gltf(world, rec, tmp_path / "p.glb")
    g = pygltflib.GLTF2().load(str(path))
    root = g.nodes[g.scenes[0].nodes[0]]
    (group,) = [g.nodes[i] for i in root.children if g.nodes[i].name == "particles"]
    frames = len(rec.times)
    assert len(group.children) == frames
    (anim,) = g.animations
    scale_of = {ch.target.node: anim.samplers[ch.sampler] for ch in anim.channels if ch.target.path == "scale"}
    for k, j in enumerate(group.children):
        prim = g.meshes[g.nodes[j].mesh].primitives[0]
        assert prim.mode == 0
        assert np.array_equal(read(g, prim.attributes.POSITION), rec.particle_position[k].astype(np.float32))
        sampler = scale_of[j]
        assert sampler.interpolation == "STEP"
        t, sc = read(g, sampler.input), read(g, sampler.output)
        # STEP: the value of the last key at or before each frame time.
        shown = [sc[np.searchsorted(t, tk, side="right") - 1, 0] for tk in rec.times.astype(np.float32)]
        assert shown == [1.0 if i == k else 0.0 for i in range(frames)]
    assert len(rr.export_gltf(world, rec, tmp_path / "q.glb", particles=False).read_bytes()) < path.stat().st_size


def test_a_scene_exports_its_initial_pose(tmp_path: Path) -> None:
    path = rr.export_gltf(scene(), tmp_path / "scene.glb", colors=(255, 0, 0))
    g = pygltflib.GLTF2().load(str(path))
    nodes = body_nodes(g)
    assert np.allclose(nodes[1].translation, (0.1, 0.2, 1.0))
    assert {tuple(m.pbrMetallicRoughness.baseColorFactor) for m in g.materials} == {(1.0, 0.0, 0.0, 1.0)}


def test_bad_paths_and_recordings_leave_no_file(tmp_path: Path) -> None:
    world, rec = recorded(steps=6)
    with pytest.raises(ValueError, match="unknown format"):
        rr.export_gltf(world, rec, tmp_path / "run.obj")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        rr.export_gltf(world, rec, tmp_path / "missing" / "run.glb")
    other = rr.Scene()
    other.add_body(rr.Sphere(0.1), density=1.0)
    with pytest.raises(ValueError, match="does not match the scene"):
        rr.export_gltf(other.build(dt=0.01), rec, tmp_path / "run.glb")
    with pytest.raises(TypeError, match="Recording"):
        rr.export_gltf(world, np.zeros(3), tmp_path / "run.glb")
    with pytest.raises(TypeError, match="World or Scene"):
        rr.export_gltf(object(), rec, tmp_path / "run.glb")
    with pytest.raises(ValueError, match="colors"):
        rr.export_gltf(world, rec, tmp_path / "run.glb", colors={9: (1, 0, 0)})
    if os.name == "posix" and os.geteuid() != 0:
        locked = tmp_path / "locked"
        locked.mkdir(mode=0o500)
        with pytest.raises(PermissionError, match="not writable"):
            rr.export_gltf(world, rec, locked / "run.glb")
        assert list(locked.iterdir()) == []
    assert [p for p in tmp_path.iterdir() if p.name != "locked"] == []


def test_a_failure_while_writing_leaves_no_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    world, rec = recorded(steps=6)
    path = tmp_path / "run.glb"
    path.write_bytes(b"old")

    def boom(self: Path, data: bytes) -> int:
        raise OSError("disk full")

    monkeypatch.setattr(Path, "write_bytes", boom)
    with pytest.raises(OSError, match="disk full"):
        rr.export_gltf(world, rec, path)
    monkeypatch.undo()
    assert os.listdir(tmp_path) == ["run.glb"] and path.read_bytes() == b"old"


def test_hulls_meshes_compounds_and_shapeless_bodies(tmp_path: Path) -> None:
    cube = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    tet_v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    tet_t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    s = rr.Scene()
    s.add_body(rr.ConvexHull(0.1 * cube + [0.0, 0.0, 0.05]), density=500.0, position=(0, 0, 1))
    s.add_body(rr.TriMesh(tet_v, tet_t), fixed=True, position=(1, 0, 0))
    s.add_body(rr.Compound([(rr.Sphere(0.1), (0.2, 0, 0)), (rr.Box((0.1, 0.1, 0.1)), (-0.2, 0, 0))]),
               density=500.0, position=(0, 1, 1))
    s.add_body(mass=2.0, inertia=(0.1, 0.2, 0.3), position=(0, 0, 3))
    world = s.build(dt=1 / 60)
    rec = world.record()
    world.step(5)
    path = rr.export_gltf(world, rec, tmp_path / "mix.glb", detail=0)
    g = pygltflib.GLTF2().load(str(path))
    nodes = body_nodes(g)
    assert len(nodes) == 4 and nodes[3].mesh is None
    assert len(g.animations[0].channels) == 8
    shapes = world.shapes()
    for i in (0, 1):
        prim = g.meshes[nodes[i].mesh].primitives[0]
        v = read(g, prim.attributes.POSITION).astype(float)
        local = Rotation.from_quat(shapes[i]["orientation"]).apply(shapes[i]["vertices"]) + shapes[i]["position"]
        assert np.allclose(v, local, atol=1e-6)  # as they are, in the body frame
        assert len(read(g, prim.indices)) == 3 * len(shapes[i]["triangles"])
    # The trimesh is double-sided, the hull is not.
    mats = [g.materials[g.meshes[nodes[i].mesh].primitives[0].material] for i in (0, 1)]
    assert not mats[0].doubleSided and mats[1].doubleSided
    # The compound: both parts in one mesh; in the world frame (rest pose, the compound's
    # frame at (0, 1, 1)) the box spans x in [-0.3, -0.1], y and z ±0.1, and the sphere's
    # vertices lie 0.1 from (0.2, 1, 1).
    prim = g.meshes[nodes[2].mesh].primitives[0]
    v = read(g, prim.attributes.POSITION).astype(float)
    w = Rotation.from_quat(rec.orientation[0, 2]).apply(v) + rec.position[0, 2] - (0.0, 1.0, 1.0)
    box, ball = w[w[:, 0] < -0.05], w[w[:, 0] >= -0.05]
    assert len(box) == 8 and len(ball) == 12
    assert np.allclose(box.min(0), [-0.3, -0.1, -0.1], atol=1e-6)
    assert np.allclose(box.max(0), [-0.1, 0.1, 0.1], atol=1e-6)
    assert np.allclose(np.linalg.norm(ball - (0.2, 0, 0), axis=1), 0.1, atol=1e-6)
    sc = trimesh.load(path)
    assert len(sc.geometry) == 3


def test_blender_imports_the_animation(tmp_path: Path) -> None:
    """Blender's own glTF importer (``pip install bpy``, Blender as a module; skipped
    without it): Blender is z-up, so after its y-up conversion the box's vertices at
    each frame are the recording's, in rigidrs coordinates (to float32 precision), and the
    ground lies at z = 0. (Run with bpy 4.2.23 on Python 3.11 while this was written.)"""
    bpy = pytest.importorskip("bpy", reason="Blender as a module: pip install bpy (matching the Python version)")
    world, rec = recorded(steps=60, every=4)  # 30 frames per simulated second
    path = rr.export_gltf(world, rec, tmp_path / "run.glb")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.fps = 30
    assert bpy.ops.import_scene.gltf(filepath=str(path)) == {"FINISHED"}
    objs = {o.name: o for o in bpy.data.objects}
    assert {"ground", "box"} <= set(objs)
    shape = world.shapes()[1]
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * HALF
    local = Rotation.from_quat(shape["orientation"]).apply(corners) + shape["position"]
    box = objs["box"]
    for k in range(len(rec.times)):
        sc.frame_set(k)  # frame k is time k / 30 s
        m = np.array(box.matrix_world)
        got = np.array([tuple(v.co) for v in box.data.vertices]) @ m[:3, :3].T + m[:3, 3]
        want = Rotation.from_quat(rec.orientation[k, 1]).apply(local) + rec.position[k, 1]
        assert np.sqrt(((got[:, None] - want[None]) ** 2).sum(-1)).min(1).max() < 1e-6
    ground = objs["ground"]
    gz = [(ground.matrix_world @ v.co).z for v in ground.data.vertices]
    assert np.allclose(gz, 0.0, atol=2e-6)  # Blender's float32 over corners 4.5 m out


def test_colours_are_stored_linear(tmp_path: Path) -> None:
    """glTF's baseColorFactor is linear RGB; ``colors`` (like the renderer's) are sRGB."""
    path = rr.export_gltf(scene(), tmp_path / "c.glb", colors={1: (0.5, 0.0, 1.0)})
    g = pygltflib.GLTF2().load(str(path))
    box = body_nodes(g)[1]
    factor = g.materials[g.meshes[box.mesh].primitives[0].material].pbrMetallicRoughness.baseColorFactor
    assert factor == pytest.approx([((0.5 + 0.055) / 1.055) ** 2.4, 0.0, 1.0, 1.0], abs=1e-12)
