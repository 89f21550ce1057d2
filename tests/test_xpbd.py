"""XPBD particles against exact references (REFERENCES.md, "Position-based dynamics").

Every reference is computed here from its formula. Where XPBD's own discrete
solution differs from the continuous one, the test states the discrete reference
(derived in the comment) and checks both: the scheme is what it claims to be, and
it converges to the physics.

Two facts used throughout, for a substep ``h`` and gravity ``g``:

* a single constraint whose C is linear in the moving particle's coordinate is
  solved exactly by one XPBD update (Δλ solves C + wΔλ + α̃(λ + Δλ) = 0), so more
  iterations change nothing;
* at a static fixed point of a chain (tree) of constraints, the corrections of a
  substep must cancel gravity's drift ``g h²`` on every particle, which fixes
  every λ: the read-back forces λ/h² equal the carried weights exactly, for any
  number of substeps and iterations. The positions (elongations) are off the
  converged solution by the Gauss–Seidel residual of the substep, which one
  top-down sweep leaves at (particles below the link) × g h² per link.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipk

import rigidrs as rr

G = 9.81


def zero_crossings(x: np.ndarray, dt: float) -> np.ndarray:
    """Times of downward zero crossings of a sampled signal (linear interpolation)."""
    s = np.sign(x)
    k = np.where((s[:-1] > 0) & (s[1:] <= 0))[0]
    return (k + x[k] / (x[k] - x[k + 1])) * dt


def pendulum(substeps: int, iterations: int = 1, seconds: float = 2.0, theta0: float = 0.5, dt: float = 1 / 60):
    scene = rr.Scene()
    a = scene.add_particle((0, 0, 0), fixed=True)
    b = scene.add_particle((np.sin(theta0), 0, -np.cos(theta0)), mass=1.0)
    scene.add_distance_constraint(a, b)  # L = 1, compliance 0
    world = scene.build(dt=dt, substeps=substeps, iterations=iterations)
    xs = []
    for _ in range(int(round(seconds / dt))):
        world.step()
        xs.append(world.particles.position[b].copy())
    return np.array(xs), world


def test_zero_compliance_single_constraint_is_iteration_independent():
    # The distance projection moves the bob straight back onto the circle: C = 0
    # after the first pass, so passes 2..64 add Δλ = −C/w of round-off size.
    one, _ = pendulum(substeps=1, iterations=1)
    many, _ = pendulum(substeps=1, iterations=64)
    assert np.abs(one - many).max() <= 1e-12


def oscillator(iterations: int, substeps: int = 1, dt: float = 1 / 240, seconds: float = 2.0):
    """m = 1 at x0 = 1.5 on a spring of rest length 1 and compliance 0.001 to a pin."""
    scene = rr.Scene(gravity=(0, 0, 0))
    a = scene.add_particle((0, 0, 0), fixed=True)
    b = scene.add_particle((1.5, 0, 0), mass=1.0)
    scene.add_distance_constraint(a, b, compliance=1e-3, rest_length=1.0)
    world = scene.build(dt=dt, substeps=substeps, iterations=iterations)
    u = []
    for _ in range(int(round(seconds / dt))):
        world.step()
        u.append(world.particles.position[b, 0] - 1.0)
    return np.array(u)


def test_compliant_oscillator_period_does_not_depend_on_iterations():
    m, alpha, dt = 1.0, 1e-3, 1 / 240
    omega = 1 / np.sqrt(m * alpha)  # XPBD's effective stiffness is 1/α
    runs = {n: oscillator(n) for n in (1, 8, 64)}
    for n in (8, 64):
        # One constraint, linear along the line of motion: exactly solved by the first pass.
        assert np.abs(runs[n] - runs[1]).max() <= 1e-12
    # The discrete reference: with u = x − 1, one XPBD substep is implicit Euler,
    # u' = (u + h v)/(1 + h²ω²), v' = (u' − u)/h: sequence computed here exactly.
    h = dt
    u, v, ref = 0.5, 0.0, []
    for _ in range(len(runs[1])):
        un = (u + h * v) / (1 + (h * omega) ** 2)
        u, v = un, (un - u) / h
        ref.append(u)
    assert np.abs(runs[1] - np.array(ref)).max() <= 1e-12
    # Its period is 2πh / atan(hω) (eigenvalues (1 ± ihω)/(1 + h²ω²)); zero crossings
    # interpolated linearly between samples 48 per period apart are good to ~1e-5.
    t = zero_crossings(runs[1], dt)
    period = np.diff(t).mean()
    discrete = 2 * np.pi * h / np.arctan(h * omega)
    exact = 2 * np.pi * np.sqrt(m * alpha)
    assert abs(period - discrete) <= 1e-5 * discrete
    # 2πh/atan(hω) = (2π/ω)(1 + (hω)²/3 + …): 0.55 % long at 240 Hz, and the
    # period converges to the exact one as h² with substeps (2.3e-5 at 16).
    assert abs(period - exact) / exact < 0.006
    h16 = dt / 16
    fine = np.diff(zero_crossings(oscillator(1, substeps=16), dt)).mean()
    discrete16 = 2 * np.pi * h16 / np.arctan(h16 * omega)
    assert abs(fine - discrete16) <= 1e-5 * discrete16
    assert abs(discrete16 - exact) / exact < (h16 * omega) ** 2 / 3 * 1.01


def hanging_chain(n, m, alpha, substeps, iterations, damping=0.0, start_exact=True, seconds=10.0, dt=1 / 60, link=0.1):
    """n particles of mass m under a pinned one, links of rest length `link`; starts
    at the converged static solution (elongation α·W) at rest, or unstretched."""
    weight = m * G * np.arange(n, 0, -1)  # weight carried by each link, top first
    scene = rr.Scene()
    ids = [scene.add_particle((0, 0, 0), fixed=True, mass=m)]
    z = -np.cumsum(link + (alpha * weight if start_exact else 0.0 * weight))
    for k in range(n):
        ids.append(scene.add_particle((0, 0, z[k]), mass=m))
        scene.add_distance_constraint(ids[-2], ids[-1], compliance=alpha, damping=damping, rest_length=link)
    world = scene.build(dt=dt, substeps=substeps, iterations=iterations)
    return world, weight


SPLITS = [(1, 1), (1, 4), (4, 1), (2, 2), (1, 16), (16, 1), (4, 4)]


@pytest.mark.parametrize("substeps,iterations", SPLITS)
def test_hanging_chain_stretches_by_compliance_times_carried_weight(substeps, iterations):
    # 10 links of a soft chain (α = 0.01 m/N, 1 kg each): link j carries W_j and
    # stretches α·W_j. The chain starts there at rest; XPBD's fixed point for any
    # split is within the Gauss–Seidel residual of one sweep, (links below)·g·h²,
    # and an undamped chain oscillates about it by as much: |e − αW| ≤ 2·9·g·h².
    n, m, alpha, dt, link = 10, 1.0, 1e-2, 1 / 60, 0.1
    world, weight = hanging_chain(n, m, alpha, substeps, iterations)
    h = dt / substeps
    worst = 0.0
    for _ in range(600):
        world.step()
        e = -np.diff(world.particles.position[:, 2]) - link
        worst = max(worst, np.abs(e - alpha * weight).max())
    assert worst <= 2 * (n - 1) * G * h * h
    # Relative to the top link's stretch that is 5 % at 1×1 and 2e-4 at 16×1;
    # with ≥ 4 iterations Gauss–Seidel converges and the stretch is α·W to 1e-4.
    assert worst / (alpha * weight[0]) < 0.05
    if iterations >= 4:
        assert worst / (alpha * weight[0]) < 1e-4


@pytest.mark.parametrize("substeps,iterations", SPLITS)
@pytest.mark.parametrize("alpha", [0.0, 1e-3])
def test_constraint_force_reads_back_the_static_load(substeps, iterations, alpha):
    # At rest, λ/h² of link j is −W_j (a stretched link pulls its lower particle
    # up: its force along x_i − x_j on particle i is negative), for every split.
    # Started unstretched and left to settle (PBD damps a stiff chain within a few
    # seconds); the bar 1e-8·W is what is left of the motion after 30 s.
    world, weight = hanging_chain(8, 0.2, alpha, substeps, iterations, start_exact=False,
                                  damping=0.0 if alpha == 0 else 2 * np.sqrt(0.2 / alpha))
    world.step(1800)
    assert np.abs(world.particles.velocity).max() < 1e-8
    forces = world.constraint_forces()
    assert forces.shape == (8,)
    np.testing.assert_allclose(-forces, weight, rtol=1e-8)


def test_pendulum_period_error_shrinks_with_substeps():
    # L = 1, θ0 = 0.5, frame 1/60: exact period 4√(L/g)·K(sin²(θ0/2)). Measured over
    # the first 2 periods (PBD's projection damps the swing, which shortens it).
    exact = 4 * np.sqrt(1 / G) * ellipk(np.sin(0.25) ** 2)
    errors = []
    for sub in (1, 2, 4, 8, 16, 32):
        x, _ = pendulum(sub, seconds=2.2 * exact)
        t = zero_crossings(x[:, 0], 1 / 60)
        errors.append(abs(np.diff(t).mean() - exact) / exact)
    # Strictly decreasing, first order: each doubling at least 1.5x better.
    assert all(b < a / 1.5 for a, b in zip(errors, errors[1:])), errors
    assert errors[-1] < 5e-4, errors


def stiff_chain(substeps, iterations, links=20, seconds=5.0, horizontal=False):
    """20 rigid links of 5 cm, 10 g each, carrying a 1 kg end (mass ratio 100)."""
    scene = rr.Scene()
    ids = [scene.add_particle((0, 0, 0), fixed=True)]
    for k in range(links):
        pos = ((k + 1) * 0.05, 0, 0) if horizontal else (0, 0, -(k + 1) * 0.05)
        ids.append(scene.add_particle(pos, mass=1.0 if k == links - 1 else 0.01))
        scene.add_distance_constraint(ids[-2], ids[-1])
    world = scene.build(dt=1 / 60, substeps=substeps, iterations=iterations)
    worst = 0.0
    for _ in range(int(seconds * 60)):
        world.step()
        lengths = np.linalg.norm(np.diff(world.particles.position, axis=0), axis=1)
        worst = max(worst, lengths.sum() / (links * 0.05) - 1)
    return worst


@pytest.mark.parametrize("horizontal", [False, True], ids=["hanging", "falling"])
def test_substeps_beat_iterations_on_a_stiff_chain(horizontal):
    # Same work (20 constraint passes per frame): 20 substeps × 1 iteration leave a
    # residual of g·h² per pass with h 20x smaller, while 20 Gauss–Seidel passes
    # on one substep barely propagate the heavy end's pull up a 20-link chain
    # (measured: 13x to 19x less stretch; required: 5x).
    sub = stiff_chain(20, 1, horizontal=horizontal)
    it = stiff_chain(1, 20, horizontal=horizontal)
    assert sub < it / 5, (sub, it)


@pytest.mark.parametrize("substeps", [16, 64])
def test_light_particle_holds_heavy_one_with_zero_compliance(substeps):
    # pin — 1 g — 1 kg, rigid links of 1 m. One symmetric pass per substep (links
    # 1, 2, then 2, 1; the repeated link 2 is already exact) has the fixed point
    # e1 = 0, e2 = (M/m)·g·h² (the lower link gives way by the mass ratio times the
    # gravity drift), with λ1/h² = −(M+m)g and λ2/h² = −Mg exactly (derivation:
    # predict +g h²; link 1 lifts the light one to C1 = 0; link 2 leaves
    # C2 = e2 + g h², moves the light one down by r = M/(M+m) of it and the heavy
    # one up by the rest; link 1 lifts the light one again: e2 = r(e2 + g h²)).
    m, M, dt = 1e-3, 1.0, 1 / 60
    scene = rr.Scene()
    a = scene.add_particle((0, 0, 0), fixed=True)
    b = scene.add_particle((0, 0, -1), mass=m)
    c = scene.add_particle((0, 0, -2), mass=M)
    scene.add_distance_constraint(a, b)
    scene.add_distance_constraint(b, c)
    world = scene.build(dt=dt, substeps=substeps)
    # The heavy end bobs on the light link and settles in ~20 s at 16 substeps.
    world.step(40 * 60)
    assert np.abs(world.particles.velocity).max() < 1e-8
    h = dt / substeps
    x = world.particles.position
    stretch = np.linalg.norm(np.diff(x, axis=0), axis=1) - 1.0
    assert abs(stretch[1] - (M / m) * G * h * h) <= 1e-6 * (M / m) * G * h * h
    assert abs(stretch[0]) <= 1e-12
    assert stretch[1] < (0.011 if substeps == 16 else 7e-4)  # of a 1 m link: held
    # Forces to 1e-8: positions carry round-off of ~2e-16 m against a drift of
    # g h² = 7e-7 m per substep, and λ is computed from them.
    np.testing.assert_allclose(world.constraint_forces(), [-(M + m) * G, -M * G], rtol=1e-8)


def test_dihedral_bending_holds_a_drooping_flap():
    # A rigid triangle (pinned) and a flap hinged on its edge (x axis), the flap's
    # tip (0.2 kg) d = 1 m from the hinge held by rigid links, the bend resisted by
    # a bending constraint of compliance α (rad/(N·m)). At rest:
    # * θ = −α·λ/h² to round-off (the compliance relation, solved exactly once the
    #   50 passes have converged);
    # * the bending moment λ/h² balances gravity's torque m g d cos θ up to the
    #   turn of ∇θ within a substep: the multipliers of one substep are summed over
    #   gradients taken along the way from the predicted position, g h² below the
    #   final one, so the balance holds to a relative g h²/d (bar m g·g h²);
    # * hence θ solves θ = α m g d cos θ to α·m g·g h².
    m, d, h = 0.2, 1.0, 1 / 240
    for alpha in (0.1, 1.0):
        scene = rr.Scene()
        p0 = scene.add_particle((0, 0, 0), fixed=True)
        p1 = scene.add_particle((1, 0, 0), fixed=True)
        p2 = scene.add_particle((0.5, 1, 0), fixed=True)
        p3 = scene.add_particle((0.5, -d, 0), mass=m)
        scene.add_distance_constraint(p3, p0)
        scene.add_distance_constraint(p3, p1)
        k = scene.add_bending_constraint(p0, p1, p2, p3, compliance=alpha, damping=2 * np.sqrt(m * d * d / alpha))
        world = scene.build(dt=1 / 60, substeps=4, iterations=50)
        world.step(1200)
        x = world.particles.position[p3]
        theta = np.arctan2(-x[2], -x[1])
        assert np.abs(world.particles.velocity).max() < 1e-10
        moment = world.constraint_forces()[k]
        assert abs(moment + theta / alpha) <= 1e-12
        assert abs(abs(moment) - m * G * d * np.cos(theta)) <= m * G * G * h * h
        ref = brentq(lambda t: t - alpha * m * G * d * np.cos(t), 0.0, 1.5)
        assert abs(theta - ref) <= alpha * m * G * G * h * h


def test_tetrahedral_volume_carries_a_load():
    # Base triangle (area A = 0.5 m²) pinned in z = 0, apex of 0.5 kg at height 1.
    # ∇V at the apex is (0, 0, A/3): the pressure p = λ/h² holds the apex up with
    # p·A/3 = m g, and V − V0 = −α p, so the apex sinks by 3αp/A = 9αmg/A² (m).
    # One constraint, linear in the apex height: exact at rest (damping, which
    # settles it, vanishes there).
    m, A = 0.5, 0.5
    for alpha in (1e-3, 1e-2):
        scene = rr.Scene()
        base = [scene.add_particle(p, fixed=True) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0)]]
        apex = scene.add_particle((0.2, 0.3, 1.0), mass=m)
        k = scene.add_volume_constraint([*base, apex], compliance=alpha,
                                        damping=2 * np.sqrt(m / alpha) / (A / 3))
        world = scene.build(dt=1 / 60)
        world.step(900)
        sink = 1.0 - world.particles.position[apex, 2]
        assert abs(sink - 9 * alpha * m * G / A**2) <= 1e-9
        assert abs(world.constraint_forces()[k] - 3 * m * G / A) <= 1e-7


def icosphere_mesh():
    t = (1 + 5**0.5) / 2
    v = np.array([(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                  (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)], float)
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
         (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return v / np.linalg.norm(v, axis=1, keepdims=True), np.array(f)


def mesh_volume(x, tris):
    return sum(np.dot(np.cross(x[a], x[b]), x[c]) for a, b, c in tris) / 6


def test_closed_mesh_volume_inflates_to_its_pressure_target():
    # A balloon (icosahedron of radius 1, no other constraint, no gravity) with
    # pressure factor 2 and compliance 0: the projection moves every vertex along
    # its area-weighted normal until V = 2·V0 (nonlinear in x, so a few substeps).
    v, f = icosphere_mesh()
    scene = rr.Scene(gravity=(0, 0, 0))
    ids = [scene.add_particle(p, mass=0.1) for p in v]
    k = scene.add_mesh_volume_constraint(f, pressure=2.0)
    world = scene.build(dt=1 / 60)
    world.step(60)
    v0 = mesh_volume(v, f)
    x = world.particles.position[ids]
    assert abs(mesh_volume(x, f) - 2 * v0) <= 1e-9 * v0
    # Symmetric inflation: the linear momentum stays 0 (corrections along ∇V sum to 0).
    assert np.abs(world.linear_momentum()).max() <= 1e-12
    assert np.isfinite(world.constraint_forces()[k])


def test_body_hanging_from_a_particle_feels_the_pull():
    # A 2 kg box hangs from a pinned particle by an attachment at its top face:
    # at rest the attachment carries its weight (λ/h² = −M g, fixed-point argument)
    # and the attachment point stays on the particle.
    M = 2.0
    scene = rr.Scene()
    pin = scene.add_particle((0, 0, 1), fixed=True)
    box = scene.add_body(rr.Box((0.1, 0.1, 0.2)), mass=M, position=(0, 0, 0.8), collision_mask=0)
    k = scene.add_attachment(pin, box)  # at the particle's position: the top face centre
    world = scene.build(dt=1 / 60, substeps=4)
    world.step(300)
    np.testing.assert_allclose(world.constraint_forces()[k], -M * G, rtol=1e-9)
    np.testing.assert_allclose(world.bodies.position[box], (0, 0, 0.8), atol=1e-9)


def attached_pair(substeps):
    """No gravity: a particle flung away from a free box it is tied to (rest 0.5 m)."""
    scene = rr.Scene(gravity=(0, 0, 0))
    box = scene.add_body(rr.Box((0.1, 0.2, 0.3)), mass=3.0, collision_mask=0)
    p = scene.add_particle((0.6, 0.0, 0.3), mass=0.5, velocity=(2.0, 1.0, 0.0))
    scene.add_attachment(p, box, point=(0.1, 0.0, 0.3), rest_length=0.5)
    world = scene.build(dt=1 / 60, substeps=substeps)
    p0, l0 = world.linear_momentum().copy(), world.angular_momentum().copy()
    world.step(120)
    return world, box, p0, l0


def test_attachment_exchanges_momentum_with_a_free_body():
    # Each correction is an equal and opposite positional impulse on the particle
    # and the body point: the total linear momentum (particles and bodies) is kept
    # to round-off (ε·|p| per substep, 960 substeps) while both move.
    world, box, p0, l0 = attached_pair(8)
    assert np.abs(world.linear_momentum() - p0).max() <= 1e-15 * np.linalg.norm(p0) * 960
    assert np.linalg.norm(world.bodies.linear_velocity[box]) > 0.1  # the box was pulled
    assert np.linalg.norm(world.bodies.angular_velocity[box]) > 0.1  # off-centre: it turns
    # The impulses are central, but v = (x − x_prev)/h turns a rotation of angle hω
    # into a chord: angular momentum is kept to first order in h only (0.9 % here),
    # and 4x the substeps leave 4x less drift (measured 3.9x).
    drift8 = np.linalg.norm(world.angular_momentum() - l0)
    world32, _, _, _ = attached_pair(32)
    drift32 = np.linalg.norm(world32.angular_momentum() - l0)
    assert drift8 < 0.01 * np.linalg.norm(l0) and 3.5 < drift8 / drift32 < 4.5


def test_particle_rests_on_the_ground_at_its_radius():
    # Point projection onto the plane with the particle radius: contact C = z − r.
    r = 0.05
    scene = rr.Scene()
    scene.add_body(rr.Plane(normal=(0, 0, 1)), fixed=True)
    p = scene.add_particle((0.3, 0.2, 1.0), mass=0.1, radius=r)
    world = scene.build(dt=1 / 60, substeps=4)
    world.step(120)
    assert abs(world.particles.position[p, 2] - r) <= 1e-12
    assert np.abs(world.particles.velocity[p]).max() <= 1e-12
    assert world.stages == ["xpbd"]


@pytest.mark.parametrize("floor", ["thin_box", "mesh"])
def test_fast_particles_do_not_tunnel_through_thin_colliders(floor):
    # 20 m/s downwards: 8 cm per substep against a 1 cm thick box or a one-sided
    # triangle mesh (no inside). Each substep the motion is swept (a ray from the
    # previous position), so the particles stop on top: z ≥ r (1e-12), a point
    # particle (r = 0) included, and keep resting there.
    scene = rr.Scene()
    if floor == "thin_box":
        scene.add_body(rr.Box((1, 1, 0.005)), fixed=True, position=(0, 0, -0.005))
    else:
        v = np.array([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], float)
        scene.add_body(rr.TriMesh(v, [(0, 1, 2), (0, 2, 3)]), fixed=True)
    ids = [scene.add_particle((0.1 * k, 0.05, 0.5), radius=r, velocity=(0.5, 0, -20.0)) for k, r in enumerate([0.0, 0.002, 0.01])]
    world = scene.build(dt=1 / 60, substeps=4)
    lowest = np.inf
    for _ in range(90):
        world.step()
        lowest = min(lowest, (world.particles.position[ids, 2] - [0.0, 0.002, 0.01]).min())
    assert lowest >= -1e-12
    assert np.abs(world.particles.velocity).max() <= 1e-9


def test_position_based_friction_stops_a_sliding_particle_at_the_coulomb_distance():
    # Sliding at v0 on μ: Coulomb's distance v0²/(2μg). The position-based friction
    # removes at most μ·(normal correction) of slip per substep, i.e. μ g h² — the
    # Coulomb deceleration — so the distance is exact up to the last substep's
    # slip (v0 h) and the first substep's contact making (bar 1 %).
    v0, mu = 2.0, 0.4
    scene = rr.Scene()
    scene.add_body(rr.Plane(normal=(0, 0, 1)), fixed=True, friction=mu)
    p = scene.add_particle((0, 0, 0.0), mass=1.0, velocity=(v0, 0, 0), friction=mu)
    world = scene.build(dt=1 / 240, substeps=4)
    world.step(480)
    travelled = world.particles.position[p, 0]
    assert abs(travelled - v0**2 / (2 * mu * G)) <= 0.01 * v0**2 / (2 * mu * G)
    assert np.abs(world.particles.velocity[p]).max() <= 1e-12


def ball_on_a_big_particle(mu, gravity, v0=(0.0, 0.0, 0.0)):
    """A 0.1 m particle resting on top of a pinned particle of radius 1000 m, whose
    top is flat to 1e-4 over 0.5 m: particle-particle friction between them."""
    scene = rr.Scene(gravity=gravity)
    scene.add_particle((0.0, 0.0, -1000.0), radius=1000.0, fixed=True, friction=mu)
    p = scene.add_particle((0.0, 0.0, 0.1), mass=1.0, radius=0.1, velocity=v0, friction=mu)
    return scene.build(dt=1 / 240, substeps=4), p


def test_particle_sliding_on_a_particle_stops_at_the_coulomb_distance():
    # As on a rigid plane: v0²/(2μg), to the last substep's slip and the big
    # particle's curvature (its slope at 0.5 m, 5e-4, adds 0.1 %; bar 1 %).
    v0, mu = 2.0, 0.4
    world, p = ball_on_a_big_particle(mu, (0.0, 0.0, -G), v0=(v0, 0.0, 0.0))
    world.step(480)
    travelled = world.particles.position[p, 0]
    assert abs(travelled - v0**2 / (2 * mu * G)) <= 0.01 * v0**2 / (2 * mu * G)
    assert np.abs(world.particles.velocity[p]).max() <= 1e-9


@pytest.mark.parametrize("slope", [0.3, 0.5])
def test_particle_on_a_particle_sticks_below_the_friction_angle_and_slides_above(slope):
    # Gravity tilted by atan(slope) from the contact normal, μ = 0.4: below the
    # friction angle (0.3) static friction holds the particle where it is (it moves
    # less than 1e-9 m in 2 s); above it (0.5) it slides at g(sin θ − μ cos θ),
    # within 1 % over 1 s (the slope of the big particle's top changes by 1e-3).
    mu = 0.4
    theta = np.arctan(slope)
    g = (G * np.sin(theta), 0.0, -G * np.cos(theta))
    world, p = ball_on_a_big_particle(mu, g)
    world.step(240)
    x = world.particles.position[p, 0]
    if slope < mu:
        assert abs(x) <= 1e-9
    else:
        a = G * (np.sin(theta) - mu * np.cos(theta))
        assert abs(x - a / 2) <= 0.01 * a / 2


def test_particles_collide_with_each_other_and_keep_their_momentum():
    # Two particles of radius 0.1 approach head-on; the contact keeps them 0.2 apart
    # (compliance 0: to round-off after the last pass) and, being a pair of equal
    # and opposite corrections, conserves the linear momentum exactly.
    scene = rr.Scene(gravity=(0, 0, 0))
    a = scene.add_particle((-0.5, 0, 0), mass=1.0, radius=0.1, velocity=(1.0, 0, 0))
    b = scene.add_particle((0.5, 0.05, 0), mass=3.0, radius=0.1, velocity=(-1.0, 0, 0))
    world = scene.build(dt=1 / 60, substeps=2)
    p0 = world.linear_momentum().copy()
    closest = np.inf
    for _ in range(90):
        world.step()
        x = world.particles.position
        closest = min(closest, np.linalg.norm(x[a] - x[b]))
    assert closest >= 0.2 - 1e-12
    assert np.abs(world.linear_momentum() - p0).max() <= 1e-12


def test_rope_builder_hangs_with_its_weight_on_the_pin():
    scene = rr.Scene()
    rope = scene.add_rope((0, 0, 0), (0, 0, -1), 20, mass=0.21, pinned=[0])
    assert rope == range(0, 21) and scene.constraint_count == 20
    world = scene.build(dt=1 / 60, substeps=10)
    world.step(600)
    # Each of the 20 movable particles weighs 0.01 kg: the top link carries 20 of them.
    np.testing.assert_allclose(-world.constraint_forces()[0], 20 * 0.01 * G, rtol=1e-8)


def test_cloth_builder_counts_and_drapes_over_a_sphere():
    nu, nv = 12, 10
    edges = (nu - 1) * nv + nu * (nv - 1) + (nu - 1) * (nv - 1)
    interior = edges - 2 * (nu - 1) - 2 * (nv - 1)
    scene = rr.Scene()
    ball = scene.add_body(rr.Sphere(0.3), fixed=True)
    cloth = scene.add_cloth((-0.5, -0.5, 0.4), (1, 0, 0), (0, 1, 0), (nu, nv), mass=0.2, radius=0.01,
                            compliance=1e-6, bending_compliance=1.0)
    assert cloth == range(0, nu * nv)
    assert scene.constraint_count == edges + interior
    world = scene.build(dt=1 / 60, substeps=8)
    world.step(120)
    x = world.particles.position
    # Nothing passes through the ball: every particle is at least its radius out
    # (bar: the contact margin's worth of last-substep motion, 1 mm).
    assert np.linalg.norm(x, axis=1).min() >= 0.3 + 0.01 - 1e-3
    assert ball == 0 and np.isfinite(x).all()


KUHN = [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7)]


def soft_box_volume(x, n):
    """Σ |V| of the builder's tetrahedra: six per cell (Kuhn), corners x + 2y + 4z."""
    node = lambda i, j, k: i + (n + 1) * (j + (n + 1) * k)  # noqa: E731
    total = 0.0
    for i, j, k in np.ndindex(n, n, n):
        c = [node(i + (q & 1), j + ((q >> 1) & 1), k + (q >> 2)) for q in range(8)]
        for t in KUHN:
            a, b, cc, d = (x[c[q]] for q in t)
            total += abs(np.dot(b - a, np.cross(cc - a, d - a))) / 6
    return total


def test_soft_box_keeps_its_volume_on_the_ground():
    n = 2
    scene = rr.Scene()
    scene.add_body(rr.Plane(normal=(0, 0, 1)), fixed=True)
    box = scene.add_soft_box((0, 0, 0.3), (0.2, 0.2, 0.2), (n, n, n), mass=1.0, compliance=1e-5, volume_compliance=0.0)
    assert box == range(0, (n + 1) ** 3)
    # Edges of the Kuhn grid: axis edges, one diagonal per face square, one per cell;
    # then one volume constraint per tetrahedron.
    edges = 3 * n * (n + 1) ** 2 + 3 * n * n * (n + 1) + n**3
    assert scene.constraint_count == edges + 6 * n**3
    world = scene.build(dt=1 / 60, substeps=8, iterations=2)
    x0 = world.particles.position.copy()
    world.step(120)
    x = world.particles.position
    assert x[:, 2].min() >= -1e-9 and x[:, 2].max() < 0.41  # fell 0.1 m and landed
    # Rigid tetrahedral volumes, 2 passes per substep: the volume is kept to the
    # Gauss–Seidel residual (bar 0.1 %) while the box squashes under its weight.
    assert abs(soft_box_volume(x, n) - soft_box_volume(x0, n)) <= 1e-3 * 0.4**3


def test_stages_appear_only_with_particles():
    scene = rr.Scene(gravity=(0, 0, 0))
    scene.add_body(rr.Sphere(0.1), density=1000.0, collision_mask=0)
    assert scene.build(dt=0.01).stages == ["translate", "rotate_isotropic"]
    scene.add_particle((0, 0, 1))
    assert scene.build(dt=0.01).stages == ["translate", "rotate_isotropic", "xpbd"]
    ids = [scene.add_particle(p) for p in [(1, 0, 0), (0, 1, 0), (0, 0, 0)]]
    scene.add_shape_matching([0, *ids], mode="rigid")
    world = scene.build(dt=0.01)
    assert world.stages == ["translate", "rotate_isotropic", "xpbd", "shape_matching", "xpbd"]
    world.step(3)
    profile = world.profile()
    assert profile["xpbd"] >= 0 and profile["shape_matching"] >= 0


def test_particles_are_simulated_after_the_drift_and_before_the_contact_relax():
    scene = rr.Scene()
    scene.add_body(rr.Plane(normal=(0, 0, 1)), fixed=True)
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0, 0, 0.1))
    scene.add_particle((1, 0, 0.5), radius=0.01)
    stages = scene.build(dt=0.01).stages
    assert stages.index("xpbd") > stages.index("translate")
    assert stages.index("xpbd") < stages.index("contact_relax")


def test_particle_views_alias_the_world():
    scene = rr.Scene()
    p = scene.add_particle((0, 0, 2), mass=0.1, radius=0.01)
    q = scene.add_particle((0, 0, 1), mass=0.1, radius=0.01, fixed=True)
    world = scene.build(dt=0.01)
    pos = world.particles.position
    assert pos.shape == (2, 3) and np.shares_memory(pos, world.particles.position)
    assert np.shares_memory(world.particles.velocity, world.particles.velocity)
    np.testing.assert_array_equal(world.particles.inverse_mass, [10.0, 0.0])
    with pytest.raises(ValueError):
        world.particles.inverse_mass[0] = 1.0
    world.particles.velocity[p] = (1.0, 0.0, 0.0)
    world.step()
    assert world.particles.position[p, 0] == pytest.approx(0.01)
    np.testing.assert_array_equal(world.particles.position[q], (0, 0, 1))
    del world
    assert pos.base is not None and pos[p, 0] == pytest.approx(0.01)  # the view keeps the world alive


def test_nan_written_through_a_view_is_refused_naming_the_particle():
    scene = rr.Scene()
    scene.add_particle((0, 0, 2))
    scene.add_particle((0, 0, 1))
    world = scene.build(dt=0.01)
    world.particles.position[1, 2] = np.nan
    before = world.particles.position.copy()
    with pytest.raises(rr.StateError, match="particle 1: position"):
        world.step()
    np.testing.assert_array_equal(world.particles.position[0], before[0])
    assert world.time == 0.0


def test_bad_particle_input_raises_and_leaves_the_scene_unchanged():
    scene = rr.Scene()
    a = scene.add_particle((0, 0, 0))
    b = scene.add_particle((1, 0, 0))
    cases = [
        (lambda: scene.add_particle((0, np.nan, 0)), "particle 2: position"),
        (lambda: scene.add_particle((0, 0, 0), mass=-1.0), "particle 2: mass"),
        (lambda: scene.add_particle((0, 0, 0), radius=-0.1), "particle 2: radius"),
        (lambda: scene.add_distance_constraint(a, b, compliance=-1e-6), r"constraint 0 \(distance\): compliance"),
        (lambda: scene.add_distance_constraint(a, 7), r"constraint 0 \(distance\): particle index 7 is out of range"),
        (lambda: scene.add_distance_constraint(a, -1), "particle index -1 is out of range"),
        (lambda: scene.add_distance_constraint(a, a), "particle 0 is constrained to itself"),
        (lambda: scene.add_bending_constraint(a, b, a, b), "constrained to itself"),
        (lambda: scene.add_volume_constraint([a, b, a, b]), "constrained to itself"),
        (lambda: scene.add_attachment(a, 3), r"constraint 0 \(attachment\): body index 3 is out of range"),
        (lambda: scene.add_rope((0, 0, 0), (1, 0, 0), 0), "segments"),
        (lambda: scene.add_rope((0, 0, 0), (1, 0, 0), 4, pinned=[9]), "pinned index 9"),
        (lambda: scene.add_rope((0, 0, 0), (1, 0, 0), 4, compliance=-1.0), "compliance"),
        (lambda: scene.add_cloth((0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 3)), "not parallel"),
    ]
    for call, message in cases:
        with pytest.raises(rr.RigidError, match=message):
            call()
        assert scene.particle_count == 2 and scene.constraint_count == 0
    c = scene.add_particle((0, 1, 0))
    d = scene.add_particle((0, 2, 0))
    with pytest.raises(rr.ShapeError, match=r"constraint 0 \(volume\).*coplanar"):
        scene.add_volume_constraint([a, b, c, d])
    with pytest.raises(rr.ShapeError, match=r"constraint 0 \(mesh volume\): a closed mesh needs at least 4"):
        scene.add_mesh_volume_constraint([[a, c, b], [a, b, d], [a, d, c]])
    with pytest.raises(rr.ShapeError, match=r"constraint 0 \(mesh volume\).*face inward"):
        scene.add_mesh_volume_constraint([[a, b, c], [a, d, b], [a, c, d], [b, d, c]])
    assert scene.constraint_count == 0 and scene.particle_count == 4
    scene.build(dt=0.01).step()


def test_particle_collision_filters_pass_what_they_exclude():
    # As between bodies: a pair touches iff group_a & mask_b and group_b & mask_a.
    # A particle of group 2 that does not collide with group 1 falls through the
    # ground (group 1); its twin with the default filter rests on it. Two particles
    # meeting head-on pass through each other when their filters exclude the pair.
    scene = rr.Scene()
    scene.add_body(rr.Plane(), fixed=True)
    rests = scene.add_particle((0.0, 0.0, 0.5), radius=0.1)
    falls = scene.add_particle((1.0, 0.0, 0.5), radius=0.1, collision_group=2, collision_mask=~1 & 0xFFFFFFFF)
    a = scene.add_particle((-0.5, 5.0, 5.0), radius=0.1, velocity=(1.0, 0.0, 0.0), collision_group=4, collision_mask=4)
    b = scene.add_particle((0.5, 5.0, 5.0), radius=0.1, velocity=(-1.0, 0.0, 0.0), collision_group=8, collision_mask=8)
    world = scene.build(dt=1 / 60, substeps=4)
    world.step(60)
    x = world.particles.position
    assert abs(x[rests, 2] - 0.1) <= 1e-9
    assert x[falls, 2] < -3.0
    # Each kept its velocity through the other: after 1 s they have swapped places.
    np.testing.assert_allclose([x[a, 0], x[b, 0]], [0.5, -0.5], rtol=0, atol=1e-12)


def test_particle_collision_filter_out_of_range_is_refused_naming_the_particle():
    scene = rr.Scene()
    scene.add_particle((0.0, 0.0, 0.0))
    for kwargs in (dict(collision_group=-1), dict(collision_mask=2**32)):
        with pytest.raises(ValueError, match=r"particle 1: collision_(group|mask)"):
            scene.add_particle((0.0, 0.0, 1.0), **kwargs)
    assert scene.particle_count == 1
    with pytest.raises(ValueError, match=r"collision_mask"):
        scene.add_rope((0, 0, 0), (0, 0, -1), 4, collision_mask=-5)
    assert scene.particle_count == 1


def test_cloth_excluded_from_the_ground_falls_through_it():
    scene = rr.Scene()
    scene.add_body(rr.Plane(), fixed=True)
    cloth = scene.add_cloth((0, 0, 0.5), (1, 0, 0), (0, 1, 0), (5, 5), radius=0.01, collision_mask=0)
    world = scene.build(dt=1 / 60, substeps=4)
    world.step(60)
    assert world.particles.position[cloth, 2].max() < -3.0
