"""rr.render: pictures of known scenes checked on pixel statistics computed from the
geometry (no stored images), animations with the right frame count, clean failures."""
from __future__ import annotations

import os
import zlib
from pathlib import Path

import numpy as np
import pytest

import rigidrs as rr
from rigidrs.view.render import SKY_HORIZON, SKY_TOP, Camera, write_png


def read_png(path: Path) -> np.ndarray:
    """Decodes the PNGs rr.render writes (8-bit RGB, filter 0), independently of it."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, size = 8, b"", None
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], "big")
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        assert zlib.crc32(kind + body) == int.from_bytes(data[pos + 8 + n:pos + 12 + n], "big")
        if kind == b"IHDR":
            size = (int.from_bytes(body[4:8], "big"), int.from_bytes(body[0:4], "big"))
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    assert size is not None
    rows = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(size[0], -1)
    assert (rows[:, 0] == 0).all()
    return rows[:, 1:].reshape(size[0], size[1], 3)


def red_box_scene() -> rr.Scene:
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True)
    s.add_body(rr.Box((0.5, 0.5, 0.5)), density=1000.0, position=(0, 0, 0.5))
    return s


def test_png_has_the_size_and_shows_the_scene(tmp_path: Path) -> None:
    path = tmp_path / "box.png"
    out = rr.render(red_box_scene(), path=path, size=(320, 240), colors={1: (1.0, 0.0, 0.0)})
    assert out == path and os.listdir(tmp_path) == ["box.png"]
    img = read_png(path).astype(int)
    assert img.shape == (240, 320, 3)
    centre = img[110:130, 150:170]
    # Lambert-shaded pure red: red channel lit, green and blue zero (fog is slight there).
    assert (centre[..., 0] > 80).all() and (centre[..., 1] < 40).all() and (centre[..., 2] < 40).all()
    # The default camera looks 25° down with a 40° field of view: the top rows are the far
    # ground faded into the horizon colour by the fog, bluish, no red.
    horizon = np.round(SKY_HORIZON * 255).astype(int)
    for corner in (img[0, 0], img[0, -1]):
        assert np.abs(corner - horizon).max() <= 12 and corner[2] > corner[0]
    # The bottom rows are near ground: grey (r = g = b), not sky.
    assert np.ptp(img[-1], axis=1).max() <= 2 and np.abs(img[-1, 0] - horizon).max() > 30
    # Looking up, the top corners are the sky itself.
    up = rr.render(red_box_scene(), size=(320, 240), camera=Camera(eye=(6, 0, 1), target=(0, 0, 3))).astype(int)
    top = np.round(SKY_TOP * 255).astype(int)
    assert np.abs(up[0, 0] - top).max() <= 20 and np.abs(up[0, -1] - top).max() <= 20


def test_coverage_of_a_ball_matches_its_projected_disc() -> None:
    """A ball of radius r at distance D seen by a camera with focal length f covers a disc
    of radius f·r/√(D² − r²) pixels."""
    s = rr.Scene()
    s.add_body(rr.Sphere(1.0), fixed=True)
    d, fov, width, height = 6.0, 40.0, 400, 300
    cam = Camera(eye=(d, 0.0, 0.0), target=(0.0, 0.0, 0.0), fov=fov)
    img = rr.render(s, size=(width, height), camera=cam, colors=(255, 0, 0), fog=False, detail=3).astype(int)
    red = (img[..., 0] > 60) & (img[..., 1] < 30)
    focal = 0.5 * height / np.tan(np.radians(fov) / 2)
    radius = focal * 1.0 / np.sqrt(d * d - 1.0)
    assert red.sum() == pytest.approx(np.pi * radius**2, rel=0.03)
    ys, xs = np.nonzero(red)
    assert xs.mean() == pytest.approx(width / 2, abs=0.5) and ys.mean() == pytest.approx(height / 2, abs=0.5)
    # The lit side (light from the upper left, behind the camera) is brighter.
    left, right = img[ys.min():ys.max(), : width // 2, 0], img[ys.min():ys.max(), width // 2:, 0]
    assert left[left > 60].mean() > right[right > 60].mean()


def test_a_nearer_body_hides_a_farther_one() -> None:
    s = rr.Scene()
    s.add_body(rr.Box((0.5, 0.5, 0.5)), fixed=True, position=(0, 0, 0))
    s.add_body(rr.Box((1.0, 1.0, 1.0)), fixed=True, position=(-3, 0, 0))
    cam = Camera(eye=(5.0, 0.0, 0.0), target=(0.0, 0.0, 0.0), fov=40.0)
    img = rr.render(s, size=(200, 200), camera=cam, colors=[(0, 0, 255), (0, 255, 0)], fog=False).astype(int)
    assert img[100, 100, 2] > 60 and img[100, 100, 1] == 0  # the small near box, in front
    assert (img[..., 1] > 60).any()  # the big far one shows around it


def test_shadow_falls_on_the_ground() -> None:
    s = red_box_scene()
    s.add_body(rr.Sphere(0.3), fixed=True, position=(0, 0, 2.0))
    lit = rr.render(s, size=(160, 120), shadows=False).astype(int)
    shaded = rr.render(s, size=(160, 120), shadows=True).astype(int)
    darker = (shaded.sum(-1) < lit.sum(-1) - 30)
    assert darker.sum() > 50 and (shaded.sum(-1) <= lit.sum(-1)).all()


def test_recording_gif_mp4_and_png_series(tmp_path: Path) -> None:
    iio = pytest.importorskip("imageio.v3")
    s = rr.Scene(gravity=(0, 0, 0))  # spinning freely: every frame differs (GIF merges equal ones)
    s.add_body(rr.Box((0.5, 0.3, 0.1)), density=1000.0, angular_velocity=(0.5, 1.0, 3.0))
    w = s.build(dt=1 / 60)
    rec = w.record(every=2)
    w.step(60)  # 31 frames over 1 s
    gif = rr.render(w, rec, tmp_path / "spin.gif", size=(64, 48), fps=10)
    frames = iio.imread(gif, index=None)
    assert frames.shape == (11, 48, 64, 3)
    assert not np.array_equal(frames[0], frames[5])  # the box turns
    rr.render(w, rec, tmp_path / "f{:03d}.png", size=(32, 24))
    assert len(list(tmp_path.glob("f*.png"))) == 31 and read_png(tmp_path / "f030.png").shape == (24, 32, 3)
    pytest.importorskip("imageio_ffmpeg")
    mp4 = rr.render(w, rec, tmp_path / "spin.mp4", size=(64, 48), fps=30)
    import imageio.v2 as iio2

    reader = iio2.get_reader(mp4)
    assert reader.count_frames() == 31 and reader.get_meta_data()["size"] == (64, 48)
    reader.close()
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []


def test_bad_paths_formats_and_recordings(tmp_path: Path) -> None:
    w = red_box_scene().build(dt=1 / 60)
    with pytest.raises(FileNotFoundError, match="does not exist"):
        rr.render(w, tmp_path / "missing" / "x.png")
    with pytest.raises(ValueError, match="unknown format"):
        rr.render(w, tmp_path / "x.bmp")
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if not os.access(locked, os.W_OK):  # root writes anyway
            with pytest.raises(PermissionError):
                rr.render(w, locked / "x.png")
    finally:
        locked.chmod(0o700)
    assert os.listdir(locked) == []
    other = rr.Scene()
    other.add_body(rr.Sphere(0.1), density=1.0)
    rec = other.build(dt=0.01).record()
    with pytest.raises(ValueError, match="does not match"):
        rr.render(w, rec, tmp_path / "x.png")
    # A failing write leaves no temporary file.
    with pytest.raises(ValueError):
        write_png(tmp_path / "bad.png", np.zeros((4, 4)))
    assert sorted(os.listdir(tmp_path)) == ["locked"]


def test_particles_are_drawn() -> None:
    s = rr.Scene()
    s.add_cloth((-0.5, -0.5, 0.0), (1.0, 0, 0), (0, 1.0, 0), (5, 5), mass=0.1)
    cam = Camera(eye=(0.0, 0.0, 3.0), target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov=40.0)
    img = rr.render(s, size=(100, 100), camera=cam, fog=False)
    assert (img.astype(int).sum(-1) > 3 * 200).sum() > 20  # white-ish particles over the sky


def test_every_kind_of_shape_shows_in_its_colour() -> None:
    """Each body gets its own pure colour; each colour must cover pixels, and a
    two-sided TriMesh (a square sheet) shows from above and from below."""
    s = rr.Scene()
    hull = rr.ConvexHull(np.array([[0, 0, 0], [0.4, 0, 0], [0, 0.4, 0], [0, 0, 0.4], [0.3, 0.3, 0.3]]))
    kinds = [rr.Sphere(0.2), rr.Box((0.2, 0.15, 0.1)), rr.Capsule(0.1, 0.15), rr.Cylinder(0.15, 0.15),
             rr.Cone(0.2, 0.2), hull, rr.Compound([(rr.Sphere(0.1), (0, 0, 0)), (rr.Box((0.1, 0.1, 0.1)), (0.2, 0, 0))])]
    for k, shape in enumerate(kinds):
        s.add_body(shape, fixed=True, position=(0.8 * k - 2.4, 0.0, 0.0))
    sheet = rr.TriMesh(np.array([[-3, -1, -0.5], [3, -1, -0.5], [3, 1, -0.5], [-3, 1, -0.5]]),
                       np.array([[0, 1, 2], [0, 2, 3]]))
    s.add_body(sheet, fixed=True)
    palette = np.array([(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 0), (255, 0, 255), (0, 255, 255),
                        (255, 128, 0), (128, 0, 255)], dtype=float)
    for eye in ((0.0, -4.0, 3.0), (0.0, -4.0, -3.0)):
        img = rr.render(s, size=(480, 240), camera=Camera(eye=eye, target=(0, 0, 0), fov=60), colors=palette,
                        fog=False, shadows=False).astype(float)
        # Shading scales a colour: its direction (normalised RGB) identifies the body.
        unit = img / np.maximum(np.linalg.norm(img, axis=-1, keepdims=True), 1)
        ref = palette / np.linalg.norm(palette, axis=1, keepdims=True)
        # From below, the sheet hides the bodies above it.
        for k in range(len(kinds) + 1) if eye[2] > 0 else [len(kinds)]:
            match = (unit @ ref[k] > 0.995) & (img.max(-1) > 40)
            assert match.sum() > 30, (eye, k)


def test_a_writer_failing_midway_leaves_no_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    iio = pytest.importorskip("imageio.v2")

    def broken(path: str, frames: object, **kwargs: object) -> None:
        Path(path).write_bytes(b"GIF89a partial")
        raise OSError("disk full")

    monkeypatch.setattr(iio, "mimsave", broken)
    w = red_box_scene().build(dt=1 / 60)
    rec = w.record()
    w.step(3)
    with pytest.raises(OSError, match="disk full"):
        rr.render(w, rec, tmp_path / "x.gif", size=(32, 24))
    assert os.listdir(tmp_path) == []
