"""rr.export_usd read back with USD's own library (pxr, from usd-core): stage metadata,
the poses at every sampled time code equal to the recording (double precision, so
1e-12), USD's own composition of the ops equal to the rotation matrix, its
interpolation between samples, meshes in the body frame, clean failures."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rigidrs as rr
from rigidrs.view.mesh import quat_matrix, shape_mesh

pxr = pytest.importorskip("pxr")  # in the test extra; skipped only where usd-core cannot be installed
from pxr import Usd, UsdGeom  # noqa: E402


def scene() -> rr.Scene:
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True, name="ground")
    s.add_body(rr.Box((0.2, 0.3, 0.1)), density=500.0, position=(0, 0, 1), angular_velocity=(1, 2, 0.5), name="box")
    s.add_body(rr.Sphere(0.15), density=500.0, position=(0.6, 0, 0.5), linear_velocity=(1, 0, 0),
               name="cone_1")
    # Two names that become the same identifier: the second gets its index appended.
    s.add_body(rr.Cone(0.2, 0.3), density=500.0, position=(-0.6, 0, 1.5), angular_velocity=(0, 3, 0), name="cone 1")
    return s


def bodies(stage: Usd.Stage) -> dict[int, Usd.Prim]:
    """Body prims by their ``rigidrs:body`` index."""
    out = {}
    for prim in stage.Traverse():
        attr = prim.GetAttribute("rigidrs:body")
        if attr:
            out[attr.Get()] = prim
    return out


@pytest.mark.parametrize("suffix", [".usd", ".usda"])
def test_poses_at_every_sample_equal_the_recording(tmp_path: Path, suffix: str) -> None:
    dt, every = 1 / 120, 3
    world = scene().build(dt=dt)
    rec = world.record(every=every)
    world.step(90)
    path = rr.export_usd(world, rec, tmp_path / f"run{suffix}")
    stage = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z and UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    tcps = stage.GetTimeCodesPerSecond()
    assert tcps == pytest.approx(1 / (dt * every), rel=1e-9)  # 40 frames per second
    assert stage.GetEndTimeCode() == pytest.approx(rec.times[-1] * tcps, rel=1e-12)
    prims = bodies(stage)
    assert sorted(prims) == [0, 1, 2, 3]
    assert [prims[i].GetName() for i in range(4)] == ["ground", "box", "cone_1", "cone_1_3"]
    assert prims[3].GetDisplayName() == "cone 1"
    shapes = world.shapes()
    for i, prim in prims.items():
        xf = UsdGeom.Xformable(prim)
        translate, orient = xf.GetOrderedXformOps()
        samples = translate.GetTimeSamples() if i else [float(k) for k in range(len(rec))]
        # Whole frames apart: the codes are 0, 1, 2, ... (rec.times × rate, snapped).
        np.testing.assert_allclose(samples, rec.times * tcps, rtol=0, atol=1e-9)
        assert samples == [float(k) for k in range(len(rec))]
        for k in range(len(rec)):
            code = Usd.TimeCode(samples[k])
            p, q = np.array(translate.Get(code)), orient.Get(code)
            np.testing.assert_allclose(p, rec.position[k, i], rtol=0, atol=1e-12)
            np.testing.assert_allclose([*q.GetImaginary(), q.GetReal()], rec.orientation[k, i], rtol=0, atol=1e-12)
        # USD composes the ops itself (row vectors: the matrix is [R^T 0; p 1]); its
        # rotation equals ours to rounding of a few products of unit numbers.
        k = len(rec) // 2
        m = np.array(xf.ComputeLocalToWorldTransform(Usd.TimeCode(samples[k])))
        np.testing.assert_allclose(m[:3, :3].T, quat_matrix(rec.orientation[k, i]), rtol=0, atol=1e-12)
        np.testing.assert_allclose(m[3, :3], rec.position[k, i], rtol=0, atol=1e-12)
        # Halfway between two samples USD interpolates the translation linearly.
        mid = Usd.TimeCode(k + 0.5)
        np.testing.assert_allclose(translate.Get(mid), (rec.position[k, i] + rec.position[k + 1, i]) / 2,
                                   rtol=0, atol=1e-12)
        mesh = UsdGeom.Mesh(stage.GetPrimAtPath(prim.GetPath().AppendChild("shape")))
        points = np.array(mesh.GetPointsAttr().Get())
        if i == 0:  # the ground: a square of ground on z = 0 (float32 points)
            np.testing.assert_allclose(points[:, 2], 0.0, atol=1e-7)
            continue
        v, t = shape_mesh(shapes[i], 2)
        np.testing.assert_allclose(points, v, rtol=0, atol=1e-6)  # float32 of lengths < 1 m
        np.testing.assert_array_equal(np.array(mesh.GetFaceVertexIndicesAttr().Get()), t.reshape(-1))
    assert len(translate.GetTimeSamples()) == len(rec)
    ground = UsdGeom.Xformable(prims[0]).GetOrderedXformOps()[0]
    assert ground.GetNumTimeSamples() == 0  # fixed: one value, no samples


def test_no_recording_holds_the_current_pose(tmp_path: Path) -> None:
    s = scene()
    path = rr.export_usd(s, tmp_path / "start.usda")
    stage = Usd.Stage.Open(str(path))
    box = UsdGeom.Xformable(bodies(stage)[1])
    translate, _ = box.GetOrderedXformOps()
    assert translate.GetNumTimeSamples() == 0
    np.testing.assert_allclose(translate.Get(), s.build(dt=0.01).bodies.position[1], rtol=0, atol=1e-12)


def test_bad_input_leaves_no_file(tmp_path: Path) -> None:
    world = scene().build(dt=1 / 120)
    rec = world.record()
    world.step(2)
    with pytest.raises(ValueError, match="unknown format '.obj'"):
        rr.export_usd(world, rec, tmp_path / "run.obj")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        rr.export_usd(world, rec, tmp_path / "missing" / "run.usd")
    other = rr.Scene()
    other.add_body(rr.Sphere(0.1), mass=1.0)
    with pytest.raises(ValueError, match="does not match the scene"):
        rr.export_usd(other.build(dt=0.01), rec, tmp_path / "run.usd")
    assert list(tmp_path.iterdir()) == []


def test_particles_are_time_sampled_points(tmp_path: Path) -> None:
    s = rr.Scene()
    for i in range(4):
        s.add_particle((0.1 * i, 0, 1), mass=0.1, velocity=(0, 0, 1))
    world = s.build(dt=1 / 100)
    rec = world.record(every=5)
    world.step(20)
    stage = Usd.Stage.Open(str(rr.export_usd(world, rec, tmp_path / "p.usda")))
    points = UsdGeom.Points(stage.GetPrimAtPath("/World/particles"))
    assert points.GetPointsAttr().GetTimeSamples() == [0.0, 1.0, 2.0, 3.0, 4.0]  # 20 frames/s
    for k in range(len(rec)):
        got = np.array(points.GetPointsAttr().Get(float(k)))
        np.testing.assert_allclose(got, rec.particle_position[k], rtol=0, atol=1e-6)  # float32 points of ~1 m
    # No collision radius: drawn 1 % of the scene's size wide, the scene being the box
    # around the particles over the whole recording.
    span = np.ptp(rec.particle_position.reshape(-1, 3), axis=0).max()
    np.testing.assert_allclose(points.GetWidthsAttr().Get(), 2 * max(0.005 * span, 1e-3), rtol=1e-6)
