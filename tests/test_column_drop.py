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

Measured (seeds 1-3): three cubes meet the bars (sideways 0.6-0.8 mm, at rest
to 1e-14 m/s); four to seven slide 0.5-4 cm sideways before they rest; from
eight on the column jiggles at 0.2-0.5 m/s after the landings (every cube
moving down at ~0.3 m/s after the velocity pass, pushed back out of up to 1 cm
of overlap by the position pass) and topples in 2 of 3 seeds, all 3 at twelve.
Rapier's column of twelve stands (its top 3.4 cm low from soft contacts).

The cause (`rust/solve/support.rs`): a contact whose bodies meet faster than
4 g h (0.16 m/s at 60 Hz) is no support contact that step, so the landings,
and the jiggle they start, go to one soft Gauss-Seidel pass per substep, and
contacts switch between that and the exact support solve from step to step.
Holding a lower body for a flat landing on one face up to 64 g h (2.6 m/s)
makes every one of these columns stand exactly (sideways 2e-12 m), but in the
4000-cube pile of `test_pile_launch.py` boxes are then thrown up (82 boxes
faster than 3 m/s, was 3) or, holding only on bodies held by slow contacts,
the pile's energy rises 1.2-1.5 % (bar 1 %, was 0.85-0.92 %): not landed.
Neither helps: rigid instead of soft Gauss-Seidel between moving bodies, or a
second support sweep after the Gauss-Seidel pass (twelve still topple).
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


def unmet(reason: str) -> pytest.MarkDecorator:
    return pytest.mark.xfail(strict=True, reason=reason)


@pytest.mark.parametrize("n", [
    3,
    pytest.param(6, marks=unmet("six cubes slide 4.0 cm sideways (seed 1) before they rest")),
    pytest.param(8, marks=unmet("eight cubes jiggle at 0.2-0.5 m/s and topple (seed 1: top 5 m away)")),
    pytest.param(12, marks=unmet("twelve cubes jiggle at 0.2-0.5 m/s and topple (seed 1: top 2.4 m away)")),
])
def test_column_of_flat_cubes_dropped_2cm_stands(n: int) -> None:
    world, offsets = column(n)
    assert stands_statically(offsets)
    world.step(240)
    b = world.bodies
    sideways = np.hypot(*(b.position[1:, :2] - offsets).T).max()
    heights = np.abs(b.position[1:, 2] - (HALF + 2 * HALF * np.arange(n))).max()
    speed = max(np.abs(b.linear_velocity[1:]).max(), HALF * np.abs(b.angular_velocity[1:]).max())
    assert sideways <= BAR and heights <= BAR and speed <= BAR, (sideways, heights, speed)
