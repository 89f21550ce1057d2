"""Gravity, applied forces and torques against exact references (REFERENCES.md,
"Under gravity and torque"): the projectile, forces at a world point, their
persistence, and dL/dt = τ.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr
import reference as ref

GRAVITY = np.array([0.0, 0.0, -9.81])
P0 = np.array([1.0, -2.0, 3.0])
V0 = np.array([3.0, -1.0, 8.0])


def projectile(integrator: str, dt: float) -> rr.World:
    """A spinning asymmetric box thrown in gravity: the rotation must not disturb
    the translation."""
    scene = rr.Scene(gravity=GRAVITY)
    scene.add_body(rr.Box(half_extents=(0.05, 0.2, 0.45)), mass=10.0, position=P0, linear_velocity=V0,
                   angular_velocity=(0.1, 5.0, 0.1))
    world = scene.build(dt=dt, integrator=integrator)
    world.profiling = False
    return world


def fly(world: rr.World, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Times, positions and velocities after each of ``n`` steps."""
    p = np.empty((n, 3))
    v = np.empty((n, 3))
    for k in range(n):
        world.step()
        p[k], v[k] = world.bodies.position[0], world.bodies.linear_velocity[0]
    return world.dt * np.arange(1, n + 1), p, v


# Position error of each method relative to the exact parabola, in units of
# g·t·dt/2 (REFERENCES.md): second-order splittings and RK4 have none; semi-
# implicit Euler (kick then drift: symplectic_euler and implicit_gyro) is ahead by
# exactly g·t·dt/2, explicit Euler (drift then kick) behind by the same.
PROJECTILE_ERROR = {"strang": 0, "rk4": 0, "yoshida4": 0, "suzuki4": 0,
                    "symplectic_euler": +1, "implicit_gyro": +1, "euler": -1}


def test_every_integrator_has_a_projectile_error() -> None:
    assert set(PROJECTILE_ERROR) == set(rr.INTEGRATORS)


@pytest.mark.parametrize("dt", [1 / 60, 1 / 240])
@pytest.mark.parametrize("integrator", list(rr.INTEGRATORS))
def test_projectile(integrator: str, dt: float) -> None:
    """p(t) = p0 + v0 t + g t²/2 + s·g·t·dt/2 and v(t) = v0 + g t after every step
    of 2 s, to round-off: at most one ulp of the largest |p| (7.5 m: 1.8e-15 m)
    and |v| (12 m/s: 2.7e-15 m/s) per step, i.e. 2e-15 m and 3e-15 m/s times the
    number of steps (measured ≤ 2.7e-13 m and 1e-13 m/s after 480 steps, 1/4 of
    that and less). The term s·g·t·dt/2 is 0.16 m at t = 2 s, dt = 1/60, so a wrong
    sign or a missing term fails by 11 orders of magnitude."""
    world = projectile(integrator, dt)
    assert "forces" in world.stages or world.stages == ["rk4"]
    n = round(2.0 / dt)
    t, p, v = fly(world, n)
    tt = t[:, None]
    p_exact = P0 + V0 * tt + 0.5 * GRAVITY * tt**2 + PROJECTILE_ERROR[integrator] * 0.5 * GRAVITY * tt * dt
    dp = np.abs(p - p_exact).max()
    dv = np.abs(v - (V0 + GRAVITY * tt)).max()
    print(f"\n{integrator} 1/{round(1 / dt)}: max |p − p_expected| {dp:.1e} m, |v − v_exact| {dv:.1e} m/s")
    assert dp <= 2e-15 * n
    assert dv <= 3e-15 * n


# --------------------------------------------------------------------------------------
# Forces at a world point
# --------------------------------------------------------------------------------------

SPHERE_R, SPHERE_M = 0.1, 2.0
SPHERE_I = 0.4 * SPHERE_M * SPHERE_R**2  # solid ball, 2/5 m r²
P_BODY = np.array([1.0, 2.0, 3.0])


def sphere_world(integrator: str = "strang", dt: float = 1 / 240) -> rr.World:
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(rr.Sphere(radius=SPHERE_R), mass=SPHERE_M, position=P_BODY)
    world = scene.build(dt=dt, integrator=integrator)
    world.profiling = False
    return world


def test_force_at_point_gives_force_and_torque() -> None:
    """apply_force(f, point) stores F = f and τ = (point − p) × f; forces add up; a
    force through the centre of mass adds no torque. Same formula, same floating
    point operations: equal to 1e-15 relative."""
    world = sphere_world()
    np.testing.assert_allclose(world.bodies.inertia[0], [SPHERE_I] * 3, rtol=1e-14)
    f1, x1 = np.array([0.0, 3.0, 0.0]), P_BODY + [0.1, 0.0, 0.05]
    f2, x2 = np.array([-1.0, 0.5, 2.0]), P_BODY + [-0.03, 0.08, 0.02]
    world.apply_force(0, f1, point=x1)
    np.testing.assert_allclose(world.bodies.force[0], f1, rtol=1e-15)
    np.testing.assert_allclose(world.bodies.torque[0], [-0.15, 0.0, 0.3], rtol=1e-14, atol=1e-16)
    world.apply_force(0, f2, point=x2)
    world.apply_force(0, f1)  # through the centre of mass
    np.testing.assert_allclose(world.bodies.force[0], 2 * f1 + f2, rtol=1e-15)
    tau = np.cross(x1 - P_BODY, f1) + np.cross(x2 - P_BODY, f2)
    np.testing.assert_allclose(world.bodies.torque[0], tau, rtol=1e-15, atol=1e-17)


@pytest.mark.parametrize("integrator", ["strang", "yoshida4", "suzuki4", "rk4"])
def test_force_at_point_moves_a_sphere(integrator: str) -> None:
    """A sphere at rest pushed off-centre for t = 0.5 s: v = F t/m, p = p0 + F t²/(2m),
    ω = τ t/I (I scalar, so ω stays along τ), and it has turned by |τ| t²/(2I)
    about τ̂ (0.95 rad) — all exact for constant loads in these integrators;
    tolerances are round-off of 120 steps: 1e-13 relative for v, ω and the angle
    (they start at 0), and for the displacement 1e-13 m, one ulp of |p0| = 3.7 m
    (8e-16 m) per step. Except RK4's rotation, which is 4th order, not exact:
    measured 1.0e-11 rad, bound 1e-9 rad."""
    world = sphere_world(integrator)
    f, x = np.array([0.4, -0.2, 0.3]), P_BODY + [0.05, 0.1, -0.02]
    world.apply_force(0, f, point=x)
    tau = np.cross(x - P_BODY, f)
    world.step(120)
    t = world.time
    b = world.bodies
    np.testing.assert_allclose(b.linear_velocity[0], f * t / SPHERE_M, rtol=1e-13)
    np.testing.assert_allclose(b.position[0] - P_BODY, f * t**2 / (2 * SPHERE_M), rtol=0, atol=1e-13)
    np.testing.assert_allclose(b.angular_velocity[0], tau * t / SPHERE_I, rtol=1e-13)
    turned = Rotation.from_rotvec(tau * t**2 / (2 * SPHERE_I)).as_matrix()
    angle = ref.rotation_angle(turned, b.rotation[0])
    bound = 1e-9 if integrator == "rk4" else 1e-13 * np.linalg.norm(tau) * t**2 / (2 * SPHERE_I)
    assert angle < bound


def test_applied_forces_persist_until_cleared() -> None:
    """A force and torque applied once act over every later step, across step()
    calls, until clear_forces(): v and ω grow linearly (exact for strang, to 1e-13
    relative), the arrays keep their values; after clearing they are zero, the
    'forces' stage leaves the pipeline (zero gravity), and v, ω stay bit for bit."""
    world = sphere_world()
    assert "forces" not in world.stages
    f, tau = np.array([1.0, 0.0, -0.5]), np.array([0.0, 0.02, 0.01])
    world.apply_force(0, f)
    world.apply_torque(0, tau)
    assert "forces" in world.stages
    for _ in range(3):
        world.step(40)
        np.testing.assert_array_equal(world.bodies.force[0], f)
        np.testing.assert_array_equal(world.bodies.torque[0], tau)
        np.testing.assert_allclose(world.bodies.linear_velocity[0], f * world.time / SPHERE_M, rtol=1e-13)
        np.testing.assert_allclose(world.bodies.angular_velocity[0], tau * world.time / SPHERE_I, rtol=1e-13)
    world.clear_forces()
    np.testing.assert_array_equal(world.bodies.force, 0.0)
    np.testing.assert_array_equal(world.bodies.torque, 0.0)
    assert "forces" not in world.stages
    v, w = world.bodies.linear_velocity.copy(), world.bodies.angular_velocity.copy()
    world.step(40)
    np.testing.assert_array_equal(world.bodies.linear_velocity, v)
    np.testing.assert_array_equal(world.bodies.angular_velocity, w)


def test_torque_arm_uses_the_current_position() -> None:
    """The torque of a force at a point is taken about where the body is when the
    force is applied, not where it started."""
    world = sphere_world()
    world.bodies.linear_velocity[0] = [1.0, 0.0, 0.0]
    world.step(60)
    p = world.bodies.position[0].copy()
    np.testing.assert_allclose(p, P_BODY + [world.time, 0.0, 0.0], rtol=1e-14)
    f, x = np.array([0.0, 0.0, 1.0]), np.array([2.0, 2.0, 3.0])
    world.apply_force(0, f, point=x)
    np.testing.assert_allclose(world.bodies.torque[0], np.cross(x - p, f), rtol=1e-14)


# --------------------------------------------------------------------------------------
# dL/dt = τ on an asymmetric body
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("integrator", ["strang", "yoshida4", "suzuki4", "rk4", "euler"])
def test_torque_changes_angular_momentum_exactly(integrator: str) -> None:
    """A constant torque on a spinning asymmetric body: world L(t) = L0 + τ t after
    every 240 steps over 10 s at 1/240. Exact for every method whose kicks add
    τ·(fraction of h) to L and whose rotation keeps world L; the bound is round-off:
    1e-12·|L| (~1e-16 relative per stage, 2400 steps of up to 5 stages; measured
    3.5e-14 for strang, ≤ 2.7e-13 for all). The motion is far from trivial: |L|
    goes from 3.4 to 6.9 kg·m²/s while the body tumbles."""
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    rot = Rotation.from_rotvec([0.2, 0.7, -0.4])
    scene.add_body(rr.Box(half_extents=(0.05, 0.2, 0.45)), mass=10.0, orientation=rot.as_quat(),
                   angular_velocity=rot.apply([0.1, 5.0, 0.1]))
    world = scene.build(dt=1 / 240, integrator=integrator)
    world.profiling = False
    tau = np.array([0.3, -0.2, 0.5])
    world.apply_torque(0, tau)
    l0 = world.bodies.angular_momentum[0].copy()
    worst = 0.0
    for _ in range(10):
        world.step(240)
        l_exact = l0 + tau * world.time
        worst = max(worst, float(np.linalg.norm(world.bodies.angular_momentum[0] - l_exact) / np.linalg.norm(l_exact)))
        np.testing.assert_allclose(world.angular_momentum(), world.bodies.angular_momentum[0], rtol=1e-15, atol=1e-15)
    print(f"\n{integrator}: max |L − (L0 + τt)|/|L| {worst:.1e}")
    assert worst < 1e-12
