"""Stacks standing still (REFERENCES.md, Contact): a vertical stack of 15 unit boxes
and a pyramid with a base of 20 (210 boxes, 2 cm apart in each row) at 60 Hz stand
for 60 s with drift < 1 cm, penetration <= the slop, and kinetic energy settling to
~0; a box 1000x heavier resting on a light box stays within the same bars (the
light box held under it: shock propagation, rigidrs/solve/shock.rs).

Measured quantities:

* penetration: the largest ``depth`` of ``world.contacts()`` after every step of
  the run. The slop is 5 mm: the engine has no ``slop`` setting (its ``margin``,
  the distance contacts are predicted ahead, defaults to the same 5 mm, Box2D's
  linear slop);
* drift: the largest displacement of any box between the settled state (1 s) and
  the end (60 s); and, since a perfect stack has no reason to move sideways at all,
  the largest horizontal displacement from where the box was placed. (Vertically
  every box sinks by the penetrations under it, which the penetration bar covers.)
* kinetic energy: "~0" is an RMS speed below 1e-4 m/s, the speed that would carry a
  box 6 mm in 60 s (below the drift bar); asleep it is exactly 0.

Both with sleeping (the default) and without it, where sleeping could hide motion.
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr

G = 9.81
DT = 1.0 / 60.0
SLOP = 0.005
DRIFT = 0.01
V_RMS = 1e-4
SETTLE = 1.0  # s
SECONDS = 60.0


def ground_scene():
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    return scene


def column(n, masses=None):
    scene = ground_scene()
    for i in range(n):
        mass = 1000.0 if masses is None else masses[i]
        scene.add_body(rr.Box((0.5, 0.5, 0.5)), mass=mass, position=(0.0, 0.0, 0.5 + i))
    return scene


def pyramid(base, gap=0.02):
    scene = ground_scene()
    for row in range(base):
        n = base - row
        for j in range(n):
            x = (j - (n - 1) / 2) * (1.0 + gap)
            scene.add_body(rr.Box((0.5, 0.5, 0.5)), density=1000.0, position=(x, 0.0, 0.5 + row))
    return scene


def stand(world, seconds=SECONDS):
    """Runs ``seconds``; returns the deepest penetration seen after any step, the
    drift after settling, the horizontal displacement from the start, and the RMS
    speed at the end."""
    boxes = slice(1, None)
    p0 = world.bodies.position[boxes].copy()
    deepest, settled = 0.0, None
    for k in range(int(round(seconds / DT))):
        world.step(1)
        depth = world.contacts()["depth"]
        if len(depth):
            deepest = max(deepest, float(depth.max()))
        if k + 1 == int(round(SETTLE / DT)):
            settled = world.bodies.position[boxes].copy()
    p = world.bodies.position[boxes]
    drift = float(np.max(np.linalg.norm(p - settled, axis=1)))
    sideways = float(np.max(np.linalg.norm(p[:, :2] - p0[:, :2], axis=1)))
    mass = world.bodies.mass[boxes].sum()
    v_rms = float(np.sqrt(2 * world.kinetic_energy() / mass))
    return deepest, drift, sideways, v_rms


def check(world, sleep, seconds=SECONDS):
    deepest, drift, sideways, v_rms = stand(world, seconds)
    assert 0.0 < deepest <= SLOP  # (> 0: contacts were seen and measured)
    assert drift < DRIFT  # REFERENCES.md: drift < 1 cm while it stands
    # From the very start, the settling is included: the boxes are placed just
    # touching, and as the compliant contacts take the load (0.28 mm each, so the
    # apex of the pyramid sinks 3.4 cm) the outer boxes of the slopes shift out.
    # Measured 12.6 mm for the pyramid at the default 4 substeps (7.3 mm at 8);
    # Rapier's moves 3 cm on the same scene.
    assert sideways < 1.5 * DRIFT
    assert v_rms <= V_RMS
    if sleep:
        assert world.bodies.sleeping[1:].all()
        assert world.kinetic_energy() == 0.0


@pytest.mark.parametrize("sleep", [True, False], ids=["sleep", "no sleep"])
def test_stack_of_15_boxes_stands_for_60_s(sleep):
    # Measured: penetration 4.2 mm, drift after 1 s 0 (asleep) / 6.7 mm, sideways
    # 7.0 / 9.1 mm, RMS speed 0 / ~1e-7 m/s.
    world = column(15).build(dt=DT, sleep=sleep)
    check(world, sleep)


@pytest.mark.parametrize("sleep", [True, False], ids=["sleep", "no sleep"])
def test_pyramid_of_210_boxes_stands_for_60_s(sleep):
    world = pyramid(20).build(dt=DT, sleep=sleep)
    assert len(world.bodies) == 211
    check(world, sleep)


@pytest.mark.parametrize("sleep", [True, False], ids=["sleep", "no sleep"])
def test_heavy_box_on_a_light_box_stands(sleep):
    # Measured: penetration 0.28 mm (g/ω² at 30 Hz: the 1000 kg box rests on the
    # held light box as on the ground), drift 0 / 0.4 µm, sideways 3.5 µm / 1.5 nm,
    # RMS speed 0 / 7e-16 m/s. (Before one-way support contacts: 22 mm sink, and
    # without sleep 22 mm drift at 1.3 cm/s.)
    world = column(2, masses=[1.0, 1000.0]).build(dt=DT, sleep=sleep)
    check(world, sleep, seconds=10.0)


@pytest.mark.parametrize("masses", [[1.0, 1.0, 1000.0], [1.0, 1000.0, 1.0e6]], ids=["1-1-1000", "1-1e3-1e6"])
def test_heavier_loads_on_light_boxes_stand(masses):
    # A 1000:1 ratio on top of a 1:1 contact, and two 1000:1 ratios stacked.
    # Measured: penetration 0.55 / 0.28 mm, drift 2.8 / 0.5 µm, RMS speed ~1e-14 m/s.
    world = column(3, masses=masses).build(dt=DT, sleep=False)
    check(world, sleep=False, seconds=10.0)


def test_heavy_box_on_a_light_box_reports_its_weight_on_the_light_box():
    # The one-way contact carries the heavy box's whole weight: over a step the
    # normal impulses sum to m g dt (momentum balance of the resting heavy box, to
    # the round-off of its ~1e-15 m/s residual speed). The light box is held, not
    # loaded: its contact with the ground reports its own weight only (the
    # documented price of shock propagation, rigidrs/solve/shock.rs).
    world = column(2, masses=[1.0, 1000.0]).build(dt=DT, sleep=False)
    world.step(120)
    c = world.contacts()
    top = c["body_a"] == 1
    assert np.all(c["body_b"][top] == 2) and np.all(c["body_b"][~top] == 1)
    np.testing.assert_allclose(c["normal_impulse"][top].sum() / DT, 1000.0 * G, rtol=1e-9)
    np.testing.assert_allclose(c["normal_impulse"][~top].sum() / DT, 1.0 * G, rtol=1e-9)


def test_heavy_box_dropped_onto_a_light_box_comes_to_rest_on_it():
    # Dropped from 0.5 m (3.1 m/s at impact): it stops on the light box without
    # pushing it into the ground. Measured: deepest contact 2.9 mm, both boxes at
    # rest (< 1e-14 m/s) after 5 s, heights within 0.6 mm of the stacked ones.
    scene = ground_scene()
    scene.add_body(rr.Box((0.5, 0.5, 0.5)), mass=1.0, position=(0.0, 0.0, 0.5))
    scene.add_body(rr.Box((0.5, 0.5, 0.5)), mass=1000.0, position=(0.0, 0.0, 2.0))
    world = scene.build(dt=DT, sleep=False)
    deepest = 0.0
    for _ in range(300):
        world.step(1)
        depth = world.contacts()["depth"]
        deepest = max(deepest, float(depth.max()) if len(depth) else 0.0)
    assert deepest <= SLOP
    np.testing.assert_allclose(world.bodies.position[1:, 2], [0.5, 1.5], rtol=0, atol=SLOP)
    assert np.abs(world.bodies.linear_velocity[1:]).max() < V_RMS


@pytest.mark.parametrize("sleep", [True, False], ids=["sleep", "no sleep"])
def test_light_box_on_a_heavy_box_stands(sleep):
    # The easy way round (1 kg on 1000 kg) for contrast: it must of course stand too.
    world = column(2, masses=[1000.0, 1.0]).build(dt=DT, sleep=sleep)
    check(world, sleep, seconds=10.0)


def test_resting_box_reports_its_weight_as_normal_impulse():
    # world.contacts() for a box at rest on the ground: the normal impulses of the step
    # (N·s over the step, so / dt gives forces) sum to the weight times dt (momentum balance of a body at rest, to the ~1e-12
    # velocity left per step; 1e-9 relative), normals point from the ground (body a) to
    # the box (body b), and a flat box has 4 points, all at the same depth by symmetry.
    scene = ground_scene()
    box = scene.add_body(rr.Box((0.5, 0.3, 0.2)), mass=7.0, position=(0.3, -0.2, 0.2))
    world = scene.build(dt=DT, sleep=False)
    world.step(120)
    c = world.contacts()
    assert set(c) == {"body_a", "body_b", "point", "normal", "depth", "normal_impulse", "friction_impulse"}
    k = len(c["depth"])
    assert k == 4
    shapes = {"body_a": (k,), "body_b": (k,), "point": (k, 3), "normal": (k, 3), "depth": (k,),
              "normal_impulse": (k,), "friction_impulse": (k, 3)}
    for name, shape in shapes.items():
        assert c[name].shape == shape, name
    assert c["body_a"].dtype == np.int64 and c["body_b"].dtype == np.int64
    assert np.all(c["body_a"] == 0) and np.all(c["body_b"] == box)
    np.testing.assert_allclose(c["normal"], [[0.0, 0.0, 1.0]] * k, rtol=0, atol=1e-15)
    assert abs(c["normal_impulse"].sum() / DT - 7.0 * G) <= 1e-9 * 7.0 * G
    # Nothing pushes it sideways: the friction impulses sum to zero (each point may hold
    # a little locked-in static friction from the settling, which is indeterminate).
    np.testing.assert_allclose(c["friction_impulse"].sum(axis=0), 0.0, rtol=0, atol=1e-9 * 7.0 * G * DT)
    assert 0.0 < c["depth"].max() <= SLOP
    # Equal to 1e-5 (4 nm here): the four points settle from a Gauss–Seidel sweep
    # that takes them in turn, which leaves the box level to a few nanometres.
    np.testing.assert_allclose(c["depth"], c["depth"].mean(), rtol=1e-5)
    # The points are the box's bottom corners, midway into the penetration: the corner
    # is `depth` below the ground, the ground's surface at 0. The points are from the
    # step's start and the pose from its end: 1e-9 m allows the resting box's residual
    # motion in one step (measured ~5e-12 m).
    pose_r, pose_p = world.bodies.rotation[box], world.bodies.position[box]
    corners = np.array([pose_p + pose_r @ [sx * 0.5, sy * 0.3, -0.2] for sx in (-1, 1) for sy in (-1, 1)])
    for point, depth in zip(c["point"], c["depth"]):
        nearest = corners[np.argmin(np.linalg.norm(corners[:, :2] - point[:2], axis=1))]
        np.testing.assert_allclose(point[:2], nearest[:2], rtol=0, atol=1e-9)
        assert abs(nearest[2] + depth) <= 1e-9
        assert abs(point[2] + depth / 2) <= 1e-9


def test_balls_stacked_on_a_ball_report_the_weight_each_contact_carries():
    # Two-ball contacts are kept in the pair itself, not in a parry manifold: their
    # warm start carries over the steps all the same. Three balls of 1, 2 and 3 kg
    # (bottom up) stacked exactly above each other on the ground: at rest, each
    # contact's normal impulse over a step is the weight above it times dt. The
    # over-damped soft contacts settle exponentially (residual speed 1e-4 m/s at
    # 1 s, 1e-10 at 4 s, 2e-14 at 10 s): at 10 s the balance holds to 1e-9.
    scene = ground_scene()
    for k, mass in enumerate([1.0, 2.0, 3.0]):
        scene.add_body(rr.Sphere(0.25), mass=mass, position=(0.0, 0.0, 0.25 + 0.5 * k))
    world = scene.build(dt=DT, sleep=False)
    world.step(600)
    c = world.contacts()
    carried = {(0, 1): 6.0, (1, 2): 5.0, (2, 3): 3.0}
    assert sorted(zip(c["body_a"].tolist(), c["body_b"].tolist())) == sorted(carried)
    for a, b, j in zip(c["body_a"], c["body_b"], c["normal_impulse"]):
        np.testing.assert_allclose(j / DT, carried[(int(a), int(b))] * G, rtol=1e-9)
