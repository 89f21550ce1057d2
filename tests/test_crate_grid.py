"""Grids of cubes stacked exactly edge to edge (crates in a warehouse).

Each cube is placed exactly on the one below and exactly beside its
neighbours, so cubes of neighbouring columns one layer apart touch along an
edge, exactly. Before the fix, 5 × 5 columns of four 0.2 m cubes never came to
rest: after 1 s at dt 1/60, 55 of the 100 cubes moved faster than 1 mm/s (up to
5.3 mm/s), and a 10 × 10 grid drifted 3.6 mm in 4 s at 145 ms a step. Four
defects, each measured:

* parry clipped two box faces that share corners into each shared corner twice
  (a face of four corners became eight points, an edge line four): an edge
  counted as a face among the support contacts and the least-norm load split
  gave the doubled corners twice their share (at rest, the columns'
  neighbours carried 0.2 N·s of a cube's 0.65 N·s weight per step at their
  edges, with 0.08 N·s of friction). Merged (`collide/coincident_points.rs`).
* An island of support blocks solved at the first substep of a step took back
  a velocity below the solver's tolerance, and the warm start repeated that
  correction in each later substep (the echo), untaken-back because it was
  below the quiet bound: the column's speed grew fourfold a step from 1e-14 m/s
  until it rocked (16 substeps) at 1e-2 m/s. Now an echo is taken back while it
  exceeds a thousandth of the change that made it (`solve/quiet.rs`).
* parry's separating-axis test of two boxes took an edge–edge axis over the
  face normal when round-off put it ahead by 1e-17 m: a cube stacked exactly
  on another then touched it at two opposite corners, the weight warm-started
  at one, and the column was kicked at 0.6 rad/s (the 6 × 6 × 6 and 4 × 4 × 8
  grids). Such a manifold is clipped again on the face
  (`collide/touching_polyhedra.rs`).
* The warm start carries the last substep's impulses; a step that took the 16
  rocking substeps after steps of 4 re-applied four times the support in its
  first substep (the 10 × 10 grid jumped from 1e-14 to 4e-5 m/s at the switch),
  and the step back to 4 a quarter of it. The warm start is now scaled by the
  ratio of the substeps (`solve/contact.rs`).

Reference: statics. Rigid cubes resting face on face under gravity, none pushed,
stay where they were placed: speeds and displacements at round-off. The bars
(1 mm/s; 0.1 mm) are those a user sees as "moving"; the measured values are
1e-13 m/s and 1e-6 m or less.
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr

HALF = 0.1
DT = 1 / 60


def grid(side: int, layers: int, gap: float) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True)
    pitch = 2 * HALF + gap
    for k in range(side * side * layers):
        i, j, layer = k % side, k // side % side, k // (side * side)
        scene.add_body(rr.Box((HALF,) * 3), density=500.0, position=(i * pitch, j * pitch, HALF * (1 + 2 * layer)))
    return scene.build(dt=DT, sleep=False)


def moving(world: rr.World) -> np.ndarray:
    return np.abs(world.bodies.linear_velocity[1:]).max(axis=1) > 1e-3


def drift(world: rr.World, start: np.ndarray) -> float:
    return float(np.linalg.norm(world.bodies.position[1:] - start[1:], axis=1).max())


def test_a_grid_of_cubes_with_gaps_between_its_columns_rests() -> None:
    world = grid(5, 4, gap=1e-3)
    world.step(60)
    assert not moving(world).any()


@pytest.mark.parametrize(("side", "layers", "steps"), [(5, 4, 60), (5, 4, 240), (10, 4, 240), (8, 3, 240), (4, 8, 240), (6, 6, 240)])
def test_a_grid_of_cubes_stacked_exactly_edge_to_edge_rests(side: int, layers: int, steps: int) -> None:
    world = grid(side, layers, gap=0.0)
    start = world.bodies.position.copy()
    world.step(steps)
    assert not moving(world).any(), f"{int(moving(world).sum())} of {side * side * layers} cubes moving"
    assert drift(world, start) < 1e-4


def test_small_corrections_are_not_echoed_into_a_runaway() -> None:
    """The echo: before the fix (with the points merged) the fastest cube of
    this grid sped up fourfold a step from 6e-15 m/s at step 22 to 2.5e-5 m/s at
    step 27. Round-off alone adds about 4e-16 m/s a step."""
    world = grid(5, 4, gap=0.0)
    fastest = []
    for _ in range(240):
        world.step(1)
        fastest.append(float(np.abs(world.bodies.linear_velocity[1:]).max()))
    assert max(fastest) < 240 * 4e-16 * 10
    assert world.last_substeps == world.substeps


def test_corners_shared_by_two_boxes_are_one_point_each() -> None:
    """A cube stacked exactly on an equal one touches it at four corners, not
    eight; one beside it a layer up touches the lower one along an edge, at its
    two ends, not four. Each corner of the face carries a quarter of the upper
    cube's weight (the least-norm split of a symmetric face), m g dt / 4."""
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True)
    lower = scene.add_body(rr.Box((HALF,) * 3), density=500.0, position=(0.0, 0.0, HALF))
    upper = scene.add_body(rr.Box((HALF,) * 3), density=500.0, position=(0.0, 0.0, 3 * HALF))
    beside = scene.add_body(rr.Box((HALF,) * 3), density=500.0, position=(2 * HALF, 0.0, HALF))
    world = scene.build(dt=DT, sleep=False)
    world.step(10)
    c = world.contacts()
    pair = lambda a, b: ((c["body_a"] == a) & (c["body_b"] == b)) | ((c["body_a"] == b) & (c["body_b"] == a))
    face = pair(lower, upper)
    assert face.sum() == 4
    assert pair(beside, upper).sum() == 2
    mass = 500.0 * (2 * HALF) ** 3
    np.testing.assert_allclose(c["normal_impulse"][face], mass * 9.81 * DT / 4, rtol=1e-6)
