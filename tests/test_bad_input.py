"""Bad input: each case raises a clear Python exception (a ``rigidrs.RigidError``
subclass, all ``ValueError``s, or ``TypeError``) whose message names the body or
field, and leaves the scene or world exactly as it was: a scene keeps its length
and still builds the bit-identical world, a world's every array is bit-identical
after the failed call (and so is its clock).

No tolerances here: "unchanged" is compared byte for byte.
"""
from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr

NAN, INF = math.nan, math.inf
DT = 0.01
VIEWS = [
    "position",
    "orientation",
    "linear_velocity",
    "angular_velocity",
    "force",
    "torque",
    "mass",
    "inverse_mass",
    "inertia",
    "inverse_inertia",
    "rotation",
    "inertia_world",
    "angular_momentum",
]

TET_V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
TET_T = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])  # outward


def message(excinfo) -> str:
    """The message and any notes (pyo3 names a bad argument in a note)."""
    e = excinfo.value
    return " ".join([str(e), *getattr(e, "__notes__", [])])


def check_raises(call, exc, words):
    assert issubclass(exc, (ValueError, TypeError))
    with pytest.raises(exc) as excinfo:
        call()
    text = message(excinfo)
    for w in words:
        assert w in text, f"{w!r} not in {text!r}"
    return excinfo.value


def base_scene():
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    scene.add_body(rr.Sphere(0.1), density=1000.0, position=(0.0, 0.0, 1.0), linear_velocity=(1.0, 0.0, 0.0))
    scene.add_body(rr.Box((0.1, 0.2, 0.3)), mass=2.0, angular_velocity=(0.1, 2.0, 0.3))
    scene.add_body(rr.Plane(), fixed=True)
    return scene


def snapshot(world):
    """Every array of the world as bytes, and its clock."""
    state = {n: getattr(world.bodies, n).tobytes() for n in VIEWS}
    state["clock"] = (world.time, world.steps)
    return state


REFERENCE = snapshot(base_scene().build(dt=DT))


def assert_scene_unchanged(scene):
    assert len(scene) == 3
    assert snapshot(scene.build(dt=DT)) == REFERENCE
    # The next body still gets the next index: no half-added body is left behind.
    assert scene.add_body(rr.Sphere(0.2), mass=1.0) == 3


# ---------------------------------------------------------------------------
# Scene.add_body
# ---------------------------------------------------------------------------

SPHERE = rr.Sphere(0.1)
R_TILT = Rotation.from_rotvec([0.4, -0.3, 0.9]).as_matrix()

ADD_BODY = {
    # mass and density: zero, negative, NaN, ±inf
    **{f"mass={v}": (dict(shape=SPHERE, mass=v), rr.RigidError, ["body 3", "mass"]) for v in (0.0, -1.0, NAN, INF)},
    **{f"density={v}": (dict(shape=SPHERE, density=v), rr.RigidError, ["body 3", "density"]) for v in (0.0, -2.0, NAN, INF, -INF)},
    **{
        f"mass={v} with inertia": (dict(mass=v, inertia=(1.0, 1.0, 1.0)), rr.RigidError, ["body 3", "mass"])
        for v in (0.0, -1.0, NAN, INF)
    },
    "fixed with negative density": (dict(shape=SPHERE, density=-1.0, fixed=True), rr.RigidError, ["body 3", "density"]),
    # A positive moment so small that 1/I overflows is no usable inertia either.
    "subnormal inertia": (dict(mass=1.0, inertia=(1e-320, 1e-320, 1e-320)), rr.RigidError, ["body 3", "inertia"]),
    # inertia: not symmetric, not positive definite, triangle inequality, non-finite, shape
    "inertia not symmetric": (
        dict(mass=1.0, inertia=[[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        rr.RigidError,
        ["body 3", "inertia", "symmetric"],
    ),
    "inertia negative moment": (dict(mass=1.0, inertia=(1.0, 1.0, -1.0)), rr.RigidError, ["body 3", "inertia", "positive definite"]),
    "inertia zero moment": (dict(mass=1.0, inertia=(1.0, 1.0, 0.0)), rr.RigidError, ["body 3", "inertia", "positive definite"]),
    "inertia indefinite tensor": (
        dict(mass=1.0, inertia=[[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),  # eigenvalues 3, -1, 1
        rr.RigidError,
        ["body 3", "inertia", "positive definite"],
    ),
    "inertia triangle (principal)": (dict(mass=1.0, inertia=(0.1, 0.1, 0.5)), rr.RigidError, ["body 3", "inertia", "triangle"]),
    "inertia triangle (just over)": (dict(mass=1.0, inertia=(1.0, 2.0, 3.001)), rr.RigidError, ["body 3", "triangle"]),
    "inertia triangle (rotated tensor)": (
        dict(mass=1.0, inertia=R_TILT @ np.diag([0.1, 0.1, 0.5]) @ R_TILT.T),
        rr.RigidError,
        ["body 3", "inertia", "triangle"],
    ),
    "inertia NaN": (dict(mass=1.0, inertia=(NAN, 1.0, 1.0)), rr.RigidError, ["body 3", "inertia", "finite"]),
    "inertia inf tensor": (dict(mass=1.0, inertia=np.diag([1.0, 1.0, INF])), rr.RigidError, ["body 3", "inertia", "finite"]),
    "inertia shape (2,)": (dict(mass=1.0, inertia=(1.0, 1.0)), ValueError, ["body 3", "inertia", "shape"]),
    "inertia shape (3, 2)": (dict(mass=1.0, inertia=np.ones((3, 2))), ValueError, ["body 3", "inertia", "shape"]),
    "inertia without mass": (dict(inertia=(1.0, 1.0, 1.0)), rr.RigidError, ["body 3", "inertia", "mass"]),
    # state: non-finite, zero quaternion, shapes, types
    **{
        f"{field}={bad}": (dict(shape=SPHERE, density=1.0, **{field: bad}), rr.RigidError, ["body 3", field, "finite"])
        for field, bad in [
            ("position", (NAN, 0.0, 0.0)),
            ("position", (0.0, INF, 0.0)),
            ("linear_velocity", (0.0, NAN, 0.0)),
            ("linear_velocity", (-INF, 0.0, 0.0)),
            ("angular_velocity", (0.0, 0.0, INF)),
            ("angular_velocity", (NAN, NAN, NAN)),
            ("orientation", (NAN, 0.0, 0.0, 1.0)),
        ]
    },
    "zero quaternion": (dict(shape=SPHERE, density=1.0, orientation=(0.0, 0.0, 0.0, 0.0)), rr.RigidError, ["body 3", "orientation"]),
    **{
        f"{field} shape {np.shape(bad)}": (dict(shape=SPHERE, density=1.0, **{field: bad}), ValueError, ["body 3", field, "shape"])
        for field, bad in [
            ("position", (0.0, 0.0)),
            ("position", [[0.0, 0.0, 0.0]]),
            ("position", 1.0),
            ("orientation", (0.0, 0.0, 1.0)),
            ("orientation", np.zeros((4, 1))),
            ("linear_velocity", (0.0, 0.0, 0.0, 0.0)),
            ("angular_velocity", ()),
        ]
    },
    "position not numeric": (dict(shape=SPHERE, density=1.0, position="abc"), TypeError, ["body 3", "position"]),
    "velocity of objects": (dict(shape=SPHERE, density=1.0, linear_velocity=[object()] * 3), TypeError, ["linear_velocity"]),
    "mass not numeric": (dict(shape=SPHERE, mass="heavy"), TypeError, ["mass"]),
    "shape not a Shape": (dict(shape="sphere", density=1.0), TypeError, ["Shape"]),
    "mass_properties not MassProperties": (dict(mass_properties=3.0), TypeError, ["MassProperties"]),
    # sources of mass
    "density and mass": (dict(shape=SPHERE, density=1.0, mass=1.0), rr.RigidError, ["body 3", "density", "mass"]),
    "mass_properties and mass": (
        dict(mass_properties=SPHERE.mass_properties(1.0), mass=1.0),
        rr.RigidError,
        ["body 3", "mass_properties"],
    ),
    "shape without mass": (dict(shape=SPHERE), rr.RigidError, ["body 3", "Sphere", "density"]),
    "nothing at all": (dict(), rr.RigidError, ["body 3", "mass"]),
    # a Plane is for fixed bodies only
    "Plane with density": (dict(shape=rr.Plane(), density=1.0), rr.RigidError, ["body 3", "Plane", "fixed"]),
    "Plane with mass": (dict(shape=rr.Plane(), mass=1.0), rr.RigidError, ["body 3", "Plane", "fixed"]),
    "Plane with mass and inertia": (dict(shape=rr.Plane(), mass=1.0, inertia=(1.0, 1.0, 1.0)), rr.RigidError, ["body 3", "Plane", "fixed"]),
    "Plane without mass": (dict(shape=rr.Plane()), rr.RigidError, ["body 3", "Plane"]),
    # regressions: a non-fixed Plane got through mass_properties= and kinematic=True (and fell)
    "Plane with mass_properties": (
        dict(shape=rr.Plane(), mass_properties=SPHERE.mass_properties(1.0)), rr.RigidError, ["body 3", "Plane", "fixed"],
    ),
    "Plane kinematic": (dict(shape=rr.Plane(), kinematic=True), rr.RigidError, ["body 3", "Plane", "fixed", "kinematic"]),
    # regressions: fixed and kinematic bodies took NaN, inf and negative inertia
    "fixed, inertia NaN": (dict(mass=1.0, inertia=(NAN, 1.0, 1.0), fixed=True), rr.RigidError, ["body 3", "inertia", "finite"]),
    "kinematic, inertia negative": (
        dict(mass=1.0, inertia=(-1.0, 1.0, 1.0), kinematic=True), rr.RigidError, ["body 3", "inertia", "positive"],
    ),
    "fixed, inertia inf": (dict(mass=1.0, inertia=(INF, 1.0, 1.0), fixed=True), rr.RigidError, ["body 3", "inertia", "finite"]),
    # regression: an overflowing mass was reported as "got 0"
    "Sphere(1e200)": (dict(shape=rr.Sphere(1e200), density=1000.0), rr.ShapeError, ["body 3", "Sphere", "overflows"]),
    # meshes that cannot carry mass, as dynamic bodies
    "open TriMesh": (dict(shape=rr.TriMesh(TET_V, TET_T[:3]), density=1.0), rr.ShapeError, ["body 3", "TriMesh", "closed"]),
    "inward TriMesh": (dict(shape=rr.TriMesh(TET_V, TET_T[:, ::-1]), density=1.0), rr.ShapeError, ["body 3", "TriMesh", "inward"]),
    "inward TriMesh with mass": (dict(shape=rr.TriMesh(TET_V, TET_T[:, ::-1]), mass=1.0), rr.ShapeError, ["body 3", "TriMesh"]),
}


@pytest.mark.parametrize("case", list(ADD_BODY), ids=list(ADD_BODY))
def test_add_body_rejects_bad_input_and_leaves_the_scene_unchanged(case):
    kwargs, exc, words = ADD_BODY[case]
    scene = base_scene()
    check_raises(lambda: scene.add_body(**kwargs), exc, words)
    assert_scene_unchanged(scene)


@pytest.mark.parametrize("kwargs", [dict(shape=SPHERE), dict(inertia=(1.0, 1.0, 1.0))], ids=["shape", "inertia"])
def test_add_body_rejects_a_subnormal_mass(kwargs):
    scene = base_scene()
    check_raises(lambda: scene.add_body(mass=1e-320, **kwargs), rr.RigidError, ["body 3", "mass"])
    assert_scene_unchanged(scene)


def test_add_body_normalises_a_huge_quaternion():
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(SPHERE, density=1.0, orientation=(1e200, 1e200, 0.0, 0.0))
    q = scene.build(dt=DT).bodies.orientation[0]
    # |q| = 1 to round-off (a few ulp: 1e-15).
    assert abs(np.linalg.norm(q) - 1.0) < 1e-15


def test_gravity_must_be_finite_and_3d():
    check_raises(lambda: rr.Scene(gravity=(0.0, 0.0, NAN)), rr.RigidError, ["gravity", "finite"])
    check_raises(lambda: rr.Scene(gravity=(0.0, -9.81)), ValueError, ["gravity", "shape"])


# ---------------------------------------------------------------------------
# Shapes and sampled mass properties
# ---------------------------------------------------------------------------

def replaced(points, index, value):
    """A copy of ``points`` with one coordinate changed."""
    out = np.array(points, dtype=float)
    out[index] = value
    return out


SQUARE = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.5, 0.5, 0.0]]
SHAPES = {
    "Sphere radius -1": (lambda: rr.Sphere(-1.0), rr.RigidError, ["Sphere radius"]),
    "Sphere radius NaN": (lambda: rr.Sphere(NAN), rr.RigidError, ["Sphere radius"]),
    "Box zero extent": (lambda: rr.Box((1.0, 0.0, 1.0)), rr.RigidError, ["Box half_extents.y"]),
    "Box inf extent": (lambda: rr.Box((1.0, 1.0, INF)), rr.RigidError, ["Box half_extents.z"]),
    "Box shape (2,)": (lambda: rr.Box((1.0, 1.0)), ValueError, ["Box half_extents", "shape"]),
    "Capsule NaN half_height": (lambda: rr.Capsule(0.1, NAN), rr.RigidError, ["Capsule half_height"]),
    "Cylinder zero radius": (lambda: rr.Cylinder(0.0, 1.0), rr.RigidError, ["Cylinder radius"]),
    "Cone negative half_height": (lambda: rr.Cone(1.0, -1.0), rr.RigidError, ["Cone half_height"]),
    "Plane zero normal": (lambda: rr.Plane(normal=(0.0, 0.0, 0.0)), rr.ShapeError, ["Plane normal"]),
    "Plane NaN normal": (lambda: rr.Plane(normal=(0.0, NAN, 1.0)), rr.RigidError, ["Plane normal"]),
    "Plane NaN offset": (lambda: rr.Plane(offset=NAN), rr.RigidError, ["Plane offset"]),
    # ConvexHull: degenerate point sets
    "ConvexHull coplanar": (lambda: rr.ConvexHull(SQUARE), rr.ShapeError, ["ConvexHull", "coplanar"]),
    "ConvexHull collinear": (lambda: rr.ConvexHull([[t, 2 * t, -t] for t in range(6)]), rr.ShapeError, ["ConvexHull", "collinear"]),
    "ConvexHull coincident": (lambda: rr.ConvexHull([[1.0, 2.0, 3.0]] * 5), rr.ShapeError, ["ConvexHull", "coincident"]),
    "ConvexHull coplanar to 1e-12": (
        lambda: rr.ConvexHull(replaced(SQUARE, (0, 2), 1e-12)),
        rr.ShapeError,
        ["ConvexHull", "coplanar"],
    ),
    "ConvexHull 3 points": (lambda: rr.ConvexHull(TET_V[:3]), rr.ShapeError, ["ConvexHull", "4 points", "got 3"]),
    "ConvexHull no points": (lambda: rr.ConvexHull(np.zeros((0, 3))), rr.ShapeError, ["ConvexHull", "4 points", "got 0"]),
    "ConvexHull NaN": (lambda: rr.ConvexHull(np.vstack([TET_V, [[NAN, 0.0, 0.0]]])), rr.RigidError, ["ConvexHull points[4]", "finite"]),
    "ConvexHull inf": (lambda: rr.ConvexHull(np.vstack([[[0.0, INF, 0.0]], TET_V])), rr.RigidError, ["ConvexHull points[0]", "finite"]),
    "ConvexHull shape (4, 2)": (lambda: rr.ConvexHull(TET_V[:, :2]), ValueError, ["ConvexHull points", "shape"]),
    "ConvexHull not numeric": (lambda: rr.ConvexHull("points"), (TypeError, ValueError), ["ConvexHull points"]),
    # TriMesh: indices and vertices
    "TriMesh index out of range": (
        lambda: rr.TriMesh(TET_V, np.vstack([TET_T[:3], [[1, 2, 4]]])),
        rr.RigidError,
        ["TriMesh triangles[3]", "index 4", "4 vertices"],
    ),
    "TriMesh negative index": (lambda: rr.TriMesh(TET_V, np.vstack([TET_T[:3], [[1, 2, -1]]])), ValueError, ["TriMesh triangles[3]"]),
    "TriMesh fractional index": (lambda: rr.TriMesh(TET_V, [[0, 2, 1], [0, 1, 3.5]]), ValueError, ["TriMesh triangles[1]"]),
    "TriMesh repeated vertex": (lambda: rr.TriMesh(TET_V, np.vstack([TET_T[:3], [[1, 1, 3]]])), rr.ShapeError, ["TriMesh triangles[3]", "repeats"]),
    "TriMesh NaN vertex": (lambda: rr.TriMesh(replaced(TET_V, (3, 2), NAN), TET_T), rr.RigidError, ["TriMesh vertices[3]", "finite"]),
    "TriMesh no triangles": (lambda: rr.TriMesh(TET_V, np.zeros((0, 3))), rr.ShapeError, ["TriMesh", "triangle"]),
    # Closed and consistently oriented, but three of its vertices are collinear: the
    # triangle through them has no area.
    "TriMesh zero-area triangle": (
        lambda: rr.TriMesh(np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 0, 1.0]]), TET_T),
        rr.ShapeError,
        ["TriMesh triangles[", "no area"],
    ),
    "TriMesh triangles shape": (lambda: rr.TriMesh(TET_V, TET_T[:, :2]), ValueError, ["TriMesh triangles", "shape"]),
    "TriMesh vertices shape": (lambda: rr.TriMesh(TET_V[:, :2], TET_T), ValueError, ["TriMesh vertices", "shape"]),
}


@pytest.mark.parametrize("case", list(SHAPES), ids=list(SHAPES))
def test_bad_shapes_are_rejected_when_made(case):
    make, exc, words = SHAPES[case]
    excs = exc if isinstance(exc, tuple) else (exc,)
    with pytest.raises(excs) as excinfo:
        make()
    assert isinstance(excinfo.value, (ValueError, TypeError))
    text = message(excinfo)
    for w in words:
        assert w in text, f"{w!r} not in {text!r}"


NO_MASS = {
    "open TriMesh": (rr.TriMesh(TET_V, TET_T[:3]), rr.ShapeError, ["TriMesh", "closed"]),
    "inward TriMesh": (rr.TriMesh(TET_V, TET_T[:, ::-1]), rr.ShapeError, ["TriMesh", "inward"]),
    "double-sided flat TriMesh": (rr.TriMesh(TET_V[:3], [[0, 1, 2], [0, 2, 1]]), rr.ShapeError, ["TriMesh", "flat"]),
    # Every triangle used twice the same way: not a consistently oriented surface.
    "TriMesh with a duplicated face": (rr.TriMesh(TET_V, np.vstack([TET_T, TET_T[:1]])), rr.ShapeError, ["TriMesh", "closed"]),
    "Plane": (rr.Plane(), rr.RigidError, ["Plane", "fixed"]),
}


@pytest.mark.parametrize("case", list(NO_MASS), ids=list(NO_MASS))
def test_shapes_without_volume_refuse_mass_properties(case):
    shape, exc, words = NO_MASS[case]
    check_raises(lambda: shape.mass_properties(1.0), exc, words)
    check_raises(shape.volume, exc, words)


def test_open_mesh_is_fine_as_a_fixed_body():
    # The open-mesh rule is about carrying mass: a fixed terrain needs none.
    scene = base_scene()
    assert scene.add_body(rr.TriMesh(TET_V, TET_T[:3]), fixed=True) == 3


@pytest.mark.parametrize("density", [0.0, -1.0, NAN, INF])
def test_shape_mass_properties_rejects_bad_density(density):
    check_raises(lambda: rr.Box((1.0, 1.0, 1.0)).mass_properties(density), rr.RigidError, ["density"])


PTS = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
SAMPLED = {
    "volumes length": ((PTS, np.ones(3), 1.0), ValueError, ["volumes", "shape"]),
    "densities length": ((PTS, 1.0, np.ones(5)), ValueError, ["densities", "shape"]),
    "points shape": ((PTS[:, :2], 1.0, 1.0), ValueError, ["points", "shape"]),
    "no points": ((np.zeros((0, 3)), 1.0, 1.0), rr.RigidError, ["points", "empty"]),
    "negative volume": ((PTS, [1.0, 1.0, -1.0, 1.0], 1.0), rr.RigidError, ["volumes[2]"]),
    "inf volume": ((PTS, INF, 1.0), rr.RigidError, ["volumes[0]"]),
    "NaN density": ((PTS, 1.0, [1.0, NAN, 1.0, 1.0]), rr.RigidError, ["densities[1]"]),
    "negative density": ((PTS, 1.0, [1.0, 1.0, 1.0, -5.0]), rr.RigidError, ["densities[3]"]),
    "NaN point": ((np.vstack([PTS, [[0.0, NAN, 0.0]]]), 1.0, 1.0), rr.RigidError, ["points[4]"]),
    "zero total mass": ((PTS, 1.0, 0.0), rr.RigidError, ["total mass"]),
    "mass overflows": ((PTS, 1e308, 10.0), rr.RigidError, ["total mass"]),
    "collinear samples": (([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]], 1.0, 1.0), rr.RigidError, ["collinear"]),
    "single point": ((PTS[:1], 1.0, 1.0), rr.RigidError, ["single point"]),
}


@pytest.mark.parametrize("case", list(SAMPLED), ids=list(SAMPLED))
def test_sampled_mass_properties_reject_bad_samples(case):
    args, exc, words = SAMPLED[case]
    check_raises(lambda: rr.mass_properties(*args), exc, words)


# ---------------------------------------------------------------------------
# Scene.build
# ---------------------------------------------------------------------------

BUILD = {
    **{f"dt={dt}": (dict(dt=dt), rr.RigidError, ["dt"]) for dt in (0.0, -0.01, NAN, INF, -INF)},
    "unknown integrator": (dict(dt=DT, integrator="verlet"), rr.RigidError, ["integrator", "verlet", "strang", "rk4"]),
    "integrator wrong case": (dict(dt=DT, integrator="Strang"), rr.RigidError, ["integrator", "Strang"]),
    "integrator empty": (dict(dt=DT, integrator=""), rr.RigidError, ["integrator"]),
    "integrator not a string": (dict(dt=DT, integrator=4), TypeError, ["integrator"]),
    "dt not a number": (dict(dt="fast"), TypeError, ["dt"]),
    "zero substeps": (dict(dt=DT, substeps=0), rr.RigidError, ["substeps"]),
    **{f"max_rotation_angle={a}": (dict(dt=DT, max_rotation_angle=a), rr.RigidError, ["max_rotation_angle"])
       for a in (0.0, -0.1, NAN, -INF)},
    "max_rotation_angle not a number": (dict(dt=DT, max_rotation_angle="small"), TypeError, ["max_rotation_angle"]),
}


@pytest.mark.parametrize("case", list(BUILD), ids=list(BUILD))
def test_build_rejects_bad_settings_and_leaves_the_scene_unchanged(case):
    kwargs, exc, words = BUILD[case]
    scene = base_scene()
    check_raises(lambda: scene.build(**kwargs), exc, words)
    assert_scene_unchanged(scene)


def test_negative_substeps_raise_a_value_error():
    check_raises(lambda: base_scene().build(dt=DT, substeps=-1), ValueError, ["substeps"])


# ---------------------------------------------------------------------------
# World: apply_force / apply_torque / step
# ---------------------------------------------------------------------------


def stepped_world():
    world = base_scene().build(dt=DT)
    world.step(3)
    return world


WORLD_CALLS = {
    "apply_force out of range": (lambda w: w.apply_force(3, (1.0, 0.0, 0.0)), rr.RigidError, ["body index 3", "out of range", "3 bodies"]),
    "apply_force far out of range": (lambda w: w.apply_force(10**6, (1.0, 0.0, 0.0)), rr.RigidError, ["body index 1000000"]),
    "apply_force fixed body": (lambda w: w.apply_force(2, (1.0, 0.0, 0.0)), rr.RigidError, ["body 2", "fixed"]),
    "apply_force fixed body at a point": (
        lambda w: w.apply_force(2, (1.0, 0.0, 0.0), point=(0.0, 0.0, 1.0)),
        rr.RigidError,
        ["body 2", "fixed"],
    ),
    "apply_force NaN": (lambda w: w.apply_force(0, (NAN, 0.0, 0.0)), rr.RigidError, ["body 0", "force", "finite"]),
    "apply_force NaN point": (lambda w: w.apply_force(1, (1.0, 0.0, 0.0), point=(0.0, INF, 0.0)), rr.RigidError, ["body 1", "point"]),
    "apply_force shape": (lambda w: w.apply_force(0, (1.0, 0.0)), ValueError, ["force", "shape"]),
    "apply_force point shape": (lambda w: w.apply_force(0, (1.0, 0.0, 0.0), point=(1.0,)), ValueError, ["point", "shape"]),
    "apply_force index not int": (lambda w: w.apply_force(0.5, (1.0, 0.0, 0.0)), TypeError, ["body"]),
    "apply_torque out of range": (lambda w: w.apply_torque(7, (0.0, 0.0, 1.0)), rr.RigidError, ["body index 7", "out of range"]),
    "apply_torque fixed body": (lambda w: w.apply_torque(2, (0.0, 0.0, 1.0)), rr.RigidError, ["body 2", "fixed"]),
    "apply_torque inf": (lambda w: w.apply_torque(1, (0.0, -INF, 0.0)), rr.RigidError, ["body 1", "torque"]),
    "step not an int": (lambda w: w.step(1.5), TypeError, ["n"]),
}


@pytest.mark.parametrize("case", list(WORLD_CALLS), ids=list(WORLD_CALLS))
def test_world_calls_reject_bad_input_and_leave_the_world_unchanged(case):
    call, exc, words = WORLD_CALLS[case]
    world = stepped_world()
    before = snapshot(world)
    stages = world.stages
    check_raises(lambda: call(world), exc, words)
    assert snapshot(world) == before
    assert world.stages == stages  # in particular no "forces" stage from a refused force


@pytest.mark.parametrize("call", ["apply_force", "apply_torque"])
def test_negative_body_index_raises_a_value_error(call):
    world = stepped_world()
    before = snapshot(world)
    check_raises(lambda: getattr(world, call)(-1, (1.0, 0.0, 0.0)), ValueError, ["body"])
    assert snapshot(world) == before


def test_negative_step_count_raises_a_value_error():
    world = stepped_world()
    check_raises(lambda: world.step(-1), ValueError, ["n"])


# ---------------------------------------------------------------------------
# Invalid state written through views: caught by the next step, nothing moves
# ---------------------------------------------------------------------------

BAD_STATE = {
    "NaN position": ("position", 1, [NAN, 0.0, 0.0], ["body 1", "position"]),
    "inf position": ("position", 0, [0.0, 0.0, INF], ["body 0", "position"]),
    "NaN position of a fixed body": ("position", 2, [NAN, NAN, NAN], ["body 2", "position"]),
    "NaN linear_velocity": ("linear_velocity", 0, [0.0, NAN, 0.0], ["body 0", "linear_velocity"]),
    "inf angular_velocity": ("angular_velocity", 1, [0.0, -INF, 0.0], ["body 1", "angular_velocity"]),
    "NaN force": ("force", 1, [0.0, 0.0, NAN], ["body 1", "force"]),
    "inf torque": ("torque", 0, [INF, 0.0, 0.0], ["body 0", "torque"]),
    "quaternion of norm 0.5": ("orientation", 1, [0.0, 0.0, 0.0, 0.5], ["body 1", "orientation", "unit", "0.5"]),
    "quaternion of norm 2": ("orientation", 0, [0.0, 2.0 ** 0.5, 0.0, 2.0 ** 0.5], ["body 0", "orientation", "unit"]),
    "zero quaternion": ("orientation", 1, [0.0, 0.0, 0.0, 0.0], ["body 1", "orientation"]),
    "NaN quaternion": ("orientation", 1, [NAN, 0.0, 0.0, 1.0], ["body 1", "orientation"]),
    "quaternion off by 1e-5": ("orientation", 1, [0.0, 0.0, 0.0, 1.0 + 1e-5], ["body 1", "orientation"]),
}


@pytest.mark.parametrize("case", list(BAD_STATE), ids=list(BAD_STATE))
def test_invalid_state_is_caught_at_the_next_step_before_anything_moves(case):
    field, body, value, words = BAD_STATE[case]
    world, twin = stepped_world(), stepped_world()
    view = getattr(world.bodies, field)
    good = view[body].copy()
    view[body] = value
    before = snapshot(world)
    check_raises(lambda: world.step(5), rr.StateError, words)
    # Nothing integrated: not the bad body, not the others, not the clock.
    assert snapshot(world) == before
    # Repaired, the world steps exactly as one that was never broken.
    view[body] = good
    world.step(5)
    twin.step(5)
    assert snapshot(world) == snapshot(twin)


def test_quaternion_round_off_is_not_an_error():
    world, twin = stepped_world(), stepped_world()
    q = world.bodies.orientation
    q[1] *= 1.0 + 1e-9  # well inside the documented 1e-6 tolerance
    world.step(2)
    twin.step(2)
    # Normalised away: |q| = 1 to a few ulp, and the motion matches the untouched twin
    # to the size of the perturbation (1e-9).
    assert abs(np.linalg.norm(q[1]) - 1.0) < 4e-16
    np.testing.assert_allclose(q, twin.bodies.orientation, rtol=0, atol=1e-8)


# ---------------------------------------------------------------------------
# Regression: a valid Plane normal of huge components
# ---------------------------------------------------------------------------


def test_plane_normal_with_huge_components_is_normalised():
    """Regression: |n|² overflowed to inf and the stored normal became (0, 0, 0)."""
    text = repr(rr.Plane(normal=(1e300, 1e300, 0.0), offset=1.0))
    normal = [float(x) for x in re.search(r"normal=\[([^\]]*)\]", text).group(1).split(",")]
    # (1, 1, 0)/√2 to round-off (1 ulp of 0.7 is 1.1e-16).
    np.testing.assert_allclose(normal, [0.5**0.5, 0.5**0.5, 0.0], rtol=0, atol=4e-16)
