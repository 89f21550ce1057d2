"""World.record: frames at the steps asked for, equal to the views at those steps,
the trajectory unchanged by recording, save/load exact, and clear errors."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import rigidrs as rr


def scene() -> rr.Scene:
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True, friction=0.5)
    for k in range(4):
        s.add_body(rr.Box((0.2, 0.1, 0.3)), density=500.0, position=(0.5 * k, 0.0, 0.4 + 0.7 * k),
                   angular_velocity=(0.3 * k, 1.0, 0.0), friction=0.5)
    s.add_body(rr.Sphere(0.15), density=1000.0, position=(-1.0, 0.0, 1.0), linear_velocity=(2.0, 0.0, 0.0))
    return s


def cloth() -> rr.Scene:
    s = rr.Scene()
    s.add_body(rr.Plane(), fixed=True)
    s.add_body(rr.Sphere(0.3), fixed=True, position=(0.5, 0.5, 0.3))
    s.add_cloth((0, 0, 1.0), (1.0, 0, 0), (0, 1.0, 0), (6, 6), mass=0.1, compliance=1e-6)
    return s


@pytest.mark.parametrize("every", [1, 3])
def test_frames_equal_the_views_at_those_steps(every: int) -> None:
    rec_world, ref = scene().build(dt=1 / 120), scene().build(dt=1 / 120)
    ref.step(2)
    rec_world.step(2)
    rec = rec_world.record(every=every)
    rec_world.step(7)
    rec_world.step(5)
    steps = list(range(2, 15, every))
    assert rec.steps.tolist() == steps
    n = len(ref.bodies)
    assert len(rec) == len(steps)
    assert rec.times.shape == (len(steps),)
    assert rec.position.shape == (len(steps), n, 3)
    assert rec.orientation.shape == (len(steps), n, 4)
    assert rec.particle_position.shape == (len(steps), 0, 3)
    for k, s in enumerate(steps):
        ref.step(s - ref.steps)
        assert rec.times[k] == ref.time
        assert np.array_equal(rec.position[k], ref.bodies.position)
        assert np.array_equal(rec.orientation[k], ref.bodies.orientation)
    # Recording runs steps one by one: the trajectory is the same bits.
    ref.step(rec_world.steps - ref.steps)
    assert np.array_equal(rec_world.bodies.position, ref.bodies.position)
    assert rec.nbytes == 8 * len(steps) * (2 + 7 * n)


def test_particles_detach_and_several_recordings() -> None:
    w, ref = cloth().build(dt=1 / 120), cloth().build(dt=1 / 120)
    a = w.record()
    b = w.record(every=4)
    w.step(8)
    a.detach()
    assert not a.attached and b.attached
    w.step(4)
    p = len(ref.particles.position)
    assert a.particle_position.shape == (9, p, 3)
    assert b.steps.tolist() == [0, 4, 8, 12]
    ref.step(8)
    assert np.array_equal(a.particle_position[-1], ref.particles.position)
    ref.step(4)
    assert np.array_equal(b.particle_position[-1], ref.particles.position)
    assert np.array_equal(w.particles.position, ref.particles.position)


def test_save_load_round_trip_is_exact(tmp_path: Path) -> None:
    w = cloth().build(dt=1 / 120)
    rec = w.record(every=2)
    w.step(10)
    path = tmp_path / "run.npz"
    rec.save(path)
    back = rr.Recording.load(str(path))
    for name in ("times", "steps", "position", "orientation", "particle_position"):
        assert np.array_equal(getattr(back, name), getattr(rec, name)), name
    assert back.every == 2 and not back.attached
    assert os.listdir(tmp_path) == ["run.npz"]


def test_bad_paths_and_files(tmp_path: Path) -> None:
    rec = scene().build(dt=1 / 120).record()
    with pytest.raises(OSError, match="cannot write the recording"):
        rec.save(tmp_path / "missing" / "run.npz")
    assert not (tmp_path / "missing").exists()
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if not os.access(locked, os.W_OK):  # root writes anyway
            with pytest.raises(OSError):
                rec.save(locked / "run.npz")
            assert os.listdir(locked) == []
    finally:
        locked.chmod(0o700)
    with pytest.raises(FileNotFoundError):
        rr.Recording.load(tmp_path / "none.npz")
    text = tmp_path / "notes.npz"
    text.write_text("not a recording")
    with pytest.raises(ValueError, match="not a rigidrs recording"):
        rr.Recording.load(text)
    other = tmp_path / "other.npz"
    np.savez(other, times=np.zeros(3))
    with pytest.raises(ValueError, match="not a rigidrs recording"):
        rr.Recording.load(other)
    with pytest.raises(ValueError, match="every"):
        scene().build(dt=1 / 120).record(every=0)


def test_shapes_read_back() -> None:
    s = rr.Scene()
    s.add_body(rr.Plane(normal=(0, 0, 1), offset=-0.5), fixed=True)
    s.add_body(rr.Box((0.1, 0.2, 0.3)), density=1000.0)
    s.add_body(rr.Cone(0.2, 0.3), density=1000.0, position=(1, 0, 0))
    s.add_body(rr.Compound([(rr.Sphere(0.1), (0, 0, 0)), (rr.Capsule(0.05, 0.2), (0.4, 0, 0))]), density=1000.0)
    hull = rr.ConvexHull(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]))
    s.add_body(hull, density=1000.0)
    w = s.build(dt=0.01)
    shapes = w.shapes()
    assert [d["kind"] for d in shapes] == ["Plane", "Box", "Cone", "Compound", "ConvexHull"]
    for a, b in zip(shapes, s.shapes()):
        assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a if k != "parts")
    assert shapes[0]["offset"] == -0.5 and np.allclose(shapes[0]["normal"], (0, 0, 1))
    assert np.allclose(shapes[1]["half_extents"], (0.1, 0.2, 0.3))
    assert np.allclose(shapes[1]["position"], 0)  # a box's centre of mass is its centre
    # Body pose ∘ shape pose puts each shape's frame where the scene put it (the cone's
    # centre of mass is a quarter of its height above its base: not its frame's origin).
    from rigidrs.view.mesh import quat_rotate

    for i, at in [(1, (0, 0, 0)), (2, (1, 0, 0))]:
        origin = w.bodies.position[i] + quat_rotate(w.bodies.orientation[i], shapes[i]["position"])
        assert np.allclose(origin, at, atol=1e-12)
    assert np.isclose(np.linalg.norm(shapes[2]["position"]), 0.15)
    parts = shapes[3]["parts"]
    assert [p["kind"] for p in parts] == ["Sphere", "Capsule"] and np.allclose(parts[1]["position"], (0.4, 0, 0))
    assert shapes[4]["triangles"].shape == (4, 3) and shapes[4]["vertices"].shape[1] == 3
    # The hull's vertices placed with both poses are the points given.
    d = shapes[4]
    world = quat_rotate(w.bodies.orientation[4], quat_rotate(d["orientation"], d["vertices"]) + d["position"])
    world += w.bodies.position[4]
    assert np.allclose(np.sort(world, axis=0), np.sort(hull_points(), axis=0), atol=1e-12)


def hull_points() -> np.ndarray:
    return np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])


def test_a_failed_step_while_recording_keeps_the_frames_of_the_steps_before() -> None:
    # Recording steps one by one through the same guard as step(n): a step that
    # diverges is undone, the frames of the steps before it stay, and the world and
    # its recording step on together.
    world = scene().build(dt=1 / 120)
    rec = world.record(every=1)
    world.step(5)
    world.bodies.angular_velocity[1] = (1e308, 1e307, 0.0)
    with pytest.raises(rr.SimulationError):
        world.step(3)
    assert len(rec.times) == 6 and world.time == pytest.approx(5 / 120)
    world.bodies.angular_velocity[1] = (0.0, 0.0, 0.0)
    world.step(2)
    assert len(rec.times) == 8
    assert np.array_equal(rec.position[-1], world.bodies.position)
