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
    "tumbled piles do not all come to rest: after 30 s at the defaults 2 / 0 / 3 / 3 cubes of pours "
    "1-4 move faster than 1 mm/s (fastest 2.6e-3 / 2.9e-4 / 2.2e-3 / 2.2e-3 m/s); with sleeping off "
    "3 / 0 / 5 / 4 of pours 1-4. Before a block's projected Gauss-Seidel stopped once a sweep moved "
    "no row by the residual taken as solved: 5 / 0 / 0 / 7 (fastest 6.8e-3 / 6.9e-4 / 5.2e-6 / "
    "1.8e-2 m/s), sleeping off 7 / 4 / 0 / 3. Pour 4's column 9-109-209-309, its top leaning on "
    "cube 308 and sliding down its face on the friction cone, crept 1.2 mm in 10 s on the floor "
    "with |f|/N 0.014 there. Between 30 and 60 s cubes still creep (pour 4's cube 390, wedged in a "
    "V between a corner of 280 and an edge of 290 at |f|/N 0.42 and 0.29, sank 0.6 mm/s with a "
    "jitter of a few um a step for 27 s and fell 0.6 m; pours 1-6 had 8-57 cubes drift more than "
    "0.1 mm). Pour 1's state at 40 s, when a pile that rocks again right after being given back its "
    "4 substeps is held at the rocking substeps twice as long (rust/solve/rocking.rs), not every "
    "31 steps: 13 -> 3 cubes drifting more than 0.1 mm over 10 s. Before a settling pile took a "
    "second solver iteration "
    "(rust/solve/second_pass.rs): 18 / 12 / 0 / 10 at the defaults, 19 / 25 / 0 / 1 / 43 / 35 "
    "with sleeping off. The mechanism found in pour 2: a cube leaning through one corner on a "
    "column's top cube (361 on 351, 282 N) slid 14 mm in 10 s with both its contacts inside their "
    "friction cones (|f|/N 0.27 and 0.08 at mu 0.5), the column's support contacts solved as blocks, "
    "exactly, the leaning corner by one Gauss-Seidel pass a substep; with the second iteration it "
    "slides 1.9 mm in 10 s. Solving that corner rigidly instead of softly left 147 cubes moving in "
    "12 pours instead of 209 but pressed box into box 0.36-0.61 mm instead of 0.01-0.33 mm: not kept."
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
