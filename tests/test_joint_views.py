"""Joint read-back and control as views, names, `set_joint_positions`, and the
choice between articulations and XPBD (the switch, loops, contacts kept articulated).
"""
from __future__ import annotations

import gc
import math

import numpy as np
import pytest

import rigidrs as rr

G = 9.81


def arm(**build: object) -> tuple[rr.Scene, rr.World]:
    """A two-link arm on hinges (the second driven), plus a spherical joint."""
    scene = rr.Scene(gravity=(0, 0, -G))
    upper = scene.add_body(rr.Box((0.25, 0.03, 0.03)), mass=1.0, position=(0.25, 0, 0), name="upper", collision_mask=0)
    lower = scene.add_body(rr.Box((0.25, 0.03, 0.03)), mass=0.5, position=(0.75, 0, 0), name="lower", collision_mask=0)
    ball = scene.add_body(rr.Sphere(0.05), mass=0.3, position=(2.0, 0, -0.5), name="ball", collision_mask=0)
    scene.add_joint("hinge", upper, None, anchor=(0, 0, 0), axis=(0, 1, 0), name="shoulder", limits=(-2.0, 2.0))
    scene.add_joint("hinge", lower, upper, anchor=(0.5, 0, 0), axis=(0, 1, 0), name="elbow",
                    drive=rr.Drive(target=0.3, stiffness=50.0, damping=5.0))
    scene.add_joint("spherical", ball, None, anchor=(2.0, 0, 0), name="pivot")
    return scene, scene.build(dt=1 / 240, **build)


def test_views_share_memory_and_read_only_ones_refuse_writes() -> None:
    _, world = arm()
    j = world.joints
    assert len(j) == 3
    for name in ("position", "velocity", "target", "force"):
        a, b = getattr(j, name), getattr(world.joints, name)
        assert a.shape == (3,) and a.dtype == np.float64
        assert np.shares_memory(a, b)
    for name in ("position", "velocity", "force"):
        with pytest.raises(ValueError):
            getattr(j, name)[0] = 1.0
    world.step(10)
    assert np.isnan(j.position[2]) and np.isnan(j.velocity[2])  # spherical: no single coordinate
    assert np.isfinite(j.position[:2]).all()


def test_a_view_keeps_the_world_alive() -> None:
    _, world = arm()
    position, target = world.joints.position, world.joints.target
    world.step(5)
    expected = position.copy()
    del world
    gc.collect()
    assert np.array_equal(position, expected, equal_nan=True)
    target[1] = 0.1  # still the world's memory, still writable


def test_names() -> None:
    _, world = arm()
    assert world.joints.names == ["shoulder", "elbow", "pivot"]
    assert world.bodies.names == ["upper", "lower", "ball"]
    scene = rr.Scene()
    a = scene.add_body(rr.Sphere(0.1), mass=1.0, name="a")
    with pytest.raises(rr.RigidError, match="body 1.*name \"a\" is taken"):
        scene.add_body(rr.Sphere(0.1), mass=1.0, name="a")
    scene.add_joint("spherical", a, None, name="j")
    with pytest.raises(rr.RigidError, match="joint 1.*name \"j\" is taken"):
        scene.add_joint("spherical", a, None, name="j")
    assert len(scene) == 1 and scene.joint_count == 1


def test_joint_positions_read_the_bodies_relative_angle() -> None:
    # The arm falls; the elbow angle read back equals the angle between the two
    # links' x axes about y (body a relative to body b), and the shoulder's that of
    # the upper link relative to the world.
    _, world = arm()
    world.step(60)
    r = world.bodies.rotation
    angle = lambda ra, rb: math.atan2(np.cross(rb[:, 0], ra[:, 0])[1], rb[:, 0] @ ra[:, 0])  # noqa: E731
    assert world.joints.position[0] == pytest.approx(angle(r[0], np.eye(3)), abs=1e-12)
    assert world.joints.position[1] == pytest.approx(angle(r[1], r[0]), abs=1e-12)


def test_set_joint_positions_poses_and_validates() -> None:
    _, world = arm()
    world.set_joint_positions([0.5, -0.25, np.nan])
    assert world.joints.position[:2].tolist() == [0.5, -0.25]
    assert world.joints.velocity[:2].tolist() == [0.0, 0.0]
    r = world.bodies.rotation
    assert r[0][:, 0] @ np.array([math.cos(0.5), 0, -math.sin(0.5)]) == pytest.approx(1.0, abs=1e-12)
    world.set_joint_positions([np.nan, np.nan, np.nan], velocities=[1.0, np.nan, np.nan])
    assert world.joints.velocity[0] == 1.0 and world.joints.position[0] == 0.5
    before = (world.bodies.position.copy(), world.joints.position.copy(), world.joints.velocity.copy())
    bad = [
        ([0.1, 0.2], ValueError, "positions"),
        ([3.0, 0.0, np.nan], rr.RigidError, "joint 0: position 3 is outside its limits"),
        ([0.0, np.inf, np.nan], rr.RigidError, "joint 1"),
        ([0.0, 0.0, 0.1], rr.RigidError, "joint 2: a spherical joint has no single coordinate"),
    ]
    for q, exc, words in bad:
        with pytest.raises(exc, match=words):
            world.set_joint_positions(q)
        assert np.array_equal(world.bodies.position, before[0])
        assert np.array_equal(world.joints.position, before[1], equal_nan=True)
        assert np.array_equal(world.joints.velocity, before[2], equal_nan=True)


def test_xpbd_joints_cannot_be_posed_by_coordinates() -> None:
    scene = rr.Scene(gravity=(0, 0, -G))
    b = scene.add_body(rr.Sphere(0.1), mass=1.0, position=(1, 0, 0))
    scene.add_joint("hinge", b, None, anchor=(0, 0, 0), axis=(0, 1, 0))
    world = scene.build(dt=1 / 60, articulations=False)
    assert "joints" in world.stages and "articulation" not in world.stages
    with pytest.raises(rr.RigidError, match="joint 0: a hinge joint that XPBD solves"):
        world.set_joint_positions([0.1])
    world.step(10)
    # XPBD hinges read back too, from their bodies' poses.
    x = world.bodies.rotation[b][:, 0]
    assert world.joints.position[0] == pytest.approx(math.atan2(-x[2], x[0]), abs=1e-9)


def test_drives_need_an_articulation() -> None:
    # The arm's elbow drive cannot run in XPBD: building it without
    # articulations names the joint and the reason.
    scene, _ = arm()
    with pytest.raises(rr.RigidError, match="joint 1: its drive.*needs an articulation"):
        scene.build(dt=1 / 240, articulations=False)


def test_solver_switch_per_joint_and_loops() -> None:
    def pendulum_pair(solver: str, loop: bool) -> rr.World:
        scene = rr.Scene(gravity=(0, 0, -G))
        a = scene.add_body(rr.Sphere(0.05), mass=1.0, position=(0, 0, -1), collision_mask=0)
        b = scene.add_body(rr.Sphere(0.05), mass=1.0, position=(0, 0, -2), collision_mask=0)
        scene.add_joint("spherical", a, None, anchor=(0, 0, 0), solver=solver)
        scene.add_joint("spherical", b, a, anchor=(0, 0, -1))
        if loop:
            scene.add_joint("distance", b, None, anchor=(0, 0, -2), anchor_b=(0.5, 0, -2))
        return scene.build(dt=1 / 60)

    assert pendulum_pair("auto", False).stages == ["articulation"]
    assert "joints" in pendulum_pair("xpbd", False).stages
    looped = pendulum_pair("auto", True)
    assert "joints" in looped.stages and "articulation" not in looped.stages
    with pytest.raises(rr.RigidError, match="joint 0: solver=\"articulation\" needs an articulation.*loop"):
        pendulum_pair("articulation", True)


def test_links_that_can_touch_a_collider_stay_articulated() -> None:
    # Contacts act on articulations: a chain whose links can reach the ground
    # articulates and steps inside the contact substeps when it touches it
    # (`articulation_contact`); masked off it, it has no contact stage at all.
    def chain(mask: int, height: float) -> rr.World:
        scene = rr.Scene(gravity=(0, 0, -G))
        scene.add_body(rr.Plane(), fixed=True)
        a = scene.add_body(rr.Box((0.1, 0.02, 0.02)), mass=1.0, position=(0.1, 0, height), collision_mask=mask)
        b = scene.add_body(rr.Box((0.1, 0.02, 0.02)), mass=1.0, position=(0.3, 0, height), collision_mask=mask)
        scene.add_joint("hinge", a, None, anchor=(0, 0, height), axis=(0, 1, 0))
        scene.add_joint("hinge", b, a, anchor=(0.2, 0, height), axis=(0, 1, 0))
        return scene.build(dt=1 / 60)

    touching = chain(0xFFFFFFFF, 0.3)
    assert "joints" not in touching.stages and "articulation_contact" in touching.stages
    assert chain(0, 0.3).stages == ["articulation"]
    touching.step(30)
    assert np.isfinite(touching.bodies.position).all()
    assert touching.bodies.position[1:, 2].min() > 0.0  # held up by the ground
    assert len(touching.articulations()) == 1


def test_fixed_joint_reads_its_static_load() -> None:
    # A welded bar (0 dofs): the reaction read back is the weight and its moment
    # about the anchor, as for the XPBD weld.
    scene = rr.Scene(gravity=(0, 0, -G))
    bar = scene.add_body(rr.Box((0.3, 0.05, 0.05)), mass=3.0, position=(5.3, 0, 0))
    scene.add_joint("fixed", bar, None, anchor=(5.0, 0, 0))
    world = scene.build(dt=1 / 60)
    assert world.stages == ["articulation"]
    world.step(10)
    np.testing.assert_allclose(world.joint_forces()[0], [0, 0, 3.0 * G], atol=1e-9)
    np.testing.assert_allclose(world.joint_torques()[0], [0, -0.3 * 3.0 * G, 0], atol=1e-9)
    np.testing.assert_allclose(world.bodies.position[bar], [5.3, 0, 0], atol=1e-15)


BAD = [
    (dict(kind="distance", drive=rr.Drive(target=1.0)), "joint 0: drive: a distance joint"),
    (dict(kind="fixed", damping=1.0), "joint 0: drive: a fixed joint"),
    (dict(kind="hinge", cone_limit=0.3), "joint 0: cone_limit"),
    (dict(kind="spherical", cone_limit=4.0), "joint 0: cone_limit must be in"),
    (dict(kind="spherical", twist_limits=(0.5, -0.5)), "joint 0: twist_limits"),
    (dict(kind="hinge", damping=-1.0), "joint 0: damping"),
    (dict(kind="hinge", armature=math.nan), "joint 0: armature"),
    (dict(kind="hinge", friction=-0.1), "joint 0: friction"),
    (dict(kind="hinge", drive=rr.Drive(target=(1.0, 2.0))), "joint 0: drive target"),
    (dict(kind="spherical", drive=rr.Drive(target=0.5)), "joint 0: drive target"),
    (dict(kind="spherical", drive=rr.Drive(target=(0, 0, 0, 0))), "joint 0: drive target"),
    (dict(kind="hinge", drive=rr.Drive(mode="velocity", stiffness=1.0)), "joint 0: drive stiffness"),
    (dict(kind="hinge", drive=rr.Drive(stiffness=-1.0)), "joint 0: drive stiffness"),
    (dict(kind="hinge", drive=rr.Drive(max_force=0.0)), "joint 0: drive max_force"),
    (dict(kind="hinge", solver="rigid"), "joint 0: solver"),
    (dict(kind="hinge", solver="xpbd", damping=1.0), "joint 0: solver"),
]


@pytest.mark.parametrize("args, words", BAD, ids=[str(i) for i in range(len(BAD))])
def test_bad_joint_options_leave_the_scene_unchanged(args: dict, words: str) -> None:
    scene = rr.Scene()
    a = scene.add_body(rr.Sphere(0.1), mass=1.0, position=(1, 0, 0))
    args = dict(args)
    kind = args.pop("kind")
    with pytest.raises(rr.RigidError, match=words):
        scene.add_joint(kind, a, None, anchor=(0, 0, 0), **args)
    assert scene.joint_count == 0


def test_bad_drive_mode() -> None:
    with pytest.raises(rr.RigidError, match="Drive mode"):
        rr.Drive(mode="torque")
    d = rr.Drive(mode="velocity", target=2.0, damping=3.0)
    assert (d.mode, d.target, d.stiffness, d.damping, d.max_force) == ("velocity", [2.0], 0.0, 3.0, math.inf)


def test_bad_build_options() -> None:
    scene, _ = arm()
    with pytest.raises(ValueError, match="articulation_substeps"):
        scene.build(dt=1 / 60, articulation_substeps=0)
    with pytest.raises(rr.RigidError, match="articulation_integrator"):
        scene.build(dt=1 / 60, articulation_integrator="rk5")
