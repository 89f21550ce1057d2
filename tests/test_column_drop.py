"""A column of flat cubes dropped onto each other from 2 cm must stand.

Axis-aligned 0.5 m cubes (ρ 1000, μ 0.5, restitution 0), each offset sideways
by up to 5 cm and 2 cm above the one under it, fall together and land face on
face. Every contact is a flat face whose normal impulses are vertical: nothing
pushes a cube sideways, so (reference, exact) no cube moves horizontally, and
the column comes to rest at the heights of a column of touching cubes,
`HALF + 2 HALF k`, because the centre of mass above every contact stays inside
the face under it (checked below from the offsets).

Bars: 1 cm sideways, a tenth of the largest offset between neighbours, and
1 cm in height; at rest within 1 cm/s after 4 s.

Regression: from eight cubes on such a column jiggled at 0.2-0.5 m/s and
toppled (top cube 2.4-5 m away; four to seven slid 0.5-4 cm), where Rapier's
column of twelve stands. The landings, faster than the 4 g h that counts as
settled, went to one Gauss-Seidel pass a substep, which pushed each cube
under a landing into its supports after their sweep; it ended the substep
moving down at ~0.3 m/s, lifted back by the position pass, for ever. Now a
flat landing on one face is held on the body under it (`rust/solve/support.rs`,
`LANDING`), and every column of 3 to 12 cubes, seeds 1-3, rests exactly:
sideways < 1e-11 m, at rest to 3e-12 m/s.
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr

HALF, GAP, G, DT = 0.25, 0.02, 9.81, 1.0 / 60.0
BAR = 0.01


def column(n: int, seed: int = 1) -> tuple[rr.World, np.ndarray]:
    rng = np.random.default_rng(seed)
    offsets = rng.uniform(-0.05, 0.05, size=(n, 2))
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=0.5, restitution=0.0)
    for k, (x, y) in enumerate(offsets):
        scene.add_body(rr.Box((HALF, HALF, HALF)), density=1000.0, friction=0.5, restitution=0.0,
                       position=(x, y, HALF + GAP / 2 + k * (2 * HALF + GAP)))
    return scene.build(dt=DT, sleep=False), offsets


def stands_statically(offsets: np.ndarray) -> bool:
    """The centre of mass of the cubes above each contact lies inside the face under it."""
    return all(np.all(np.abs(offsets[k:].mean(axis=0) - offsets[k - 1]) < HALF) for k in range(1, len(offsets)))


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("n", [3, 6, 8, 12])
def test_column_of_flat_cubes_dropped_2cm_stands(n: int, seed: int) -> None:
    world, offsets = column(n, seed)
    assert stands_statically(offsets)
    world.step(240)
    b = world.bodies
    sideways = np.hypot(*(b.position[1:, :2] - offsets).T).max()
    heights = np.abs(b.position[1:, 2] - (HALF + 2 * HALF * np.arange(n))).max()
    speed = max(np.abs(b.linear_velocity[1:]).max(), HALF * np.abs(b.angular_velocity[1:]).max())
    assert sideways <= BAR and heights <= BAR and speed <= BAR, (sideways, heights, speed)
