"""NumPy views of a world's bodies: they alias the world's memory, writes through the
writable ones drive the simulation, the read-only ones refuse writes, they outlive
the Python name of their world, derived ones are refreshed by ``step``, and an
empty world has empty views.

Tolerances. A single translation p + h v is one multiply-add: a few ulp of |p|,
so 1e-14 x max(|p|, 1) leaves margin without hiding a missed or doubled step
(which would be off by |v| dt ≥ 1e-3). Closed-form motions over a few steps
(constant force, constant torque, rotation of a sphere) accumulate round-off of a
few ulp per step: 1e-13 relative over ≤ 100 steps.
"""
from __future__ import annotations

import gc

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr

WRITABLE = ["position", "orientation", "linear_velocity", "angular_velocity", "force", "torque"]
READ_ONLY = ["mass", "inverse_mass", "inertia", "inverse_inertia", "rotation", "inertia_world", "angular_momentum"]
DERIVED = ["rotation", "inertia_world", "angular_momentum"]
ROW_SHAPE = {
    "position": (3,),
    "orientation": (4,),
    "linear_velocity": (3,),
    "angular_velocity": (3,),
    "force": (3,),
    "torque": (3,),
    "mass": (),
    "inverse_mass": (),
    "inertia": (3,),
    "inverse_inertia": (3,),
    "rotation": (3, 3),
    "inertia_world": (3, 3),
    "angular_momentum": (3,),
}
DT = 0.01


def close(actual, expected, rtol, scale=None):
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    if scale is None:
        scale = max(np.abs(expected).max(), 1.0)
    err = np.abs(actual - expected).max()
    assert err <= rtol * scale, f"error {err:.3e} > {rtol:.0e} x {scale:.3e}\n{actual}\nvs\n{expected}"


def make_world(gravity=(0.0, 0.0, 0.0), integrator="strang"):
    """Body 0: a sphere (isotropic), body 1: an asymmetric box, body 2: a fixed box."""
    scene = rr.Scene(gravity=gravity)
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(1.0, 2.0, 3.0), linear_velocity=(0.5, -0.25, 1.0))
    scene.add_body(
        rr.Box((0.05, 0.2, 0.45)),
        mass=10.0,
        position=(-1.0, 0.0, 0.5),
        orientation=Rotation.from_rotvec([0.3, 0.2, -0.1]).as_quat(),
        angular_velocity=(0.1, 5.0, 0.1),
    )
    scene.add_body(rr.Box((1.0, 1.0, 0.1)), fixed=True, position=(0.0, 0.0, -1.0))
    return scene.build(dt=DT, integrator=integrator)


@pytest.mark.parametrize("name", WRITABLE + READ_ONLY)
def test_two_reads_of_a_view_share_the_worlds_memory(name):
    world = make_world()
    v1, v2 = getattr(world.bodies, name), getattr(world.bodies, name)
    assert v1.dtype == np.float64
    assert v1.shape == (3, *ROW_SHAPE[name])
    assert np.shares_memory(v1, v2)
    assert isinstance(v1.base, rr.World)
    assert v1.flags.writeable == (name in WRITABLE)


def test_views_of_different_fields_do_not_overlap():
    b = make_world().bodies
    views = [getattr(b, n) for n in WRITABLE + READ_ONLY]
    for i, x in enumerate(views):
        for y in views[i + 1 :]:
            assert not np.shares_memory(x, y)


@pytest.mark.parametrize("integrator", sorted(rr.INTEGRATORS))
def test_written_velocity_moves_the_body_by_v_dt(integrator):
    world = make_world(integrator=integrator)
    b = world.bodies
    v = np.array([[3.0, -1.5, 0.25], [-0.5, 0.75, 2.0]])
    b.linear_velocity[:2] = v
    p_new = np.array([[0.1, 0.2, 0.3], [4.0, -5.0, 6.0]])
    b.position[:2] = p_new
    world.step()
    # No force acts (zero gravity): every integrator translates by exactly v dt.
    close(b.position[:2], p_new + v * DT, rtol=1e-14, scale=6.0)
    close(b.linear_velocity[:2], v, rtol=1e-15)


def test_written_angular_velocity_and_orientation_rotate_a_sphere_exactly():
    world = make_world()
    b = world.bodies
    q0 = Rotation.from_rotvec([0.4, -1.2, 0.7])
    w = np.array([2.0, -1.0, 3.0])
    b.orientation[0] = q0.as_quat()
    b.angular_velocity[0] = w
    n = 50
    world.step(n)
    # A sphere keeps ω; its orientation after t is exp(ω t) R0 (rotate_isotropic is
    # that exponential map, exact for any step size).
    expected = (Rotation.from_rotvec(w * n * DT) * q0).as_matrix()
    close(Rotation.from_quat(b.orientation[0]).as_matrix(), expected, rtol=1e-13)
    close(b.rotation[0], expected, rtol=1e-13)
    close(b.angular_velocity[0], w, rtol=1e-14)


def test_written_angular_velocity_about_a_principal_axis_spins_a_box_steadily():
    world = make_world()
    b = world.bodies
    r0 = Rotation.from_quat(b.orientation[1].copy())
    axis_world = r0.as_matrix()[:, 2]  # the body's long axis: a principal axis
    w = 4.0 * axis_world
    b.angular_velocity[1] = w
    world.step(40)
    # Steady rotation about a principal axis is an exact solution of Euler's equations.
    # ω has off-axis parts of ~1e-16 (round-off of R0ᵀw) about the stable long axis:
    # they do not grow, so 40 steps stay within a few hundred ulp: 1e-12.
    expected = (Rotation.from_rotvec(w * 40 * DT) * r0).as_matrix()
    close(b.rotation[1], expected, rtol=1e-12)
    close(b.angular_velocity[1], w, rtol=1e-12)


def test_written_force_accelerates_and_persists():
    world = make_world()
    b = world.bodies
    m = b.mass[0]
    p0, v0 = b.position[0].copy(), b.linear_velocity[0].copy()
    f = np.array([1.0, -2.0, 0.5])
    b.force[0] = f
    n = 100
    world.step(n)
    t = n * DT
    # Kick-drift-kick is exact for a constant force: x = x0 + v0 t + ½ (f/m) t².
    close(b.linear_velocity[0], v0 + f / m * t, rtol=1e-13)
    close(b.position[0], p0 + v0 * t + 0.5 * f / m * t**2, rtol=1e-13)
    close(b.force[0], f, rtol=0.0)  # persists, untouched
    close(b.linear_velocity[1], [0.0, 0.0, 0.0], rtol=0.0)  # only body 0 was pushed


def test_written_torque_spins_up_a_sphere():
    world = make_world()
    b = world.bodies
    inertia = b.inertia[0, 0]
    tau = np.array([0.02, 0.0, -0.01])
    b.torque[0] = tau
    n = 60
    world.step(n)
    # Isotropic body: L = I ω and dL/dt = τ, so ω(t) = τ t / I.
    close(b.angular_velocity[0], tau * n * DT / inertia, rtol=1e-13)
    close(b.angular_momentum[0], tau * n * DT, rtol=1e-13)
    close(b.torque[0], tau, rtol=0.0)


@pytest.mark.parametrize("name", READ_ONLY)
def test_read_only_views_refuse_writes(name):
    world = make_world()
    view = getattr(world.bodies, name)
    before = view.copy()
    with pytest.raises(ValueError, match="read-only"):
        view[0] = 1.0
    with pytest.raises(ValueError):
        view += 1.0
    with pytest.raises(ValueError):
        view.setflags(write=True)
    np.testing.assert_array_equal(view, before)
    world.step()
    # Nothing that a step relies on was changed: the next read is the same object's memory.
    assert np.shares_memory(view, getattr(world.bodies, name))


def test_a_view_keeps_its_world_alive_and_working():
    world = make_world()
    b = world.bodies
    pos, rot, mass = b.position, b.rotation, b.mass
    bodies_only = world.bodies
    expected_pos, expected_rot, expected_mass = pos.copy(), rot.copy(), mass.copy()
    v = b.linear_velocity[:2].copy()
    del world, b
    gc.collect()
    # Churn the allocator: freed memory would now be reused and overwritten.
    for _ in range(20):
        other = make_world()
        other.bodies.position[:] = -7.0
        other.step(3)
        del other
        junk = [np.full(1000, 13.0) for _ in range(50)]
        del junk
    gc.collect()
    np.testing.assert_array_equal(pos, expected_pos)
    np.testing.assert_array_equal(rot, expected_rot)
    np.testing.assert_array_equal(mass, expected_mass)
    # The world is still reachable through the view, and still steps the same memory.
    world = pos.base
    assert isinstance(world, rr.World)
    world.step(2)
    close(pos[:2], expected_pos[:2] + v * 2 * DT, rtol=1e-14, scale=4.0)
    pos[0] = (9.0, 9.0, 9.0)  # writing after the original name is gone: no crash
    assert np.array_equal(bodies_only.position[0], [9.0, 9.0, 9.0])
    del world
    gc.collect()
    np.testing.assert_array_equal(bodies_only.mass, expected_mass)


def test_a_bodies_object_alone_keeps_its_world_alive():
    bodies = make_world().bodies
    gc.collect()
    for _ in range(10):
        make_world().bodies.position[:] = np.nan
    assert len(bodies) == 3
    close(bodies.position[0], [1.0, 2.0, 3.0], rtol=0.0)
    close(bodies.mass[1], 10.0, rtol=0.0)


def test_derived_views_are_refreshed_by_step():
    world = make_world()
    b = world.bodies
    rot, iw, lw = b.rotation, b.inertia_world, b.angular_momentum
    before = rot.copy(), iw.copy(), lw.copy()
    world.step(25)  # the box (body 1) tumbles by ~1.25 rad
    # The arrays obtained before the step now show the state after it.
    r = Rotation.from_quat(b.orientation).as_matrix()
    close(rot, r, rtol=1e-13)
    i_world = np.einsum("nij,nj,nkj->nik", r[:2], b.inertia[:2], r[:2])
    close(iw[:2], i_world, rtol=1e-13, scale=np.abs(i_world).max())
    close(lw[:2], np.einsum("nij,nj->ni", i_world, b.angular_velocity[:2]), rtol=1e-13)
    # ... and it is a different state (a stale view would fail here).
    assert np.abs(rot[1] - before[0][1]).max() > 0.1
    assert np.abs(iw[1] - before[1][1]).max() > 0.1
    # The fixed body's derived values: its pose, infinite inertia, no momentum.
    close(rot[2], np.eye(3), rtol=0.0)
    assert np.all(np.isinf(np.diag(iw[2])))
    close(lw[2], np.zeros(3), rtol=0.0)


def test_derived_views_follow_an_orientation_written_before_the_step():
    world = make_world()
    b = world.bodies
    rot = b.rotation
    q = Rotation.from_rotvec([0.0, 0.0, 1.0])
    b.orientation[2] = q.as_quat()  # a fixed body may be moved by the user
    world.step()
    close(rot[2], q.as_matrix(), rtol=1e-15)


def test_empty_world_has_empty_views():
    world = rr.Scene().build(dt=DT)
    b = world.bodies
    assert len(b) == 0
    for name in WRITABLE + READ_ONLY:
        view = getattr(b, name)
        assert view.shape == (0, *ROW_SHAPE[name]), name
        assert view.dtype == np.float64
    world.step(3)
    assert world.stages == []
    assert world.steps == 3
    close(world.time, 3 * DT, rtol=1e-15)
    assert world.kinetic_energy() == 0.0
