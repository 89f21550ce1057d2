"""rr.view: the browser viewer started headless on a free port. Checks the scene it
serves (one mesh per shape, posed at the recording's frames, the live world's state
after steps), that the page answers over HTTP, and clean failures. No display, no
browser: the page is drawn by whatever browser connects."""
from __future__ import annotations

import urllib.request

import numpy as np
import pytest

import rigidrs as rr
from rigidrs.view.mesh import shape_mesh

pytest.importorskip("viser")  # in the test extra; skipped only where it cannot be installed


def scene() -> rr.Scene:
    s = rr.Scene(gravity=(0.0, 0.0, -9.81))
    s.add_body(rr.Plane(), fixed=True)
    s.add_body(rr.Box((0.2, 0.3, 0.1)), density=500.0, position=(0, 0, 3), angular_velocity=(1, 2, 0.5), name="box")
    s.add_body(rr.Sphere(0.15), density=500.0, position=(0.6, 0, 2), linear_velocity=(1, 0, 0))
    s.add_body(rr.Capsule(0.1, 0.2), density=500.0, position=(-0.6, 0, 2.5), angular_velocity=(0, 3, 0))
    return s


def wxyz(q: np.ndarray) -> np.ndarray:
    return q[..., [3, 0, 1, 2]]


def test_recording_frames_posed_exactly_and_page_served() -> None:
    world = scene().build(dt=1 / 120)
    rec = world.record(every=3)
    world.step(60)  # 0.5 s of free fall: every body moves between frames
    v = rr.view(world, rec, port=0, block=False, playing=False)
    try:
        assert v.port > 0
        with urllib.request.urlopen(f"http://127.0.0.1:{v.port}/", timeout=10) as r:
            assert r.status == 200 and b"<html" in r.read(4096).lower()
        shapes = world.shapes()
        assert len(v.meshes) == len(shapes)
        assert sum(h is not None for h in v.meshes) == sum(d is not None for d in shapes) == 4
        for k in (len(rec) - 1, 7, -4):
            v.show(k)
            assert v.frame == k % len(rec)
            # The nodes hold the recording's float64 poses as given (quaternion reordered
            # only), hence 1e-12 rather than a display tolerance.
            for i, h in enumerate(v.meshes):
                np.testing.assert_allclose(h.position, rec.position[k, i], rtol=0, atol=1e-12)
                np.testing.assert_allclose(h.wxyz, wxyz(rec.orientation[k, i]), rtol=0, atol=1e-12)
        # A body's mesh is its shape in the body frame, as the renderer tessellates it.
        for i in (1, 2, 3):
            v_ref, t_ref = shape_mesh(shapes[i], 2)
            assert v.meshes[i].vertices.shape == v_ref.shape
            np.testing.assert_allclose(v.meshes[i].vertices, v_ref, rtol=0, atol=1e-6)  # float32 vertices
        v._select(1)
        assert "box" in v._info.content and f"{world.bodies.mass[1]:.4g} kg" in v._info.content
        with pytest.raises(IndexError, match="out of range"):
            v.show(len(rec))
    finally:
        v.close()
    assert v.server is None


def test_live_world_steps_and_shows_its_state() -> None:
    world = scene().build(dt=1 / 120)
    v = rr.view(world, port=0, block=False, playing=False)
    try:
        v.step(10)
        assert world.steps == 10
        pos, quat = np.array(world.bodies.position), np.array(world.bodies.orientation)
        for i, h in enumerate(v.meshes):
            np.testing.assert_allclose(h.position, pos[i], rtol=0, atol=1e-12)
            np.testing.assert_allclose(h.wxyz, wxyz(quat[i]), rtol=0, atol=1e-12)
        # Free fall from rest along z for the sphere's vertical: z = 2 - g t^2 / 2 up to
        # the integrator's O(dt) offset of the discrete kick (< g dt t = 0.0068 m here).
        t = world.time
        assert abs(h.position[2] - (2.5 - 0.5 * 9.81 * t * t)) < 9.81 * world.dt * t
        with pytest.raises(ValueError, match="recording"):
            v.show(0)
    finally:
        v.close()


def test_recording_alone_and_bad_input() -> None:
    world = scene().build(dt=1 / 120)
    rec = world.record(every=10)
    world.step(20)
    v = rr.view(rec, port=0, block=False, playing=False)
    try:
        assert len(v.meshes) == 4
        v.show(2)
        np.testing.assert_allclose(v.meshes[3].position, rec.position[2, 3], rtol=0, atol=1e-12)
    finally:
        v.close()
    other = rr.Scene()
    other.add_body(rr.Sphere(0.1), mass=1.0)
    with pytest.raises(ValueError, match="does not match the scene: 4 bodies"):
        rr.view(other.build(dt=0.01), rec, port=0, block=False)
    with pytest.raises(TypeError, match="World, Scene or Recording"):
        rr.view("scene.toml", port=0, block=False)
    with pytest.raises(ValueError, match="speed"):
        rr.view(world, port=0, block=False, speed=0.0)
