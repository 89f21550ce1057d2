"""Finite runaways (issue 10): a step that ends with kinetic energy no force in the
scene can explain raises ``SimulationError`` naming the body, the stage and the
time, with the world exactly as before that step; legitimate sources of energy
(drives, applied forces, what the user writes, restitution, kinematic bodies,
overlaps pushed apart, bodies written off their joints) never trip it.

The budget (``rust/world/runaway.rs``, README "Divergence caught and undone"):
kinetic energy at the last reset (after the first step since, in a world with
XPBD joints, particles or articulations, whose constraints snap back), plus the
gravity potential lost, plus the work of applied forces, drives, kinematic
bodies and contact push-out, plus ``½ M v_push²`` once; a step over 100 times
that is a runaway. Checked every 8 steps and after the first step since a reset
or a write; a failed check finds the first step over budget.
"""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

import rigidrs as rr

FACTOR = 100.0
V_PUSH = 3.0  # max_push_velocity's default (m/s)


def kinetic(world: rr.World) -> float:
    """½ m v² + ½ ωᵀ I ω of the dynamic bodies, from the views (the world-frame
    inertia is derived: read once, it is kept fresh from the next call on, so a
    `step(0)` refreshes it)."""
    b = world.bodies
    _ = b.inertia_world
    world.step(0)
    e = 0.0
    for i in range(len(b.mass)):
        if not np.isfinite(b.mass[i]):
            continue
        v, w = b.linear_velocity[i], b.angular_velocity[i]
        e += 0.5 * b.mass[i] * float(v @ v) + 0.5 * float(w @ b.inertia_world[i] @ w)
    return e


def spinner() -> rr.Scene:
    """A box (half extents 0.1, 0.2, 0.4 m, 64 kg) spinning about its middle axis
    with a tilt: the explicit gyroscopic term of symplectic_euler at ω·dt ≈ 0.6
    pumps its energy up (measured: flat for 150 steps, then ×100 within a few)."""
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(rr.Box((0.1, 0.2, 0.4)), density=1000.0, angular_velocity=(5.0, 10.0, 5.0))
    return scene


def test_a_spin_up_by_an_unstable_integrator_is_caught_and_undone() -> None:
    world = spinner().build(dt=0.05, integrator="symplectic_euler")
    with pytest.raises(rr.SimulationError) as info:
        world.step(1000)
    message = str(info.value)
    assert "ran away in stage 'gyroscopic'" in message and "body 0 has" in message, message
    failed = world.steps  # the world is back before the failing step
    assert 100 < failed < 1000
    assert f"the step from t = {failed * 0.05:.6f} s" in message

    # Exactly as before that step: a twin stepped to the same count in one call.
    twin = spinner().build(dt=0.05, integrator="symplectic_euler")
    twin.step(failed)
    for name in ("position", "orientation", "linear_velocity", "angular_velocity"):
        assert np.array_equal(getattr(world.bodies, name), getattr(twin.bodies, name)), name

    # The bound it broke is the formula: K as built + ½ M v_push² (no gravity,
    # forces, drives, contacts), ×100; the energy it ended with is over it, and
    # the state it was put back to is under it. (Printed to 5 digits: 1e-4
    # relative.)
    first = spinner().build(dt=0.05, integrator="symplectic_euler")
    budget = kinetic(first) + 0.5 * float(first.bodies.mass[0]) * V_PUSH**2
    ended, explained = (float(x) for x in re.findall(r"ended with (\S+) J.*the (\S+) J that", message)[0])
    assert explained == pytest.approx(budget, rel=1e-4)
    assert ended > FACTOR * explained
    assert kinetic(world) <= FACTOR * budget


def test_a_runaway_over_several_calls_is_caught_at_a_call_start() -> None:
    # Stepped one step per call, a runaway can be found by the check at the start
    # of a call (the last steps of the calls before): the world stays as it was.
    world = spinner().build(dt=0.05, integrator="symplectic_euler")
    for _ in range(1000):
        before = world.bodies.angular_velocity.copy()
        try:
            world.step(1)
        except rr.SimulationError as e:
            assert "ran away" in str(e) and "body 0" in str(e), str(e)
            assert np.array_equal(world.bodies.angular_velocity, before)
            break
    else:
        pytest.fail("the runaway was not caught")
    # Stepped again as it is, it is refused again (the new budget judges the
    # first step from the state it starts at) and stays as it was; with a sane
    # spin written, it steps on.
    before = world.bodies.angular_velocity.copy()
    with pytest.raises(rr.SimulationError, match="ran away"):
        world.step(1)
    assert np.array_equal(world.bodies.angular_velocity, before)
    world.bodies.angular_velocity[0] = (5.0, 10.0, 5.0)
    world.step(1)


def spun_up(scale: float) -> tuple[rr.World, float]:
    """The spinner after one step with its spin written ``scale`` times the
    initial one, and its kinetic energy as written. One step of
    symplectic_euler at dt 0.05 multiplies it by ×3.8 at 10, ×12 at 20 (within
    the bound) and by more than 100 at 100 (measured)."""
    world = spinner().build(dt=0.05, integrator="symplectic_euler")
    world.step(1)
    kinetic(world)  # brings the world-frame inertia up to date
    inertia = world.bodies.inertia_world[0].copy()
    w = np.array([5.0, 10.0, 5.0]) * scale
    # Read without another call (`kinetic` makes one): the write only changes ω.
    world.bodies.angular_velocity[0] = w
    return world, 0.5 * float(w @ inertia @ w)


def test_a_runaway_in_the_first_step_after_a_write_is_caught() -> None:
    # Regression: the budget took the state after the step following a write
    # as its reference, so a write of absurd but finite velocities that the
    # first step multiplied was never judged (a cube spun at 1e6 rad/s in a
    # column went ×4300 in that step; tests/test_fast_spin_in_contact.py).
    world, written = spun_up(100.0)
    mass = float(world.bodies.mass[0])
    before = world.bodies.angular_velocity.copy()
    with pytest.raises(rr.SimulationError) as info:
        world.step(1)
    message = str(info.value)
    assert "ran away in stage 'gyroscopic'" in message, message
    # Put back as written, the step count unchanged.
    assert world.steps == 1
    assert np.array_equal(world.bodies.angular_velocity, before)
    # The bound: what the budget held (K after the first step, + ½ M v_push²)
    # plus K as written, + ½ M v_push² again; the step ended over 100 times it.
    first = spinner().build(dt=0.05, integrator="symplectic_euler")
    held = kinetic(first) + 0.5 * mass * V_PUSH**2
    ended, explained = (float(x) for x in re.findall(r"ended with (\S+) J.*the (\S+) J that", message)[0])
    assert explained == pytest.approx(held + written + 0.5 * mass * V_PUSH**2, rel=1e-4)
    assert ended > FACTOR * explained


@pytest.mark.parametrize("scale", [10.0, 20.0])
def test_a_fast_write_the_first_step_keeps_within_bounds_is_not_a_runaway(scale: float) -> None:
    world, written = spun_up(scale)
    world.step(1)
    assert written < kinetic(world) < FACTOR * written


def test_a_runaway_in_the_first_step_of_a_world_is_caught() -> None:
    # The first step of a world is judged from the state as built.
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(rr.Box((0.1, 0.2, 0.4)), density=1000.0, angular_velocity=(500.0, 1000.0, 500.0))
    world = scene.build(dt=0.05, integrator="symplectic_euler")
    with pytest.raises(rr.SimulationError, match="ran away in stage 'gyroscopic'"):
        world.step(1)
    assert world.steps == 0
    assert np.array_equal(world.bodies.angular_velocity[0], (500.0, 1000.0, 500.0))


def test_a_drive_spinning_a_wheel_up_is_not_a_runaway() -> None:
    # A velocity drive (damping 50 N·m·s/rad, no force limit) spins a disc from rest
    # to 200 rad/s: all of its kinetic energy is the drive's work.
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    disc = scene.add_body(rr.Cylinder(0.3, 0.02), density=1000.0)
    scene.add_joint("hinge", disc, None, anchor=(0.0, 0.0, 0.0), axis=(0.0, 1.0, 0.0),
                    drive=rr.Drive(mode="velocity", target=200.0, damping=50.0))
    world = scene.build(dt=1 / 240)
    world.step(2400)
    energy = kinetic(world)
    i_axis = float(world.bodies.inertia_world[disc][1, 1])  # about the hinge (a diameter), kg·m²
    # ½ I ω² at the target, to 1 % (the drive settles as exp(-c t / I), I/c = 5 ms).
    assert energy == pytest.approx(0.5 * i_axis * 200.0**2, rel=1e-2)
    assert kinetic(world) > FACTOR * 0.5 * float(world.bodies.mass[disc]) * V_PUSH**2


def test_a_force_the_user_applies_is_not_a_runaway() -> None:
    # 1 kN on a 1 kg ball at rest for 1 s: K = (F t)² / 2m = 5e5 J, from nothing.
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(rr.Sphere(0.1), mass=1.0)
    world = scene.build(dt=1 / 100)
    world.apply_force(0, (1000.0, 0.0, 0.0))
    world.step(100)
    assert kinetic(world) == pytest.approx(0.5 * 1000.0**2, rel=1e-12)


def test_a_velocity_the_user_writes_is_not_a_runaway() -> None:
    # A resting box set flying at 1 km/s through a view, between two calls.
    scene = rr.Scene()
    scene.add_body(rr.Plane(), fixed=True)
    box = scene.add_body(rr.Box((0.1, 0.1, 0.1)), density=1000.0, position=(0.0, 0.0, 0.1))
    world = scene.build(dt=1 / 240)
    world.step(30)
    world.bodies.linear_velocity[box] = (1000.0, 0.0, 500.0)
    world.step(60)
    # Free flight under gravity after it leaves the plane: vz = 500 − g t.
    assert world.bodies.linear_velocity[box, 0] == pytest.approx(1000.0, rel=1e-9)
    assert world.bodies.linear_velocity[box, 2] == pytest.approx(500.0 - 9.81 * 60 / 240, rel=1e-6)


def test_an_elastic_bounce_and_overlaps_pushed_apart_are_not_runaways() -> None:
    # Twenty boxes in one place fly apart (their push-out adds up along the pile)
    # while a ball bounces on the floor with restitution 1, out of their reach
    # (they leave at up to 18 m/s; at 5 m one struck the ball after 1.6 s).
    scene = rr.Scene()
    scene.add_body(rr.Plane(), fixed=True, restitution=1.0)
    ball = scene.add_body(rr.Sphere(0.1), density=1000.0, position=(100.0, 0.0, 10.0), restitution=1.0)
    for k in range(20):
        scene.add_body(rr.Box((0.2, 0.2, 0.2)), density=1000.0, position=(0.01 * k, 0.0, 3.0))
    world = scene.build(dt=1 / 240)
    world.step(720)
    speeds = np.linalg.norm(world.bodies.linear_velocity[2:], axis=1)
    assert speeds.max() > V_PUSH  # the pile's push-out added up past the cap
    # The ball's energy is conserved through its bounces to 1 % (restitution 1).
    b = world.bodies
    e = 0.5 * float(b.linear_velocity[ball] @ b.linear_velocity[ball]) + 9.81 * (b.position[ball, 2] - 0.1)
    assert e == pytest.approx(9.81 * 9.9, rel=1e-2)


def test_a_kinematic_paddle_and_a_body_written_off_its_joint_are_not_runaways() -> None:
    # A kinematic paddle at 30 m/s sends a resting ball off at ~60 m/s; a pendulum
    # bob written 0.5 m off its XPBD joint snaps back within a step.
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(rr.Box((0.05, 1.0, 1.0)), kinematic=True, position=(-1.0, 0.0, 0.0),
                   linear_velocity=(30.0, 0.0, 0.0), restitution=1.0)
    ball = scene.add_body(rr.Sphere(0.1), density=100.0, restitution=1.0)
    bob = scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0.0, 5.0, -1.0))
    scene.add_joint("spherical", bob, None, anchor=(0.0, 5.0, 0.0), solver="xpbd")
    world = scene.build(dt=1 / 240)
    world.step(60)
    # A restitution-1 hit by an infinitely heavy paddle: 2 × 30 m/s, to 5 %.
    assert world.bodies.linear_velocity[ball, 0] == pytest.approx(60.0, rel=5e-2)
    world.bodies.position[bob] = (0.5, 5.0, -1.0)
    world.step(60)
    assert math.isfinite(kinetic(world))
