"""Coulomb friction against the exact references of REFERENCES.md (Contact):

* a block on an incline slides with ``a = g (sin θ − μ cos θ)`` and does not creep
  (< 1 mm in 10 s) when ``tan θ < μ``, with sleeping on and off;
* a block sliding on flat ground stops after ``v0² / (2 μ g)``;
* diagonal push: the friction force opposes the sliding direction exactly (a true
  cone, not a pyramid), so the acceleration is parallel to the push within 1°;
* a sphere launched sliding starts to roll at ``t* = 2 v0 / (7 μ g)`` with
  ``v* = 5 v0 / 7`` after slipping ``12 v0² / (49 μ g)``;
* static friction μs holds what is below it, sliding friction μk acts beyond;
* materials combine by the geometric mean of friction.

Everything runs at the engine's defaults (240 Hz here, 4 substeps, 1 iteration)
unless a test says otherwise: the bars are for the solver a user gets.

Tolerances. A body sliding under constant forces has a constant acceleration, and
the velocity-level step a touching body takes (kick, solve, drift) integrates a
constant acceleration exactly in the velocity; what is left is the contact solver's
convergence, allowed 1e-3 of the acceleration (a μ error of 3e-4 at μ = 0.3).
Distances integrate that velocity with a first-order drift, off by at most one
substep of travel ``v0 h``. Times are sampled at step ends: within one step ``dt``.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr

G = 9.81
DT = 1.0 / 240.0
H = DT / 4  # the default 4 substeps with contacts
A_TOL = 1e-3  # relative, accelerations (see the module doc)
HALF = np.array([0.2, 0.15, 0.1])  # the block: 0.4 x 0.3 x 0.2 m
DENSITY = 500.0


# ---------------------------------------------------------------------------
# Scenes
# ---------------------------------------------------------------------------


def incline(theta, mu, *, tilted_plane=True, mu_s=None, v0=0.0, seconds=1.0, **build):
    """A block at rest (or launched down-slope at ``v0``) on a slope of angle ``theta``.

    ``tilted_plane``: the ground is a plane of normal (sin θ, 0, cos θ) and the block is
    turned to lie on it; otherwise the ground is flat and gravity is tilted by θ (the
    same physics, with no placement round-off). Returns the world, the block, the
    down-slope unit vector, and the per-step down-slope displacement and speed."""
    n = np.array([math.sin(theta), 0.0, math.cos(theta)])
    if tilted_plane:
        down = np.array([math.cos(theta), 0.0, -math.sin(theta)])
        scene = rr.Scene(gravity=(0.0, 0.0, -G))
        scene.add_body(rr.Plane(normal=n, offset=0.0), fixed=True, friction=mu, static_friction=mu_s)
        q = Rotation.from_rotvec([0.0, theta, 0.0]).as_quat()
        pos = n * HALF[2]
    else:
        down = np.array([1.0, 0.0, 0.0])
        scene = rr.Scene(gravity=tuple(G * np.array([math.sin(theta), 0.0, -math.cos(theta)])))
        scene.add_body(rr.Plane(), fixed=True, friction=mu, static_friction=mu_s)
        q = [0.0, 0.0, 0.0, 1.0]
        pos = np.array([0.0, 0.0, HALF[2]])
    block = scene.add_body(
        rr.Box(HALF), density=DENSITY, position=pos, orientation=q, friction=mu, static_friction=mu_s,
        linear_velocity=v0 * down,
    )
    world = scene.build(dt=DT, **build)
    x, v = run(world, block, down, seconds)
    return world, block, down, x, v


def run(world, body, direction, seconds):
    """Steps ``seconds``; returns displacement and speed along ``direction`` per step."""
    n = int(round(seconds / DT))
    p0 = world.bodies.position[body].copy()
    x, v = np.empty(n + 1), np.empty(n + 1)
    x[0], v[0] = 0.0, world.bodies.linear_velocity[body] @ direction
    for k in range(n):
        world.step(1)
        x[k + 1] = (world.bodies.position[body] - p0) @ direction
        v[k + 1] = world.bodies.linear_velocity[body] @ direction
    return x, v


def flat(shape, mu, *, mu_s=None, velocity=(0.0, 0.0, 0.0), yaw=0.0, floor_mu=None, **build):
    """A body resting on flat ground, launched with ``velocity``."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=mu if floor_mu is None else floor_mu, static_friction=mu_s)
    height = shape.radius if isinstance(shape, rr.Sphere) else shape.half_extents[2]
    body = scene.add_body(
        shape, density=DENSITY, position=(0.0, 0.0, height), orientation=Rotation.from_rotvec([0, 0, yaw]).as_quat(),
        friction=mu, static_friction=mu_s, linear_velocity=velocity,
    )
    return scene.build(dt=DT, **build), body


def history(world, body, seconds):
    """Position, velocity and angular velocity of ``body`` after each step."""
    n = int(round(seconds / DT))
    out = {k: np.empty((n + 1, 3)) for k in ("p", "v", "w")}
    for k in range(n + 1):
        if k:
            world.step(1)
        out["p"][k] = world.bodies.position[body]
        out["v"][k] = world.bodies.linear_velocity[body]
        out["w"][k] = world.bodies.angular_velocity[body]
    out["t"] = np.arange(n + 1) * DT
    return out


def angle_deg(a, b):
    """Angle between 2D vectors (rows), degrees."""
    cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    dot = np.sum(a[..., :2] * b[..., :2], axis=-1)
    return np.degrees(np.abs(np.arctan2(cross, dot)))


# ---------------------------------------------------------------------------
# Incline
# ---------------------------------------------------------------------------

GEOMETRY = [True, False]
GEOMETRY_IDS = ["tilted plane", "tilted gravity"]


@pytest.mark.parametrize("tilted_plane", GEOMETRY, ids=GEOMETRY_IDS)
@pytest.mark.parametrize("degrees", [30.0, 45.0])
def test_block_slides_down_an_incline_with_the_coulomb_acceleration(degrees, tilted_plane):
    # Measured: a / a_ref − 1 = +7.7 % (30°), +3.1 % (45°), both geometries; with
    # iterations=4 +6.9 % and +2.7 %. The block also yaws (0.001-0.01 rad/s after 1 s).
    theta, mu = math.radians(degrees), 0.3
    world, block, down, x, v = incline(theta, mu, tilted_plane=tilted_plane)
    a_ref = G * (math.sin(theta) - mu * math.cos(theta))
    k0 = int(0.25 / DT)  # past the first steps (no warm start yet)
    a = (v[-1] - v[k0]) / ((len(v) - 1 - k0) * DT)
    assert abs(a - a_ref) <= A_TOL * a_ref


@pytest.mark.parametrize("tilted_plane", GEOMETRY, ids=GEOMETRY_IDS)
def test_frictionless_block_slides_with_g_sin_theta(tilted_plane):
    theta = math.radians(20.0)
    world, block, down, x, v = incline(theta, 0.0, tilted_plane=tilted_plane)
    a_ref = G * math.sin(theta)
    a = (v[-1] - v[1]) / ((len(v) - 2) * DT)
    assert abs(a - a_ref) <= A_TOL * a_ref
    assert "friction" not in world.stages


@pytest.mark.parametrize("sleep", [True, False], ids=["sleep", "no sleep"])
@pytest.mark.parametrize("tilted_plane", GEOMETRY, ids=GEOMETRY_IDS)
@pytest.mark.parametrize(
    "fraction",
    [
        0.5,
        0.75,
        0.9,
    ],
)
def test_block_below_the_friction_angle_does_not_creep(fraction, tilted_plane, sleep):
    mu = 0.5
    theta = math.atan(fraction * mu)
    world, block, down, x, v = incline(theta, mu, tilted_plane=tilted_plane, seconds=10.0, sleep=sleep)
    assert np.max(np.abs(x)) < 1e-3  # REFERENCES.md: < 1 mm in 10 s
    assert world.bodies.sleeping[block] == sleep  # at rest it falls asleep iff allowed


@pytest.mark.parametrize("fraction", [0.5, 0.75])
def test_resting_block_on_an_incline_reports_friction_balancing_gravity(fraction):
    # At rest the contact forces balance the weight: Σ friction impulse / dt =
    # −m g sin θ along the slope and Σ normal impulse / dt = m g cos θ. The block's
    # velocity is zero to ~1e-15 m/s, so the balance holds to ~1e-9 relative; 1e-6 allows
    # the soft contact's last settling.
    mu = 0.5
    theta = math.atan(fraction * mu)
    world, block, down, x, v = incline(theta, mu, tilted_plane=False, seconds=2.0, sleep=False)
    c = world.contacts()
    m = world.bodies.mass[block]
    np.testing.assert_allclose(c["friction_impulse"].sum(axis=0) / DT, [-m * G * math.sin(theta), 0.0, 0.0],
                               rtol=0, atol=1e-6 * m * G)
    assert abs(c["normal_impulse"].sum() / DT - m * G * math.cos(theta)) <= 1e-6 * m * G
    # Each point's friction is inside its cone.
    assert np.all(np.linalg.norm(c["friction_impulse"], axis=1) <= mu * c["normal_impulse"] * (1 + 1e-9))


# ---------------------------------------------------------------------------
# Sliding to rest
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("mu", [0.2, 0.5])
def test_block_slides_to_rest_after_v0_squared_over_two_mu_g(mu):
    # Measured: 2.526 m for 2.294 m (μ = 0.2, +10.1 %), 1.043 m for 0.917 m (μ = 0.5,
    # +13.7 %); iterations=4: +6.7 %, +6.4 %; and it ends 3-7 mm to the side of its path.
    v0 = 3.0
    world, block = flat(rr.Box(HALF), mu, velocity=(v0, 0.0, 0.0))
    t_stop = v0 / (mu * G)
    h = history(world, block, t_stop + 0.5)
    d = np.linalg.norm(h["p"][-1, :2] - h["p"][0, :2])
    assert abs(d - v0**2 / (2 * mu * G)) <= v0 * H
    # Stopped: below 1e-3 v0. While it slides, friction's torque shifts the load to
    # the leading edge of the compliant contact; when it stops the box rocks back on
    # it (measured ≤ 2.3e-4 m/s, decaying with the contact's damping), so "at rest"
    # means slower than that rocking, not zero.
    speed = np.linalg.norm(h["v"], axis=1)
    stopped = h["t"][np.argmax(speed <= 1e-3 * v0)]
    assert t_stop - DT <= stopped <= t_stop + DT
    assert np.max(speed[h["t"] > t_stop + DT]) <= 1e-3 * v0


# ---------------------------------------------------------------------------
# Diagonal push: a true cone
# ---------------------------------------------------------------------------
# A pyramid clamps the friction along two fixed tangent axes separately; sliding at
# 30° from them it would brake along 45°, and a push at 30° (F = m g, μ = 0.5) would
# accelerate the block along 0°. The cone keeps both exactly on the push line.

DIAGONAL = [(10.0, 0.0), (30.0, 0.0), (60.0, 0.0), (30.0, 20.0), (60.0, 20.0)]
DIAGONAL_IDS = [f"{a:g}deg yaw{y:g}" for a, y in DIAGONAL]


@pytest.mark.parametrize("degrees,yaw", DIAGONAL, ids=DIAGONAL_IDS)
def test_diagonal_slide_decelerates_against_its_velocity(degrees, yaw):
    # Measured: the deceleration is 5.0°-13.8° off −v and the velocity turns by
    # 4.1°-11.7° in 0.4 s (30°, yaw 0: from 30° to 41.7°); |a| = 0.79-0.99 μ g. The
    # same with iterations=4.
    mu, v0, phi = 0.5, 3.0, math.radians(degrees)
    u = np.array([math.cos(phi), math.sin(phi), 0.0])
    world, block = flat(rr.Box(HALF), mu, velocity=v0 * u, yaw=math.radians(yaw))
    h = history(world, block, 0.4)  # stops at 0.61 s
    acc = np.diff(h["v"], axis=0) / DT
    sel = slice(2, None)  # after the first two steps (no warm start yet)
    assert np.max(angle_deg(acc[sel], -h["v"][1:][sel])) <= 1.0
    assert np.max(angle_deg(h["v"], u[None, :])) <= 1.0
    np.testing.assert_allclose(np.linalg.norm(acc[sel, :2], axis=1), mu * G, rtol=A_TOL)


@pytest.mark.parametrize("degrees,yaw", DIAGONAL, ids=DIAGONAL_IDS)
def test_diagonal_push_accelerates_along_the_push(degrees, yaw):
    # Measured: 1.4°-6.7° off the push (30°, yaw 0: 5.9°-6.7°), |a| 2-21 % high, and
    # the block spins up about z (0.2-0.6 rad/s in 0.5 s); the same with iterations=4.
    mu, phi = 0.5, math.radians(degrees)
    u = np.array([math.cos(phi), math.sin(phi), 0.0])
    world, block = flat(rr.Box(HALF), mu, yaw=math.radians(yaw))
    m = world.bodies.mass[block]
    world.apply_force(block, m * G * u)  # F = m g > μ m g: it slides
    h = history(world, block, 0.5)
    acc = np.diff(h["v"], axis=0) / DT
    sel = slice(2, None)
    assert np.max(angle_deg(acc[sel], u[None, :])) <= 1.0  # REFERENCES.md: within 1°
    np.testing.assert_allclose(np.linalg.norm(acc[sel, :2], axis=1), G * (1.0 - mu), rtol=A_TOL)


# ---------------------------------------------------------------------------
# Sphere launched sliding: slip, then roll
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("mu,v0", [(0.2, 1.0), (0.5, 3.0)])
def test_sphere_launched_sliding_starts_rolling_at_t_star(mu, v0):
    r = 0.1
    t_star, v_star, s_star = 2 * v0 / (7 * mu * G), 5 * v0 / 7, 12 * v0**2 / (49 * mu * G)
    world, ball = flat(rr.Sphere(r), mu, velocity=(v0, 0.0, 0.0))
    h = history(world, ball, t_star + 0.5)
    slip = h["v"][:, 0] - h["w"][:, 1] * r  # rolling along +x: v = ω_y r
    # While it slides the slip falls at 3.5 μ g; it must be gone at the first sample
    # after t*, not before t*.
    k = int(np.argmax(slip <= 1e-6 * v0))
    assert t_star <= h["t"][k] <= t_star + DT
    # Rolling on a rigid contact: no sag, the ball settles at the rest depth
    # δ = 2e-4 × slop (1 µm, rigidrs/solve/impulse.rs REST_DEPTH) whatever its load,
    # and its contact point, δ/2 inside
    # each surface, is at rest: v = ω (r − δ/2), so v − ω r = −ω δ/2 (to 1e-12 v0).
    depth = world.contacts()["depth"].max()
    delta = 2e-4 * 0.005
    assert abs(depth - delta) <= 1e-12
    after = h["t"] > t_star + DT
    np.testing.assert_allclose(slip[after], -h["w"][after, 1] * delta / 2, rtol=0, atol=1e-12 * v0)
    # The lever arm r' = r − δ/2 about the contact point keeps the angular momentum
    # m v0 r' = m v r' + (2/5) m r² v / r', so v* = v0 r'² / (r'² + 2 r² / 5) (5 v0 / 7
    # for δ = 0; 3e-6 lower here). Measured within 4e-6 of it: the slip ends inside a
    # substep, whose velocity-level step is first order.
    arm = r - delta / 2
    assert abs(h["v"][-1, 0] - v0 * arm**2 / (arm**2 + 0.4 * r**2)) <= 1e-5 * v_star
    # Slip distance: x(T) − v*(T − t*), to one substep of travel.
    s = h["p"][-1, 0] - h["p"][0, 0] - h["v"][-1, 0] * (h["t"][-1] - t_star)
    assert abs(s - s_star) <= v0 * H


# ---------------------------------------------------------------------------
# Static and dynamic friction
# ---------------------------------------------------------------------------



def test_static_friction_holds_a_push_between_mu_k_and_mu_s():
    # F = 0.5 m g with μk = 0.4 < 0.5 < μs = 0.6: nothing moves. Measured: slides 2.65 m
    # in 2 s (2.34 m with iterations=4).
    world, block = flat(rr.Box(HALF), 0.4, mu_s=0.6, sleep=False)
    world.apply_force(block, (0.5 * world.bodies.mass[block] * G, 0.0, 0.0))
    h = history(world, block, 2.0)
    assert np.max(np.linalg.norm(h["p"] - h["p"][0], axis=1)) < 1e-3  # the no-creep bar


def test_kinetic_friction_acts_beyond_mu_s():
    # F = 0.7 m g > μs m g: slides with a = F/m − μk g = 0.3 g. Measured: 3.223 m/s² for
    # 2.943 (+9.5 %); iterations=4: +8.5 %.
    world, block = flat(rr.Box(HALF), 0.4, mu_s=0.6)
    world.apply_force(block, (0.7 * world.bodies.mass[block] * G, 0.0, 0.0))
    h = history(world, block, 1.0)
    k0 = int(0.25 / DT)
    a = (h["v"][-1, 0] - h["v"][k0, 0]) / (h["t"][-1] - h["t"][k0])
    assert abs(a - 0.3 * G) <= A_TOL * 0.3 * G


def test_static_friction_holds_a_block_on_an_incline_steeper_than_mu_k():
    # tan θ = 0.5 between μk = 0.4 and μs = 0.6. Measured: slides 54.4 m in 10 s (53.1 m
    # with iterations=4).
    theta = math.atan(0.5)
    world, block, down, x, v = incline(theta, 0.4, mu_s=0.6, tilted_plane=False, seconds=10.0, sleep=False)
    assert np.max(np.abs(x)) < 1e-3


def test_launched_block_keeps_sliding_with_mu_k_on_that_incline():
    # Moving, it feels μk: a = g (sin θ − μk cos θ) > 0. Measured: 1.128 m/s² for 0.877
    # (+28.5 %); iterations=4: +25.4 %.
    theta = math.atan(0.5)
    world, block, down, x, v = incline(theta, 0.4, mu_s=0.6, v0=0.5, tilted_plane=False)
    a_ref = G * (math.sin(theta) - 0.4 * math.cos(theta))
    k0 = int(0.25 / DT)
    a = (v[-1] - v[k0]) / ((len(v) - 1 - k0) * DT)
    assert abs(a - a_ref) <= A_TOL * a_ref


# ---------------------------------------------------------------------------
# Combine rule
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("mu_body,mu_floor", [(0.2, 0.8), (0.9, 0.1), (0.3, 0.75)])
def test_friction_combines_by_the_geometric_mean(mu_body, mu_floor):
    # A contact between μ1 and μ2 behaves as one between two surfaces of sqrt(μ1 μ2)
    # (and the same for static friction): the two runs agree to round-off of the
    # combined coefficient (1 ulp of it moves the 0.5 s trajectory by ~1e-15 m).
    mu = math.sqrt(mu_body * mu_floor)
    runs = []
    for body, floor in [(mu_body, mu_floor), (mu, mu)]:
        world, block = flat(rr.Box(HALF), body, floor_mu=floor, velocity=(4.0, 1.0, 0.0))
        runs.append(history(world, block, 0.5))
    assert np.linalg.norm(runs[0]["v"][-1] - runs[0]["v"][0]) > 1.0  # friction did act
    for key in ("p", "v", "w"):
        np.testing.assert_allclose(runs[0][key], runs[1][key], rtol=0, atol=1e-12)


@pytest.mark.parametrize("mu", [0.4, 0.8])
def test_sliding_contact_points_sit_on_the_cone(mu):
    # While a box slides every contact point's friction impulse is on its cone,
    # |λt| = μ λn. Per point and substep the clamp is exact; summed over the step's
    # substeps the ratio moves by the normal impulse's change between substeps
    # (~2e-5 relative on an incline); 1e-3 relative.
    world, block = flat(rr.Box(HALF), mu, velocity=(4.0, 0.0, 0.0))
    world.step(24)  # 0.1 s: still sliding
    assert world.bodies.linear_velocity[block, 0] > 1.0
    c = world.contacts()
    assert len(c["normal_impulse"]) == 4
    ratio = np.linalg.norm(c["friction_impulse"], axis=1) / c["normal_impulse"]
    np.testing.assert_allclose(ratio, mu, rtol=1e-3)


# ---------------------------------------------------------------------------
# REFERENCES.md "Contacts and joints at default settings": the friction angle
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("degrees", [25.0, 15.0, 40.0])
@pytest.mark.parametrize("tilted_plane", GEOMETRY, ids=GEOMETRY_IDS)
def test_friction_angle_holds_just_above_and_slides_just_below(degrees, tilted_plane):
    # μs = tan θ + 0.01: creeps less than 0.1 mm in 5 s (measured 1e-6 m, the rest
    # depth it settles into). μ = tan θ − 0.01: slides at g(sin θ − μ cos θ) ± 2 %
    # (measured within 2e-5) and, with sleeping on (the default), does not fall
    # asleep while it slides (before: asleep after 8.6 mm of a 165 mm slide).
    theta = math.radians(degrees)
    held = math.tan(theta) + 0.01
    _, _, _, x, _ = incline(theta, held, mu_s=held, tilted_plane=tilted_plane, seconds=5.0)
    assert np.abs(x).max() < 1e-4
    mu = math.tan(theta) - 0.01
    world, block, _, x, v = incline(theta, mu, mu_s=mu, tilted_plane=tilted_plane, seconds=3.0)
    a_ref = G * (math.sin(theta) - mu * math.cos(theta))
    t = np.arange(len(v)) * DT
    a = np.polyfit(t[10:], v[10:], 1)[0]
    assert abs(a / a_ref - 1) <= 0.02
    assert not world.bodies.sleeping[block]
    assert abs(x[-1] / (0.5 * a_ref * t[-1] ** 2) - 1) <= 0.02


# ---------------------------------------------------------------------------
# REFERENCES.md: a top spinning on its tip
# ---------------------------------------------------------------------------


def spinning_top(rate, radius=0.05, height=0.04, tilt_deg=15.0, spin=200.0, mu=1.0):
    """A solid cone, apex down on a rough floor, in steady precession: the slow
    root of M g l = φ̇ I3 ω3 − φ̇² I1' cos θ, I1' about the tip, l = 3h/4."""
    theta = math.radians(tilt_deg)
    probe = rr.Scene()
    probe.add_body(rr.Cone(radius, height / 2), density=1000.0)
    pw = probe.build(dt=0.01)
    m, (i1, _, i3) = pw.bodies.mass[0], pw.bodies.inertia[0]
    l = 0.75 * height
    i1_tip = i1 + m * l * l
    slow = (i3 * spin - math.sqrt((i3 * spin) ** 2 - 4 * i1_tip * m * G * l * math.cos(theta))) / (2 * i1_tip * math.cos(theta))
    axis = np.array([math.sin(theta), 0.0, math.cos(theta)])  # apex to centre of mass
    turn, _ = Rotation.align_vectors([-axis], [[0.0, 0.0, 1.0]])  # the cone's +z (apex) points down the axis
    omega = (spin - slow * math.cos(theta)) * axis + slow * np.array([0.0, 0.0, 1.0])
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=mu)
    top = scene.add_body(rr.Cone(radius, height / 2), density=1000.0, position=-turn.apply([0.0, 0.0, height / 2]),
                         orientation=turn.as_quat(), angular_velocity=omega, linear_velocity=np.cross(omega, l * axis),
                         friction=mu)
    return scene.build(dt=1.0 / rate), top, slow, l, theta


def top_motion(world, top, l, seconds):
    """Spin about the axis, tilt (rad), tip position and precession angle after each step."""
    spins, tilts, tips, phis = [], [], [], []
    for _ in range(int(round(seconds / world.dt))):
        world.step(1)
        axis = -world.bodies.rotation[top][:, 2]
        spins.append(world.bodies.angular_velocity[top] @ axis)
        tilts.append(math.acos(axis[2]))
        tips.append(world.bodies.position[top] - l * axis)
        phis.append(math.atan2(axis[1], axis[0]))
    return np.array(spins), np.array(tilts), np.array(tips), np.unwrap(phis)


def test_top_on_its_tip_keeps_its_spin_and_precesses_at_the_slow_root():
    # Only the tip touches: the rim, predicted 2.6 cm above the floor as it sweeps
    # round at 10 m/s, carries no friction and leaves the patch at the tip (before:
    # two thirds of the spin lost in 0.1 s, and the top fell). Measured at 120 Hz
    # over 4 s: spin within 0.21 % (bar 1 %), precession +0.31 % (bar 2 %).
    world, top, slow, l, theta = spinning_top(120)
    spins, tilts, tips, phis = top_motion(world, top, l, 4.0)
    assert np.abs(spins / 200.0 - 1).max() <= 0.01
    t = (np.arange(len(phis)) + 1) * world.dt
    assert abs(np.polyfit(t, phis, 1)[0] / slow - 1) <= 0.02


def test_top_on_its_tip_keeps_its_tilt_and_its_tip_in_place():
    # Regression: the tip's contact arm followed the top's translation only, so
    # within a step it lagged the precession turning the axis, and the floor's
    # impulse acted with a lever a step behind: +2.45 deg of tilt and 17 mm of tip
    # drift over 4 s at 120 Hz, the same at 4, 8 or 16 substeps (an error in dt).
    # The tip is a corner (a cone's apex), a material point that turns with the
    # body: measured at 120 Hz over 4 s, tilt within 0.08 deg (bar 1 deg), tip
    # within 4.5 mm (bar 5 mm; first order in the substep: at the end 3.1 / 1.5 / 0.7 mm at
    # 4 / 8 / 16 substeps).
    world, top, slow, l, theta = spinning_top(120)
    spins, tilts, tips, phis = top_motion(world, top, l, 4.0)
    assert np.abs(np.degrees(tilts - theta)).max() <= 1.0
    assert np.linalg.norm(tips[:, :2] - tips[0, :2], axis=1).max() <= 5e-3
