"""``threads=``: a world gives the same bits for every thread count, on scenes of
every kind (many islands, a pyramid, free bodies in large numbers so that the
parallel stages run, articulations, cloth, contact scenes with enough pairs that
the narrow phase and the constraints' build run in parallel), and bad counts are
refused."""
from __future__ import annotations

from typing import Callable

import numpy as np
import pytest

import rigidrs as rr
from snapshot_scenes import SCENES, assert_same, state

G = 9.81


def stacks(n: int = 16, height: int = 3) -> rr.World:
    """``n`` separate stacks of boxes: as many islands."""
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    for s in range(n):
        for k in range(height):
            scene.add_body(rr.Box((0.1, 0.1, 0.1)), density=500.0, position=(0.5 * (s % 20), 0.5 * (s // 20), 0.1 + 0.21 * k))
    return scene.build(dt=1 / 60, sleep=False)


def free_bodies(n: int = 13_000) -> rr.World:
    """Free boxes, rods and balls, 4333 of each class: over the 4096 bodies of a
    list that the parallel rotation takes; one in 50 fast enough for rotation
    substeps."""
    scene = rr.Scene(gravity=(0, 0, -G))
    rng = np.random.default_rng(1)
    shapes = [rr.Box((0.05, 0.1, 0.2)), rr.Box((0.05, 0.05, 0.2)), rr.Sphere(0.1)]
    for k in range(n):
        w = rng.normal(size=3) * (60.0 if k % 50 == 0 else 5.0)
        scene.add_body(shapes[k % 3], density=1000.0, position=(k, 0, 0), angular_velocity=w)
    return scene.build(dt=1 / 60)


# Contact pairs from which a step runs on the pool and splits its narrow phase
# and the constraints' build over threads (`MIN_PARALLEL_PAIRS` in
# narrow_phase.rs). A step with support islands to sweep side by side goes
# there too: the heap's, checked in Rust (`island_sweeps.rs`).
PARALLEL_PAIRS = 4096
# Pairs of shapes other than two balls, their manifolds found again, from
# which a step goes there too (`MIN_PARALLEL_MANIFOLD_PAIRS`): their manifolds
# cost far more to find and build. (A pyramid at rest keeps its manifolds: it
# goes to the pool in its first steps only.)
PARALLEL_MANIFOLD_PAIRS = 640


def ball_pit(n: int = 3000, floor: rr.Shape | None = None) -> rr.World:
    """Balls poured in a box, touching from the first step: ball pairs (on
    `floor`, default a plane, under a layer of cubes when given)."""
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(floor or rr.Plane(), fixed=True)
    for x, y in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        scene.add_body(rr.Plane(normal=(-x, -y, 0), offset=-1.0), fixed=True)
    rng = np.random.default_rng(2)
    for k in range(n):
        jitter = rng.uniform(-0.005, 0.005, size=2)
        x, y, z = (k % 10 - 4.5) * 0.2 + jitter[0], (k // 10 % 10 - 4.5) * 0.2 + jitter[1], 0.1 + 0.199 * (k // 100)
        shape = rr.Box((0.095,) * 3) if floor is not None and k < 100 else rr.Sphere(0.1)
        scene.add_body(shape, density=1000.0, position=(x, y, z))
    return scene.build(dt=1 / 60, sleep=False)


def box_heap(n: int = 1200) -> rr.World:
    """Cubes tilted at random, dropped in layers onto each other and the ground:
    box manifolds that appear, vanish and keep their geometry, and support blocks."""
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    rng = np.random.default_rng(3)
    for k in range(n):
        axis = rng.normal(size=3)
        q = np.append(np.sin(0.05) * axis / np.linalg.norm(axis), np.cos(0.05))
        x, y, z = (k % 20) * 0.23, (k // 20 % 20) * 0.23, 0.12 + 0.23 * (k // 400)
        scene.add_body(rr.Box((0.1, 0.1, 0.1)), density=500.0, position=(x, y, z), orientation=q)
    return scene.build(dt=1 / 60, sleep=False)


def ball_pit_on_triangles() -> rr.World:
    """The ball pit on a floor of 0.25 m squares cut in triangles, its lowest
    layer cubes: each cube on two to eight triangles, their manifolds gathered
    into one constraint (`rust/solve/coplanar.rs`), in the parallel build."""
    from test_mesh_floor_friction import floor
    return ball_pit(floor=floor(8, size=2.0))


BUILDERS: dict[str, Callable[[], rr.World]] = {
    "stacks": stacks,
    "pyramid": SCENES["pyramid"],
    "free_bodies": free_bodies,
    "chain_over_box": SCENES["chain_over_box"],
    "xpbd_joints": SCENES["xpbd_joints"],
    "cloth": SCENES["cloth"],
    "kicked_column": SCENES["kicked_column"],
    "tile_floor": SCENES["tile_floor"],
    "wheels": SCENES["wheels"],
    "ball_pit": ball_pit,
    "ball_pit_on_triangles": ball_pit_on_triangles,
    "box_heap": box_heap,
    "many_stacks": lambda: stacks(n=400),
    "pyramid_of_465_boxes": lambda: SCENES["pyramid"](30),
}
PARALLEL_CONTACTS = {"ball_pit": PARALLEL_PAIRS, "ball_pit_on_triangles": PARALLEL_PAIRS,
                     "pyramid_of_465_boxes": PARALLEL_MANIFOLD_PAIRS}


@pytest.mark.parametrize("name", list(BUILDERS))
def test_every_thread_count_gives_the_same_bits(name: str) -> None:
    runs = []
    for threads in (1, 2, 3):
        world = BUILDERS[name]()
        world.threads = threads
        assert world.threads == threads
        world.step(30)
        runs.append(state(world))
        if name in PARALLEL_CONTACTS:
            c = world.contacts()
            pairs = {(a, b) for a, b in zip(c["body_a"], c["body_b"])}
            least = PARALLEL_CONTACTS[name]
            assert len(pairs) >= least, f"{len(pairs)} touching pairs: the parallel stages would not run"
    assert_same(runs[0], runs[1])
    assert_same(runs[0], runs[2])


def test_threads_is_a_build_argument_and_bad_counts_are_refused() -> None:
    scene = rr.Scene()
    scene.add_body(rr.Sphere(0.1), mass=1.0)
    assert scene.build(0.01, threads=3).threads == 3
    assert scene.build(0.01).threads >= 1  # default: every core
    with pytest.raises(rr.RigidError, match="threads must be at least 1, got 0"):
        scene.build(0.01, threads=0)
    with pytest.raises(ValueError, match="threads must be an integer"):
        scene.build(0.01, threads=-2)
    world = scene.build(0.01)
    with pytest.raises(ValueError, match="threads must be an integer"):
        world.threads = 0
    # The count travels with the world (snapshots, pickles).
    import pickle
    world.threads = 2
    assert pickle.loads(pickle.dumps(world)).threads == 2
