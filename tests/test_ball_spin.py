"""A ball's contact: its normal impulse through the centre, its spin resisted on
the Hertz patch its depth presses.

A rigid ball touches in one point, and a point has no lever against a spin about
the contact normal. A ball rolling to and fro in the groove of two others turns
about both contacts' normals, so nothing stopped it: poured ball piles kept
balls rolling at up to 5e-4 m/s after 10 s (`test_stacks.py`). A real ball
touches on a small disc, Hertz's, of radius ``a = √(R δ)`` (``R`` the balls'
combined radius ``R1 R2 / (R1 + R2)``, a flat side's infinite; ``δ`` the depth),
and Coulomb friction uniform over it resists a spin with the torque
``(3π/16) a μ N``. rigidrs takes ``δ`` as the contact's depth at the step start,
at least the depth resting contacts settle to (``REST_DEPTH`` of the slop: 1 µm
at the defaults), and shares the patch's Coulomb friction between the slip and
the spin on the ellipsoidal limit surface (the spin takes what the force leaves:
a ball sliding at its cone resists no spin).

References, computed below: a ball spinning about the vertical on the floor at
rest slows at ``α = (3π/16) √(R δ) μ m g / I``, ``I = 2/5 m R²``, a constant
rate (the solver's impulse per substep is the same each substep: the fit is
exact to round-off, measured 3e-13 relative; bar 1e-9). A ball thrown sliding
with a spin about the vertical keeps that spin exactly while it slides
(``t < 2 v0 / (7 μ g)``) and then slows at ``α``.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rigidrs as rr

G = 9.81
DT = 1.0 / 60.0
SLOP = 0.005
REST_DEPTH = 2e-4 * SLOP  # rigidrs/solve/impulse.rs REST_DEPTH of the default slop


def ball_on_floor(radius: float, mu: float, v0: float, w0: float) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=mu)
    scene.add_body(rr.Sphere(radius), density=1000.0, friction=mu, position=(0.0, 0.0, radius),
                   linear_velocity=(v0, 0.0, 0.0), angular_velocity=(0.0, 0.0, w0))
    return scene.build(dt=DT, sleep=False)


def hertz_spin_deceleration(radius: float, mu: float) -> float:
    inertia_per_mass = 0.4 * radius * radius
    return 3.0 * math.pi / 16.0 * math.sqrt(radius * REST_DEPTH) * mu * G / inertia_per_mass


def spins(world: rr.World, steps: int) -> np.ndarray:
    out = []
    for _ in range(steps):
        world.step(1)
        out.append(world.bodies.angular_velocity[1, 2])
    return np.array(out)


@pytest.mark.parametrize("radius,mu", [(0.1, 0.5), (0.03, 0.9), (0.5, 0.2)])
def test_a_ball_spinning_on_the_floor_slows_at_the_hertz_patch_rate(radius, mu):
    world = ball_on_floor(radius, mu, 0.0, 5.0)
    w = spins(world, 60)  # 1 s: the smallest ball stops after 2
    t = np.arange(1, 61) * DT
    slope = np.polyfit(t, w, 1)[0]
    np.testing.assert_allclose(-slope, hertz_spin_deceleration(radius, mu), rtol=1e-9)
    assert np.abs(world.bodies.position[1, :2]).max() < 1e-12  # it spins in place
    np.testing.assert_allclose(world.contacts()["depth"], [REST_DEPTH], rtol=1e-6)


def test_a_ball_sliding_at_its_cone_resists_no_spin_until_it_rolls():
    radius, mu, v0, w0 = 0.1, 0.5, 2.0, 5.0
    world = ball_on_floor(radius, mu, v0, w0)
    t_roll = 2.0 * v0 / (7.0 * mu * G)
    w = spins(world, 60)
    t = np.arange(1, 61) * DT
    sliding = t < t_roll - DT
    assert sliding.sum() >= 5
    np.testing.assert_array_equal(w[sliding], w0)
    rolling = t > t_roll + DT
    slope = np.polyfit(t[rolling], w[rolling], 1)[0]
    np.testing.assert_allclose(-slope, hertz_spin_deceleration(radius, mu), rtol=1e-9)



@pytest.mark.parametrize("x,y,points", [(0.0, 0.13, 2), (0.0, 0.0, 4)], ids=["on a seam", "where four tiles meet"])
def test_a_ball_spinning_on_a_seam_of_flush_tiles_slows_as_on_the_floor(x, y, points):
    # Across flush fixed tiles a ball's contacts with each tile are one
    # constraint (rust/solve/flush_pairs.rs); it was built from a single ball
    # contact's, whose normal pass solved only the first point (each point
    # must be) and whose patch lost its spin friction. Where four tiles meet,
    # its four points were taken for a face and solved as a support block,
    # which has no row for the spin: the ball spun on at 5 rad/s.
    radius, mu = 0.1, 0.5
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    for i in (-1, 0):
        for j in (-1, 0):
            scene.add_body(rr.Box((0.25, 0.25, 0.25)), fixed=True, position=(0.5 * i + 0.25, 0.5 * j + 0.25, -0.25),
                           friction=mu)
    scene.add_body(rr.Sphere(radius), density=1000.0, friction=mu, position=(x, y, radius),
                   angular_velocity=(0.0, 0.0, 5.0))
    world = scene.build(dt=DT, sleep=False)
    ball = len(world.bodies) - 1
    w = []
    for _ in range(60):
        world.step(1)
        w.append(world.bodies.angular_velocity[ball, 2])
    c = world.contacts()
    assert len(c["depth"]) == points  # a point on each tile under it
    m = world.bodies.mass[ball]
    np.testing.assert_allclose(c["normal_impulse"].sum() / DT, m * G, rtol=1e-6)
    slope = np.polyfit(np.arange(1, 61) * DT, w, 1)[0]
    np.testing.assert_allclose(-slope, hertz_spin_deceleration(radius, mu), rtol=1e-6)
    assert np.abs(world.bodies.position[ball, :2] - (x, y)).max() < 1e-9
