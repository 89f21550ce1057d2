"""A box on a turntable: static friction in a rotating frame.

A kinematic platform turns at ω about the vertical; a box set on it at radius r,
moving with it, needs the centripetal force m ω² r, which static friction gives
while ω² r ≤ μs g. Held, the box goes round on its circle: its radius stays r
and it turns with the platform (the issue "Contacts you can trust" asks stiction
without creep within 0.1 mm).

Not met (strict xfail). Friction is solved on velocities: the box's velocity is
made the platform's at the contact, and the substep's drift carries it along the
tangent, outward by r (ω h)² / 2 a substep, which nothing takes back. Measured at
dt = 1/60 (4 substeps), r = 0.5 m, after 10 s: 2.61 / 10.53 / 43.45 mm outward at
ω = 0.5 / 1 / 2 rad/s (r ω² dt T / 8 to 1 %), a quarter of that at 240 Hz. A fix
needs static friction held on positions (anchors kept while a patch sticks).
Beyond the friction limit, the box slides off: that is checked as is.
"""
from __future__ import annotations

import math

import pytest

import rigidrs as rr

G, MU, R0, HALF, DT = 9.81, 0.5, 0.5, 0.05, 1 / 60


def spin(omega: float, seconds: float) -> float:
    """The box's distance from the axis after `seconds` (m)."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    scene.add_body(rr.Box((1.0, 1.0, HALF)), kinematic=True, position=(0.0, 0.0, HALF),
                   angular_velocity=(0.0, 0.0, omega), friction=MU)
    box = scene.add_body(rr.Box((HALF,) * 3), density=1000.0, position=(R0, 0.0, 3 * HALF),
                         linear_velocity=(0.0, omega * R0, 0.0), angular_velocity=(0.0, 0.0, omega), friction=MU)
    world = scene.build(dt=DT, sleep=False)
    world.step(round(seconds / DT))
    x, y, _ = world.bodies.position[box]
    return math.hypot(x, y)


@pytest.mark.xfail(strict=True, reason="velocity-level stiction: the box creeps outward r ω² dt T / 8 "
                   "(10 s: 2.61 / 10.53 / 43.45 mm at ω = 0.5 / 1 / 2 rad/s, 60 Hz)")
@pytest.mark.parametrize("omega", [0.5, 1.0, 2.0])
def test_a_box_held_by_static_friction_stays_on_its_circle(omega: float) -> None:
    assert omega ** 2 * R0 < MU * G  # friction can hold it
    assert abs(spin(omega, 10.0) - R0) < 1e-4


def test_a_box_beyond_the_friction_limit_slides_off() -> None:
    # ω² r = 8 m/s² > μ g = 4.9 m/s²: it leaves the 1 m platform within 3 s.
    omega = 4.0
    assert omega ** 2 * R0 > MU * G
    assert spin(omega, 3.0) > 1.0 + HALF
