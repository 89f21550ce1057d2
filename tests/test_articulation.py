"""Articulations in reduced coordinates: the pendulum against its exact period,
convergence orders, a floating base's momenta, the pipeline.

References are computed here from the formulas: the large-amplitude period
4 K(k²)/ω0 (SciPy's `ellipk`, k = sin(θ0/2)) of a physical pendulum, and
DOP853 at rtol 1e-12 for the double pendulum (tests/chain_reference.py).
Crossings of the angle through 0 are located by cubic Hermite interpolation of
the joint's angle and rate at the steps around them (error O(h⁴), ~1e-11 s
here), so the measured period is the integrator's, not the interpolation's.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipk

import rigidrs as rr
from chain_reference import G, box_inertia_about_y, chain_scene, joints_xz, reference, world_ends

FRAME = 1 / 60


def hermite_crossings(t: list[float], x: list[float], v: list[float]) -> list[float]:
    """Times where x falls through 0, from the cubic Hermite interpolant."""
    out = []
    for k in range(1, len(x)):
        if x[k - 1] > 0 >= x[k]:
            h = t[k] - t[k - 1]

            def p(s: float, k: int = k, h: float = h) -> float:
                return ((2 * s**3 - 3 * s**2 + 1) * x[k - 1] + (s**3 - 2 * s**2 + s) * h * v[k - 1]
                        + (-2 * s**3 + 3 * s**2) * x[k] + (s**3 - s**2) * h * v[k])

            out.append(t[k - 1] + h * brentq(p, 0.0, 1.0, xtol=1e-15))
    return out


def pendulum(length: float, theta0: float, dt: float, integrator: str = "leapfrog", periods: float = 3.2,
             substeps: int | None = None, kind: str = "hinge") -> tuple[float, float, np.ndarray]:
    """(measured period, exact period, angles) of a ball (r = 5 cm, 1 kg) on a hinge
    (or spherical joint) at `length` from the pivot, released at rest from `theta0`."""
    radius, mass = 0.05, 1.0
    scene = rr.Scene(gravity=(0, 0, -G))
    ball = scene.add_body(rr.Sphere(radius), mass=mass,
                          position=(length * math.sin(theta0), 0, -length * math.cos(theta0)))
    scene.add_joint(kind, ball, None, anchor=(0, 0, 0), axis=(0, 1, 0))
    world = scene.build(dt=dt, articulation_integrator=integrator, articulation_substeps=substeps)
    i_pivot = 0.4 * mass * radius**2 + mass * length**2
    exact = 4 * ellipk(math.sin(theta0 / 2) ** 2) * math.sqrt(i_pivot / (mass * G * length))
    t, x, v = [], [], []
    for _ in range(int(periods * exact / dt)):
        world.step()
        p, vel = world.bodies.position[ball], world.bodies.linear_velocity[ball]
        # The swing angle from the vertical, and its rate, from the body's state.
        t.append(world.time)
        x.append(math.atan2(p[0], -p[2]))
        v.append((-p[2] * vel[0] + p[0] * vel[2]) / (p[0] ** 2 + p[2] ** 2))
    crossings = hermite_crossings(t, x, v)
    return (crossings[-1] - crossings[0]) / (len(crossings) - 1), exact, np.array(x)


@pytest.mark.parametrize("kind", ["hinge", "spherical"])
def test_default_pendulum_period_within_2e4(kind: str) -> None:
    # Bar (issue 14): 1 m from 0.5 rad at 1/60 within 2e-4 with the default.
    # The leapfrog is Störmer–Verlet here: (ωh)²/24 = 1.1e-4 (measured −1.096e-4).
    measured, exact, _ = pendulum(1.0, 0.5, FRAME, kind=kind)
    assert abs(measured / exact - 1) <= 2e-4


def test_high_order_pendulum_period_within_1e7() -> None:
    # RK4 on the joint chart: measured 5.5e-8 at 1/60 (bar 1e-7).
    measured, exact, _ = pendulum(1.0, 0.5, FRAME, integrator="rk4")
    assert abs(measured / exact - 1) <= 1e-7


@pytest.mark.parametrize("integrator", ["leapfrog", "rk4"])
def test_amplitude_after_100_periods(integrator: str) -> None:
    # No numerical damping: the leapfrog is symplectic here (its amplitude
    # oscillates by O(h²) and returns), RK4 damps by ~(ωh)⁶/144 per step (2e-6
    # over 12 000 steps). Bar: within 1e-3 of 0.5 rad after 100 periods.
    _, exact, x = pendulum(1.0, 0.5, FRAME, integrator=integrator, periods=100.5)
    last = x[-int(exact / FRAME):]
    assert abs(np.abs(last).max() - 0.5) <= 1e-3


@pytest.mark.parametrize("length, theta0", [(0.3, 0.5), (2.0, 1.5), (1.0, math.radians(170))])
@pytest.mark.parametrize("integrator", sorted(rr.ARTICULATION_INTEGRATORS))
def test_period_error_converges_at_the_nominal_order(length: float, theta0: float, integrator: str) -> None:
    # One substep per step (no automatic refinement), dt and dt/2 at a resolution
    # where the error is far above round-off: the slope log2(e(dt)/e(dt/2)) is
    # the nominal order within ±0.25 (euler on a pendulum is symplectic, so its
    # period error is second order like the leapfrog's; its positions are first
    # order: the next test). At 170° RK4's fourth-order term is small: measured
    # slopes 4.9, 5.0, 5.1 from ωdt = 0.4 down to 0.05 (faster than nominal).
    order = {"leapfrog": 2, "euler": 2, "rk4": 4}[integrator]
    omega = math.sqrt(G / length)
    dt = 0.08 / omega if integrator == "rk4" else 0.05 / omega
    errors = []
    for h in (dt, dt / 2):
        measured, exact, _ = pendulum(length, theta0, h, integrator=integrator, substeps=1, periods=2.2)
        errors.append(abs(measured / exact - 1))
    slope = math.log2(errors[0] / errors[1])
    if integrator == "rk4" and theta0 > 2.5:
        assert order - 0.25 <= slope <= order + 1.25, errors
    else:
        assert slope == pytest.approx(order, abs=0.25), errors


def double_pendulum_error(integrator: str, dt: float) -> float:
    lengths, masses = np.array([0.6, 0.4]), np.array([1.0, 0.5])
    theta0 = np.array([1.2, 0.3])
    scene, bodies = chain_scene(theta0, lengths, masses, 0.02)
    world = scene.build(dt=dt, articulation_integrator=integrator, articulation_substeps=1)
    world.step(int(round(0.5 / dt)))
    ref = reference(theta0, lengths, masses, box_inertia_about_y(masses, lengths, 0.02), np.array([0.0, 0.5]))[-1]
    return float(np.abs(world_ends(world, bodies, lengths) - joints_xz(ref, lengths)).max())


@pytest.mark.parametrize("integrator", sorted(rr.ARTICULATION_INTEGRATORS))
def test_double_pendulum_positions_converge_at_the_nominal_order(integrator: str) -> None:
    # Velocity-dependent forces (Coriolis, centrifugal): positions at t = 0.5 s
    # against DOP853, at dt and dt/2 (one substep each). Slope within ±0.3.
    order = rr.ARTICULATION_INTEGRATORS[integrator]
    dt = 1 / 120 if integrator == "rk4" else 1 / 480
    e1, e2 = double_pendulum_error(integrator, dt), double_pendulum_error(integrator, dt / 2)
    assert math.log2(e1 / e2) == pytest.approx(order, abs=0.3), (e1, e2)


def test_integrator_names_and_orders() -> None:
    assert rr.ARTICULATION_INTEGRATORS == {"leapfrog": 2, "euler": 1, "rk4": 4}
    with pytest.raises(rr.RigidError, match="articulation_integrator"):
        rr.Scene().build(dt=FRAME, articulation_integrator="verlet")


def floating_pair(substeps: int | None = None) -> tuple[rr.World, int, int]:
    """Two boxes on a hinge in free space (a floating base), both spinning."""
    scene = rr.Scene(gravity=(0, 0, 0))
    a = scene.add_body(rr.Box((0.2, 0.1, 0.05)), mass=1.0, linear_velocity=(0.3, 0, 0.1), angular_velocity=(0.5, 2.0, 1.0))
    b = scene.add_body(rr.Box((0.1, 0.15, 0.05)), mass=2.0, position=(0.5, 0.1, 0), angular_velocity=(-1.0, 0.3, 3.0))
    scene.add_joint("hinge", b, a, anchor=(0.25, 0.05, 0), axis=(0, 0, 1))
    return scene.build(dt=FRAME, articulation_substeps=substeps), a, b


def momentum_drift(substeps: int | None) -> tuple[float, float, float]:
    world, _, _ = floating_pair(substeps)
    p0, l0, e0 = world.linear_momentum(), world.angular_momentum(), world.kinetic_energy()
    worst = np.zeros(3)
    for _ in range(60):
        world.step(10)
        now = [np.linalg.norm(world.linear_momentum() - p0) / np.linalg.norm(p0),
               np.linalg.norm(world.angular_momentum() - l0) / np.linalg.norm(l0),
               abs(world.kinetic_energy() - e0) / e0]
        worst = np.maximum(worst, now)
    return tuple(worst)


def test_floating_base_keeps_its_momenta_to_second_order() -> None:
    # A free root (6 dofs) and a hinge. The joint forces are internal, but an
    # integrator in joint coordinates is not variational: angular momentum and
    # energy are kept to its O(h²), bounded (no drift over the 10 s). Linear
    # momentum is balanced exactly after every substep (its change is known:
    # the external impulses; rust/articulation/momentum.rs), which also brings
    # the others down. Measured worst relative changes (p, L, E): 2.5e-14,
    # 6.9e-4, 8.8e-5 at the automatic single substep (ω dt = 0.05 here);
    # 3.6e-14, 4.5e-5, 2.1e-6 at 4 substeps and L, E ÷4.0, ÷3.9 at 8 (before
    # the balance: p 1.0e-3, 6.2e-5). Asserted: p to round-off (1e-12: the sums
    # of a few hundred steps), L and E ÷[3.5, 4.5] per halving, and the
    # automatic case within 1e-2.
    coarse, fine = momentum_drift(4), momentum_drift(8)
    assert max(coarse[0], fine[0]) <= 1e-12, (coarse, fine)
    for c, f in zip(coarse[1:], fine[1:]):
        assert 3.5 <= c / f <= 4.5, (coarse, fine)
    auto = momentum_drift(None)
    assert auto[0] <= 1e-12 and max(auto) <= 1e-2, auto
    world, a, b = floating_pair()
    assert world.stages == ["articulation"]
    info = world.articulations()
    assert info[0]["bodies"] == [a, b] and info[0]["joints"] == [-1, 0] and info[0]["dofs"] == 7


def test_same_scene_same_steps_same_bits() -> None:
    w1, _, _ = floating_pair()
    w2, _, _ = floating_pair()
    w1.step(100)
    w2.step(100)
    assert np.array_equal(w1.bodies.position, w2.bodies.position)
    assert np.array_equal(w1.bodies.orientation, w2.bodies.orientation)
    assert np.array_equal(w1.bodies.angular_velocity, w2.bodies.angular_velocity)


def test_stage_and_profile() -> None:
    world, _, _ = floating_pair()
    world.step(5)
    prof = world.profile()
    assert "articulation" in world.stages and prof["articulation"] > 0.0 and prof["steps"] == 5


def test_writing_a_link_pose_is_overwritten_by_the_next_step() -> None:
    # Documented: an articulated link's pose and velocity are outputs of its
    # joints; a write through the body views lasts until the next step.
    measured_world, _, b = floating_pair(substeps=4)
    twin, _, _ = floating_pair(substeps=4)
    measured_world.bodies.position[b] += 10.0
    measured_world.step()
    twin.step()
    assert np.array_equal(measured_world.bodies.position, twin.bodies.position)
