"""Scenes of every kind for the snapshot tests, and the bitwise comparison of two
worlds: every view plus time and step count."""
from __future__ import annotations

from typing import Callable

import numpy as np

import rigidrs as rr
from rigidrs.work_precision.contact import KickedColumn

G = 9.81


def ground() -> rr.Scene:
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    return scene


def pile(rocket: bool = False) -> rr.World:
    """60 boxes and spheres in four jittered layers dropped on the ground: a pile
    with contacts of every age by step 60; with ``rocket``, body 61 far above
    it, a ball no contact reaches."""
    scene = ground()
    rng = np.random.default_rng(3)
    for k in range(60):
        i, j, layer = k % 4, (k // 4) % 4, k // 16
        x, y = 0.32 * (i - 1.5) + rng.uniform(-0.03, 0.03), 0.32 * (j - 1.5) + rng.uniform(-0.03, 0.03)
        shape = rr.Box((0.13, 0.1, 0.12)) if k % 2 else rr.Sphere(0.12)
        q = rng.normal(size=4)
        scene.add_body(shape, density=500.0, position=(x, y, 0.2 + 0.3 * layer), orientation=q / np.linalg.norm(q))
    if rocket:
        scene.add_body(rr.Sphere(0.1), mass=1.0, position=(5, 5, 100))
    return scene.build(dt=1 / 120)


def pyramid(base: int = 8) -> rr.World:
    scene = ground()
    for row in range(base):
        n = base - row
        for j in range(n):
            scene.add_body(rr.Box((0.5, 0.5, 0.5)), density=1000.0, position=((j - (n - 1) / 2) * 1.02, 0.0, 0.5 + row))
    # Awake, so that every step solves its contacts from the warm starts.
    return scene.build(dt=1 / 60, sleep=False)


def xpbd_joints() -> rr.World:
    """A closed loop (so XPBD, not an articulation) of five capsules, hinged, swinging."""
    scene = ground()
    bodies = [scene.add_body(rr.Capsule(0.05, 0.2), mass=1.0, position=(0.5 * k, 0, 2.0), orientation=(0, 0.7071067811865476, 0, 0.7071067811865476)) for k in range(5)]
    scene.add_joint("spherical", bodies[0], None, anchor=(-0.25, 0, 2.0), solver="xpbd")
    for a, b in zip(bodies[1:], bodies[:-1]):
        scene.add_joint("hinge", a, b, anchor=(0.5 * a - 0.25, 0, 2.0), axis=(0, 1, 0), solver="xpbd")
    scene.add_joint("distance", bodies[-1], None, anchor=(2.25, 0, 2.0), anchor_b=(2.5, 0, 2.5), solver="xpbd")
    return scene.build(dt=1 / 120)


def chain_over_box(links: int = 12) -> rr.World:
    """An articulated chain dropped across a box: links in contact."""
    link, thick, height = 0.05, 0.01, 0.5
    scene = ground()
    scene.add_body(rr.Box((0.15, 0.15, 0.15)), fixed=True, position=(0, 0, 0.15))
    x0 = -links * link / 2
    prev = None
    for k in range(links):
        b = scene.add_body(rr.Box((link / 2, thick, thick)), mass=0.05, position=(x0 + (k + 0.5) * link, 0, height))
        if prev is not None:
            scene.add_joint("spherical", b, prev, anchor=(x0 + k * link, 0, height), damping=2e-4)
        prev = b
    return scene.build(dt=1 / 60)


def cloth() -> rr.World:
    scene = ground()
    scene.add_body(rr.Sphere(0.3), fixed=True, position=(0.5, 0.5, 0.3))
    scene.add_cloth((0, 0, 1.0), (1, 0, 0), (0, 1, 0), (12, 12), mass=0.3, compliance=1e-7, bending_compliance=1.0)
    return scene.build(dt=1 / 60)


def shape_matching() -> rr.World:
    """A plastic soft box dropped on a rigid box: clusters, rest shapes that flow."""
    scene = ground()
    scene.add_body(rr.Box((0.3, 0.3, 0.1)), mass=2.0, position=(0, 0, 0.1))
    scene.add_shape_matched_body(rr.Box((0.2, 0.2, 0.2)), spacing=0.1, position=(0.05, 0, 0.8), mass=1.0,
                                 radius=0.03, plastic_yield=0.01, plastic_creep=5.0, plastic_max=0.5)
    return scene.build(dt=1 / 60)


def sleeping() -> rr.World:
    """Boxes at rest on the ground fall asleep early; one dropped later wakes some."""
    scene = ground()
    for k in range(6):
        scene.add_body(rr.Box((0.2, 0.2, 0.2)), density=500.0, position=(0.5 * k, 0, 0.2))
    scene.add_body(rr.Sphere(0.1), density=500.0, position=(1.0, 0, 4.0))
    return scene.build(dt=1 / 60, sleep_time=0.2)


def meshes() -> rr.World:
    """Compounds and hulls tumbling onto a fixed triangle mesh: parry's per-pair
    workspaces and sub-shape manifolds."""
    scene = rr.Scene(gravity=(0, 0, -G))
    xs = np.linspace(-2, 2, 9)
    vertices = [(x, y, 0.05 * np.sin(3 * x + y)) for y in xs for x in xs]
    triangles = [t for j in range(8) for i in range(8) for t in (
        (j * 9 + i, j * 9 + i + 1, (j + 1) * 9 + i + 1), (j * 9 + i, (j + 1) * 9 + i + 1, (j + 1) * 9 + i))]
    scene.add_body(rr.TriMesh(vertices, triangles), fixed=True)
    dumbbell = [(rr.Sphere(0.1), (0, 0, 0.2)), (rr.Box((0.1, 0.1, 0.1)), (0, 0, -0.2))]
    rng = np.random.default_rng(5)
    for k in range(8):
        shape = rr.Compound(dumbbell) if k % 2 else rr.ConvexHull(rng.normal(size=(12, 3)) * 0.15)
        scene.add_body(shape, density=500.0, position=(0.4 * k - 1.4, 0, 0.4 + 0.1 * k), angular_velocity=(1, 2, 0))
    return scene.build(dt=1 / 60)


def kicked_column() -> rr.World:
    """Ten cubes resting 5 cm off each other's axis, kicked (the work-precision
    report's scene): they rock, so the steps take the rocking substeps (16, held
    0.5 s after the last rocking) and their state (`rust/solve/rocking.rs`) must
    come back with a snapshot."""
    return KickedColumn().scene(1).build(dt=1 / 60, sleep=False)


def tile_floor() -> rr.World:
    """Cubes sliding and spinning over flush box tiles across their seams:
    constraints joined across pairs (`rust/solve/flush_pairs.rs`), some
    joining and parting every step."""
    scene = rr.Scene(gravity=(0, 0, -G))
    for i in range(-4, 4):
        for j in range(-4, 4):
            scene.add_body(rr.Box((0.25, 0.25, 0.25)), fixed=True, position=(0.5 * i + 0.25, 0.5 * j + 0.25, -0.25),
                           friction=0.3)
    rng = np.random.default_rng(5)
    for k in range(12):
        x, y = rng.uniform(-1.5, 1.5, size=2)
        v = rng.normal(size=2) * 2.0
        scene.add_body(rr.Box((0.1, 0.1, 0.1)), density=1000.0, position=(x, y, 0.1 + 0.25 * (k % 3)),
                       linear_velocity=(v[0], v[1], 0.0), angular_velocity=(0.0, 0.0, rng.normal() * 3.0), friction=0.3)
    return scene.build(dt=1 / 60)


def wheels() -> rr.World:
    """A cart on four hinged cylinder wheels (an articulation) rolling over a
    bump, and loose capsules and cylinders rolling and tumbling: contacts read
    on rounded surfaces (`rust/solve/solver_body.rs`, `Rounding`)."""
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    scene.add_body(rr.Box((0.05, 1.0, 0.01)), fixed=True, position=(0.8, 0.0, 0.01))
    lying = (np.sin(np.pi / 4), 0.0, 0.0, np.cos(np.pi / 4))
    r = 0.1
    chassis = scene.add_body(rr.Box((0.3, 0.15, 0.03)), density=300.0, position=(0.0, 0.0, r), linear_velocity=(1.5, 0, 0))
    for x in (-0.25, 0.25):
        for y in (-0.25, 0.25):
            wheel = scene.add_body(rr.Cylinder(radius=r, half_height=0.03), density=500.0, position=(x, y, r),
                                   orientation=lying, linear_velocity=(1.5, 0, 0), angular_velocity=(0, 15.0, 0))
            scene.add_joint("hinge", chassis, wheel, anchor=(x, y, r), axis=(0.0, 1.0, 0.0))
    rng = np.random.default_rng(7)
    for k in range(6):
        shape = rr.Capsule(radius=0.05, half_height=0.1) if k % 2 else rr.Cylinder(radius=0.05, half_height=0.1)
        w = rng.normal(size=3) * 4.0
        scene.add_body(shape, density=800.0, position=(0.3 * k - 0.8, 1.2, 0.05 + 0.2 * (k % 3)), orientation=lying,
                       linear_velocity=(0.0, -1.0, 0.0), angular_velocity=(w[0] + 20.0, w[1], w[2]))
    return scene.build(dt=1 / 60, sleep=False)


def split_pit() -> rr.World:
    """1000 balls touching in a lattice in a box, on two threads: some 2800
    contacts, all solved both ways, laid out in two halves and passed over side
    by side from the second step (`rust/solve/seams.rs`); the layout follows the
    last step's plan, kept in the snapshot."""
    scene = rr.Scene(gravity=(0, 0, -G))
    half, t = 1.0, 0.1
    for c, h in (((0, 0, -t), (half + 2 * t, half + 2 * t, t)), ((half + t, 0, 1), (t, half + 2 * t, 1)),
                 ((-half - t, 0, 1), (t, half + 2 * t, 1)), ((0, half + t, 1), (half, t, 1)), ((0, -half - t, 1), (half, t, 1))):
        scene.add_body(rr.Box(h), fixed=True, position=c)
    for i in range(1000):
        x, y, z = i % 10, i // 10 % 10, i // 100
        j = 1e-3 * ((i * 0.754877) % 1.0 - 0.5)
        scene.add_body(rr.Sphere(0.1), density=1000.0, position=((x - 4.5) * 0.2 + j, (y - 4.5) * 0.2 - j, 0.1 + z * 0.2))
    return scene.build(dt=1 / 60, sleep=False, threads=2)


SCENES: dict[str, Callable[[], rr.World]] = {
    "pile": pile,
    "pyramid": pyramid,
    "xpbd_joints": xpbd_joints,
    "chain_over_box": chain_over_box,
    "cloth": cloth,
    "shape_matching": shape_matching,
    "sleeping": sleeping,
    "meshes": meshes,
    "kicked_column": kicked_column,
    "tile_floor": tile_floor,
    "wheels": wheels,
    "split_pit": split_pit,
}


def state(world: rr.World) -> dict[str, np.ndarray]:
    """Every view of a world (copies), with time and step count."""
    b, p, j = world.bodies, world.particles, world.joints
    out = {f"bodies.{k}": getattr(b, k).copy() for k in (
        "position", "orientation", "linear_velocity", "angular_velocity", "force", "torque", "mass",
        "inverse_mass", "inertia", "inverse_inertia", "sleeping", "rotation", "inertia_world", "angular_momentum")}
    out.update({f"particles.{k}": getattr(p, k).copy() for k in ("position", "velocity", "inverse_mass", "mass", "radius")})
    out.update({f"joints.{k}": getattr(j, k).copy() for k in ("position", "velocity", "target", "force")})
    out["time"] = np.array([world.time])
    out["last_substeps"] = np.array([world.last_substeps])
    out["steps"] = np.array([world.steps])
    return out


def assert_same(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> None:
    """Bitwise, byte by byte (so the NaN coordinates of joints without one compare
    equal, and -0.0 differs from 0.0)."""
    assert a.keys() == b.keys()
    for k in a:
        assert a[k].shape == b[k].shape, k
        assert np.array_equal(a[k].view(np.uint8), b[k].view(np.uint8)), k
