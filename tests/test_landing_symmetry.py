"""A cube dropped tilted about one of its face axes lands square on an edge, turns
down onto its face and rests. The scene is its own mirror image across the plane
through the cube's centre normal to the tilt axis, so by that symmetry the cube can
neither turn about the other two axes nor move along the tilt axis: with tilt
axis x, ``v_x``, ``ω_y`` and ``ω_z`` stay zero (reference: 0 exactly).

Bar: 1e-3 m/s and rad/s, a millimetre a second, below anything a user sees. What
is left is the position pass, whose projected Gauss–Seidel still takes a face's
points one at a time (measured ≤ 5.3e-5 m/s and ≤ 1.5e-4 rad/s; 4e-9 without
friction) over the first 0.5 s; before the fix the same drops left 0.3–1.9 rad/s.

Watched until the cube rests (2 s; until stop 40 only its first 0.5 s, while it
still rocks on its edge): a mode across the mirror plane
(v along the edge, ω about the other face axis) alternates in sign and grows
×1.3–1.8 a step from round-off while the cube rocks (9e-5 rad/s at 0.5 s), and
when the face comes down (0.7–0.8 s) it breaks the symmetry at every tilt
tried (0.1, 0.2, 0.3 rad; up to 0.68 rad/s about the vertical at 0.1): strict
xfails below, with the numbers. Without friction the cube keeps it.

Regression: the two corners of the landing edge were solved one after the other,
the first took 5 % more impulse, and a cube landing at 8.5 m/s with restitution 0
left spinning about the vertical at up to 1.9 rad/s (0.33 rad/s at a 0.1 rad tilt);
a face slapping down after it took 216 and 42 N·s on two mirrored corners.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rigidrs as rr

HALF = 0.25
SPEED = 8.5  # m/s at first touch, as the top of a ten-cube column lands
BAR = 1e-3


def drop(axis: int, tilt: float, friction: float, seconds: float = 2.0) -> np.ndarray:
    """Largest |v_along axis|, |ω about the other two axes| over `seconds` at dt 1/60 s."""
    e = np.zeros(3)
    e[axis] = 1.0
    q = (*(e * math.sin(tilt / 2)), math.cos(tilt / 2))
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True, friction=friction, restitution=0.0)
    scene.add_body(
        rr.Box((HALF, HALF, HALF)), density=1000.0, position=(0.0, 0.0, HALF * math.sqrt(3) + 0.01),
        orientation=q, linear_velocity=(0.0, 0.0, -SPEED), friction=friction, restitution=0.0,
    )
    world = scene.build(dt=1.0 / 60.0)
    others = [k for k in range(3) if k != axis]
    worst = np.zeros(3)
    for _ in range(round(seconds * 60)):
        world.step()
        v, w = world.bodies.linear_velocity[1], world.bodies.angular_velocity[1]
        worst = np.maximum(worst, np.abs([v[axis], w[others[0]], w[others[1]]]))
    return worst


ROCKING = pytest.mark.xfail(strict=True, reason=(
    "a mode across the mirror plane grows x1.3-1.8 a step from round-off while the cube rocks on its "
    "edge and breaks the symmetry as its face comes down: worst |v_axis|, |w| across over 2 s = "
    "0.14 m/s, 0.25 and 0.68 rad/s at tilt 0.1 (both axes); 3.8e-3, 1.2e-2, 1.6e-3 (axis 0) and "
    "0.025, 0.099, 0.063 (axis 1) at tilt 0.2; 4e-4, 4.0e-3, 2.3e-3 at tilt 0.3; within the first "
    "0.5 s at most 1.2e-4 and 3.5e-4"))


@pytest.mark.parametrize("axis", [0, 1])
@pytest.mark.parametrize("tilt", [0.1, 0.2, 0.3])
@ROCKING
def test_cube_landing_square_on_an_edge_keeps_its_mirror_symmetry(axis: int, tilt: float) -> None:
    worst = drop(axis, tilt, friction=0.5)
    assert np.all(worst <= BAR), f"tilt {tilt} about axis {axis}: |v_axis|, |ω| across = {worst}"


@pytest.mark.parametrize("axis", [0, 1])
@pytest.mark.parametrize("tilt", [0.1, 0.2, 0.3])
def test_cube_landing_square_on_an_edge_keeps_its_mirror_symmetry_while_it_rocks(axis: int, tilt: float) -> None:
    # The first 0.5 s, while it rocks on its edge (the bar this test held
    # until stop 40, which the rest of the fall does not meet).
    worst = drop(axis, tilt, friction=0.5, seconds=0.5)
    assert np.all(worst <= BAR), f"tilt {tilt} about axis {axis}: |v_axis|, |ω| across = {worst}"


def test_cube_landing_square_without_friction_keeps_its_mirror_symmetry() -> None:
    worst = drop(0, 0.2, friction=0.0)
    assert np.all(worst <= BAR), worst
