"""Newton's cradle (REFERENCES.md, Contact): equal balls in a row with small gaps,
e = 1; the first one comes in at v0. Bars: momentum conserved to 1e-12 (relative to
m v0), kinetic energy to 1e-6, the last ball leaves with at least 0.99 v0 and every
other ball keeps at most 0.01 v0.

No gravity: the balls float in a line, so the only forces are the contacts. With
equal masses and e = 1, each pairwise impact swaps the two velocities, which is
what the engine's impacts (swept in time order within a substep) must reproduce.
Momentum is exchanged by equal and opposite impulses, so it is kept to round-off:
~1e-16 per impulse, a few hundred impulses, hence 1e-12.
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr

DT = 1.0 / 240.0
R = 0.05  # ball radius (m)


def cradle(n, gap, v0, *, movers=1, friction=0.0, threshold=0.0, **build):
    """``n`` steel balls along x, ``gap`` apart; the first ``movers`` come in at v0 from
    10 cm away (so the first impact falls inside a step, not at its start)."""
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    for i in range(n):
        x = i * (2 * R + gap) - (0.1 if i < movers else 0.0)
        scene.add_body(
            rr.Sphere(R), density=7800.0, position=(x, 0.0, 0.0),
            linear_velocity=(v0 if i < movers else 0.0, 0.0, 0.0), restitution=1.0, friction=friction,
        )
    return scene.build(dt=DT, restitution_threshold=threshold, **build)


def run(world, seconds):
    """Largest momentum and energy errors over the run, and the final velocities."""
    p0, e0 = world.linear_momentum().copy(), world.kinetic_energy()
    l0 = world.angular_momentum().copy()
    dp = de = dl = 0.0
    for _ in range(int(seconds / DT)):
        world.step(1)
        dp = max(dp, float(np.max(np.abs(world.linear_momentum() - p0))))
        dl = max(dl, float(np.max(np.abs(world.angular_momentum() - l0))))
        de = max(de, abs(world.kinetic_energy() - e0) / e0)
    return dp, dl, de, world.bodies.linear_velocity.copy()


@pytest.mark.parametrize("v0", [1.0, 5.0])
@pytest.mark.parametrize("gap", [1e-2, 1e-3, 1e-4, 0.0], ids=["1cm", "1mm", "0.1mm", "touching"])
@pytest.mark.parametrize("n", [3, 5])
def test_newtons_cradle_passes_the_momentum_down_the_line(n, gap, v0):
    world = cradle(n, gap, v0)
    m = world.bodies.mass[0]
    dp, dl, de, v = run(world, 0.5)  # the last ball is 0.3-0.4 m away by then
    assert dp <= 1e-12 * m * v0
    assert de <= 1e-6
    assert v[-1, 0] >= 0.99 * v0
    assert np.all(np.linalg.norm(v[:-1], axis=1) <= 0.01 * v0)
    # Head-on along x through the centres: no sideways motion, no spin.
    assert np.all(np.abs(v[:, 1:]) <= 1e-12 * v0)
    assert np.all(np.abs(world.bodies.angular_velocity) <= 1e-12)
    # Angular momentum about the origin: all motion is along the x axis (r ∥ p).
    assert dl <= 1e-12 * m * v0 * (n * 2 * R)


@pytest.mark.parametrize("gap", [1e-3, 0.0], ids=["1mm", "touching"])
def test_two_balls_in_two_balls_out(gap):
    # Two coming in at v0 send the last two out at v0: still the same bars per ball.
    n, v0 = 5, 2.0
    world = cradle(n, gap, v0, movers=2)
    m = world.bodies.mass[0]
    dp, dl, de, v = run(world, 0.5)
    assert dp <= 1e-12 * 2 * m * v0
    assert de <= 1e-6
    assert np.all(v[-2:, 0] >= 0.99 * v0)
    assert np.all(np.linalg.norm(v[:-2], axis=1) <= 0.01 * v0)


@pytest.mark.parametrize("v0", [0.05, 0.5, 2.0])
def test_cradle_with_default_friction_and_threshold(v0):
    # The defaults: friction 0.5 (nothing slides sideways in a head-on line, so
    # friction must not change anything) and the default restitution threshold,
    # twice what gravity gives in a substep: none here, so every approach
    # bounces. (The default was a fixed 1 m/s: at 0.05 and 0.5 m/s the balls
    # came out of their impacts together, as if plastic: 80 % of the energy lost
    # over five balls at 1 m/s.)
    n = 5
    world = cradle(n, 1e-3, v0, friction=0.5, threshold=None)
    assert "friction" in world.stages
    m = world.bodies.mass[0]
    dp, dl, de, v = run(world, 0.1 / v0 + 0.5)  # the first ball starts 10 cm away
    assert dp <= 1e-12 * m * v0
    assert de <= 1e-6
    assert v[-1, 0] >= 0.99 * v0
    assert np.all(np.linalg.norm(v[:-1], axis=1) <= 0.01 * v0)


@pytest.mark.parametrize("sleep", [True, False], ids=["sleep", "no sleep"])
@pytest.mark.parametrize("gap", [1e-3, 0.0], ids=["1mm", "touching"])
def test_cradle_resting_on_a_frictionless_floor(gap, sleep):
    # Under gravity, on a frictionless plane: the floor pushes only vertically, so the
    # horizontal momentum keeps the 1e-12 bar; the balls stay on the floor (no vertical
    # speed beyond round-off of g h), so kinetic energy alone keeps the 1e-6 bar.
    n, v0 = 5, 2.0
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True, friction=0.0)
    for i in range(n):
        scene.add_body(
            rr.Sphere(R), density=7800.0, position=(i * (2 * R + gap) - (0.1 if i == 0 else 0.0), 0.0, R),
            linear_velocity=(v0 if i == 0 else 0.0, 0.0, 0.0), restitution=1.0, friction=0.0,
        )
    world = scene.build(dt=DT, restitution_threshold=0.0, sleep=sleep)
    m = world.bodies.mass[1]
    px0, e0 = world.linear_momentum()[0], world.kinetic_energy()
    dp = de = 0.0
    for _ in range(120):
        world.step(1)
        dp = max(dp, abs(world.linear_momentum()[0] - px0))
        de = max(de, abs(world.kinetic_energy() - e0) / e0)
    v = world.bodies.linear_velocity[1:]
    assert dp <= 1e-12 * m * v0
    assert de <= 1e-6
    assert v[-1, 0] >= 0.99 * v0
    assert np.all(np.linalg.norm(v[:-1], axis=1) <= 0.01 * v0)
