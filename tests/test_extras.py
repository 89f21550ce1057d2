"""Energies and contacts per frame (rigidrs.view.extras): the kinetic energy read back
in Python against the closed form (box moments, an independent rotation from scipy)
and the core's own sum; a Capture's frames aligned with the Recording's; the contacts
of a box at rest carrying its weight; one .npz holding both."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr
from rigidrs.view.extras import Capture, Extras, kinetic_energy, particle_kinetic_energy

G = 9.81


def test_kinetic_energy_against_the_closed_form() -> None:
    m, (a, b, c) = 3.0, (0.1, 0.2, 0.35)
    q = Rotation.from_rotvec([0.3, -0.8, 0.5])
    v, w = np.array([0.4, -1.0, 2.0]), np.array([1.5, -0.7, 2.2])
    s = rr.Scene(gravity=(0, 0, -G))
    s.add_body(rr.Plane(), fixed=True)
    s.add_body(rr.Box((a, b, c)), mass=m, position=(0, 0, 5), orientation=q.as_quat(), linear_velocity=v,
               angular_velocity=w)
    s.add_particle((1, 1, 1), mass=0.5, velocity=(0, 3, 4))
    world = s.build(dt=0.01)
    # Box of edges 2a, 2b, 2c: I = m/3 (b² + c², a² + c², a² + b²) about its own axes,
    # which are its principal axes (distinct moments), so the body frame is q's.
    moments = m / 3 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    w_body = q.inv().apply(w)
    expected = 0.5 * m * v @ v + 0.5 * np.sum(moments * w_body**2)
    e = kinetic_energy(world)
    assert e[0] == 0.0  # the fixed plane
    # Rounding of a few products of O(1) numbers: 1e-12 relative.
    assert e[1] == pytest.approx(expected, rel=1e-12)
    assert particle_kinetic_energy(world) == pytest.approx(0.5 * 0.5 * 25.0, rel=1e-15)
    assert e.sum() + particle_kinetic_energy(world) == pytest.approx(world.kinetic_energy(), rel=1e-12)


def resting_box() -> rr.Scene:
    s = rr.Scene(gravity=(0, 0, -G))
    s.add_body(rr.Plane(), fixed=True)
    s.add_body(rr.Box((0.1, 0.2, 0.3)), mass=2.0, position=(0, 0, 0.35))  # drops 5 cm, then rests
    s.add_body(rr.Sphere(0.1), mass=1.0, position=(1, 0, 2), linear_velocity=(0.5, 0, 0))
    return s


def test_capture_frames_match_the_recording_and_a_twin_world(tmp_path: Path) -> None:
    dt, every, steps = 1 / 120, 5, 242  # a last partial interval: no frame for it
    world = resting_box().build(dt=dt, sleep=False)
    rec = world.record(every=every)
    cap = Capture(world, every, contacts=True)
    cap.step(100)
    cap.step(steps - 100)  # runs across calls keep the rhythm
    ex = cap.extras
    np.testing.assert_array_equal(ex.steps, rec.steps)
    np.testing.assert_array_equal(ex.times, rec.times)
    twin = resting_box().build(dt=dt, sleep=False)
    for k, n in enumerate(ex.steps):
        twin.step(int(n) - twin.steps)
        assert ex.potential[k] == twin.potential_energy()  # same bits: a deterministic twin
        assert ex.kinetic[k] == pytest.approx(twin.kinetic_energy(), rel=1e-12, abs=1e-15)
        c = ex.contacts(k)
        for name, arr in twin.contacts().items():
            np.testing.assert_array_equal(c[name], arr)
    # On the plane (the last frame, 2 s in: the box at rest, the sphere rolling) each
    # body's contacts carry its weight: their normal impulses over one step add up to
    # m g dt (to the solver's convergence).
    last = ex.contacts(-1)
    for body, mass in ((1, 2.0), (2, 1.0)):
        mine = (last["body_a"] == body) | (last["body_b"] == body)
        assert mine.any()
        assert last["normal_impulse"][mine].sum() == pytest.approx(mass * G * dt, rel=1e-6)
    # Before the sphere lands (t = 0.6 s) the only loss is the box's landing: it drops
    # 5 cm and stops (inelastic contact), losing m g h = 0.981 J; it rests sunk by less
    # than 1 mm (the contact slop), which bounds the difference by m g · 1 mm.
    e = ex.kinetic + ex.potential
    before = e[ex.times < 0.5]
    assert e[0] - before[-1] == pytest.approx(2.0 * G * 0.05, abs=2.0 * G * 1e-3)
    assert np.ptp(before[ex.times[ex.times < 0.5] > 0.3]) < 1e-9  # box at rest, sphere in flight

    path = tmp_path / "run.npz"
    ex.save(path, rec)
    again = Extras.load(path)
    np.testing.assert_array_equal(again.kinetic, ex.kinetic)
    np.testing.assert_array_equal(again.contacts(7)["point"], ex.contacts(7)["point"])
    np.testing.assert_array_equal(rr.Recording.load(path).position, rec.position)
    assert [p.name for p in tmp_path.iterdir()] == ["run.npz"]


def test_bad_input() -> None:
    world = resting_box().build(dt=0.01)
    with pytest.raises(ValueError, match="every must be a positive"):
        Capture(world, 0)
    with pytest.raises(ValueError, match="no contacts were captured"):
        Capture(world).extras.contacts(0)


def test_load_of_a_plain_recording_says_so(tmp_path: Path) -> None:
    world = resting_box().build(dt=0.01)
    rec = world.record()
    world.step(2)
    rec.save(tmp_path / "rec.npz")
    with pytest.raises(ValueError, match="holds no energies or contacts"):
        Extras.load(tmp_path / "rec.npz")
