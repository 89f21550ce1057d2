"""The pipeline a world runs is the one its scene needs, and ``world.stages`` says so:
no force stage without gravity or applied forces (re-checked at every step), the
cheapest rotation for each inertia class, no gyroscopic stage without a body that
needs it, nothing for fixed bodies; ``world.profile()`` reports per stage that ran.

Stage lists are compared exactly; the motion checks that prove a stage did (not)
run use the round-off bars of test_views.py (1e-14 of the state's size for one
step). No timing is asserted: profile values are only checked to be >= 0.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr

DT = 0.01
ZERO_G = (0.0, 0.0, 0.0)
SPLITTINGS = ["euler", "symplectic_euler", "implicit_gyro", "strang", "yoshida4", "suzuki4"]
WITH_GYRO = {"symplectic_euler", "implicit_gyro"}
ROTATE = {"rotate_isotropic", "rotate_symmetric", "rotate_asymmetric"}
# Drifts (translate + rotations) per step of each splitting: composition stages.
DRIFTS = {"euler": 1, "symplectic_euler": 1, "implicit_gyro": 1, "strang": 1, "yoshida4": 3, "suzuki4": 5}

SPHERE = rr.Sphere(0.1)  # isotropic
CUBE = rr.Box((0.2, 0.2, 0.2))  # isotropic inertia, not a sphere
CYLINDER = rr.Cylinder(0.1, 0.3)  # symmetric
BOX = rr.Box((0.05, 0.2, 0.45))  # asymmetric


def world_of(*shapes, gravity=ZERO_G, integrator="strang", fixed=()):
    """Bodies whose filters exclude every pair: no collision stage, only integration."""
    scene = rr.Scene(gravity=gravity)
    for s in shapes:
        scene.add_body(s, density=1000.0, angular_velocity=(0.3, -0.2, 0.5), collision_mask=0)
    for s in fixed:
        scene.add_body(s, fixed=True, collision_mask=0)
    return scene.build(dt=DT, integrator=integrator)


def expected(integrator, classes, forces):
    """The documented pipeline: [gyroscopic] then, per drift, [forces] translate
    rotate_<class>... and a closing [forces] (Euler kicks after its drift)."""
    if integrator == "rk4":
        return ["rk4"]
    rot = [f"rotate_{c}" for c in ("isotropic", "symmetric", "asymmetric") if c in classes]
    stages = ["gyroscopic"] if integrator in WITH_GYRO and classes - {"isotropic"} else []
    if integrator == "euler":
        return stages + ["translate", *rot] + (["forces"] if forces else [])
    for _ in range(DRIFTS[integrator]):
        stages += (["forces"] if forces else []) + ["translate", *rot]
    if forces and integrator not in WITH_GYRO:  # semi-implicit Euler kicks only first
        stages.append("forces")
    return stages


@pytest.mark.parametrize("integrator", sorted(rr.INTEGRATORS))
@pytest.mark.parametrize(
    "shapes,classes",
    [
        ([SPHERE], {"isotropic"}),
        ([CUBE], {"isotropic"}),
        ([CYLINDER], {"symmetric"}),
        ([BOX], {"asymmetric"}),
        ([SPHERE, CYLINDER, BOX, SPHERE], {"isotropic", "symmetric", "asymmetric"}),
    ],
    ids=["sphere", "cube", "cylinder", "box", "mixed"],
)
@pytest.mark.parametrize("gravity", [ZERO_G, (0.0, 0.0, -9.81)], ids=["no_gravity", "gravity"])
def test_stages_follow_the_scene(integrator, shapes, classes, gravity):
    world = world_of(*shapes, gravity=gravity, integrator=integrator, fixed=[BOX])
    assert world.stages == expected(integrator, classes, forces=gravity != ZERO_G)


def test_expected_pipeline_of_the_default_integrator_is_the_documented_one():
    # README: a box near its intermediate axis under no gravity.
    assert world_of(BOX).stages == ["translate", "rotate_asymmetric"]
    assert world_of(BOX, gravity=(0, 0, -9.81)).stages == ["forces", "translate", "rotate_asymmetric", "forces"]


@pytest.mark.parametrize("integrator", sorted(rr.INTEGRATORS))
def test_spheres_have_no_gyroscopic_work(integrator):
    stages = world_of(SPHERE, SPHERE, integrator=integrator).stages
    assert "gyroscopic" not in stages
    assert not (set(stages) & {"rotate_symmetric", "rotate_asymmetric"})
    if integrator != "rk4":
        assert "rotate_isotropic" in stages


@pytest.mark.parametrize("integrator", ["symplectic_euler", "implicit_gyro"])
def test_gyroscopic_stage_only_with_a_non_isotropic_dynamic_body(integrator):
    assert "gyroscopic" not in world_of(SPHERE, CUBE, integrator=integrator).stages
    # A fixed box is not a body the gyroscopic term touches.
    assert "gyroscopic" not in world_of(SPHERE, integrator=integrator, fixed=[BOX]).stages
    assert world_of(SPHERE, CYLINDER, integrator=integrator).stages[0] == "gyroscopic"
    assert world_of(BOX, integrator=integrator).stages[0] == "gyroscopic"


def test_inertia_classes_from_explicit_moments_and_tensors():
    scene = rr.Scene(gravity=ZERO_G)
    scene.add_body(mass=1.0, inertia=(2.0, 2.0, 2.0))
    assert scene.build(dt=DT).stages == ["translate", "rotate_isotropic"]
    scene.add_body(mass=1.0, inertia=(1.0, 2.0, 2.0))  # symmetric about x
    assert scene.build(dt=DT).stages == ["translate", "rotate_isotropic", "rotate_symmetric"]
    # A rotated symmetric tensor is still symmetric once in its principal frame.
    r = Rotation.from_rotvec([0.3, 0.7, -0.2]).as_matrix()
    only = rr.Scene(gravity=ZERO_G)
    only.add_body(mass=1.0, inertia=r @ np.diag([1.0, 1.5, 1.5]) @ r.T)
    assert only.build(dt=DT).stages == ["translate", "rotate_symmetric"]


@pytest.mark.parametrize("integrator", sorted(rr.INTEGRATORS))
@pytest.mark.parametrize("gravity", [ZERO_G, (0.0, 0.0, -9.81)], ids=["no_gravity", "gravity"])
def test_a_world_of_fixed_bodies_has_no_stage(integrator, gravity):
    world = world_of(gravity=gravity, integrator=integrator, fixed=[BOX, SPHERE, rr.Plane()])
    assert world.stages == []
    pose = world.bodies.position.copy(), world.bodies.orientation.copy()
    world.step(10)
    assert world.steps == 10
    np.testing.assert_array_equal(world.bodies.position, pose[0])
    np.testing.assert_array_equal(world.bodies.orientation, pose[1])
    assert world.profile() == {"steps": 10}


def test_an_empty_world_has_no_stage():
    assert rr.Scene().build(dt=DT).stages == []


def test_fixed_bodies_add_no_stage_to_dynamic_ones():
    alone = world_of(SPHERE, gravity=(0.0, 0.0, -9.81))
    with_fixed = world_of(SPHERE, gravity=(0.0, 0.0, -9.81), fixed=[BOX, CYLINDER, rr.Plane()])
    assert with_fixed.stages == alone.stages == ["forces", "translate", "rotate_isotropic", "forces"]


@pytest.mark.parametrize("integrator", sorted(rr.INTEGRATORS))
def test_forces_stage_follows_applied_forces(integrator):
    world = world_of(SPHERE, BOX, integrator=integrator, fixed=[CUBE])
    base = world.stages
    assert "forces" not in base
    world.apply_force(1, (0.0, 0.0, 1.0))
    assert world.stages == expected(integrator, {"isotropic", "asymmetric"}, forces=True)
    world.clear_forces()
    assert world.stages == base
    world.bodies.force[0] = (1.0, 0.0, 0.0)  # written through the view
    assert world.stages == expected(integrator, {"isotropic", "asymmetric"}, forces=True)
    world.bodies.force[0] = 0.0
    assert world.stages == base
    world.apply_torque(0, (0.0, 0.1, 0.0))
    assert world.stages == expected(integrator, {"isotropic", "asymmetric"}, forces=True)
    world.clear_forces()
    # A force on a fixed body moves nothing and adds no stage.
    world.bodies.force[2] = (5.0, 0.0, 0.0)
    assert world.stages == base


def test_forces_are_rechecked_at_every_step_call():
    world = world_of(SPHERE)
    b = world.bodies
    m = b.mass[0]
    world.step()
    np.testing.assert_array_equal(b.linear_velocity[0], np.zeros(3))
    f = np.array([2.0, 0.0, -1.0])
    b.force[0] = f  # between two step calls, through the view
    world.step(4)
    # The force acted from the next step on: v = f t / m (exact to round-off).
    np.testing.assert_allclose(b.linear_velocity[0], f * 4 * DT / m, rtol=1e-14)
    world.clear_forces()
    v = b.linear_velocity[0].copy()
    world.step(3)
    np.testing.assert_array_equal(b.linear_velocity[0], v)  # no force stage: velocity untouched


def test_apply_force_at_a_point_adds_the_torque_about_the_centre_of_mass():
    world = world_of(SPHERE, BOX, fixed=[CUBE])
    b = world.bodies
    p = b.position[1].copy()
    f = np.array([0.0, 3.0, -1.0])
    point = p + np.array([0.5, 0.0, 0.2])
    world.apply_force(1, f, point=point)
    world.apply_force(1, f)  # adds up: persists until cleared
    # Stored values: F = 2f, τ = (point − p) × f (a few flops: round-off 1e-15).
    np.testing.assert_allclose(b.force[1], 2 * f, rtol=0, atol=1e-15)
    np.testing.assert_allclose(b.torque[1], np.cross(point - p, f), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(b.force[0], np.zeros(3))


@pytest.mark.parametrize("integrator", sorted(rr.INTEGRATORS))
def test_profile_reports_the_stages_that_ran_and_the_steps(integrator):
    world = world_of(SPHERE, CYLINDER, BOX, gravity=(0.0, 0.0, -9.81), integrator=integrator)
    world.step(7)
    world.step(3)
    prof = world.profile()
    assert set(prof) == set(world.stages) | {"steps"}
    assert prof["steps"] == 10
    assert all(v >= 0.0 for k, v in prof.items() if k != "steps")
    # reset (the default) starts a new window
    assert world.profile() == {"steps": 0}
    world.step(2)
    assert world.profile(reset=False)["steps"] == 2
    world.step(1)
    prof = world.profile()
    assert prof["steps"] == 3
    assert set(prof) == set(world.stages) | {"steps"}


def test_profile_only_lists_stages_that_ran_in_the_window():
    world = world_of(SPHERE, BOX)
    world.step(2)
    assert set(world.profile()) == {"translate", "rotate_isotropic", "rotate_asymmetric", "steps"}
    world.apply_force(0, (1.0, 0.0, 0.0))
    world.step(2)
    assert set(world.profile()) == {"forces", "translate", "rotate_isotropic", "rotate_asymmetric", "steps"}
    world.clear_forces()
    world.step(1)
    assert "forces" not in world.profile()


def test_profiling_off_records_steps_but_no_stage():
    world = world_of(SPHERE, BOX)
    assert world.profiling is True  # documented default
    world.profiling = False
    world.step(5)
    assert world.profile() == {"steps": 5}
    world.profiling = True
    world.step(1)
    assert set(world.profile()) == {"translate", "rotate_isotropic", "rotate_asymmetric", "steps"}


@pytest.mark.parametrize("integrator", SPLITTINGS)
def test_substeps_do_not_change_the_stage_list(integrator):
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(BOX, density=1000.0)
    one = scene.build(dt=DT, integrator=integrator)
    four = scene.build(dt=DT, integrator=integrator, substeps=4)
    assert four.stages == one.stages  # stages of one (sub)step
    four.step(2)
    assert four.profile()["steps"] == 2


def test_a_refused_step_is_not_counted_in_the_profile():
    world = world_of(SPHERE, BOX)
    world.step(2)
    world.bodies.position[1, 0] = np.nan
    with pytest.raises(rr.StateError):
        world.step(5)
    assert world.steps == 2
    assert world.profile()["steps"] == 2
