"""Contacts on articulated links, through the contact solver (issue 14): static
forces against the statics formula, momentum exchanged exactly, a chain draping
over a box, a floating robot standing on its feet, an arm pushing a box, links
of one articulation and of two colliding, determinism, what the stages show.

References are computed here from the formulas; tolerances say why.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rigidrs as rr

G = 9.81
FRAME = 1 / 60
SLOP = 0.005  # the default `slop`


def ground_force(world: rr.World, ground: int) -> float:
    """Normal force (N) the body `ground` carried over the last step."""
    c = world.contacts()
    on = (c["body_a"] == ground) | (c["body_b"] == ground)
    return float(c["normal_impulse"][on].sum() / world.dt)


def support_force(world: rr.World, supports: list[int]) -> np.ndarray:
    """The force (N, normal and friction) the bodies `supports` exerted on the
    others over the last step."""
    c = world.contacts()
    total = np.zeros(3)
    for k in range(len(c["body_a"])):
        impulse = c["normal"][k] * c["normal_impulse"][k] + c["friction_impulse"][k]  # on body_b
        if c["body_a"][k] in supports and c["body_b"][k] not in supports:
            total += impulse
        elif c["body_b"][k] in supports and c["body_a"][k] not in supports:
            total -= impulse
    return total / world.dt


# --- statics -------------------------------------------------------------------


def pendulum_on_a_wall(theta: float, mass: float, ell: float) -> tuple[rr.World, int, int]:
    """A ball on a rod hinged at the origin, leaning at `theta` against a
    frictionless wall it would swing away from."""
    r = 0.05
    scene = rr.Scene(gravity=(0, 0, -G))
    bob = scene.add_body(rr.Sphere(r), mass=mass, position=(ell * math.sin(theta), 0, -ell * math.cos(theta)), friction=0.0)
    scene.add_joint("hinge", bob, None, anchor=(0, 0, 0), axis=(0, 1, 0))
    face = ell * math.sin(theta) - r
    wall = scene.add_body(rr.Box((0.1, 0.5, 0.5)), fixed=True, position=(face - 0.1, 0, -ell * math.cos(theta)), friction=0.0)
    return scene.build(dt=FRAME, sleep=False), bob, wall


@pytest.mark.parametrize("theta, mass, ell", [(0.3, 2.0, 1.0), (0.8, 0.5, 0.4)])
def test_pendulum_leaning_on_a_wall_reports_the_static_force(theta: float, mass: float, ell: float) -> None:
    # Moments about the hinge: m g ℓ sin θ = N ℓ cos θ, so N = m g tan θ, with θ
    # the angle it rests at (the contact settles 1 µm deep: θ moves by 1e-6).
    world, bob, wall = pendulum_on_a_wall(theta, mass, ell)
    assert "articulation_contact" in world.stages and "joints" not in world.stages
    world.step(120)
    x, _, z = world.bodies.position[bob]
    expected = mass * G * math.tan(math.atan2(x, -z))
    measured = ground_force(world, wall)
    # Bar 1 %; measured 4e-16 (the contact is solved exactly at rest).
    assert measured == pytest.approx(expected, rel=1e-6)
    c = world.contacts()
    assert set(c["body_a"]) | set(c["body_b"]) == {bob, wall}
    assert np.abs(world.bodies.linear_velocity[bob]).max() < 1e-9


# --- momentum --------------------------------------------------------------------


def arm_and_box(dt: float, kind: str = "hinge") -> tuple[rr.World, list[int], int]:
    """A floating three-link arm in zero gravity and a box flying into its tip."""
    scene = rr.Scene(gravity=(0, 0, 0))
    links: list[int] = []
    for k in range(3):
        b = scene.add_body(rr.Box((0.1, 0.03, 0.03)), mass=1.0 + 0.5 * k, position=(0.2 * k + 0.1, 0, 0))
        if links:
            scene.add_joint(kind, b, links[-1], anchor=(0.2 * k, 0, 0), axis=(0, 0, 1))
        links.append(b)
    box = scene.add_body(rr.Box((0.05, 0.05, 0.05)), mass=2.0, position=(0.45, -0.5, 0.0), linear_velocity=(0, 2.0, 0))
    return scene.build(dt=dt, sleep=False), links, box


@pytest.mark.parametrize("kind", ["hinge", "spherical"])
def test_box_hitting_a_floating_arm_keeps_linear_momentum_to_round_off(kind: str) -> None:
    # Contact impulses are equal and opposite at one world point, and a floating
    # base's momentum is balanced after every substep (rust/articulation/momentum.rs):
    # the total linear momentum is that of the box before the hit, to round-off,
    # through the hit and after (measured 1.1e-14 and 2.8e-14 N·s of 4 N·s).
    world, links, box = arm_and_box(FRAME, kind)
    p0 = world.linear_momentum()
    e0 = world.kinetic_energy()
    worst, hit = 0.0, False
    for _ in range(40):
        world.step(1)
        worst = max(worst, float(np.abs(world.linear_momentum() - p0).max()))
        c = world.contacts()
        hit |= bool((c["normal_impulse"] > 0).any())
        # Restitution 0: energy is only lost.
        assert world.kinetic_energy() <= e0 * (1 + 1e-12)
    assert hit
    assert worst <= 1e-12 * np.linalg.norm(p0)
    # The arm took most of the box's momentum (an inelastic hit on its tip).
    arm_p = sum(world.bodies.mass[b] * world.bodies.linear_velocity[b] for b in links)
    assert np.linalg.norm(arm_p) > 0.3 * np.linalg.norm(p0)


def test_two_pendulums_collide_inelastically() -> None:
    # Two equal pendulums side by side (two articulations), bobs touching at
    # rest: the one released from θ0 reaches the bottom at ω = sqrt(2 m g ℓ (1 −
    # cos θ0) / I), I = m ℓ² + 2/5 m r², and hits the other there horizontally
    # at the height of both centres: with e = 0, equal inertias about parallel
    # axes and equal levers, both leave at ω/2.
    ell, r, theta, m = 0.5, 0.05, 0.4, 1.0
    scene = rr.Scene(gravity=(0, 0, -G))
    for k, angle in enumerate((-theta, 0.0)):
        x0 = 2 * r * k
        b = scene.add_body(rr.Sphere(r), mass=m, position=(x0 + ell * math.sin(angle), 0, -ell * math.cos(angle)), friction=0.0)
        scene.add_joint("hinge", b, None, anchor=(x0, 0, 0), axis=(0, 1, 0))
    world = scene.build(dt=1 / 240, sleep=False)
    assert len(world.articulations()) == 2
    inertia = m * ell**2 + 0.4 * m * r**2
    omega = math.sqrt(2 * m * G * ell * (1 - math.cos(theta)) / inertia)
    before = world.joints.velocity.copy()
    while world.joints.velocity[1] == 0.0:
        before = world.joints.velocity.copy()
        world.step(1)
    # The swing before the hit, to the leapfrog's error at 1/240 s (measured
    # 4e-5); after it, both at half (measured 8e-5: the hit falls inside a step).
    assert abs(before[0]) == pytest.approx(omega, rel=1e-4)
    np.testing.assert_allclose(world.joints.velocity, before[0] / 2, rtol=1e-3)


# --- a chain over a box ----------------------------------------------------------


def chain_over_box(links: int = 20, kind: str = "spherical", damping: float = 2e-4, sleep: bool = False) -> tuple[rr.World, list[int], list[tuple[int, int, float]]]:
    """A chain of 5 cm bars (1 cm thick, 50 g) dropped flat from 0.5 m across a 0.3 m box."""
    link, thick, mass, height = 0.05, 0.01, 0.05, 0.5
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    scene.add_body(rr.Box((0.15, 0.15, 0.15)), fixed=True, position=(0, 0, 0.15))
    x0 = -links * link / 2
    bodies: list[int] = []
    for k in range(links):
        b = scene.add_body(rr.Box((link / 2, thick, thick)), mass=mass, position=(x0 + (k + 0.5) * link, 0, height))
        if bodies:
            scene.add_joint(kind, b, bodies[-1], anchor=(x0 + k * link, 0, height), axis=(0, 1, 0), damping=damping)
        bodies.append(b)
    pairs = [(bodies[k], bodies[k - 1], link / 2) for k in range(1, links)]
    return scene.build(dt=FRAME, sleep=sleep), bodies, pairs


def joint_gap(world: rr.World, pairs: list[tuple[int, int, float]]) -> float:
    """Largest distance (m) between the joined ends of consecutive bars."""
    worst = 0.0
    for child, parent, half in pairs:
        a = world.bodies.position[child] + world.bodies.rotation[child] @ np.array([-half, 0, 0])
        b = world.bodies.position[parent] + world.bodies.rotation[parent] @ np.array([half, 0, 0])
        worst = max(worst, float(np.linalg.norm(a - b)))
    return worst


@pytest.mark.parametrize("kind", ["spherical", "hinge"])
def test_chain_drapes_over_a_box_and_comes_to_rest(kind: str) -> None:
    # The chain falls 0.2 m onto the box, whips over its edges (rates up to
    # ~100 rad/s: the contact substeps rise to keep h·ω ≤ 0.25) and settles
    # across it, ends on the ground. Joint damping 2e-4 N·m·s/rad (a time
    # constant of ~0.2 s on a bar) stands for a real chain's joint friction:
    # without it the hanging parts sway on (see the next test).
    world, bodies, pairs = chain_over_box(kind=kind)
    mass = 20 * 0.05
    e0 = world.kinetic_energy() + world.potential_energy()
    for _ in range(600):
        world.step(1)
        # Never more energy than it started with; joints never open.
        assert world.kinetic_energy() + world.potential_energy() <= e0 + 1e-9
        assert joint_gap(world, pairs) < 1e-12
    c = world.contacts()
    assert c["depth"].max() <= SLOP
    pos = world.bodies.position[bodies]
    assert pos[:, 2].min() > 0.0 and pos[:, 2].max() < 0.32  # on and around the box
    # At rest after 10 s: kinetic energy below 1e-7 J, 5e-8 of what the fall
    # released (m g × 0.2 m); measured 4.7e-9 and 9.8e-9 J, decaying ~tenfold per
    # 1.5 s with the damping.
    assert world.kinetic_energy() < 5e-8 * mass * G * 0.2
    # The box and the ground carry the chain's weight, normal and friction
    # forces together (1 %; measured 1.2e-5 and 2.8e-6 vertically, 2e-4 of it
    # sideways).
    np.testing.assert_allclose(support_force(world, [0, 1]), [0, 0, mass * G], atol=1e-2 * mass * G)


def test_undamped_chain_over_a_box_keeps_its_energy_bounded() -> None:
    # Ideal joints: the parts hanging between the box and the ground keep
    # swaying (nothing rubs), but the energy never grows: measured within
    # +0.08 % of its value at 1 s over the next 5 s, and never above the start.
    world, _, pairs = chain_over_box(kind="hinge", damping=0.0)
    e0 = world.kinetic_energy() + world.potential_energy()
    world.step(60)
    e1 = world.kinetic_energy() + world.potential_energy()
    for _ in range(300):
        world.step(1)
        e = world.kinetic_energy() + world.potential_energy()
        assert e <= e0 and e <= e1 * 1.01
    assert joint_gap(world, pairs) < 1e-12


def test_chain_links_collide_with_each_other_but_not_with_their_neighbours() -> None:
    # A hinge chain dropped vertically onto the ground folds on itself: links of
    # one articulation collide unless a joint ties them (its neighbours).
    link, thick = 0.05, 0.01
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    bodies: list[int] = []
    for k in range(12):
        z = 0.02 + (k + 0.5) * link
        b = scene.add_body(rr.Box((thick, thick, link / 2)), mass=0.05, position=(0.001 * k, 0, z))
        if bodies:
            scene.add_joint("hinge", b, bodies[-1], anchor=(0.001 * k, 0, z - link / 2), axis=(0, 1, 0), damping=2e-4)
        bodies.append(b)
    world = scene.build(dt=FRAME, sleep=False)
    self_contacts = 0
    for _ in range(240):
        world.step(1)
        c = world.contacts()
        both = np.isin(c["body_a"], bodies) & np.isin(c["body_b"], bodies)
        assert not (np.abs(c["body_a"][both] - c["body_b"][both]) == 1).any()
        self_contacts += int(both.sum())
        # Thin bars folding fast overlap while they hit (measured up to 8 mm
        # in a step), never through: at most their own thickness.
        assert c["depth"].max(initial=0.0) < 2 * thick
    assert self_contacts > 0
    # Folded and at rest, within the slop.
    assert world.contacts()["depth"].max() <= SLOP


# --- a floating robot --------------------------------------------------------------


def robot(sleep: bool = False, splay: float = 0.3) -> tuple[rr.World, int, int, list[int]]:
    """A 4 kg box torso on four 0.5 kg legs (hinges about y, splayed by
    `splay` rad), held by position drives at their build angles."""
    scene = rr.Scene(gravity=(0, 0, -G))
    ground = scene.add_body(rr.Plane(), fixed=True, friction=0.8)
    leg = 0.2
    zt = leg * math.cos(splay) + 0.05
    torso = scene.add_body(rr.Box((0.2, 0.1, 0.05)), mass=4.0, position=(0, 0, zt), friction=0.8)
    legs = []
    for sx in (-1, 1):
        for sy in (-1, 1):
            hip = np.array([0.15 * sx, 0.08 * sy, zt - 0.05])
            tilt = sx * splay  # feet outwards
            centre = hip + 0.5 * leg * np.array([math.sin(tilt), 0, -math.cos(tilt)])
            q = (0, math.sin(-tilt / 2), 0, math.cos(-tilt / 2))
            b = scene.add_body(rr.Box((0.02, 0.02, leg / 2)), mass=0.5, position=tuple(centre), orientation=q, friction=0.8)
            scene.add_joint("hinge", b, torso, anchor=tuple(hip), axis=(0, 1, 0),
                            drive=rr.Drive(mode="position", target=0.0, stiffness=400.0, damping=10.0))
            legs.append(b)
    return scene.build(dt=FRAME, sleep=sleep), ground, torso, legs


def test_floating_robot_stands_and_its_feet_carry_its_weight() -> None:
    world, ground, torso, legs = robot()
    info = world.articulations()
    assert len(info) == 1 and info[0]["dofs"] == 10 and info[0]["joints"][0] == -1  # a floating base
    weight = (4.0 + 4 * 0.5) * G
    world.step(60)
    x0 = world.bodies.position[torso].copy()
    for _ in range(10):
        world.step(60)
        # The feet carry the weight: 1 % bar, measured 2e-15 (at rest the
        # contacts are solved exactly each substep).
        assert ground_force(world, ground) == pytest.approx(weight, rel=1e-2)
    # Base drift over 10 s: bar 1 cm, measured 1.2e-6 m (settling into the
    # 1 µm rest depth of its contacts).
    assert np.linalg.norm(world.bodies.position[torso] - x0) < 1e-2
    # The drives hold the legs: each carries a quarter of the torso at its
    # splay angle, so sags by that load over the stiffness (measured 2.6e-6 rad).
    assert np.abs(world.joints.position).max() < 1e-2
    assert world.contacts()["depth"].max() <= SLOP


def test_sleeping_robot_wakes_when_a_target_changes() -> None:
    world, ground, torso, legs = robot(sleep=True)
    world.step(120)
    assert world.bodies.position[torso][2] > 0.1
    z = world.bodies.position[torso][2]
    # Asleep: a step changes nothing (the islands at rest cost nothing).
    before = world.bodies.position.copy()
    world.step(1)
    assert np.array_equal(world.bodies.position, before)
    # A new drive target wakes it: the legs fold in and the torso moves.
    world.joints.target[:] = [0.2, 0.2, -0.2, -0.2]
    world.step(60)
    assert abs(world.bodies.position[torso][2] - z) > 1e-4


# --- an arm pushing a box -----------------------------------------------------------


def test_arm_pushes_a_box_at_its_drive_speed_with_the_sliding_friction() -> None:
    # A fixed-base arm: a slide along y (velocity drive) carrying two hinged links
    # held straight by position drives, the last a paddle. It pushes a 1 kg box
    # on a floor with μ = 0.4 at constant speed: the paddle presses with μ m g,
    # and the drive, holding a load F at damping c, runs at target − F/c.
    mu, m, speed, c = 0.4, 1.0, 0.3, 1e4
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=mu)
    h = 0.05
    l1 = scene.add_body(rr.Box((0.15, 0.02, 0.02)), mass=1.0, position=(0.15, 0, h), friction=0.0)
    l2 = scene.add_body(rr.Box((0.15, 0.02, 0.02)), mass=0.7, position=(0.45, 0, h), friction=0.0)
    l3 = scene.add_body(rr.Box((0.05, 0.01, 0.04)), mass=0.3, position=(0.65, 0, h), friction=0.0)
    scene.add_joint("prismatic", l1, None, anchor=(0, 0, h), axis=(0, 1, 0), drive=rr.Drive(mode="velocity", target=speed, damping=c))
    hold = rr.Drive(mode="position", target=0.0, stiffness=1e4, damping=100.0)
    scene.add_joint("hinge", l2, l1, anchor=(0.3, 0, h), axis=(0, 0, 1), drive=hold)
    scene.add_joint("hinge", l3, l2, anchor=(0.6, 0, h), axis=(0, 0, 1), drive=hold)
    box = scene.add_body(rr.Box((0.04, 0.04, 0.04)), mass=m, position=(0.66, 0.06, 0.04), friction=mu)
    world = scene.build(dt=FRAME, sleep=False)
    arm = [l1, l2, l3]
    for _ in range(60):
        world.step(1)
    cts = world.contacts()
    on_box = (np.isin(cts["body_a"], arm) & (cts["body_b"] == box)) | (np.isin(cts["body_b"], arm) & (cts["body_a"] == box))
    push = cts["normal_impulse"][on_box].sum() / world.dt
    # 1 % bars; measured 4e-11 and 4e-8.
    assert push == pytest.approx(mu * m * G, rel=1e-2)
    v = world.bodies.linear_velocity[box]
    assert v[1] == pytest.approx(speed - mu * m * G / c, rel=1e-3)
    # Sideways only by the hinges' compliance (load / stiffness ~1e-4 rad):
    # measured 5e-5 m/s.
    assert abs(v[0]) < 1e-3 * speed
    assert world.joints.velocity[0] == pytest.approx(speed - mu * m * G / c, rel=1e-3)


# --- pipeline ------------------------------------------------------------------------


def test_same_scene_same_steps_same_bits() -> None:
    runs = []
    for _ in range(2):
        world, _, _ = chain_over_box()
        world.step(90)
        runs.append((world.bodies.position.copy(), world.bodies.orientation.copy(), world.bodies.angular_velocity.copy()))
    for a, b in zip(*runs):
        assert np.array_equal(a, b)


def test_stages_show_the_contacts_on_articulations() -> None:
    world, _, _ = chain_over_box(links=4)
    stages = world.stages
    assert "joints" not in stages and "articulation" in stages
    k = stages.index("articulation_contact")
    assert stages[k + 1] == "contact_solve"  # the kick, then the solve
    assert stages.index("contact_relax") > stages.index("articulation_contact", k + 1)  # the drift before the relax
    world.step(30)
    prof = world.profile()
    assert prof["articulation_contact"] > 0.0
    # Without colliders that can touch, none of it.
    scene = rr.Scene(gravity=(0, 0, -G))
    a = scene.add_body(rr.Sphere(0.1), mass=1.0, position=(1, 0, 0))
    scene.add_joint("hinge", a, None, anchor=(0, 0, 0), axis=(0, 1, 0))
    assert scene.build(dt=FRAME).stages == ["articulation"]


def test_a_link_that_asks_for_ccd_keeps_its_system_xpbd() -> None:
    # CCD puts a body back along its sweep, which would open an articulation's
    # joint: such a system stays XPBD (its joints are then projected).
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    a = scene.add_body(rr.Sphere(0.05), mass=1.0, position=(0.5, 0, 1.0), ccd=True)
    scene.add_joint("hinge", a, None, anchor=(0, 0, 1.0), axis=(0, 1, 0))
    world = scene.build(dt=FRAME)
    assert "joints" in world.stages and world.articulations() == []


def test_contact_along_a_hinge_axis_does_not_blow_up() -> None:
    """Regression: a contact whose normal lies along the hinges' axis (a fixed
    cylinder overlapping the root link of a horizontal two-link arm, the hand on
    the floor) has a response of round-off (1e-31 to 1e-63 of the free body's)
    and a rank-one tangent mass; their plain inverses pushed with 1e31 and more:
    NaN in the first step. With a cylinder as wide as the capsule the contacts
    push only along z, which nothing can move the arm along: it must stay
    exactly where it is. A thinner one (radius 5 mm) is also met sideways and
    pushes the arm out of the overlap: the step must stay finite (it was NaN in
    the second step)."""
    q = (0, -0.7071067811865476, 0, 0.7071067811865476)  # capsule axis along x
    for root_radius in (0.011, 0.005):
        s = rr.Scene(gravity=(0, 0, -9.81))
        arm = s.add_body(rr.Compound([(rr.Capsule(0.01, 0.06), (0.06, 0, 0), q)]), mass=0.0419, position=(0, 0, 0.01),
                         collision_group=1 << 30, collision_mask=0xFFFFFFFF & ~(1 << 30))
        s.add_joint("hinge", arm, None, anchor=(0, 0, 0.01), axis=(0, 0, 1))
        hand = s.add_body(rr.Compound([(rr.Capsule(0.01, 0.05), (0.05, 0, 0), q), (rr.Sphere(0.01), (0.12, 0, 0))]),
                          mass=0.0398, position=(0.12, 0, 0.01),
                          collision_group=1 << 30, collision_mask=0xFFFFFFFF & ~(1 << 30))
        s.add_joint("hinge", hand, arm, anchor=(0.12, 0, 0.01), axis=(0, 0, 1), limits=(-2.79, 2.79))
        s.add_body(rr.Plane(), fixed=True)
        s.add_body(rr.Cylinder(root_radius, 0.01), fixed=True, position=(0, 0, 0.01))
        world = s.build(dt=1 / 240)
        start = world.bodies.position.copy()
        world.step(240)
        assert np.all(np.isfinite(world.bodies.position)) and np.all(np.isfinite(world.joints.velocity))
        if root_radius == 0.011:
            assert np.max(np.abs(world.joints.position)) <= 1e-12
            assert np.max(np.abs(world.bodies.position - start)) <= 1e-12
