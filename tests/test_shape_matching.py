"""Shape matching (Müller et al. 2005) against exact references (REFERENCES.md,
"Polar decomposition and shape matching").

The clusters run in worlds without gravity whose particles start at rest, so a
step's prediction moves nothing (or moves them by exactly h·v, which the tests
subtract): what changes in one step is the shape-matching correction itself.
Round-off bars: coordinates are O(1) m and each goal sums O(30) products, so a
correction that should vanish is left at ~1e-15 m; the bars are 1e-12.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull
from scipy.spatial.transform import Rotation

import rigidrs as rr

DT = 1 / 60
MODES = ["rigid", "linear", "quadratic"]


def grid_points(n=(3, 3, 3), size=(0.4, 0.3, 0.2), jitter=0.02, seed=1):
    """A slightly irregular grid (anisotropic moments, no symmetry to hide behind)."""
    rng = np.random.default_rng(seed)
    axes = [np.linspace(-s / 2, s / 2, k) for s, k in zip(size, n)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return pts + rng.uniform(-jitter, jitter, pts.shape) + np.array([0.3, -0.2, 1.0])


def cluster_world(points, masses=None, **cluster):
    scene = rr.Scene(gravity=(0, 0, 0))
    masses = np.full(len(points), 0.1) if masses is None else masses
    ids = [scene.add_particle(p, mass=m) for p, m in zip(points, masses)]
    scene.add_shape_matching(ids, **cluster)
    return scene.build(dt=DT), np.array(ids)


def half_turns():
    axes = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1), (1, -2, 0.5)]
    return [Rotation.from_rotvec(np.pi * np.array(a) / np.linalg.norm(a)) for a in axes]


ROTATIONS = half_turns() + list(Rotation.random(4, random_state=7))


@pytest.mark.parametrize("mode", MODES)
def test_rigid_motion_of_the_rest_shape_gives_zero_correction(mode):
    # Any rotation (half turns about five axes included: Müller's iteration sits
    # on a saddle there when warm-started from the identity) and translation of
    # the rest shape is its own goal in every mode and for every β.
    points = grid_points()
    masses = np.linspace(0.05, 0.2, len(points))
    world, ids = cluster_world(points, masses, mode=mode, beta=0.7, stiffness=1.0)
    c = (masses[:, None] * points).sum(0) / masses.sum()
    for rot in ROTATIONS:
        moved = rot.apply(points - c) + c + np.array([0.5, -1.0, 2.0])
        world.particles.position[ids] = moved
        world.particles.velocity[ids] = 0.0
        world.step()
        assert np.abs(world.particles.position[ids] - moved).max() <= 1e-12
        np.testing.assert_allclose(world.clusters()["rotation"][0], rot.as_matrix(), atol=1e-12)


def correction(world, ids):
    """One step from the current state: Δ = x1 − (x0 + h v0), and x0 + h v0."""
    x0, v0 = world.particles.position[ids].copy(), world.particles.velocity[ids].copy()
    world.step()
    pred = x0 + DT * v0
    return world.particles.position[ids] - pred, pred


def momentum_changes(delta, pred, m):
    c = (m[:, None] * pred).sum(0) / m.sum()
    linear = (m[:, None] * delta).sum(0)
    angular = (m[:, None] * np.cross(pred - c, delta)).sum(0)
    return linear, angular


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("beta", [0.0, 0.5, 1.0])
def test_corrections_conserve_linear_and_angular_momentum(mode, beta):
    # A deformed, moving cluster: the correction of one step Δ satisfies Σ m Δ = 0
    # (the goals keep the centre) and Σ m (x − c) × Δ = 0 (Σ m (T q̃) pᵀ is
    # symmetric for the rigid, linear and quadratic transforms T). Bars: 1e-12 of
    # Σ m |Δ| (times the cluster size for the angular one).
    rng = np.random.default_rng(3)
    points = grid_points()
    masses = rng.uniform(0.05, 0.2, len(points))
    world, ids = cluster_world(points, masses, mode=mode, beta=beta, stiffness=0.7)
    world.particles.position[ids] = Rotation.from_rotvec((0.3, -1.0, 0.4)).apply(points) + rng.normal(0, 0.03, points.shape)
    world.particles.velocity[ids] = rng.normal(0, 0.5, points.shape)
    for _ in range(3):
        delta, pred = correction(world, ids)
        scale = (masses * np.linalg.norm(delta, axis=1)).sum()
        assert scale > 1e-4  # there is a correction to speak of
        linear, angular = momentum_changes(delta, pred, masses)
        assert np.abs(linear).max() <= 1e-12 * scale
        assert np.abs(angular).max() <= 1e-12 * scale * 0.5


def test_overlapping_clusters_conserve_momentum_together():
    # Two clusters sharing a slab of particles: each matches with the shared
    # particles' mass split between them (m/2 each) and a shared particle moves by
    # the mean of its two corrections, so the sum of the two momentum-free
    # corrections is what is applied: still momentum-free.
    points = grid_points(n=(5, 3, 3), size=(0.6, 0.3, 0.2))
    masses = np.linspace(0.05, 0.3, len(points))
    x = points[:, 0] - points[:, 0].mean()
    scene = rr.Scene(gravity=(0, 0, 0))
    ids = np.array([scene.add_particle(p, mass=m) for p, m in zip(points, masses)])
    left, right = ids[x < 0.05], ids[x > -0.05]
    assert len(set(left) & set(right)) == 9
    scene.add_shape_matching(list(left), mode="linear", beta=0.6)
    scene.add_shape_matching(list(right), mode="quadratic", beta=0.4, stiffness=0.5)
    world = scene.build(dt=DT)
    rng = np.random.default_rng(5)
    world.particles.position[:] = points + rng.normal(0, 0.03, points.shape)
    world.particles.velocity[:] = rng.normal(0, 0.3, points.shape)
    p0 = world.linear_momentum().copy()
    delta, pred = correction(world, ids)
    scale = (masses * np.linalg.norm(delta, axis=1)).sum()
    linear, angular = momentum_changes(delta, pred, masses)
    assert np.abs(linear).max() <= 1e-12 * scale and np.abs(angular).max() <= 1e-12 * scale
    world.step(100)
    # Over 100 more steps only round-off accumulates: per step, ε times the
    # momentum-sized terms Σ m |x| / h that the corrections are made of.
    x = world.particles.position
    assert np.abs(world.linear_momentum() - p0).max() <= 100 * 1e-15 * (masses * np.linalg.norm(x, axis=1)).sum() / DT


def hull_volume(x):
    return ConvexHull(x).volume


def test_beta_one_goal_keeps_the_volume_of_a_stretched_cluster():
    # β = 1, stiffness 1: one step puts the particles on the goal A q + c. With the
    # volume kept, A = Apq Aqq⁻¹ / det(·)^(1/3) has det 1: every volume of the rest
    # shape is kept, here its convex hull's (1e-12 relative). Without it the goal is
    # the stretch itself: 1.5x the volume.
    points = grid_points()
    c = points.mean(0)
    stretched = (points - c) * np.array([1.5, 1.0, 1.0]) + c
    for keep, ratio in [(True, 1.0), (False, 1.5)]:
        world, ids = cluster_world(points, mode="linear", beta=1.0, preserve_volume=keep)
        world.particles.position[ids] = stretched
        world.step()
        x = world.particles.position[ids]
        assert abs(hull_volume(x) / hull_volume(points) - ratio) <= 1e-12
        # And it is a stretch along x (not a rotation of the rest shape).
        assert np.ptp(x[:, 0]) > 1.1 * np.ptp(points[:, 0])


def bent_bar(c=0.5):
    points = grid_points(n=(7, 3, 3), size=(1.0, 0.2, 0.2), jitter=0.0)
    x = points[:, 0] - points[:, 0].mean()
    bent = points.copy()
    bent[:, 2] += c * x**2
    return points, bent


def curvature(x):
    """Least-squares c of z = a + b x + c x² over all particles."""
    u = x[:, 0] - x[:, 0].mean()
    return np.linalg.lstsq(np.stack([np.ones_like(u), u, u * u], 1), x[:, 2], rcond=None)[0][2]


def test_quadratic_cluster_holds_a_parabolic_bend_a_linear_one_cannot():
    # The bend z += c x² is a quadratic map of the rest shape: the quadratic goal
    # (β = 1) reproduces it exactly (zero correction, 1e-12) and keeps it for as
    # long as we step; the best linear map cannot: the linear cluster is pulled
    # straight (curvature from 0.5 to below 0.01 within a second).
    points, bent = bent_bar()
    quad, ids = cluster_world(points, mode="quadratic", beta=1.0)
    quad.particles.position[ids] = bent
    quad.step()
    assert np.abs(quad.particles.position[ids] - bent).max() <= 1e-12
    quad.step(60)
    assert abs(curvature(quad.particles.position[ids]) - 0.5) <= 1e-9
    lin, ids = cluster_world(points, mode="linear", beta=1.0, preserve_volume=False)
    lin.particles.position[ids] = bent
    lin.step()
    assert np.abs(lin.particles.position[ids] - bent).max() > 0.02
    lin.step(60)
    assert abs(curvature(lin.particles.position[ids])) < 0.01


def test_plastic_deformation_stays_under_its_cap_and_the_body_rests_in_its_new_shape():
    # A cube cluster held stretched (volume-preserving, diag(1.4, 1/√1.4, 1/√1.4))
    # for a second flows plastically (yield 0.05, creep 20/s) up to the cap
    # ‖Sp − I‖_F = 0.2, never beyond. Released, it relaxes (β = 0.5) to the plastic
    # rest shape: at rest its fitted deformation from the original rest shape,
    # S = Rᵀ A, is Sp (1e-9), and stays far from the identity: a new shape. (It
    # overshoots on release and flows back a little: ‖Sp − I‖ ends at 0.18.)
    points = grid_points(size=(0.3, 0.3, 0.3), jitter=0.0)
    cap = 0.2
    world, ids = cluster_world(points, mode="linear", beta=0.5, plastic_yield=0.05, plastic_creep=20.0, plastic_max=cap)
    c = points.mean(0)
    s = 1.4
    held = (points - c) * np.array([s, s**-0.5, s**-0.5]) + c
    for _ in range(60):
        world.particles.position[ids] = held
        world.particles.velocity[ids] = 0.0
        world.step()
        sp = world.clusters()["plastic"][0]
        assert np.linalg.norm(sp - np.eye(3)) <= cap + 1e-12
        assert abs(np.linalg.det(sp) - 1) <= 1e-12
    assert np.linalg.norm(sp - np.eye(3)) >= cap - 1e-9  # it reached the cap
    world.particles.velocity[ids] = 0.0
    world.step(180)
    sp = world.clusters()["plastic"][0]
    assert np.linalg.norm(sp - np.eye(3)) <= cap + 1e-12
    assert np.abs(world.particles.velocity[ids]).max() < 1e-9
    x = world.particles.position[ids]
    q, p = points - c, x - x.mean(0)
    a = (p.T @ q) @ np.linalg.inv(q.T @ q)
    u, _, vt = np.linalg.svd(a)
    r = u @ vt
    np.testing.assert_allclose(r.T @ a, sp, atol=1e-9)
    assert np.linalg.norm(r.T @ a - np.eye(3)) >= 0.15


@pytest.mark.parametrize("mode", MODES)
def test_shape_matched_box_lands_on_the_ground_through_its_particles(mode):
    # A box filled with particles every 5 cm (radius 2 cm) dropped from 0.3 m on a
    # ground plane: its particles collide with the plane, the body comes to rest
    # on it (lowest particle at its radius, 1e-6: the contacts' last pass is exact,
    # the shape matching before it moves the bottom row by the settling residual)
    # and, stiffness 1, keeps its shape (pairwise distances within 1 mm).
    scene = rr.Scene()
    scene.add_body(rr.Plane(normal=(0, 0, 1)), fixed=True)
    r = 0.02
    rng, clusters = scene.add_shape_matched_body(rr.Box((0.1, 0.1, 0.1)), spacing=0.05, position=(0, 0, 0.4),
                                                orientation=Rotation.from_rotvec((0, 0, 0.3)).as_quat(),
                                                mass=1.0, radius=r, mode=mode, beta=0.3)
    assert len(rng) == 125 and clusters == [0]
    world = scene.build(dt=DT, substeps=8)
    assert world.stages == ["xpbd", "shape_matching", "xpbd"]
    x0 = world.particles.position.copy()
    world.step(180)
    x = world.particles.position
    assert abs(x[:, 2].min() - r) <= 1e-6
    assert np.abs(world.particles.velocity).max() < 1e-3
    d0 = np.linalg.norm(x0[:, None] - x0[None], axis=-1)
    d = np.linalg.norm(x[:, None] - x[None], axis=-1)
    assert np.abs(d - d0).max() < 1e-3


def test_shape_matched_body_from_a_mesh_with_overlapping_clusters():
    # An octahedron mesh (vertices + grid points inside) matched by overlapping
    # linear clusters lands on a box: it rests on the box's top (z = 0.2) at its
    # particles' radius, every particle in at least one cluster.
    v = np.array([(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)], float) * 0.2
    t = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    scene = rr.Scene()
    scene.add_body(rr.Box((1, 1, 0.1)), fixed=True, position=(0, 0, 0.1))
    particles, clusters = scene.add_shape_matched_body(rr.TriMesh(v, t), spacing=0.08, position=(0, 0, 0.6),
                                                      radius=0.01, mode="linear", beta=0.5, cluster_size=0.16)
    assert len(particles) > 6 and len(clusters) > 1
    world = scene.build(dt=DT, substeps=8)
    world.step(120)
    z = world.particles.position[:, 2]
    assert abs(z.min() - (0.2 + 0.01)) <= 1e-3
    assert np.abs(world.particles.velocity).max() < 0.05


def test_shape_matched_body_from_points():
    pts = grid_points()
    scene = rr.Scene(gravity=(0, 0, 0))
    particles, clusters = scene.add_shape_matched_body(pts, mode="rigid")
    assert particles == range(0, len(pts)) and clusters == [0]
    with pytest.raises(ValueError, match="spacing"):
        scene.add_shape_matched_body(pts, spacing=0.1)
    with pytest.raises(ValueError, match="spacing"):
        scene.add_shape_matched_body(rr.Sphere(0.1))


def test_degenerate_clusters_are_refused_and_the_scene_is_unchanged():
    scene = rr.Scene()
    line = [scene.add_particle((k * 0.1, 0, 0)) for k in range(5)]
    same = [scene.add_particle((1, 1, 1)) for _ in range(4)]
    flat = [scene.add_particle((x, y, 0)) for x in (0, 1, 2) for y in (0, 1)]
    cube = [scene.add_particle((x, y, z)) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    cases = [
        (line, {}, rr.ShapeError, "cluster 0: the cluster's particles are collinear"),
        (line, {"mode": "rigid"}, rr.ShapeError, "collinear"),
        (same, {"mode": "rigid"}, rr.ShapeError, "coincident"),
        (flat, {}, rr.ShapeError, "coplanar"),
        (cube, {"mode": "quadratic"}, rr.ShapeError, "at least 10 particles"),
        (cube, {"mode": "cubic"}, rr.RigidError, "mode must be"),
        (cube, {"beta": 1.5}, rr.RigidError, "beta must be in"),
        (cube, {"stiffness": -0.1}, rr.RigidError, "stiffness must be in"),
        (cube, {"plastic_yield": -1.0}, rr.RigidError, "plastic_yield"),
        (cube, {"plastic_creep": 1.0}, rr.RigidError, "plastic_creep needs plastic_yield"),
        (cube[:3] + [99], {}, rr.RigidError, "particle index 99 is out of range"),
        (cube[:4] + cube[:1], {}, rr.RigidError, "appears twice"),
    ]
    for ids, kw, err, message in cases:
        with pytest.raises(err, match=message):
            scene.add_shape_matching(ids, **kw)
        assert scene.cluster_count == 0
    assert scene.add_shape_matching(flat, mode="rigid") == 0  # a plate can turn rigidly
    scene.build(dt=DT).step()
