"""A body standing on two unequal feet turns about the vertical while it slides.

Found while fixing the triangulated floor (`test_mesh_floor_friction.py`): a
compound of a 0.2 × 0.2 × 0.1 m box and a 0.1 × 0.1 × 0.1 m box 0.3 m apart
across its path, sliding at 5 m/s (μ 0.3) on a `Plane`, yaws at up to 3.1
rad/s. The feet's manifolds share the plane, so they form one patch (see
`rust/solve/coplanar.rs`) whose friction acts at the centroid of the hull of
both feet; the body's centre of pressure lies under its centre of mass, which
for unequal feet is elsewhere, and the friction turns it. With equal feet the
two coincide and it slides straight. Kept apart, as a patch per foot, equal
feet yaw too (3.4 rad/s): each patch is limited by its own load, and a rigid
body on eight points carries its load in any split that balances its moments
(1 : 5 here). Friction at each patch's centre of pressure (tried) holds equal
feet apart (0.011 rad/s) but lets the noise of the substeps' loads turn a
single face on a mesh (0.07–0.30 rad/s, from 1e-8): not kept (README, known
limitations).

Reference: Coulomb friction on a body sliding without turning acts against
the slip at every point with the point's load, so its moment about the
vertical is that of the whole load at the centre of pressure, which lies
under the centre of mass for a body that does not roll: no yaw, and the
body stops after v0² / (2 μ g). Bars as in `test_mesh_floor_friction.py`.
"""
from __future__ import annotations

import pytest

import rigidrs as rr

G, MU, V0 = 9.81, 0.3, 5.0


def slide_on_feet(small: float) -> tuple[float, float]:
    """Largest yaw rate (rad/s) and distance slid (m) of two feet, the second
    of half side `small` (m)."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=MU)
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


def test_one_foot_slides_straight() -> None:
    # The same body on one foot's face (a box): one patch, no yaw.
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=MU)
    body = scene.add_body(rr.Box((0.1, 0.25, 0.05)), density=1000.0, position=(-3.0, 0.13, 0.05),
                          linear_velocity=(V0, 0.0, 0.0), friction=MU)
    world = scene.build(dt=1 / 60)
    yaw = 0.0
    for _ in range(150):
        world.step(1)
        yaw = max(yaw, abs(float(world.bodies.angular_velocity[body, 2])))
    assert yaw < 1e-2
    assert float(world.bodies.position[body, 0]) + 3.0 == pytest.approx(V0**2 / (2 * MU * G), rel=1e-2)


def test_two_equal_feet_slide_straight() -> None:
    # One patch over both feet: the hull's centroid is under the centre of
    # mass by symmetry.
    yaw, distance = slide_on_feet(0.1)
    assert yaw < 1e-2, f"yaw rate up to {yaw:.3g} rad/s"
    assert distance == pytest.approx(V0**2 / (2 * MU * G), rel=1e-2)


@pytest.mark.xfail(strict=True, reason="one patch over both feet, its friction at the centroid of their hull, "
                   "not under the centre of mass: yaw up to 3.1 rad/s, 4.259 m slid (measured)")
def test_two_unequal_feet_slide_straight() -> None:
    yaw, distance = slide_on_feet(0.05)
    assert yaw < 1e-2, f"yaw rate up to {yaw:.3g} rad/s"
    assert distance == pytest.approx(V0**2 / (2 * MU * G), rel=1e-2)
