"""Cubes laid in running bond (bricks in a wall), each layer shifted by half a
cube so every cube rests on two below, placed exactly.

Found this session after the crate-grid fixes (`tests/test_crate_grid.py`),
by trying the next stacking a user would build. A single row of such a wall
rests; two rows side by side, exactly touching, do not: in 8 × 2 bricks by six
courses (90 cubes), at step 76 the fastest cube jumps from 9e-14 to 3e-7 m/s
with no contact appearing, vanishing or changing its normal, the rocking
substeps come on and 89 of 90 cubes move after 4 s (up to 3.3 cm/s, 4.6 mm
from their places). Not fixed (README, known limitations); `0ef1ebd` did no
better (8 × 4 × 6: 178 of 180 moving, 5.5 cm/s; now 173, 2.7 cm/s).

Reference: statics. Rigid cubes resting on faces under gravity, none pushed,
stay where they were placed (speeds and displacements at round-off; bars
1 mm/s and 0.1 mm, as for the crate grids).
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr

HALF = 0.1


def wall(length: int, rows: int, courses: int) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True)
    for course in range(courses):
        shifted = course % 2 == 1
        for i in range(length - (1 if shifted else 0)):
            for j in range(rows):
                x = (HALF if shifted else 0.0) + 2 * HALF * i
                scene.add_body(rr.Box((HALF,) * 3), density=500.0, position=(x, 2 * HALF * j, HALF * (1 + 2 * course)))
    return scene.build(dt=1 / 60, sleep=False)


def at_rest(world: rr.World, start: np.ndarray) -> tuple[int, float]:
    moving = int((np.abs(world.bodies.linear_velocity[1:]).max(axis=1) > 1e-3).sum())
    return moving, float(np.linalg.norm(world.bodies.position[1:] - start[1:], axis=1).max())


def test_a_wall_one_brick_thick_rests() -> None:
    world = wall(8, 1, 6)
    start = world.bodies.position.copy()
    world.step(240)
    moving, drift = at_rest(world, start)
    assert moving == 0 and drift < 1e-4


@pytest.mark.xfail(strict=True, reason="8 x 2 bricks by 6 courses: 89 of 90 cubes above 1 mm/s after 4 s (3.3 cm/s), "
                   "4.6 mm drift; the first jump (9e-14 -> 3e-7 m/s at step 76) comes with no contact change (measured)")
def test_a_wall_two_bricks_thick_rests() -> None:
    world = wall(8, 2, 6)
    start = world.bodies.position.copy()
    world.step(240)
    moving, drift = at_rest(world, start)
    assert moving == 0 and drift < 1e-4, f"{moving} moving, drift {drift:.2e} m"
