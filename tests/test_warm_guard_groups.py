"""Regression: one collapsing pile took the warm start of every other.

The warm guard (`rust/solve/warm_guard.rs`) does a velocity pass again from
zero impulses where the warm start pumped energy into a group of bodies in
contact. It used to do so for the whole world: in the 4000-cube tumbling pile
of `test_pile_launch.py` it fired in 62 % of the substeps, every contact of the
pile lost its warm start each time, and the columns of the pile, solved from
zero again and again, sank (mean height at 2 s 1.93-1.95 m, Rapier's 2.47 m;
contacts up to 21 cm deep). Now only the groups that gained energy are done
again (mean height 2.46 m, deepest contact 10 cm).

Reference, exact: bodies that share no contact with the pile move as they
would in a world of their own, to the bit, so a column standing beside a
tumbling pile steps exactly as the same column alone. Both worlds are built
with `substeps=4`: by default a world takes more substeps while a slow body
rocks on its supports anywhere in it (`rust/solve/rocking.rs`), which the
pile's cubes do, and the column alone would then step with other substeps.
"""
import numpy as np

import rigidrs as rr

HALF = 0.25


def world(with_pile: bool) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True, friction=0.5, restitution=0.0)
    box = rr.Box((HALF, HALF, HALF))
    for k in range(8):  # a column set down touching, offset by 2 cm a cube
        scene.add_body(box, density=1000.0, friction=0.5, restitution=0.0,
                       position=(-50.0 + 0.02 * (k % 2), 0.0, HALF + 2 * HALF * k))
    if with_pile:
        rng = np.random.default_rng(1)
        pitch = 2 * HALF * np.sqrt(3) + 0.05
        for k in range(6):
            for i in range(5):
                for j in range(5):
                    axis = rng.normal(size=3)
                    axis /= np.linalg.norm(axis)
                    angle = rng.uniform(0.05, 0.3)
                    scene.add_body(box, density=1000.0, friction=0.5, restitution=0.0,
                                   position=(i * pitch, j * pitch, HALF + 0.05 + k * pitch),
                                   orientation=(*(axis * np.sin(angle / 2)), np.cos(angle / 2)))
    return scene.build(dt=1 / 60, sleep=False, substeps=4)


def test_a_collapsing_pile_leaves_a_column_elsewhere_as_it_would_be_alone() -> None:
    alone, beside = world(False), world(True)
    column, tumbling = slice(1, 9), 0.0
    for _ in range(90):
        alone.step(1)
        beside.step(1)
        for view in ("position", "orientation", "linear_velocity", "angular_velocity"):
            a = getattr(alone.bodies, view)[column]
            b = getattr(beside.bodies, view)[column]
            assert np.array_equal(a, b), (view, alone.steps, np.abs(a - b).max())
        tumbling = max(tumbling, beside.kinetic_energy())
    assert tumbling > 1e5  # the pile did tumble: 150 cubes of 125 kg at ~5 m/s
