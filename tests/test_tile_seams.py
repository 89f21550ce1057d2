"""Bodies sliding or rolling across a floor of fixed boxes catch on the seams.

Found by sliding a 0.2 m cube at 5 m/s (μ 0.3) and rolling a 0.1 m ball at
3 m/s across a floor of 0.5 m box tiles placed exactly edge to edge, flush on
top. On a `Plane` the cube keeps flat and stops after 4.238 m (Coulomb:
4.247) and the ball rolls on at 3 m/s. On the tiles the cube hops 7.7 cm,
spins up to 18 rad/s and stops after 1.76 m; the ball hops 9 cm and has
rolled 4.38 m instead of 7.5 after 2.5 s. A body resting a little into the
tile it is on reaches the next tile's top edge, whose contact normal leans
back against the motion (the "internal edge" or "ghost collision" of every
engine that collides the tiles one by one). The fix is to give such an edge
contact the normal of the face contact it lies in (as Jolt's internal edge
removal does): not done (README, known limitations).

References: on a flat floor, Coulomb friction stops a sliding cube after
v0² / (2 μ g) without lifting or turning it, and a ball rolling without
slipping keeps its speed (no rolling resistance). The bars (1 mm of lift,
1 % of distance) are far above what the plane gives (no lift, 0.2 % short).
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr

G, MU, HALF = 9.81, 0.3, 0.1


def travel(body: rr.Shape, speed: float, spin: float, tiles: bool) -> tuple[float, float]:
    """Distance along x after 2.5 s (m) and the largest lift (m)."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    if tiles:
        for i in range(-10, 10):
            for j in range(-2, 2):
                scene.add_body(rr.Box((0.25, 0.25, 0.25)), fixed=True, position=(0.5 * i + 0.25, 0.5 * j + 0.25, -0.25),
                               friction=MU)
    else:
        scene.add_body(rr.Plane(), fixed=True, friction=MU)
    b = scene.add_body(body, density=1000.0, position=(-3.0, 0.13, HALF), linear_velocity=(speed, 0.0, 0.0),
                       angular_velocity=(0.0, spin, 0.0), friction=MU)
    world = scene.build(dt=1 / 60)
    lift = 0.0
    for _ in range(150):
        world.step(1)
        lift = max(lift, float(world.bodies.position[b, 2]) - HALF)
    return float(world.bodies.position[b, 0]) + 3.0, lift


CASES = [("cube", rr.Box((HALF,) * 3), 5.0, 0.0, 5.0**2 / (2 * MU * G)),
         ("ball", rr.Sphere(HALF), 3.0, 30.0, 3.0 * 2.5)]


@pytest.mark.parametrize("name, body, speed, spin, expected", CASES, ids=[c[0] for c in CASES])
def test_on_a_plane_a_body_slides_or_rolls_as_coulomb_says(name: str, body: rr.Shape, speed: float, spin: float,
                                                           expected: float) -> None:
    distance, lift = travel(body, speed, spin, tiles=False)
    assert lift < 1e-3
    assert distance == pytest.approx(expected, rel=1e-2)


@pytest.mark.xfail(strict=True, reason="internal edges of flush box tiles: the cube hops 7.7 cm and stops after "
                   "1.76 m (4.247 expected), the ball hops 9 cm and rolls 4.38 m of 7.5 (measured)")
@pytest.mark.parametrize("name, body, speed, spin, expected", CASES, ids=[c[0] for c in CASES])
def test_across_flush_box_tiles_a_body_slides_or_rolls_as_on_a_plane(name: str, body: rr.Shape, speed: float,
                                                                      spin: float, expected: float) -> None:
    distance, lift = travel(body, speed, spin, tiles=True)
    assert lift < 1e-3, f"lifted {lift:.3g} m"
    assert distance == pytest.approx(expected, rel=1e-2)
