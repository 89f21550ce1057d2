"""Tall towers of cubes, kicked a little, must stand and come to rest.

Thirty cubes of 0.5 m (ρ 1000, μ 0.5, restitution 0) stand in line on the
ground; every cube is kicked sideways and spun (σ 1 cm/s and 0.01 rad/s, or
ten times that). Reference, from energy: the kick (computed below) is less
than the least energy that tips any part of the tower over an edge of the
face it stands on, `M g (√(a² + h²) − h)` for the top `k` cubes (mass
`M = k m`, centre of mass `h = k a` above that face, `a` the half edge), and
contacts that are inelastic and rub only take energy out. So the tower stands
(top within 1 cm of its resting height) and comes to rest (every cube below
1 mm/s after 4 s).

Before `rust/solve/overshoot.rs` took up with a Gauss–Seidel pass what the
sweeps' step fraction threw away, the tower of thirty kicked at 1 cm/s kept
3–8 % of each sweep's change in its first step, its cubes fell into each other
at 6 cm/s and it collapsed (top 4.7–5.0 m low after 4 s). Over the 36 towers
of `examples/tower_matrix.rs` (10, 20, 30 cubes; aligned or 5 cm off axis;
two kicks; three seeds) at 60 Hz, 18 came to rest and 16 toppled; now all 36
come to rest, in a fifth of the CPU time. Rapier, same tower of thirty kicked
at 1 cm/s: stands 242 mm low (the sag of its soft contacts), jittering at
1 cm/s after 4 s.

At 1 kHz the rocking substeps took 16 substeps of 62.5 µs, and the kicked
column of ten of `tests/test_kicked_column.py` jittered at 0.9–1.7 cm/s for
ever, 16 substeps every step (2 of 36 towers at rest); the rocking substeps
are now at most 1/960 s long, none are added at 1 kHz and every one comes to
rest.

At 0.5 and 0.25 ms (substeps of 125 and 62.5 µs) 18 and 0 of the 36 towers
came to rest: the speed below which two moving bodies count as resting on each
other included the rest depth closed in one substep, which grows as 1/h
(`REST_CLOSING` in `rust/solve/support.rs`). Bounded, all 36 come to rest at
both.
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr
from rigidrs.work_precision.contact import KickedColumn

HALF, G, DT = 0.25, 9.81, 1.0 / 60.0
MASS = 1000.0 * (2 * HALF) ** 3
REST_SPEED, STAND = 1e-3, 0.01


def tower(n: int, kick: float, seed: int) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=0.5, restitution=0.0)
    rng = np.random.default_rng(seed)
    for k in range(n):
        v = rng.normal(size=3) * kick * np.array([1.0, 1.0, 0.0])
        w = rng.normal(size=3) * kick
        scene.add_body(rr.Box((HALF,) * 3), density=1000.0, position=(0.0, 0.0, HALF * (1 + 2 * k)),
                       linear_velocity=tuple(v), angular_velocity=tuple(w), friction=0.5, restitution=0.0)
    return scene.build(dt=DT, sleep=False)


def least_tipping_energy(n: int) -> float:
    """The least energy that tips the top k cubes (any k) over an edge of the face under them."""
    return min(k * MASS * G * (np.hypot(HALF, k * HALF) - k * HALF) for k in range(1, n + 1))


def unsettled(world: rr.World, n: int, steps: int) -> str:
    world.step(steps)
    speed = float(np.linalg.norm(world.bodies.linear_velocity[1:], axis=1).max())
    top = float(world.bodies.position[n, 2]) - HALF * (2 * n - 1)
    if abs(top) >= STAND or speed >= REST_SPEED:
        return f"top {top * 1e3:+.1f} mm, fastest cube {speed:.1e} m/s"
    return ""


@pytest.mark.parametrize("kick", [0.01, 0.1])
def test_kicked_tower_of_thirty_stands_and_comes_to_rest(kick: float) -> None:
    failed = []
    for seed in (1, 2, 3):
        world = tower(30, kick, seed)
        assert world.kinetic_energy() < least_tipping_energy(30)
        why = unsettled(world, 30, 240)
        if why:
            failed.append(f"seed {seed}: {why}")
    assert not failed, "; ".join(failed)


def test_kicked_column_at_one_kilohertz_comes_to_rest_without_extra_substeps() -> None:
    # The kicked column of ten (cubes 5 cm off each other's axis, σ 0.1 m/s
    # and 0.1 rad/s) at dt = 1 ms: the default 4 substeps are 250 µs, shorter
    # than the rocking substeps' 1/960 s, so none are added.
    failed = []
    for seed in (1, 2, 3):
        problem = KickedColumn()
        problem.cubes, problem.seed = 10, seed
        world = problem.scene(1).build(dt=1e-3, sleep=False)
        taken = set()
        for _ in range(4000):
            world.step(1)
            taken.add(world.last_substeps)
        assert taken == {4}
        why = unsettled(world, 10, 0)
        if why:
            failed.append(f"seed {seed}: {why}")
    assert not failed, "; ".join(failed)


@pytest.mark.parametrize("dt", [5e-4, 2.5e-4])
def test_kicked_column_at_fine_steps_comes_to_rest(dt: float) -> None:
    # The kicked column of ten at substeps of 125 and 62.5 µs. The speed
    # below which two moving bodies count as resting on each other grew as
    # 1/h there (the rest depth closed in a substep: 1.6 cm/s at 62.5 µs),
    # the sweeps held lower bodies that jittered at 1-2 cm/s, and the columns
    # never came to rest (0 of 36 kicked towers at 0.25 ms).
    failed = []
    for seed in (1, 2, 3):
        problem = KickedColumn()
        problem.cubes, problem.seed = 10, seed
        world = problem.scene(1).build(dt=dt, sleep=False)
        why = unsettled(world, 10, round(4.0 / dt))
        if why:
            failed.append(f"seed {seed}: {why}")
    assert not failed, "; ".join(failed)


def test_rocking_substeps_follow_the_step_length() -> None:
    # The same kicked column rocks at 30 Hz and 60 Hz: substeps of at most
    # 1/960 s are 32 and 16 a step while it does.
    for dt, n in [(1.0 / 30.0, 32), (1.0 / 60.0, 16)]:
        problem = KickedColumn()
        problem.cubes, problem.seed = 10, 3
        world = problem.scene(1).build(dt=dt, sleep=False)
        taken = []
        for _ in range(30):
            world.step(1)
            taken.append(world.last_substeps)
        assert max(taken) == n, (dt, taken)
