"""Drives, joint damping, armature, friction and limits of articulated joints,
against closed forms.

A hinge about z (no gravity torque) on a 1 m × 0.1 m × 0.1 m box of 2 kg whose
centre is 0.5 m from the axis: J = m (l² + t²)/12 + m (l/2)². Drives, damping and
friction are solved implicitly over each step (backward Euler on the control
force with a look-ahead over the drift): stable for any stiffness, first order
in the drive's own ω·dt, so its error against the closed form halves with dt.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr

G = 9.81
J = 2.0 * (1.0 + 0.01) / 12 + 2.0 * 0.25


def bar(dt: float = 1 / 240, **joint: object) -> tuple[rr.World, int]:
    scene = rr.Scene(gravity=(0, 0, 0))
    b = scene.add_body(rr.Box((0.5, 0.05, 0.05)), mass=2.0, position=(0.5, 0, 0))
    scene.add_joint("hinge", b, None, anchor=(0, 0, 0), axis=(0, 0, 1), **joint)
    return scene.build(dt=dt), b


def response(k: float, c: float, target: float, dt: float, seconds: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    world, _ = bar(dt, drive=rr.Drive(mode="position", target=target, stiffness=k, damping=c))
    t, angle = [], []
    for _ in range(int(round(seconds / dt))):
        world.step()
        t.append(world.time)
        angle.append(world.joints.position[0])
    return np.array(t), np.array(angle)


def closed_form(k: float, c: float, target: float, t: np.ndarray) -> np.ndarray:
    """J θ'' + c θ' + k θ = k θ*, from rest at 0 (under- or critically damped)."""
    wn, zeta = math.sqrt(k / J), c / (2 * math.sqrt(k * J))
    if zeta >= 1.0:
        return target * (1 - np.exp(-wn * t) * (1 + wn * t))
    wd = wn * math.sqrt(1 - zeta * zeta)
    return target * (1 - np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t)))


@pytest.mark.parametrize("k, c, dt", [(5.0, 0.5, 1 / 480), (20.0, 2 * math.sqrt(20.0 * J), 1 / 240)],
                         ids=["underdamped", "critical"])
def test_position_drive_follows_the_closed_form_response(k: float, c: float, dt: float) -> None:
    # Largest error over 2 s, relative to the step 0.8 rad. The drive is first
    # order in ωn·dt (backward Euler, for stability at any stiffness): measured
    # 1.16 % at 1/240 and 0.58 % at 1/480 for ωn = 2.7 rad/s, ζ = 0.14; 0.4 % at
    # 1/240 for ωn = 5.5, ζ = 1 (critical damping is kinder). Bar: 1 % at
    # ωn·dt ≤ 0.025, and the error halves (÷[1.8, 2.2]) when dt halves.
    assert math.sqrt(k / J) * dt <= 0.025
    t, angle = response(k, c, 0.8, dt)
    err = np.abs(angle - closed_form(k, c, 0.8, t)).max() / 0.8
    assert err <= 0.01, err
    t2, angle2 = response(k, c, 0.8, dt / 2)
    err2 = np.abs(angle2 - closed_form(k, c, 0.8, t2)).max() / 0.8
    assert 1.8 <= err / err2 <= 2.2, (err, err2)


def test_stiff_drive_is_stable_at_60_hz() -> None:
    # k = 1e7 N·m/rad on J = 0.67 kg·m² (ωn dt = 65): an explicit scheme explodes;
    # here the drive settles on its target within two steps and stays there.
    world, _ = bar(1 / 60, drive=rr.Drive(target=0.5, stiffness=1e7, damping=1e3))
    angles = []
    for _ in range(60):
        world.step()
        angles.append(world.joints.position[0])
    assert abs(angles[2] - 0.5) <= 1e-6
    assert np.abs(np.array(angles[2:]) - 0.5).max() <= 1e-6
    assert abs(world.joints.velocity[0]) <= 1e-6


def test_velocity_drive_holds_its_speed_under_load() -> None:
    # damping·(ω* − ω) = load at steady state: ω = 3 − 5/50 = 2.9 rad/s, which
    # the angle advances at exactly; the force read back is the drive's,
    # balancing the load. The velocity read at the end of a step lags the
    # drive by half a step of the load alone: h/2 · 5/J (see the leapfrog).
    dt = 1 / 240
    world, b = bar(dt, drive=rr.Drive(mode="velocity", target=3.0, damping=50.0))
    world.apply_torque(b, (0, 0, -5.0))
    world.step(720)
    before = world.joints.position[0]
    world.step(240)
    assert world.joints.position[0] - before == pytest.approx(3.0 - 5.0 / 50.0, rel=1e-9)
    assert world.joints.force[0] == pytest.approx(5.0, rel=1e-9)
    assert world.joints.velocity[0] == pytest.approx(2.9 - dt / 2 * 5.0 / J, rel=1e-9)


def test_max_force_clamps_the_drive() -> None:
    # With max_force 2 N·m against a 5 N·m load the joint accelerates backwards at
    # (2 − 5)/J from rest: ω(t) = −3 t / J (exact for a constant torque).
    world, b = bar(drive=rr.Drive(mode="velocity", target=3.0, damping=50.0, max_force=2.0))
    world.apply_torque(b, (0, 0, -5.0))
    world.step(480)
    assert world.joints.force[0] == pytest.approx(2.0, rel=1e-12)
    assert world.joints.velocity[0] == pytest.approx(-3.0 * 2.0 / J, rel=1e-9)


def test_target_view_steers_the_drive() -> None:
    world, _ = bar(drive=rr.Drive(target=0.0, stiffness=200.0, damping=40.0))
    world.joints.target[0] = -0.7
    world.step(2400)
    assert world.joints.position[0] == pytest.approx(-0.7, abs=1e-6)


def test_spherical_position_drive_reaches_its_target_rotation() -> None:
    target = Rotation.from_rotvec([0.3, -0.4, 0.5])
    scene = rr.Scene(gravity=(0, 0, 0))
    b = scene.add_body(rr.Box((0.1, 0.2, 0.3)), mass=1.0, position=(0, 0, -0.3))
    scene.add_joint("spherical", b, None, anchor=(0, 0, 0),
                    drive=rr.Drive(mode="position", target=target.as_quat(), stiffness=50.0, damping=5.0))
    world = scene.build(dt=1 / 240)
    world.step(2400)
    now = Rotation.from_matrix(world.bodies.rotation[b])
    assert (now * target.inv()).magnitude() <= 1e-6


def test_prismatic_drive_and_limit() -> None:
    scene = rr.Scene(gravity=(0, 0, -G))
    b = scene.add_body(rr.Box((0.05, 0.05, 0.05)), mass=2.0)
    scene.add_joint("prismatic", b, None, axis=(0, 0, 1), limits=(-0.3, 0.3),
                    drive=rr.Drive(target=0.2, stiffness=400.0, damping=80.0))
    world = scene.build(dt=1 / 240)
    world.step(2400)
    # Static: k (0.2 − z) = m g.
    assert world.joints.position[0] == pytest.approx(0.2 - 2.0 * G / 400.0, abs=1e-9)
    world.joints.target[0] = -5.0  # the limit stops it
    world.step(480)
    assert world.joints.position[0] == pytest.approx(-0.3, abs=1e-12)


def test_joint_damping_decays_the_rate_exponentially() -> None:
    world, _ = bar(damping=0.3)
    world.set_joint_positions([0.0], [2.0])
    world.step(240)
    assert world.joints.velocity[0] == pytest.approx(2.0 * math.exp(-0.3 / J), rel=1e-3)


def test_armature_adds_to_the_inertia() -> None:
    # A pendulum bar (about y, gravity on): small-amplitude period 2π √((I + a)/(m g d)).
    periods = []
    for armature in (0.0, 0.5):
        scene = rr.Scene(gravity=(0, 0, -G))
        b = scene.add_body(rr.Box((0.5, 0.05, 0.05)), mass=2.0, position=(0, 0, -0.5),
                           orientation=Rotation.from_rotvec([0, math.pi / 2, 0]).as_quat())
        scene.add_joint("hinge", b, None, anchor=(0, 0, 0), axis=(0, 1, 0), armature=armature)
        world = scene.build(dt=1 / 480)
        world.set_joint_positions([0.01])
        t, x = [], []
        for _ in range(2880):
            world.step()
            t.append(world.time)
            x.append(world.joints.position[0])
        ups = [t[k] for k in range(1, len(x)) if x[k - 1] < 0.0 <= x[k]]
        periods.append((ups[-1] - ups[0]) / (len(ups) - 1))
        exact = 2 * math.pi * math.sqrt((J + armature) / (2.0 * G * 0.5))
        assert periods[-1] == pytest.approx(exact, rel=2e-3)


@pytest.mark.parametrize("load", [0.5, 1.5])
def test_joint_friction_holds_below_and_slides_above(load: float) -> None:
    # Coulomb friction 1 N·m: a 0.5 N·m load creeps below 1e-4 rad in 1 s (the
    # regularization speed is 1e-4 rad/s); 1.5 N·m turns it by ½ (load − 1) t²/J.
    world, b = bar(friction=1.0)
    world.apply_torque(b, (0, 0, load))
    world.step(240)
    if load < 1.0:
        assert abs(world.joints.position[0]) <= 1e-4
        assert world.joints.force[0] == pytest.approx(-load, rel=1e-6)
    else:
        assert world.joints.position[0] == pytest.approx(0.5 * (load - 1.0) / J, rel=1e-2)
        assert world.joints.force[0] == pytest.approx(-1.0, rel=1e-12)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_hinge_limits_are_hard(side: float) -> None:
    # A 0.5 m bar falls from horizontal onto its limit (0.5 rad). The limit is an
    # impulse that ends the drift on it: never past it (to round-off), at rest on
    # it, and the force read back is the weight's moment m g (l/2) cos 0.5.
    half = 0.25
    scene = rr.Scene(gravity=(0, 0, -G))
    b = scene.add_body(rr.Box((half, 0.02, 0.05)), mass=1.0, position=(side * half, 0, 0), collision_mask=0)
    scene.add_joint("hinge", b, None, anchor=(0, 0, 0), axis=(0, 1, 0), limits=(-0.5, 0.5))
    world = scene.build(dt=1 / 60)
    worst = 0.0
    for _ in range(180):
        world.step()
        worst = max(worst, side * world.joints.position[0])
    assert worst <= 0.5 + 1e-12
    assert side * world.joints.position[0] == pytest.approx(0.5, abs=1e-12)
    assert world.joints.force[0] == pytest.approx(-side * G * half * math.cos(0.5), rel=1e-9)


def test_cone_and_twist_limits() -> None:
    # A rod spun about two axes against a 0.3 rad cone and a ±0.4 rad twist
    # range. Each limit row is linear in the joint's angular velocity and the
    # drift is a finite rotation, so with both rows active the swing it ends on
    # is exact to O((ω h)²): measured overshoot 8.8e-6 rad (cone alone: 2e-16).
    scene = rr.Scene(gravity=(0, 0, -G))
    rod = scene.add_body(rr.Box((0.02, 0.05, 0.25)), mass=1.0, position=(0, 0, -0.25),
                         angular_velocity=(3.0, 0.0, 2.0), collision_mask=0)
    scene.add_joint("spherical", rod, None, anchor=(0, 0, 0), axis=(0, 0, 1), cone_limit=0.3, twist_limits=(-0.4, 0.4))
    world = scene.build(dt=1 / 60)
    swing, twist = 0.0, 0.0
    for _ in range(240):
        world.step()
        r = Rotation.from_matrix(world.bodies.rotation[rod])
        z = r.apply([0, 0, 1.0])
        swing = max(swing, math.acos(min(1.0, z[2])))
        # Twist about the rod's own axis: swing-twist split of the rotation.
        q = r.as_quat()
        twist = max(twist, abs(2 * math.atan2(q[2], q[3])))
    assert swing <= 0.3 + 1e-4
    assert twist <= 0.4 + 1e-4
    assert swing >= 0.29 and twist >= 0.39  # both limits were reached
