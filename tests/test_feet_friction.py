"""A body standing on two feet turned about the vertical while it slid.

Found while fixing the triangulated floor (`test_mesh_floor_friction.py`): a
compound of a 0.2 × 0.2 × 0.1 m box and a second box 0.3 m apart across its
path, sliding at 5 m/s (μ 0.3), yawed at up to 3.4 rad/s on a `Plane` with
equal feet (3.2 with one foot half the size), and up to 2.1 rad/s on
triangulated floors. Each foot was a friction patch of its own, limited by its
own load, and a rigid body on eight points carries its load in any split
that balances its moments (1 : 5 for equal feet: the inner edge of one, the
outer edge of the other); the two frictions differed by a factor five and
turned the body. One patch over both feet at the centroid of their hull
(tried) holds equal feet but turns unequal ones (3.1 rad/s): the hull's
centroid is not under the centre of mass. Friction at each patch's centre of
pressure (tried) holds equal feet kept apart (0.011 rad/s) but lets the noise
of the substeps' loads turn a single face on a mesh (0.07–0.30 rad/s, from
1e-8). Fixed by one patch for a pair's manifolds of one normal, centred on
the centroid of the union of their polygons (`rust/solve/coplanar.rs`,
`rust/solve/friction.rs`): below 1e-10 rad/s on the plane and the floors
below, and the distance of a plane's box.

Reference: Coulomb friction on a body sliding without turning acts against
the slip at every point with the point's load, so its moment about the
vertical is that of the whole load at the centre of pressure, which lies
under the centre of mass for a body that does not roll: no yaw, and the
body stops after v0² / (2 μ g). Bars as in `test_mesh_floor_friction.py`.
"""
from __future__ import annotations

import pytest

import rigidrs as rr
from test_mesh_floor_friction import floor

G, MU, V0 = 9.81, 0.3, 5.0


def slide_on_feet(ground: rr.Shape, small: float) -> tuple[float, float]:
    """Largest yaw rate (rad/s) and distance slid (m) of two feet on `ground`,
    the second of half side `small` (m)."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(ground, fixed=True, friction=MU)
    feet = rr.Compound([(rr.Box((0.1, 0.1, 0.05)), (0.0, -0.15, 0.05)),
                        (rr.Box((small, small, 0.05)), (0.0, 0.15, 0.05))])
    body = scene.add_body(feet, density=1000.0, position=(-3.0, 0.13, 0.0),
                          linear_velocity=(V0, 0.0, 0.0), friction=MU)
    world = scene.build(dt=1 / 60)
    x0, yaw = float(world.bodies.position[body, 0]), 0.0
    for _ in range(150):
        world.step(1)
        yaw = max(yaw, abs(float(world.bodies.angular_velocity[body, 2])))
    return yaw, float(world.bodies.position[body, 0]) - x0


@pytest.mark.parametrize("cells", [0, 1, 20], ids=["plane", "two triangles", "20 x 20 squares"])
@pytest.mark.parametrize("small", [0.1, 0.05], ids=["equal feet", "unequal feet"])
def test_two_feet_slide_straight(cells: int, small: float) -> None:
    yaw, distance = slide_on_feet(floor(cells) if cells else rr.Plane(), small)
    assert yaw < 1e-2, f"yaw rate up to {yaw:.3g} rad/s"
    assert distance == pytest.approx(V0**2 / (2 * MU * G), rel=1e-2)
