"""Regression: bodies sliding or rolling across a floor of fixed boxes caught on the seams.

Found by sliding a 0.2 m cube at 5 m/s (μ 0.3) and rolling a 0.1 m ball at
3 m/s across a floor of 0.5 m box tiles placed exactly edge to edge, flush on
top. On a `Plane` the cube keeps flat and stops after 4.238 m (Coulomb:
4.247) and the ball rolls on at 3 m/s. On the tiles the cube hopped 7.7 cm,
spun up to 18 rad/s and stopped after 1.76 m; the ball hopped 9 cm and had
rolled 4.38 m instead of 7.5 after 2.5 s. A body resting a little into the
tile it is on reaches the next tile's top edge, or its side face just below
it, whose contact normal points back against the motion (the "internal edge"
or "ghost collision" of engines that collide tiles one by one).
`rust/collide/internal_edges.rs` now gives a contact with a fixed shape that
lies within the plane of a face the body rests on (down to its sinking) that
face's normal. After: the cube slides 4.238 m and lifts 2e-8 m, the ball
rolls 7.5 m and lifts 1e-6 m. A real step and a wall still stop them.

References: on a flat floor, Coulomb friction stops a sliding cube after
v0² / (2 μ g) without lifting or turning it, and a ball rolling without
slipping keeps its speed (no rolling resistance). The bars (1 mm of lift,
1 % of distance) are far above what the plane gives (no lift, 0.2 % short).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rigidrs as rr

G, MU, HALF = 9.81, 0.3, 0.1


def tile(kind: str) -> rr.Shape:
    """A 0.5 m tile centred on its origin: a box, the same as a convex hull, or
    its top face alone as a two-triangle mesh."""
    h = 0.25
    if kind == "hull":
        return rr.ConvexHull(np.array([[x, y, z] for x in (-h, h) for y in (-h, h) for z in (-h, h)]))
    if kind == "mesh":
        top = np.array([[-h, -h, h], [h, -h, h], [h, h, h], [-h, h, h]])
        return rr.TriMesh(top, np.array([[0, 1, 2], [0, 2, 3]]))
    return rr.Box((h, h, h))


def floor_tiles(scene: rr.Scene, friction: float, step: float = 0.0, kind: str = "box",
                restitution: float = 0.0) -> None:
    """Fixed 0.5 m tiles (see `tile`), flush edge to edge, top at 0 (from x = 0
    on, at `step`), over x in [-5, 5] m and y in [-1, 1] m: seams along y = 0,
    ±0.5 m."""
    for i in range(-10, 10):
        for j in range(-2, 2):
            top = step if i >= 0 else 0.0
            scene.add_body(tile(kind), fixed=True, position=(0.5 * i + 0.25, 0.5 * j + 0.25, top - 0.25),
                           friction=friction, restitution=restitution)


def travel(body: rr.Shape, speed: float, spin: float, tiles: bool, step: float = 0.0, wall: bool = False,
           y: float = 0.13) -> tuple[float, float]:
    """Distance along x after 2.5 s (m) and the largest lift (m). `step`: the
    tiles from x = 0 on stand that much higher (m); `wall`: a fixed box stands
    on the tiles at x = 0; `y`: of the path (m; seams along y = 0, ±0.5)."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    if tiles:
        floor_tiles(scene, MU, step)
        if wall:
            scene.add_body(rr.Box((0.25, 1.0, 0.5)), fixed=True, position=(0.25, 0.0, 0.5), friction=MU)
    else:
        scene.add_body(rr.Plane(), fixed=True, friction=MU)
    b = scene.add_body(body, density=1000.0, position=(-3.0, y, HALF), linear_velocity=(speed, 0.0, 0.0),
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


@pytest.mark.parametrize("name, body, speed, spin, expected", CASES, ids=[c[0] for c in CASES])
def test_across_flush_box_tiles_a_body_slides_or_rolls_as_on_a_plane(name: str, body: rr.Shape, speed: float,
                                                                      spin: float, expected: float) -> None:
    distance, lift = travel(body, speed, spin, tiles=True)
    assert lift < 1e-3, f"lifted {lift:.3g} m"
    assert distance == pytest.approx(expected, rel=1e-2)


@pytest.mark.parametrize("name, body, speed, spin, expected", CASES, ids=[c[0] for c in CASES])
def test_a_real_step_or_a_wall_still_stops_them(name: str, body: rr.Shape, speed: float, spin: float,
                                                expected: float) -> None:
    # A 2 cm step at x = 0 (3 m ahead) is not a seam: the cube (sliding base
    # 0.2 m, it reaches it at about 3.3 m/s) is stopped by it; the ball (r 0.1)
    # climbs it, losing speed. A wall 1 m high stops both before it.
    stepped, _ = travel(body, speed, spin, tiles=True, step=0.02)
    walled, _ = travel(body, speed, spin, tiles=True, wall=True)
    assert walled < 3.0 - HALF + 1e-3, f"went {walled:.3g} m, the wall is at 3.0 m"
    assert stepped < 0.99 * expected, f"went {stepped:.3g} m past a 2 cm step ({expected:.3g} m on the flat)"


@pytest.mark.parametrize("y", [0.05, 0.0])
def test_a_cube_straddling_a_seam_does_not_hop_where_four_tiles_meet(y: float) -> None:
    # Sliding along the seam y = 0 (0.05 m off it, or on it) the cube turns a
    # little (see test_mesh_floor_friction.py) and, at each seam across its
    # path, comes within the prediction of the side faces of the two tiles
    # ahead. The contact with one, along its top edge, lies in the floor's
    # plane and in the plane of the other's side face; it was given the side
    # face's normal, which stopped the cube's front and threw it up 7.7 cm
    # (10.7 cm on the seam). Now the face the cube rests on wins: it lifts
    # below a micrometre, as on a plane (2e-8 m).
    _, lift = travel(rr.Box((HALF,) * 3), 5.0, 0.0, tiles=True, y=y)
    assert lift < 1e-5, f"lifted {lift:.3g} m"


@pytest.mark.parametrize("x,y", [(0.0, 0.0), (0.0, 0.25)], ids=["where four tiles meet", "across a seam"])
def test_a_cube_bouncing_flat_on_tile_seams_rebounds_as_on_a_plane(x: float, y: float) -> None:
    # Its contacts with the tiles under it are one constraint
    # (rust/solve/flush_pairs.rs), whose impact takes its own points at the
    # time of impact. Reference: a flat landing at v reverses to e v (e the
    # pair's restitution, the larger of the two materials'): the cube,
    # dropped from h = 1 m, lands after √(2h/g) = 0.45 s and rises e² h again
    # by 0.68 s, straight up, without turning (it lands again at 0.90 s).
    e, h = 0.5, 1.0
    land, apex = math.sqrt(2 * h / G), math.sqrt(2 * h / G) * (1 + e / 2)
    peaks = []
    for floor in ("plane", "tiles"):
        scene = rr.Scene(gravity=(0.0, 0.0, -G))
        if floor == "plane":
            scene.add_body(rr.Plane(), fixed=True, friction=0.5, restitution=0.5)
        else:
            floor_tiles(scene, 0.5, restitution=0.5)
        b = scene.add_body(rr.Box((HALF,) * 3), density=1000.0, position=(x, y, HALF + h), friction=0.5,
                           restitution=e)
        world = scene.build(dt=1 / 60)
        heights, turn = [], 0.0
        for _ in range(round((apex + 0.1) * 60)):
            world.step(1)
            heights.append(float(world.bodies.position[b, 2]) - HALF)
            turn = max(turn, float(np.abs(world.bodies.angular_velocity[b]).max()))
        low = int(np.argmin(heights[:round((land + 0.1) * 60)]))
        peaks.append(max(heights[low:]))
        assert turn < 1e-9, f"on the {floor} it turned at {turn:.3g} rad/s"
        assert np.hypot(world.bodies.position[b, 0] - x, world.bodies.position[b, 1] - y) < 1e-9
    # The step's own error (a discrete fall) is the plane's too: the tiles
    # must give the plane's answer, and both e² h to 5 %.
    assert peaks[1] == pytest.approx(peaks[0], rel=1e-9)
    assert peaks[0] == pytest.approx(e**2 * h, rel=5e-2)
