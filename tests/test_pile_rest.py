"""A tumbled pile of cubes comes to rest at the defaults.

400 cubes (0.5 m, 125 kg, μ 0.5) dropped as a loose lattice of four layers,
each turned by a small random angle (`test_pile_launch.lattice`, the scene of
`benches/peers/box_pile.py` at side 10), built with the defaults (sleeping on).
A user expects such a pile to settle and fall asleep within seconds; a cube
still moving at 1 mm/s after 30 s creeps 6 cm a minute. Bar: every cube slower
than 1 mm/s after 30 s, in every pour (which pours keep creeping changes with
round-off: one pour alone passes or fails by chance).
"""
import numpy as np
import pytest

from test_pile_launch import lattice

POURS = (1, 2, 3, 4)

PILES_CREEP = (
    "tumbled piles do not all come to rest: after 30 s at the defaults, 18 / 12 / 0 / 10 cubes of "
    "pours 1-4 move faster than 1 mm/s (fastest 1.1e-2 / 1.4e-2 / 2.3e-8 / 2.6e-3 m/s), and with sleeping off "
    "19 / 25 / 0 / 1 of pours 1-4. In pour 2 a cube standing on a column (351 on 251) is pushed "
    "sideways by a cube leaning on its side (361, 282 N through one corner): the column's support "
    "contacts are solved as blocks, exactly, the leaning corner by one soft Gauss-Seidel pass a "
    "substep between two moving bodies, and the two never agree: the cube keeps moving at 1-3 mm/s "
    "and once in a few steps the whole column under it is kicked at 1e-3 m/s. The world then takes "
    "16 rocking substeps for ever. The same state rebuilt without its warm starts stays at rest. "
    "Solving that corner rigidly instead (the law of contacts with fixed bodies) left 147 cubes "
    "moving in 12 pours instead of 209, but pressed box into box 0.36-0.61 mm instead of "
    "0.01-0.33 mm: not kept."
)


def fastest_after(seed: int, seconds: float = 30.0) -> tuple[int, float]:
    """The number of cubes faster than 1 mm/s, and the fastest (m/s), after `seconds`."""
    world = lattice(10, 4, seed).build(dt=1 / 60)
    world.step(int(round(seconds * 60)))
    speed = np.linalg.norm(world.bodies.linear_velocity[1:], axis=1)
    return int((speed > 1e-3).sum()), float(speed.max())


@pytest.mark.xfail(strict=True, reason=PILES_CREEP)
def test_a_tumbled_pile_of_cubes_comes_to_rest_in_every_pour():
    measured = {seed: fastest_after(seed) for seed in POURS}
    assert all(fastest <= 1e-3 for _, fastest in measured.values()), measured
