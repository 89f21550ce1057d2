"""A box sliding straight across a triangulated or tiled floor turns about the vertical.

Found by sliding a 0.2 m cube (μ 0.3, 5 m/s along x) over a flat
10 × 10 m floor given as a `TriMesh` of 20 × 20 squares split along their
diagonals: it yawed up to 7.8 rad/s and slid 4.372 m, where on a `Plane` it
keeps its heading (yaw rate below 1e-10 rad/s) and stops after 4.238 m. On a
floor of two triangles it slides straight until it crosses the diagonal, then
yaws at up to 0.54 rad/s. Over flush box tiles, straddling a seam along its
path (0.05 m off it), it yawed up to 8.7 rad/s, drifted 0.43 m aside and
stopped after 2.16 m (on the seam itself: 3.1 rad/s, 1.81 m). parry gives one
manifold per triangle (and each tile is a pair of its own), and rigidrs
one friction patch per manifold: a face resting on several triangles is held
by several patches, each limited by its own share of the load, and how a
rigid face's load splits between them is arbitrary, so their forces need not
add up to no torque. The fix is one patch for a body's coplanar manifolds
against fixed shapes (not done: README, known limitations).

Reference: Coulomb friction on a flat face sliding without turning acts
against the slip at every point, so it has no moment about the vertical
through the face's centre of pressure, which for a cube on a level floor lies
under its centre: the yaw rate stays zero and the box stops after
v0² / (2 μ g). The bar, 0.01 rad/s and 1 %, is far above the plane's
round-off and the first order of the contact substeps (0.2 % short here).
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr
from test_tile_seams import floor_tiles

G, MU, V0, HALF = 9.81, 0.3, 5.0, 0.1


def floor(cells: int, size: float = 10.0) -> rr.TriMesh:
    xs = np.linspace(-size / 2, size / 2, cells + 1)
    vertices = np.array([[x, y, 0.0] for y in xs for x in xs])
    faces = []
    for j in range(cells):
        for i in range(cells):
            a = j * (cells + 1) + i
            faces += [[a, a + 1, a + cells + 2], [a, a + cells + 2, a + cells + 1]]
    return rr.TriMesh(vertices, np.array(faces))


def slide(ground: rr.Shape | None, y: float = 0.13) -> tuple[float, float]:
    """Largest yaw rate (rad/s) and distance slid (m) of the cube (`None`:
    on box tiles with seams along y = 0, ±0.5 m)."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    if ground is None:
        floor_tiles(scene, MU)
    else:
        scene.add_body(ground, fixed=True, friction=MU)
    box = scene.add_body(rr.Box((HALF,) * 3), density=1000.0, position=(-3.0, y, HALF),
                         linear_velocity=(V0, 0.0, 0.0), friction=MU)
    world = scene.build(dt=1 / 60)
    yaw = 0.0
    for _ in range(150):
        world.step(1)
        yaw = max(yaw, abs(float(world.bodies.angular_velocity[box, 2])))
    return yaw, float(world.bodies.position[box, 0]) + 3.0


def test_a_box_sliding_on_a_plane_keeps_its_heading() -> None:
    yaw, distance = slide(rr.Plane())
    assert yaw < 1e-2
    assert distance == pytest.approx(V0**2 / (2 * MU * G), rel=1e-2)


@pytest.mark.xfail(strict=True, reason="one friction patch per triangle's manifold: yaw up to 7.8 rad/s, "
                   "4.372 m slid against 4.247 (+2.9 %) on a floor of 20 x 20 squares (measured)")
def test_a_box_sliding_on_a_triangulated_floor_keeps_its_heading() -> None:
    yaw, distance = slide(floor(20))
    assert yaw < 1e-2, f"yaw rate up to {yaw:.3g} rad/s"
    assert distance == pytest.approx(V0**2 / (2 * MU * G), rel=1e-2)


@pytest.mark.xfail(strict=True, reason="one friction patch per tile: straddling a seam 0.05 m off its path the "
                   "cube yaws up to 8.7 rad/s and stops after 2.16 m of 4.247 (measured)")
def test_a_box_sliding_along_a_seam_of_box_tiles_keeps_its_heading() -> None:
    yaw, distance = slide(None, y=0.05)
    assert yaw < 1e-2, f"yaw rate up to {yaw:.3g} rad/s"
    assert distance == pytest.approx(V0**2 / (2 * MU * G), rel=1e-2)


def test_a_box_sliding_across_seams_of_box_tiles_keeps_its_heading() -> None:
    # Across the seams (none along its path), each seam splits the face front
    # and back, symmetric about the path: it slides as on a plane.
    yaw, distance = slide(None, y=0.13)
    assert yaw < 1e-2
    assert distance == pytest.approx(V0**2 / (2 * MU * G), rel=1e-2)
