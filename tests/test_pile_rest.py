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

POURS = range(1, 9)

PILES_CREEP = (
    "tumbled piles do not all come to rest: after 30 s at the defaults 0 / 0 / 0 / 0 / 7 / 0 / 0 / 0 "
    "cubes of pours 1-8 move faster than 1 mm/s (fastest 1.9e-12 / 2.0e-12 / 5.2e-4 / 0 / 4.7e-3 / "
    "9.7e-4 / 1.7e-9 / 2.0e-9 m/s), since an island whose sweeps overshot gets Gauss-Seidel alone in "
    "the next velocity pass (rust/solve/overshoot.rs, remedy 3; stop 61). Before: 0 / 0 / 0 / 0 / 7 / 1 / 1 / 0 "
    "(fastest 1.9e-9 / 9.9e-12 / 1.1e-12 / 2.7e-10 / "
    "2.9e-3 / 1.2e-3 / 1.2e-3 / 1.9e-12 m/s), since the exact face solves multiply by the reciprocals "
    "of their factor's diagonal (small_lcp.rs: other round-off). The driver, found at stop 53: from the "
    "creeping state at 30 s, the same 10 s without the support blocks' position pass (position.rs) move "
    "every cube of pours 6 and 7 at most 0.14 / 0.18 mm and leave nothing faster than 1 mm/s in pours 5-7 "
    "(pour 5's three fastest moved 0.05 mm, though another of its cubes moved 26 mm), against 5.9 / 8.7 / "
    "2.0 mm with it; without the relax pass's friction, or with the blocks swept again after the "
    "velocity pass's friction, they creep as before. Pour 6: the column 68-168-268-368, its top leant on "
    "sideways by 358 (on a 28-degree face of 258), every contact inside its cone (|f|/N 0.08-0.33), 368 "
    "creeping at 0.9 mm/s. Skipping the position push of a block whose body leans on another moving body "
    "set pour 7 at rest and pour 5 under the bar, and left pour 6 creeping (5.7 mm in 10 s): not kept. Of the cubes reported fastest, pour 5's "
    "389 (2.9 mm/s) moved 0.005 mm/s on average from 30 to 40 s, its 233 (2.0 mm/s) 0.59 mm/s; pour 6's "
    "368 (1.2 mm/s) 0.87 mm/s; pour 7's 253 (1.2 mm/s) 0.20 mm/s. A second sweep of every island "
    "after the relax pass's friction (tried at stop 51) set pour 5 at rest and left pours 6 and 7 "
    "creeping (cubes 347 and 315 reporting 1.4 and 2.1 mm/s): not kept. Before (stop 50): 0 / 0 / 0 / 0 / "
    "1 / 2 / 0 / 0 cubes (fastest 2.1e-12 / 0 / 1.2e-14 / 1.1e-9 / 1.1e-3 / 1.7e-3 / 0 / 2.1e-9 m/s), "
    "after still pairs kept their manifolds (narrow_phase.rs, STILL). Before that: 0 / 3 / 0 / 0 in pours 1-4 (fastest 1.7e-12 / 4.0e-3 / 3.3e-13 / 6.2e-9 m/s; "
    "sleeping off the same counts); of pours 1-6, 0 / 2 / 0 / 0 / 6 / 5 still moved at 60 s. Before a patch's friction "
    "shares were cleared from points beyond the prediction (solve/contact.rs finish: a stale share "
    "pushed pour 4's cube 390, wedged in a V between cubes 280 and 290 at |f|/N 0.42 and 0.29, down "
    "the groove at 0.6 mm/s until it fell 0.6 m): 2 / 0 / 2 / 5 at 30 s, 8 / 0 / 1 / 7 / 21 / 7 at 60 s. "
    "Before a block's projected Gauss-Seidel stopped once its rows' velocities had converged: "
    "5 / 0 / 0 / 7; before a settling pile took a second solver iteration: 18 / 12 / 0 / 10. Pour 2's "
    "mechanism, found at stop 42: a cube leaning through one corner on a column's top cube (361 on "
    "351, 282 N) slid 14 mm in 10 s with both its contacts inside their friction cones, the column's "
    "support contacts solved as blocks, exactly, the leaning corner by one Gauss-Seidel pass a "
    "substep (1.9 mm in 10 s with the second iteration). Pour 5's, found at stop 49: its fastest, cube "
    "389, reports 1.0-1.1 mm/s downward while its centre moves 0.11 mm/s; it stands on 289 (itself "
    "sliding at 0.17 mm/s) and carries 399, which leans on its side at the edge of its cone (|f|/N "
    "0.50 = mu): the velocity reported is what the relax pass leaves after 399's friction, which the "
    "next substep's sweep of 389's support block takes back."
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
