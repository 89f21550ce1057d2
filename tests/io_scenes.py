"""Scenes that together use every input a scene file holds: each shape kind, every
way of giving mass, materials, filters, names, ccd, fixed and kinematic bodies,
velocities; every joint kind with its options and drives; every particle-side
call. Values are awkward on purpose (non-unit quaternions and normals, -0.0,
infinities) so that a lossy round trip shows."""
from __future__ import annotations

from typing import Any, Callable

import numpy as np

import rigidrs as rr


def bodies() -> tuple[rr.Scene, dict[str, Any]]:
    scene = rr.Scene(gravity=(0.1, -0.0, -9.7))
    scene.add_body(rr.Plane((0.0, 0.3, 1.1), offset=-0.05), fixed=True, friction=0.7, static_friction=0.9, name="floor")
    rng = np.random.default_rng(11)
    hull = rr.ConvexHull(rng.normal(size=(14, 3)) * 0.12)
    cube_v = [(x, y, z) for z in (-0.1, 0.1) for y in (-0.1, 0.1) for x in (-0.1, 0.1)]
    cube_t = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
              (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    compound = rr.Compound([(rr.Sphere(0.08), (0.0, 0.0, 0.15)),
                            (rr.Box((0.05, 0.06, 0.07)), (0.0, 0.0, -0.1), (0.0, 0.0, 0.3, 1.1)),
                            (rr.ConvexHull(rng.normal(size=(8, 3)) * 0.05), (0.1, 0.0, 0.0))])
    q = rng.normal(size=4)
    tensor = np.array([[0.02, 0.001, 0.0], [0.001, 0.03, -0.002], [0.0, -0.002, 0.025]])
    mp = rr.mass_properties(rng.normal(size=(20, 3)) * 0.1, 1e-3, rng.uniform(500, 900, size=20))
    specs: list[tuple[rr.Shape | None, dict[str, Any]]] = [
        (rr.Sphere(0.1), dict(density=700.0, position=(0, 0, 0.5), linear_velocity=(0.3, -0.0, 1.0))),
        (rr.Box((0.1, 0.15, 0.2)), dict(mass=2.5, orientation=q, restitution=0.4, ccd=True, name="box")),
        (rr.Capsule(0.05, 0.2), dict(density=1100.0, inertia=None, angular_velocity=(1.0, 2.0, -3.0), collision_group=2, collision_mask=5)),
        (rr.Cylinder(0.1, 0.05), dict(mass=1.0, inertia=(0.01, 0.02, 0.03), position=(1, 0, 0.4))),
        (rr.Cone(0.1, 0.2), dict(mass=1.3, inertia=tensor, position=(-1, 0, 0.4), friction=0.2)),
        (hull, dict(density=400.0, position=(0, 1, 0.6))),
        (rr.TriMesh(cube_v, cube_t), dict(density=300.0, position=(0, -1, 0.6))),
        (compound, dict(density=800.0, position=(0.5, 0.5, 0.8), orientation=(0.0, 0.0, 0.3, 1.1))),
        (rr.Box((0.2, 0.2, 0.02)), dict(kinematic=True, position=(2, 2, 0.3), linear_velocity=(0, 0, 0.1))),
        (None, dict(mass_properties=mp, position=(0, 0, 3))),
        (rr.Sphere(0.05), dict(mass_properties=rr.Sphere(0.05).mass_properties(900.0), position=(0.2, 0, 2))),
    ]
    for shape, kw in specs:
        scene.add_body(shape, **kw)
    return scene, dict(dt=1 / 240, substeps=3, contact_hertz=40.0, max_rotation_angle=float("inf"))


def joints() -> tuple[rr.Scene, dict[str, Any]]:
    scene = rr.Scene()
    base = scene.add_body(rr.Box((0.1, 0.1, 0.1)), fixed=True, position=(0, 0, 2))
    links = [scene.add_body(rr.Capsule(0.03, 0.1), mass=0.5 + 0.1 * k, position=(0.25 * (k + 1), 0, 2),
                            orientation=(0, 0.7071067811865476, 0, 0.7071067811865476)) for k in range(4)]
    scene.add_joint("hinge", links[0], base, anchor=(0.1, 0, 2), axis=(0, 2, 0), limits=(-1.0, 1.2), name="shoulder",
                    drive=rr.Drive("position", target=0.3, stiffness=50.0, damping=2.0, max_force=30.0), armature=0.01, friction=0.05)
    scene.add_joint("prismatic", links[1], links[0], axis=(1, 0, 0), limits=(-0.05, 0.05), damping=0.5,
                    drive=rr.Drive("velocity", target=0.1, damping=5.0))
    scene.add_joint("spherical", links[2], links[1], anchor=(0.625, 0, 2), cone_limit=0.8, twist_limits=(-0.3, 0.4),
                    drive=rr.Drive("position", target=(0.1, 0.0, 0.0, 1.2), stiffness=3.0, damping=0.1))
    scene.add_joint("fixed", links[3], links[2], anchor=(0.875, 0, 2), solver="articulation")
    loop = [scene.add_body(rr.Sphere(0.05), mass=0.2, position=(0, 0.3 * k + 0.5, 1.0)) for k in range(3)]
    scene.add_joint("distance", loop[0], None, anchor=(0, 0.5, 1.0), anchor_b=(0, 0.5, 1.5), solver="xpbd", compliance=1e-6)
    scene.add_joint("distance", loop[1], loop[0], rest_length=0.35, solver="xpbd", angular_compliance=1e-5)
    scene.add_joint("distance", loop[2], loop[1], limits=(0.0, 0.4), solver="xpbd")
    scene.add_joint("hinge", loop[2], loop[0], anchor=(0, 1.0, 1.0), axis=(1, 0, 0), solver="auto")
    return scene, dict(dt=1 / 120, articulation_integrator="rk4", iterations=2)


def particles() -> tuple[rr.Scene, dict[str, Any]]:
    scene = rr.Scene()
    scene.add_body(rr.Plane(), fixed=True)
    holder = scene.add_body(rr.Sphere(0.1), kinematic=True, position=(0, 0, 2))
    ids = [scene.add_particle((0.1 * k, 0.03 * (k % 2), 1.5 + 0.02 * k), mass=0.1, radius=0.02, velocity=(0, 0.1, 0),
                              fixed=k == 0, friction=0.3, collision_group=3) for k in range(4)]
    scene.add_particle((0.1, 0.1, 1.5))
    scene.add_distance_constraint(ids[0], ids[1], compliance=1e-5, damping=0.01)
    scene.add_distance_constraint(ids[1], ids[2], rest_length=0.12)
    scene.add_bending_constraint(ids[1], ids[2], ids[3], 4, compliance=0.5, damping=0.01)
    scene.add_volume_constraint([ids[0], ids[1], ids[2], 4], compliance=1e-4)
    scene.add_attachment(ids[3], holder, point=(0.3, 0.0, 1.9), rest_length=0.1, compliance=1e-4)
    rope = scene.add_rope((1, 0, 2), (2, 0, 2), 8, mass=0.2, radius=0.01, compliance=1e-6, pinned=[0])
    scene.add_attachment(rope[-1], holder)
    scene.add_cloth((-1, -1, 1.2), (0.8, 0, 0), (0, 0.8, 0.1), (6, 5), mass=0.2, compliance=1e-6,
                    bending_compliance=2.0, pinned=[0, 5], collision_mask=6)
    scene.add_cloth((-1, 1, 1.2), (0.5, 0, 0), (0, 0.5, 0), (4, 4), bending_compliance=1.0, bending_damping=0.0)
    box = scene.add_soft_box((1, 1, 0.5), (0.1, 0.1, 0.1), (2, 1, 1), mass=0.5, radius=0.02, compliance=1e-5, volume_compliance=1e-7)
    scene.add_shape_matching(list(box)[:6], mode="rigid", stiffness=0.8)
    sm_points = np.random.default_rng(2).normal(size=(12, 3)) * 0.1 + (2.0, 2.0, 0.6)
    scene.add_shape_matched_body(sm_points, mass=0.4, radius=0.03, mode="quadratic", beta=0.2, plastic_yield=0.05,
                                 plastic_creep=2.0)
    scene.add_shape_matched_body(rr.Box((0.15, 0.1, 0.1)), spacing=0.07, position=(-2, 0, 0.5),
                                 orientation=(0.1, 0.0, 0.0, 0.9), cluster_size=0.1, preserve_volume=False, plastic_yield=0.1,
                                 plastic_max=0.3)
    tet = [scene.add_particle(p, mass=0.05) for p in ((3, 0, 1), (3.2, 0, 1), (3, 0.2, 1), (3, 0, 1.2))]
    faces = [(tet[0], tet[2], tet[1]), (tet[0], tet[1], tet[3]), (tet[0], tet[3], tet[2]), (tet[1], tet[2], tet[3])]
    for a, b in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)):
        scene.add_distance_constraint(tet[a], tet[b], compliance=1e-4)
    scene.add_mesh_volume_constraint(faces, compliance=1e-6, pressure=1.5)
    return scene, dict(dt=1 / 60, iterations=3, sleep=False)


SCENES: dict[str, Callable[[], tuple[rr.Scene, dict[str, Any]]]] = {
    "bodies": bodies,
    "joints": joints,
    "particles": particles,
}
