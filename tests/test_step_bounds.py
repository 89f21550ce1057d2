"""No single step runs away in time (issue 10): absurd spins take at most 1024
rotation substeps per body and drift (they took 65 536: minutes per step for a
few bodies spun up by a runaway), and continuous collision detection of a body
at 1e4 m/s spinning at 1e4 rad/s is a bounded linear sweep of the ball that holds
it (parry's nonlinear sweep has no iteration bound) that still stops it at a wall.
"""
from __future__ import annotations

import numpy as np

import rigidrs as rr


def test_absurd_spins_take_capped_rotation_substeps_and_keep_their_momentum() -> None:
    # 256 boxes at |ω| = 1e6 rad/s, dt = 1/60: 16 667 rad a step, 83 000 splits
    # of strang's 0.2 rad uncapped; capped at 1024, each split turns a box by
    # ~16 rad, still a composition of exact rotations: |L| is kept to round-off
    # (1e-9 relative over 3 steps: ~1e3 splits of ~1e-16 each, and margin).
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    rng = np.random.default_rng(7)
    for k in range(256):
        w = rng.normal(size=3)
        scene.add_body(rr.Box((0.1, 0.2, 0.4)), density=1000.0, position=(3.0 * k, 0.0, 0.0),
                       angular_velocity=1e6 * w / np.linalg.norm(w))
    world = scene.build(dt=1 / 60)
    b = world.bodies
    _ = b.angular_momentum
    world.step(0)  # the derived arrays are fresh from the call after the first read
    before = np.linalg.norm(b.angular_momentum, axis=1)
    world.step(3)
    assert "rotate_fast" in world.stages
    after = np.linalg.norm(b.angular_momentum, axis=1)
    assert np.all(np.abs(after - before) <= 1e-9 * before)


def shoot_spinning_compound(ccd: bool) -> list[float]:
    """A box-and-ball compound (within 0.5 m of its centre) fired at a 1 cm wall
    (faces at x = ±5 mm) from 10 m at 1e4 m/s, spinning at 1e4 rad/s about z
    (10 rad per substep at 240 Hz, 4 substeps: past the π/2 that parry's
    nonlinear sweep is asked to follow); its centre's x after each step."""
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(rr.Box((0.005, 3.0, 3.0)), fixed=True)
    part = rr.Compound([(rr.Box((0.2, 0.1, 0.1)), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
                        (rr.Sphere(0.1), (0.3, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))])
    body = scene.add_body(part, density=1000.0, position=(-10.0, 0.0, 0.0), linear_velocity=(1e4, 0.0, 0.0),
                          angular_velocity=(0.0, 0.0, 1e4), ccd=ccd)
    world = scene.build(dt=1 / 240)
    xs = []
    for _ in range(10):
        world.step(1)
        xs.append(float(world.bodies.position[body, 0]))
    return xs


def test_ccd_of_a_compound_at_1e4_m_s_spinning_at_1e4_rad_s_stops_at_the_wall() -> None:
    # With CCD its centre never reaches the wall's plane x = 0 (the ball sweep
    # stops it at or before its first contact); without, it goes through (41 m a
    # step): the shot is a real tunnelling case.
    assert max(shoot_spinning_compound(ccd=True)) < 0.0
    assert max(shoot_spinning_compound(ccd=False)) > 1.0
