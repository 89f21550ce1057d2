"""A box on a turntable: static friction in a rotating frame.

A kinematic platform turns at ω about the vertical; a box set on it at radius r,
moving with it, needs the centripetal force m ω² r, which static friction gives
while ω² r ≤ μs g. Held, the box goes round on its circle: its radius stays r
and it turns with the platform (the issue "Contacts you can trust" asks stiction
without creep within 0.1 mm).

Friction is solved on velocities. The platform's material point under the box
travels the chord of its arc in a substep, and the box is given that chord's
velocity (`SolverBody::chord_gap`); given the tangent `ω × r` instead, the
substep carried it outward by r (ω h)² / 2, which nothing took back:
2.61 / 10.53 / 43.45 mm in 10 s at ω = 0.5 / 1 / 2 rad/s (r = 0.5 m, 60 Hz),
regression `test_a_box_held_by_static_friction_stays_on_its_circle`.
Beyond the friction limit, the box slides off: that is checked as is. A free
(dynamic) turntable too: there the chords' difference is the friction's
velocity target (`Patch::drift`), not a change of arm, so the two bodies'
impulses act at one point and their angular momentum is kept.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rigidrs as rr

G, MU, R0, HALF, DT = 9.81, 0.5, 0.5, 0.05, 1 / 60


def spin(omega: float, seconds: float, *, round_table: bool = False, centre=(0.0, 0.0),
         velocity=(0.0, 0.0), dt: float = DT) -> tuple[np.ndarray, np.ndarray, float]:
    """The box's position and orientation after `seconds`, and the time."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    table = rr.Cylinder(1.0, HALF) if round_table else rr.Box((1.0, 1.0, HALF))
    cx, cy = centre
    vx, vy = velocity
    scene.add_body(table, kinematic=True, position=(cx, cy, HALF),
                   linear_velocity=(vx, vy, 0.0), angular_velocity=(0.0, 0.0, omega), friction=MU)
    box = scene.add_body(rr.Box((HALF,) * 3), density=1000.0, position=(cx + R0, cy, 3 * HALF),
                         linear_velocity=(vx, vy + omega * R0, 0.0), angular_velocity=(0.0, 0.0, omega),
                         friction=MU)
    world = scene.build(dt=dt, sleep=False)
    steps = round(seconds / dt)
    world.step(steps)
    return world.bodies.position[box].copy(), world.bodies.orientation[box].copy(), steps * dt


def on_circle(omega: float, **kw) -> tuple[float, float, float]:
    """Radius error (m), lag behind the platform along the circle (rad) and
    yaw error (rad) after 10 s."""
    vx, vy = kw.get("velocity", (0.0, 0.0))
    cx, cy = kw.get("centre", (0.0, 0.0))
    p, q, t = spin(omega, 10.0, **kw)
    x, y = p[0] - cx - vx * t, p[1] - cy - vy * t
    angle = math.atan2(y, x)
    expected = omega * t
    wrap = lambda a: (a + math.pi) % (2 * math.pi) - math.pi  # noqa: E731
    yaw = 2 * math.atan2(q[2], q[3])
    return math.hypot(x, y) - R0, wrap(angle - expected), wrap(yaw - expected)


@pytest.mark.parametrize("omega", [0.5, 1.0, 2.0])
def test_a_box_held_by_static_friction_stays_on_its_circle(omega: float) -> None:
    assert omega ** 2 * R0 < MU * G  # friction can hold it
    radius, lag, yaw = on_circle(omega)
    assert abs(radius) < 1e-4
    # It goes round with the platform: 10 s at 2 rad/s is 20 rad; 1e-4 m of arc.
    assert abs(lag) * R0 < 1e-4
    assert abs(yaw) < 1e-4


@pytest.mark.parametrize("case", ["round table", "moving table", "240 Hz"])
def test_a_held_box_stays_on_its_circle_on_any_turntable(case: str) -> None:
    kw = {"round table": {"round_table": True},
          "moving table": {"centre": (2.0, -1.0), "velocity": (0.3, 0.2)},
          "240 Hz": {"dt": 1 / 240}}[case]
    radius, lag, yaw = on_circle(1.0, **kw)
    assert abs(radius) < 1e-4
    assert abs(lag) * R0 < 1e-4
    assert abs(yaw) < 1e-4


def test_a_box_beyond_the_friction_limit_slides_off() -> None:
    # ω² r = 8 m/s² > μ g = 4.9 m/s²: it leaves the 1 m platform within 3 s.
    omega = 4.0
    assert omega ** 2 * R0 > MU * G
    p, _, _ = spin(omega, 3.0)
    assert math.hypot(p[0], p[1]) > 1.0 + HALF


@pytest.mark.parametrize("omega", [1.0, 2.0])
def test_a_box_on_a_free_turntable_stays_on_its_circle(omega: float) -> None:
    # A heavy disk spinning on a frictionless floor, the box riding on it.
    # Read on the tangents it crept out 10.53 / 43.45 mm in 10 s; the chords'
    # difference as the friction's target keeps both bodies' impulses at one
    # point (test_collision_momentum.py holds).
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=0.0)
    table = scene.add_body(rr.Cylinder(1.0, HALF), density=5000.0, position=(0.0, 0.0, HALF),
                           angular_velocity=(0.0, 0.0, omega), friction=MU)
    box = scene.add_body(rr.Box((HALF,) * 3), density=1000.0, position=(R0, 0.0, 3 * HALF),
                         linear_velocity=(0.0, omega * R0, 0.0), angular_velocity=(0.0, 0.0, omega), friction=MU)
    world = scene.build(dt=DT, sleep=False)
    world.step(round(10.0 / DT))
    x, y, _ = world.bodies.position[box] - world.bodies.position[table]
    assert abs(math.hypot(x, y) - R0) < 1e-4
    # It turned with the table.
    q = world.bodies.orientation[table]
    yaw = 2 * math.atan2(q[2], q[3])
    lag = (math.atan2(y, x) - yaw + math.pi) % (2 * math.pi) - math.pi
    assert abs(lag) * R0 < 1e-4
