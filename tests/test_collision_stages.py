"""Only the collision work a scene calls for, and ``world.stages`` shows it (issue 3,
"Only the effects a scene calls for"):

* no collision stage at all when no two colliders can ever touch (a single body,
  fixed bodies only, or filters that exclude every pair); such a world steps
  bit for bit like the same bodies without shapes;
* no ``friction`` stage when every friction coefficient is zero (or every pair that
  can touch combines to zero);
* no ``ccd`` stage unless a body asks for it, and ``impacts`` only with restitution;
* sleeping: a resting stack falls asleep (``world.bodies.sleeping``), its drift
  stages leave the plan and its contacts are no longer computed; it wakes when a
  thrown body touches it or when the user writes a velocity or a force, while a
  separate sleeping island stays asleep;
* a kinematic body moves exactly with the velocity it is given and pushes a
  dynamic box, waking it.

Stage lists are compared as sets of names or exactly; "nothing moves" is bitwise.
"""
from __future__ import annotations

import numpy as np
import pytest

import rigidrs as rr

G = (0.0, 0.0, -9.81)
DT = 1.0 / 60.0
COLLISION = {"broad_phase", "narrow_phase", "contact_solve", "contact_relax", "friction", "impacts", "ccd", "sleep"}
DRIFT = {"forces", "translate", "rotate_isotropic", "rotate_symmetric", "rotate_asymmetric", "gyroscopic"}


# ---------------------------------------------------------------------------
# No collision stage when nothing can touch
# ---------------------------------------------------------------------------


def lone_ball(**kwargs):
    scene = rr.Scene(gravity=G)
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0.0, 0.0, 1.0), linear_velocity=(1.0, 0.0, 0.0), **kwargs)
    return scene


NOTHING_TOUCHES = {
    "single body": lambda: lone_ball(),
    "single body asking for ccd": lambda: lone_ball(ccd=True, restitution=0.5),
    "masks exclude every pair": lambda: scene_with(dict(collision_mask=0), dict(collision_mask=0), dict(collision_mask=0)),
    "groups outside every mask": lambda: scene_with(*[dict(collision_group=1, collision_mask=2)] * 3),
    "pairwise exclusions": lambda: scene_with(
        dict(collision_group=1, collision_mask=4), dict(collision_group=2, collision_mask=4), dict(collision_group=4, collision_mask=0)
    ),
    "only fixed bodies have shapes": lambda: fixed_only(),
}


def scene_with(ball_a, ball_b, ground):
    """Two overlapping dynamic balls resting on a ground plane, with the given filters."""
    scene = rr.Scene(gravity=G)
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0.0, 0.0, 0.1), restitution=0.5, **ball_a)
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0.05, 0.0, 0.12), ccd=True, **ball_b)
    scene.add_body(rr.Plane(), fixed=True, **ground)
    return scene


def fixed_only():
    scene = rr.Scene(gravity=G)
    scene.add_body(rr.Box((1.0, 1.0, 1.0)), fixed=True)
    scene.add_body(rr.Sphere(0.5), fixed=True, position=(0.0, 0.0, 1.2))
    scene.add_body(rr.Plane(), fixed=True)
    scene.add_body(mass=1.0, inertia=(0.1, 0.1, 0.1), position=(0.0, 0.0, 0.5))  # no shape: collides with nothing
    return scene


@pytest.mark.parametrize("case", list(NOTHING_TOUCHES))
def test_no_collision_stage_when_no_two_colliders_can_touch(case):
    world = NOTHING_TOUCHES[case]().build(dt=DT)
    assert set(world.stages) & COLLISION == set()
    assert world.stages == ["forces", "translate", "rotate_isotropic", "forces"]
    assert world.substeps == 1  # the default without contacts
    world.step(30)
    assert len(world.contacts()["depth"]) == 0


def test_world_without_possible_contacts_steps_like_one_without_shapes():
    # The same balls as mass + inertia only: bit for bit the same motion (the filters
    # really removed every bit of collision work, including the substeps).
    filtered = scene_with(dict(collision_mask=0), dict(collision_mask=0), dict(collision_mask=0)).build(dt=DT)
    scene = rr.Scene(gravity=G)
    for i in range(2):
        scene.add_body(mass=filtered.bodies.mass[i], inertia=filtered.bodies.inertia[i],
                       position=filtered.bodies.position[i])
    bare = scene.build(dt=DT)
    filtered.step(60)
    bare.step(60)
    assert filtered.bodies.position[:2].tobytes() == bare.bodies.position.tobytes()
    assert filtered.bodies.linear_velocity[:2].tobytes() == bare.bodies.linear_velocity.tobytes()


def test_a_pair_that_can_touch_brings_the_collision_stages():
    world = scene_with({}, {}, {}).build(dt=DT)
    assert {"broad_phase", "narrow_phase", "contact_solve", "contact_relax"} <= set(world.stages)
    assert world.substeps == 4


# ---------------------------------------------------------------------------
# friction, ccd, impacts
# ---------------------------------------------------------------------------


def box_on_ground(box_mu=0.5, ground_mu=0.5, box_e=0.0, ground_e=0.0, ccd=False, velocity=(2.0, 0.0, 0.0)):
    scene = rr.Scene(gravity=G)
    scene.add_body(rr.Plane(), fixed=True, friction=ground_mu, restitution=ground_e)
    box = scene.add_body(rr.Box((0.2, 0.2, 0.2)), density=500.0, position=(0.0, 0.0, 0.2), friction=box_mu,
                         restitution=box_e, ccd=ccd, linear_velocity=velocity)
    return scene.build(dt=DT), box


@pytest.mark.parametrize(
    "box_mu,ground_mu,expected",
    [(0.5, 0.5, True), (0.0, 0.0, False), (0.0, 0.5, False), (0.5, 0.0, False)],
    ids=["both 0.5", "both 0", "box 0", "ground 0"],
)
def test_friction_stage_only_when_some_pair_has_friction(box_mu, ground_mu, expected):
    # The geometric mean makes a zero-friction surface frictionless against anything.
    world, box = box_on_ground(box_mu, ground_mu)
    assert ("friction" in world.stages) == expected
    world.step(30)
    v = world.bodies.linear_velocity[box, 0]
    if expected:
        assert v < 2.0 - 0.1  # it brakes (μ g t = 2.45 m/s over 0.5 s: it has stopped)
    else:
        assert v == 2.0  # frictionless: nothing touches the tangential velocity, not even round-off


def test_frictional_pair_among_frictionless_ones_keeps_the_friction_stage():
    # Ground frictionless, but two balls with friction can touch each other.
    scene = rr.Scene(gravity=G)
    scene.add_body(rr.Plane(), fixed=True, friction=0.0)
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0.0, 0.0, 0.1))
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0.5, 0.0, 0.1))
    assert "friction" in scene.build(dt=DT).stages


@pytest.mark.parametrize("ccd", [False, True])
def test_ccd_stage_only_when_a_body_asks(ccd):
    world, box = box_on_ground(ccd=ccd)
    assert ("ccd" in world.stages) == ccd


@pytest.mark.parametrize(
    "box_e,ground_e,expected",
    [(0.0, 0.0, False), (0.5, 0.0, True), (0.0, 0.5, True), (1.0, 1.0, True)],
)
def test_impacts_stage_only_with_restitution(box_e, ground_e, expected):
    world, box = box_on_ground(box_e=box_e, ground_e=ground_e)
    assert ("impacts" in world.stages) == expected


# ---------------------------------------------------------------------------
# Bodies in free flight take the integrator's whole step
# ---------------------------------------------------------------------------


def spinning_box_in(scene):
    return scene.add_body(rr.Box((0.1, 0.2, 0.3)), density=500.0, position=(5.0, 0.0, 10.0),
                          angular_velocity=(0.3, 4.0, 0.2), linear_velocity=(1.0, 0.0, 3.0))


@pytest.mark.parametrize("integrator", sorted(rr.INTEGRATORS))
def test_a_body_in_free_flight_moves_as_in_a_world_without_colliders(integrator):
    """Substeps are for contacts: a body that touches nothing this step takes the
    integrator's step of dt once, so its trajectory is the one a world without any
    collider gives (where there is one substep), to the bit, while other bodies
    in the same world collide with 4 substeps."""
    busy = rr.Scene(gravity=G)
    box = spinning_box_in(busy)
    busy.add_body(rr.Plane(), fixed=True)
    busy.add_body(rr.Box((0.2, 0.2, 0.2)), density=500.0, position=(0.0, 0.0, 0.5), angular_velocity=(0.0, 1.0, 0.0))
    busy.add_body(rr.Sphere(0.1), density=500.0, position=(1.0, 0.0, 0.1), restitution=0.5)
    alone = rr.Scene(gravity=G)
    ref = spinning_box_in(alone)
    w_busy = busy.build(dt=1 / 120, integrator=integrator, sleep=False)
    w_alone = alone.build(dt=1 / 120, integrator=integrator)
    assert (w_busy.substeps, w_alone.substeps) == (4, 1)
    w_busy.step(120)
    w_alone.step(120)
    assert len(w_busy.contacts()["depth"]) > 0  # the others did collide
    for field in ("position", "orientation", "linear_velocity", "angular_velocity"):
        np.testing.assert_array_equal(getattr(w_busy.bodies, field)[box], getattr(w_alone.bodies, field)[ref])


# ---------------------------------------------------------------------------
# Sleeping
# ---------------------------------------------------------------------------


def two_stacks(sleep=True):
    """Two 3-box stacks 5 m apart (two islands), a ball high up away from both."""
    scene = rr.Scene(gravity=G)
    scene.add_body(rr.Plane(), fixed=True)
    left = [scene.add_body(rr.Box((0.5, 0.5, 0.5)), density=100.0, position=(0.0, 0.0, 0.5 + i)) for i in range(3)]
    right = [scene.add_body(rr.Box((0.5, 0.5, 0.5)), density=100.0, position=(5.0, 0.0, 0.5 + i)) for i in range(3)]
    ball = scene.add_body(rr.Sphere(0.2), density=1000.0, position=(-3.0, 0.0, 0.2))
    return scene.build(dt=DT, sleep=sleep), left, right, ball


def asleep_world():
    world, left, right, ball = two_stacks()
    world.step(90)  # 1.5 s: settled (< 0.5 s) and asleep 0.5 s later
    return world, left, right, ball


def test_resting_stacks_fall_asleep_and_cost_nothing():
    world, left, right, ball = asleep_world()
    assert world.bodies.sleeping[left + right + [ball]].all()
    assert not world.bodies.sleeping[0]  # the fixed ground is not a sleeper
    assert set(world.stages) & DRIFT == set()  # no kick, no drift: nothing to integrate
    # No contact is computed between sleeping bodies (nor with the ground).
    assert len(world.contacts()["depth"]) == 0
    # And nothing moves: positions to the bit; orientations to the round-off of the
    # unit-norm clean-up every step call does (an ulp, 1.1e-16; 2 ulp allowed).
    position, orientation = world.bodies.position.copy(), world.bodies.orientation.copy()
    for _ in range(60):
        world.step(1)
    assert world.bodies.position.tobytes() == position.tobytes()
    np.testing.assert_allclose(world.bodies.orientation, orientation, rtol=0, atol=2.3e-16)
    assert world.kinetic_energy() == 0.0


def test_without_sleep_the_stacks_keep_their_stages():
    world, left, right, ball = two_stacks(sleep=False)
    world.step(90)
    assert not world.bodies.sleeping.any()
    assert "sleep" not in world.stages
    assert {"forces", "translate"} <= set(world.stages)
    assert len(world.contacts()["depth"]) > 0


def test_a_thrown_body_wakes_the_island_it_touches_only():
    world, left, right, ball = asleep_world()
    bottom = world.bodies.position[left[0]].copy()
    # Throw the ball at the left stack's bottom box.
    world.bodies.linear_velocity[ball] = (10.0, 0.0, 0.0)
    world.step(1)
    assert not world.bodies.sleeping[ball]  # a written velocity wakes it at once
    assert world.bodies.sleeping[left].all()  # not yet touched: still asleep
    assert {"forces", "translate"} <= set(world.stages)
    world.step(30)
    assert not world.bodies.sleeping[left].any()  # the whole touched island woke
    assert np.linalg.norm(world.bodies.position[left[0]] - bottom) > 0.01  # and was hit
    assert world.bodies.sleeping[right].all()  # the other island did not
    assert np.all(world.bodies.linear_velocity[right] == 0.0)


@pytest.mark.parametrize("poke", ["linear_velocity", "angular_velocity", "force", "torque"])
def test_writing_a_velocity_or_force_wakes_the_island(poke):
    world, left, right, ball = asleep_world()
    top = left[2]
    before = world.bodies.position[top].copy()
    if poke in ("force", "torque"):
        # Beyond what friction holds: the 100 kg box's static friction (μ = 0.5)
        # holds 490 N sideways and, over its 1 m face, about 190 N·m of twist.
        getattr(world, f"apply_{poke}")(top, (600.0, 0.0, 0.0) if poke == "force" else (0.0, 0.0, 500.0))
    else:
        getattr(world.bodies, poke)[top] = (0.5, 0.0, 0.0) if poke == "linear_velocity" else (0.0, 0.0, 1.0)
    world.step(1)
    assert not world.bodies.sleeping[left].any()  # its whole island woke
    assert world.bodies.sleeping[right].all()
    world.step(5)
    assert np.any(world.bodies.position[top] != before)  # and it moved


def test_sleeping_body_moved_through_the_view_is_collided_where_it_now_is():
    """Regression: sleeping bodies keep their broad-phase boxes until their pose
    changes. A sleeping box teleported under a falling ball must stop the ball there
    (a stale box would let the ball fall through it to the ground)."""
    world, left, right, ball = asleep_world()
    target = right[0]
    world.bodies.position[target] = (-3.0, 4.0, 0.5)  # still asleep, on the ground
    world.bodies.position[ball] = (-3.0, 4.0, 2.0)
    world.bodies.linear_velocity[ball] = (0.0, 0.0, -1.0)
    world.step(120)
    # The ball (r 0.2) rests on the box top (z 1.0), centre at 1.2, within the
    # 5 mm contact slop plus the soft contact's sag (< 1 cm here).
    assert world.bodies.position[ball][2] == pytest.approx(1.2, abs=0.01)
    assert world.bodies.position[target][2] == pytest.approx(0.5, abs=0.01)


# ---------------------------------------------------------------------------
# Kinematic bodies
# ---------------------------------------------------------------------------


def test_kinematic_paddle_pushes_a_sleeping_box():
    v = 1.0
    scene = rr.Scene(gravity=G)
    scene.add_body(rr.Plane(), fixed=True, friction=0.3)
    box = scene.add_body(rr.Box((0.2, 0.2, 0.2)), density=500.0, position=(0.0, 0.0, 0.2), friction=0.3)
    p0 = np.array([-1.5, 0.0, 0.35])
    paddle = scene.add_body(rr.Box((0.05, 0.5, 0.3)), kinematic=True, position=p0, linear_velocity=(v, 0.0, 0.0))
    world = scene.build(dt=DT)
    assert "kinematic" in world.stages
    world.step(60)  # 1 s: the box has fallen asleep; the paddle is 0.25 m from it
    assert world.bodies.sleeping[box]
    world.step(60)  # 1 s more: the paddle reached the box and has pushed it for 0.75 s
    assert not world.bodies.sleeping[box]
    # The paddle moves exactly with the velocity it was given: p0 + v t (round-off of
    # 480 substep additions, ~1e-15 m), unaffected by the box (infinite mass).
    np.testing.assert_allclose(world.bodies.position[paddle], p0 + [v * world.time, 0.0, 0.0], rtol=0, atol=1e-12)
    assert np.all(world.bodies.linear_velocity[paddle] == [v, 0.0, 0.0])
    assert np.all(world.bodies.angular_velocity[paddle] == 0.0)
    # The box is carried at the paddle's speed (the contact holds the approach at 0; the
    # soft contact lets it lag by ~1e-7 relative), against the paddle's face: the gap is
    # at most the contact margin and the overlap at most the 5 mm slop.
    assert abs(world.bodies.linear_velocity[box, 0] - v) <= 1e-4 * v
    gap = (world.bodies.position[box, 0] - 0.2) - (world.bodies.position[paddle, 0] + 0.05)
    assert -0.005 <= gap <= 0.005
