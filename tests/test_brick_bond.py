"""Cubes laid in running bond (bricks in a wall), each layer shifted by half a
cube so every cube rests on two below, placed exactly.

Found after the crate-grid fixes (`tests/test_crate_grid.py`), by trying the
next stacking a user would build. A single row of such a wall rested; two or
four rows side by side, exactly touching, did not: 8 × 2 bricks by six courses
(90 cubes) jumped from 9e-14 to 3e-7 m/s at step 76 with no contact change, and
after 4 s 89 of 90 cubes moved (up to 3.3 cm/s, 4.6 mm from their places);
8 × 4 × 6, 179 of 180 (5.6 cm/s). Two defects, each enough alone:

* a brick on two bricks whose tops differ by round-off rests on three of its
  four corners; the block's exact solve, which holds every row at its target,
  pulls at the fourth, which carries nothing, and that counted as rocking: the
  step switched to the rocking substeps (16), which jolted the wall at step 68
  (7 mm/s). A point now counts as letting go only if it carried load
  (`rust/solve/rocking.rs`);
* an island the sweeps had solved to 1e-11 m/s got a "fraction of the sweeps'
  change to keep" computed from round-off (0.31), and below 0.9 a Gauss–Seidel
  pass whose soft steps moved resting cubes at 3e-4 m/s; rows left within the
  residual taken as solved now keep the change whole
  (`rust/solve/overshoot.rs`). With the first fixed alone, 87 of 90 moved.

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


@pytest.mark.parametrize("rows", [2, 4])
def test_a_wall_several_bricks_thick_rests_on_its_unloaded_corners(rows: int) -> None:
    world = wall(8, rows, 6)
    start = world.bodies.position.copy()
    world.step(240)
    moving, drift = at_rest(world, start)
    assert moving == 0 and drift < 1e-4, f"{moving} moving, drift {drift:.2e} m"
