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


def _chromium() -> str | None:
    import shutil

    return next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)


@pytest.mark.skipif(_chromium() is None, reason="no Chromium on this machine (not pip-installable: apt install chromium)")
def test_headless_chromium_draws_the_scene() -> None:
    """The page in a real browser (headless Chromium, software WebGL): its screenshot shows
    the box in its palette blue and the sphere in its palette yellow."""
    sync = pytest.importorskip("playwright.sync_api", reason="pip install playwright").sync_playwright
    import io
    import time

    imageio = pytest.importorskip("imageio.v2")
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True)
    s.add_body(rr.Box((0.3, 0.3, 0.3)), density=500.0, position=(0, 0, 0.3))  # palette 1: blue
    s.add_body(rr.Sphere(0.3), density=500.0, position=(1.0, 0, 0.3))  # palette 2: yellow
    v = rr.view(s, port=0, block=False, playing=False)
    try:
        with sync() as p:
            browser = p.chromium.launch(executable_path=_chromium(),
                                        args=["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-sandbox"])
            page = browser.new_page(viewport={"width": 640, "height": 480})
            page.goto(v.url)
            blue = yellow = 0
            deadline = time.monotonic() + 30.0
            while time.monotonic() < deadline:  # until three.js has drawn the meshes
                img = imageio.imread(io.BytesIO(page.screenshot())).astype(int)[..., :3]
                r, g, b = img[..., 0], img[..., 1], img[..., 2]
                # Shaded palette blue (0.25, 0.55, 0.85) and yellow (0.95, 0.70, 0.20): the
                # hue survives any shading; grey ground, white panel and sky do not pass.
                blue = int(((b > r + 60) & (b > g + 20)).sum())
                yellow = int(((r > b + 80) & (g > b + 60)).sum())
                if blue > 1500 and yellow > 1500:
                    break
                page.wait_for_timeout(500)
            browser.close()
        # Each body of 0.6 m, seen from the default camera, covers ~60 x 60 pixels.
        assert blue > 1500 and yellow > 1500, (blue, yellow)
    finally:
        v.close()
