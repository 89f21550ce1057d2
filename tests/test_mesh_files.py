"""Mesh files through trimesh: a box written by trimesh reads back with mass
ρ·V and the analytic box inertia; multi-mesh files are flattened with their
transforms; open, flat and broken meshes are refused with the file named and
what to do; CoACD splits a non-convex mesh into convex parts; a scene file may
reference a mesh file relative to itself."""
from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

import rigidrs as rr

trimesh = pytest.importorskip("trimesh", reason="the io extra (trimesh) is not installed: pip install '.[test]'")

EXTENTS = np.array([0.3, 0.5, 0.7])  # file units (mm below)
RHO = 1200.0


def box_file(folder: Path, suffix: str, extents: np.ndarray = EXTENTS) -> Path:
    path = folder / f"box{suffix}"
    trimesh.creation.box(extents=extents).export(path)
    return path


def box_inertia(mass: float, e: np.ndarray) -> np.ndarray:
    return mass / 12.0 * np.array([e[1] ** 2 + e[2] ** 2, e[0] ** 2 + e[2] ** 2, e[0] ** 2 + e[1] ** 2])


@pytest.mark.parametrize("suffix", [".stl", ".obj", ".ply", ".glb"])
def test_a_box_file_has_the_box_mass_and_inertia(suffix: str, tmp_path: Path) -> None:
    scale = 0.001 if suffix == ".stl" else 1.0
    path = box_file(tmp_path, suffix, EXTENTS / scale)
    scene = rr.Scene(gravity=(0, 0, 0))
    scene.add_body(rr.TriMesh.from_file(path, scale=scale), density=RHO)
    scene.add_body(rr.ConvexHull.from_file(path, scale=scale), density=RHO)
    world = scene.build(dt=0.01)
    mass = RHO * float(np.prod(EXTENTS))
    # Volume by the divergence theorem over 12 triangles of float32-stored corners
    # (STL/GLB keep float32: 0.3 is off by ~1e-8 relative), so 1e-7, not round-off.
    np.testing.assert_allclose(world.bodies.mass, [mass, mass], rtol=1e-7)
    expected = np.sort(box_inertia(mass, EXTENTS))
    for b in range(2):
        np.testing.assert_allclose(np.sort(world.bodies.inertia[b]), expected, rtol=1e-6)
    # And trimesh's own mass properties of the same file agree.
    mesh = trimesh.load(path, force="mesh")
    mesh.apply_scale(scale)
    mesh.density = RHO
    np.testing.assert_allclose(world.bodies.mass[0], mesh.mass, rtol=1e-12)
    np.testing.assert_allclose(np.sort(world.bodies.inertia[0]), np.sort(np.diag(mesh.moment_inertia)), rtol=1e-9)


def test_a_multi_mesh_gltf_is_flattened_with_its_transforms(tmp_path: Path) -> None:
    a = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    b = trimesh.creation.box(extents=(0.1, 0.1, 0.4))
    doc = trimesh.Scene()
    doc.add_geometry(a, node_name="a", transform=trimesh.transformations.translation_matrix((1.0, 0, 0)))
    doc.add_geometry(b, node_name="b", transform=trimesh.transformations.translation_matrix((-1.0, 0, 0)))
    path = tmp_path / "two.glb"
    doc.export(path)
    v, t = rr.io.load_mesh(path)
    assert len(t) == 24
    np.testing.assert_allclose(v.min(axis=0), [-1.05, -0.1, -0.2], atol=1e-7)  # float32 in the file
    np.testing.assert_allclose(v.max(axis=0), [1.1, 0.1, 0.2], atol=1e-7)
    scene = rr.Scene()
    scene.add_body(rr.TriMesh.from_file(path), density=1.0)
    np.testing.assert_allclose(scene.build(dt=0.01).bodies.mass, [0.008 + 0.004], rtol=1e-6)


def open_box(tmp_path: Path) -> Path:
    mesh = trimesh.creation.box(extents=(0.2, 0.3, 0.4))
    keep = mesh.face_normals[:, 0] > -0.5  # the -x side's two triangles go: a square hole
    path = tmp_path / "open.stl"
    trimesh.Trimesh(mesh.vertices, mesh.faces[keep], process=False).export(path)
    return path


def test_an_open_mesh_on_a_dynamic_body_says_what_to_do(tmp_path: Path) -> None:
    path = open_box(tmp_path)
    scene = rr.Scene()
    shape = rr.TriMesh.from_file(path)
    scene.add_body(shape, fixed=True)  # a fixed body may be open (terrain, walls)
    with pytest.raises(rr.ShapeError) as info:
        scene.add_body(shape, density=1.0)
    for advice in ("fix=True", "ConvexHull.from_file", "Compound.from_file", "mass= with inertia="):
        assert advice in str(info.value)
    # fix=True fills the hole: the mass is the whole box's.
    fixed = rr.Scene()
    fixed.add_body(rr.TriMesh.from_file(path, fix=True), density=1.0)
    np.testing.assert_allclose(fixed.build(dt=0.01).bodies.mass, [0.2 * 0.3 * 0.4], rtol=1e-6)


def test_flat_missing_and_broken_files_are_named(tmp_path: Path) -> None:
    flat = tmp_path / "flat.obj"
    trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]]).export(flat)
    with pytest.raises(rr.ShapeError, match=r"flat\.obj: .*volume"):
        rr.ConvexHull.from_file(flat)
    scene = rr.Scene()
    with pytest.raises(rr.ShapeError, match="TriMesh"):
        scene.add_body(rr.TriMesh.from_file(flat), density=1.0)
    assert len(scene) == 0
    with pytest.raises(FileNotFoundError, match="nothere.stl"):
        rr.TriMesh.from_file(tmp_path / "nothere.stl")
    garbage = tmp_path / "garbage.ply"
    garbage.write_bytes(b"ply\nformat nonsense\n\x00\x01")
    with pytest.raises(ValueError, match=r"garbage\.ply"):
        rr.TriMesh.from_file(garbage)
    with pytest.raises(ValueError, match=r"unknown mesh file extension '\.dxf'; supported: \.stl, \.obj"):
        (tmp_path / "x.dxf").write_text("0\nSECTION\n")
        rr.TriMesh.from_file(tmp_path / "x.dxf")
    with pytest.raises(ValueError, match="scale must be positive"):
        rr.TriMesh.from_file(box_file(tmp_path, ".stl"), scale=-1.0)


def l_shape(tmp_path: Path) -> tuple[Path, float]:
    """An L-shaped prism (outline in x-z, 0.2 thick in y), written by trimesh."""
    outline = [(0, 0), (1, 0), (1, 0.2), (0.2, 0.2), (0.2, 1), (0, 1)]
    v = [(x, y, z) for y in (-0.1, 0.1) for x, z in outline]
    caps = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]
    faces = [c for c in caps] + [(a + 6, c + 6, b + 6) for a, b, c in caps]
    for i in range(6):
        j = (i + 1) % 6
        faces += [(i, i + 6, j), (j, i + 6, j + 6)]
    mesh = trimesh.Trimesh(v, faces)
    trimesh.repair.fix_normals(mesh)
    assert mesh.is_watertight and mesh.volume > 0
    path = tmp_path / "l.obj"
    mesh.export(path)
    return path, (1.0 * 0.2 + 0.2 * 0.8) * 0.2


def test_coacd_splits_a_non_convex_mesh_into_convex_parts(tmp_path: Path) -> None:
    pytest.importorskip("coacd", reason="coacd has no wheel for this platform")
    path, volume = l_shape(tmp_path)
    parts = rr.Compound.from_file(path, threshold=0.05)
    hull = rr.Compound.from_file(path, decompose="hull")
    assert len(_parts(parts)) >= 2 and len(_parts(hull)) == 1
    # The convex hull of the L fills its notch (half of its 1 x 1 bounding square
    # minus the L's own area: 0.5 - 0.02 - 0.02 = 0.32 of area more than 0.36);
    # the parts do not: their volume is the L's (measured 2 parts, +6.8e-4: CoACD's
    # parts overlap slightly along the cut; 5e-3 leaves room for its versions).
    np.testing.assert_allclose(hull.volume(), (0.36 + 0.32) * 0.2, rtol=1e-9)
    assert abs(parts.volume() - volume) < 5e-3 * volume


def _parts(shape: rr.Shape) -> list[object]:
    scene = rr.Scene()
    scene.add_body(shape, fixed=True)
    d = scene.shapes()[0]
    assert d is not None
    return list(d["parts"])


def test_a_scene_file_references_a_mesh_file_relative_to_itself(tmp_path: Path) -> None:
    folder = tmp_path / "model"
    folder.mkdir()
    box_file(folder, ".stl", EXTENTS * 1000.0)
    (folder / "scene.toml").write_text(
        'schema_version = 1\n\n[[bodies]]\ndensity = 1200.0\nshape = {kind = "TriMesh", file = "box.stl", scale = 0.001}\n'
        '\n[[bodies]]\nmass = 2.0\nshape = {kind = "ConvexHull", file = "box.stl", scale = 0.001}\n'
    )
    scene = rr.load_scene(folder / "scene.toml")
    world = scene.build(dt=0.01)
    np.testing.assert_allclose(world.bodies.mass, [RHO * np.prod(EXTENTS), 2.0], rtol=1e-7)
    # Saved, the mesh is written inline: the copy stands alone and is the same scene.
    scene.save(tmp_path / "inline.json")
    assert pickle.dumps(rr.load_scene(tmp_path / "inline.json")) == pickle.dumps(scene)
    (folder / "box.stl").unlink()
    with pytest.raises(FileNotFoundError, match="box.stl"):
        rr.load_scene(folder / "scene.toml")


def test_without_trimesh_the_error_names_the_extra(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import sys

    path = box_file(tmp_path, ".stl")
    monkeypatch.setitem(sys.modules, "trimesh", None)  # as if not installed
    with pytest.raises(ImportError, match=r"pip install 'rigidrs\[io\]'"):
        rr.TriMesh.from_file(path)
    # Scene files need only the core.
    scene = rr.Scene()
    scene.add_body(rr.Sphere(0.1), mass=1.0)
    scene.save(tmp_path / "s.json")
    assert len(rr.load_scene(tmp_path / "s.json")) == 1


def test_a_textured_obj_with_split_corners_reads_closed(tmp_path: Path) -> None:
    """OBJ corners split by per-face normals and texture coordinates are merged by
    position: the box is closed and carries its mass."""
    box = trimesh.creation.box(extents=(0.2, 0.4, 0.6))
    corners = box.vertices[box.faces].reshape(-1, 3).tolist()
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in corners]
    lines += [f"vt {k % 2} {k // 2 % 2}" for k in range(len(corners))]
    lines += [f"vn {x!r} {y!r} {z!r}" for x, y, z in box.face_normals.tolist()]
    lines += [f"f {3 * f + 1}/{3 * f + 1}/{f + 1} {3 * f + 2}/{3 * f + 2}/{f + 1} {3 * f + 3}/{3 * f + 3}/{f + 1}"
              for f in range(len(box.faces))]
    path = tmp_path / "split.obj"
    path.write_text("\n".join(lines) + "\n")
    scene = rr.Scene()
    scene.add_body(rr.TriMesh.from_file(path), density=1000.0)
    np.testing.assert_allclose(scene.build(dt=0.01).bodies.mass, [1000.0 * 0.2 * 0.4 * 0.6], rtol=1e-12)
