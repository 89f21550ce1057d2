"""Bad collision input (issue 3): non-finite or negative friction and restitution,
restitution above 1, static friction below friction, bad collision filters,
degenerate shapes, meshes with NaN, bad contact settings in ``build``. Each raises a
clear Python exception (a ``rigidrs.RigidError`` subclass, all ``ValueError``s, or
``TypeError``; DESIGN.md) whose message names the body and the field, and leaves
the scene exactly as it was: same length, the next body gets the next index, and it
still builds a world that steps bit for bit like one from a scene never given the
bad input.

No tolerances: "unchanged" is compared byte for byte.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import rigidrs as rr

NAN, INF = math.nan, math.inf
DT = 1.0 / 240.0


def message(excinfo) -> str:
    e = excinfo.value
    return " ".join([str(e), *getattr(e, "__notes__", [])])


def check_raises(call, exc, words):
    with pytest.raises(exc) as excinfo:
        call()
    assert isinstance(excinfo.value, (ValueError, TypeError))  # DESIGN.md: no other kinds
    text = message(excinfo)
    for w in words:
        assert w in text, f"{w!r} not in {text!r}"


def base_scene():
    """A scene with contacts, restitution, friction and a CCD body: every stage."""
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Plane(), fixed=True, friction=0.4)
    scene.add_body(rr.Box((0.2, 0.2, 0.2)), density=500.0, position=(0.0, 0.0, 0.2), linear_velocity=(1.0, 0.0, 0.0))
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0.1, 0.0, 1.0), restitution=0.5, ccd=True,
                   linear_velocity=(0.0, 0.0, -5.0))
    return scene


def fingerprint(scene):
    world = scene.build(dt=DT)
    world.step(30)
    return (world.stages, world.bodies.position.tobytes(), world.bodies.orientation.tobytes(),
            world.bodies.linear_velocity.tobytes(), world.bodies.angular_velocity.tobytes())


REFERENCE = fingerprint(base_scene())


def assert_scene_unchanged(scene):
    assert len(scene) == 3
    assert fingerprint(scene) == REFERENCE
    assert scene.add_body(rr.Sphere(0.2), mass=1.0, position=(5.0, 0.0, 5.0)) == 3


# ---------------------------------------------------------------------------
# Materials, filters and flags in add_body
# ---------------------------------------------------------------------------

BALL = dict(shape=rr.Sphere(0.1), density=1000.0, position=(3.0, 0.0, 1.0))

ADD_BODY = {
    **{f"friction={v}": (dict(friction=v), rr.RigidError, ["body 3", "friction"]) for v in (NAN, INF, -INF, -0.1)},
    **{f"static_friction={v}": (dict(static_friction=v), rr.RigidError, ["body 3", "static_friction"])
       for v in (NAN, INF, -1.0)},
    "static_friction below friction": (dict(friction=0.5, static_friction=0.4), rr.RigidError,
                                       ["body 3", "static_friction", "friction"]),
    **{f"restitution={v}": (dict(restitution=v), rr.RigidError, ["body 3", "restitution"])
       for v in (NAN, INF, -0.1, 1.5, 1.0 + 1e-15)},
    "friction None": (dict(friction=None), TypeError, ["friction"]),
    "friction a string": (dict(friction="rough"), TypeError, ["friction"]),
    "restitution None": (dict(restitution=None), TypeError, ["restitution"]),
    "ccd not a bool": (dict(ccd="yes"), TypeError, ["ccd"]),
    "collision_group a float": (dict(collision_group=1.5), TypeError, ["collision_group"]),
}

FILTER_RANGE = {
    "collision_group=-1": dict(collision_group=-1),
    "collision_group=2**32": dict(collision_group=2**32),
    "collision_mask=-1": dict(collision_mask=-1),
}


@pytest.mark.parametrize("case", list(ADD_BODY))
def test_add_body_rejects_bad_materials_and_leaves_the_scene_unchanged(case):
    kwargs, exc, words = ADD_BODY[case]
    scene = base_scene()
    check_raises(lambda: scene.add_body(**{**BALL, **kwargs}), exc, words)
    assert_scene_unchanged(scene)


@pytest.mark.parametrize("case", list(FILTER_RANGE))
def test_collision_filters_out_of_range_raise_a_value_error(case):
    scene = base_scene()
    check_raises(lambda: scene.add_body(**{**BALL, **FILTER_RANGE[case]}), ValueError, ["body 3", case.split("=")[0]])
    assert_scene_unchanged(scene)


def test_filter_bounds_are_accepted():
    # 0 (collides with nothing) and 2^32 - 1 (all bits) are valid.
    scene = base_scene()
    assert scene.add_body(**BALL, collision_group=0, collision_mask=2**32 - 1) == 3
    assert scene.add_body(**BALL, collision_group=2**32 - 1, collision_mask=0) == 4


@pytest.mark.parametrize(
    "kwargs,words",
    [
        (dict(mass=1.0, inertia=(0.1, 0.1, 0.1), ccd=True), ["body 3", "ccd", "shape"]),
        (dict(shape=rr.Sphere(0.1), fixed=True, kinematic=True), ["body 3", "fixed", "kinematic"]),
        (dict(shape=rr.Plane(), density=1.0), ["body 3", "Plane", "fixed"]),
    ],
    ids=["ccd without a shape", "fixed and kinematic", "dynamic plane"],
)
def test_add_body_rejects_contradictory_flags(kwargs, words):
    scene = base_scene()
    check_raises(lambda: scene.add_body(**kwargs), rr.RigidError, words)
    assert_scene_unchanged(scene)


# ---------------------------------------------------------------------------
# Degenerate shapes and meshes
# ---------------------------------------------------------------------------

TET_V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
TET_T = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
FLOOR_V = np.array([[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]], dtype=float)
FLOOR_T = [[0, 1, 2], [0, 2, 3]]

SHAPES = {
    "Sphere radius 0": (lambda: rr.Sphere(0.0), rr.RigidError, ["Sphere radius"]),
    "Sphere radius inf": (lambda: rr.Sphere(INF), rr.RigidError, ["Sphere radius"]),
    "Box negative extent": (lambda: rr.Box((1.0, -1.0, 1.0)), rr.RigidError, ["Box half_extents.y"]),
    "Capsule radius 0": (lambda: rr.Capsule(0.0, 1.0), rr.RigidError, ["Capsule radius"]),
    "Cylinder half_height 0": (lambda: rr.Cylinder(1.0, 0.0), rr.RigidError, ["Cylinder half_height"]),
    "Cone radius inf": (lambda: rr.Cone(INF, 1.0), rr.RigidError, ["Cone radius"]),
    "Cone radius NaN": (lambda: rr.Cone(NAN, 1.0), rr.RigidError, ["Cone radius"]),
    "ConvexHull flat to 1e-300": (lambda: rr.ConvexHull(np.vstack([TET_V[:3], [[0.0, 0.0, 1e-300]]])), rr.ShapeError,
                                  ["ConvexHull"]),
    "TriMesh NaN vertex": (lambda: rr.TriMesh(np.vstack([FLOOR_V[:3], [[NAN, 0.0, 0.0]]]), FLOOR_T), rr.RigidError,
                           ["TriMesh vertices[3]", "finite"]),
    "TriMesh inf vertex": (lambda: rr.TriMesh(np.vstack([[[0.0, INF, 0.0]], FLOOR_V[1:]]), FLOOR_T), rr.RigidError,
                           ["TriMesh vertices[0]", "finite"]),
    "TriMesh index out of range": (lambda: rr.TriMesh(FLOOR_V, [[0, 1, 2], [0, 2, 4]]), rr.RigidError,
                                   ["TriMesh triangles[1]", "4"]),
    "Compound empty": (lambda: rr.Compound([]), rr.ShapeError, ["Compound", "part"]),
    "Compound with a Plane": (lambda: rr.Compound([(rr.Plane(), (0.0, 0.0, 0.0))]), rr.ShapeError, ["Compound part 0", "Plane"]),
    "Compound with a TriMesh": (lambda: rr.Compound([(rr.TriMesh(TET_V, TET_T), (0.0, 0.0, 0.0))]), rr.ShapeError,
                                ["Compound part 0", "TriMesh"]),
    "Compound in a Compound": (lambda: rr.Compound([(rr.Compound([(rr.Sphere(1.0), (0, 0, 0))]), (0.0, 0.0, 0.0))]),
                               rr.ShapeError, ["Compound part 0", "Compound"]),
    "Compound NaN position": (lambda: rr.Compound([(rr.Sphere(1.0), (0.0, 0.0, 0.0)), (rr.Sphere(1.0), (NAN, 0.0, 0.0))]),
                              rr.RigidError, ["Compound part 1", "position"]),
    "Compound zero quaternion": (lambda: rr.Compound([(rr.Sphere(1.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))]),
                                 rr.RigidError, ["Compound part 0", "orientation"]),
    "Compound part not a tuple": (lambda: rr.Compound([rr.Sphere(1.0)]), TypeError, ["Compound part 0"]),
    "Compound part too short": (lambda: rr.Compound([(rr.Sphere(1.0),)]), ValueError, ["Compound part 0"]),
    "Compound part not a shape": (lambda: rr.Compound([("ball", (0.0, 0.0, 0.0))]), TypeError, ["Compound part 0", "Shape"]),
}


@pytest.mark.parametrize("case", list(SHAPES))
def test_degenerate_shapes_are_rejected_when_made(case):
    make, exc, words = SHAPES[case]
    check_raises(make, exc, words)


def test_compound_of_a_non_sequence_names_the_parts():
    check_raises(lambda: rr.Compound(5), TypeError, ["Compound", "parts"])


DEGENERATE_TRIANGLES = {
    "collinear triangle": (np.vstack([FLOOR_V, [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]]]), [*FLOOR_T, [0, 4, 5]]),
    "triangle with two coincident corners": (np.vstack([FLOOR_V, [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]]), [*FLOOR_T, [1, 4, 5]]),
}


@pytest.mark.parametrize("case", list(DEGENERATE_TRIANGLES))
def test_mesh_with_a_zero_area_triangle_is_rejected(case):
    vertices, triangles = DEGENERATE_TRIANGLES[case]
    check_raises(lambda: rr.TriMesh(vertices, triangles), rr.ShapeError, ["TriMesh triangles[2]"])


def test_open_mesh_floor_is_accepted_as_a_fixed_body():
    # A mesh that is not closed cannot carry mass, but a fixed terrain needs none.
    scene = base_scene()
    assert scene.add_body(rr.TriMesh(FLOOR_V, FLOOR_T), fixed=True, position=(0.0, 0.0, -1.0)) == 3


# ---------------------------------------------------------------------------
# Contact settings in build
# ---------------------------------------------------------------------------

BUILD = {
    **{f"slop={v}": (dict(slop=v), rr.RigidError, ["slop"]) for v in (-0.001, NAN, INF)},
    "iterations=0": (dict(iterations=0), rr.RigidError, ["iterations"]),
    "iterations=-1": (dict(iterations=-1), ValueError, ["iterations"]),
    "iterations=2**40": (dict(iterations=2**40), ValueError, ["iterations"]),
    "iterations=1.5": (dict(iterations=1.5), TypeError, ["iterations"]),
    "substeps=0": (dict(substeps=0), rr.RigidError, ["substeps"]),
    "substeps=-4": (dict(substeps=-4), ValueError, ["substeps"]),
    **{f"contact_hertz={v}": (dict(contact_hertz=v), rr.RigidError, ["contact_hertz"]) for v in (-1.0, NAN, INF)},
    **{f"contact_damping_ratio={v}": (dict(contact_damping_ratio=v), rr.RigidError, ["contact_damping_ratio"])
       for v in (-1.0, NAN)},
    **{f"max_push_velocity={v}": (dict(max_push_velocity=v), rr.RigidError, ["max_push_velocity"])
       for v in (0.0, -1.0, NAN, INF)},
    **{f"restitution_threshold={v}": (dict(restitution_threshold=v), rr.RigidError, ["restitution_threshold"])
       for v in (-0.5, NAN, INF)},
    "sleep_linear=-1": (dict(sleep_linear=-1.0), rr.RigidError, ["sleep", "linear"]),
    "sleep_angular=NaN": (dict(sleep_angular=NAN), rr.RigidError, ["sleep", "angular"]),
    **{f"sleep_time={v}": (dict(sleep_time=v), rr.RigidError, ["sleep", "time"]) for v in (-0.5, INF)},
    "sleep not a bool": (dict(sleep="no"), TypeError, ["sleep"]),
}


@pytest.mark.parametrize("case", list(BUILD))
def test_build_rejects_bad_contact_settings_and_leaves_the_scene_unchanged(case):
    kwargs, exc, words = BUILD[case]
    scene = base_scene()
    check_raises(lambda: scene.build(dt=DT, **kwargs), exc, words)
    assert_scene_unchanged(scene)


@pytest.mark.parametrize(
    "kwargs",
    [dict(slop=0.0), dict(restitution_threshold=0.0), dict(contact_hertz=0.0), dict(contact_damping_ratio=0.0),
     dict(sleep_time=0.0), dict(sleep=False)],
    ids=lambda k: next(iter(k.items())).__repr__(),
)
def test_build_accepts_the_documented_edge_values(kwargs):
    # Zero is documented as allowed for the threshold ("0 allowed") and is a valid
    # non-negative value for the others; the world runs and keeps the ball above ground.
    world = base_scene().build(dt=DT, **kwargs)
    world.step(60)
    assert np.all(np.isfinite(world.bodies.position))
    assert world.bodies.position[2, 2] > 0.0


def test_contact_hertz_above_the_substep_rate_warns_and_is_capped():
    # A contact stiffer than a quarter of the substep rate overshoots within one
    # substep; the solver caps it there (4 substeps at 60 Hz: 60 Hz), and a user who
    # asked for more is told, with the cap and what to change.
    cap = 0.25 * 4 / DT
    with pytest.warns(UserWarning, match=r"contact_hertz=1000.*substeps") as caught:
        world = base_scene().build(dt=DT, substeps=4, contact_hertz=1000.0)
    assert f"{cap:.4f}" in str(caught[0].message)
    world.step(60)
    assert np.all(np.isfinite(world.bodies.position))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        base_scene().build(dt=DT, substeps=4, contact_hertz=cap)


def test_default_contact_hertz_does_not_warn_at_one_substep():
    # The default rate is the engine's choice, capped quietly; only a rate the user
    # asked for and does not get is worth a warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        base_scene().build(dt=1 / 60, substeps=1).step(10)
