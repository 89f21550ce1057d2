"""A fixed mesh collides on one side: a body starting behind it is warned of.

parry's oriented meshes (the internal-edge fix needs the orientation) give a
contact only on a triangle's front, the side it runs counter-clockwise from. A
floor mesh whose triangles face down let a ball and a box fall through it (19 m
in 2 s) without a word, and so did a bowl of that winding; `Scene.build` now
warns, naming the body and the mesh, and says how to turn the mesh round. What
is checked: the warning where a body's centre lies behind a triangle of a fixed
mesh it can touch, none where it lies in front, beside the mesh or is filtered
out, and the pass-through it warns of (free fall, `g t² / 2` to round-off).
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import rigidrs as rr

G, DT = 9.81, 1 / 60


def floor(facing_up: bool = True) -> rr.TriMesh:
    """A 4 m square of 32 triangles in z = 0."""
    xs = np.linspace(-2.0, 2.0, 5)
    vertices = np.array([[x, y, 0.0] for y in xs for x in xs])
    faces = np.array([f for j in range(4) for i in range(4)
                      for a in [j * 5 + i] for f in ([a, a + 1, a + 6], [a, a + 6, a + 5])])
    return rr.TriMesh(vertices, faces if facing_up else faces[:, ::-1])


def build(facing_up: bool, position: tuple[float, float, float], **body) -> tuple[list[str], rr.World, int]:
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(floor(facing_up), fixed=True)
    ball = scene.add_body(rr.Sphere(0.1), density=1000.0, position=position, **body)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        world = scene.build(dt=DT)
    return [str(w.message) for w in caught if issubclass(w.category, UserWarning)], world, ball


def test_a_body_behind_a_floor_facing_down_is_warned_of_and_falls_through() -> None:
    said, world, ball = build(False, (0.3, 0.2, 0.5))
    assert len(said) == 1 and "body 1 starts behind the mesh of body 0" in said[0] and "triangles[:, ::-1]" in said[0]
    world.step(60)
    t = 60 * DT
    assert world.bodies.position[ball, 2] == pytest.approx(0.5 - G * t * t / 2, abs=G * DT * t)


@pytest.mark.parametrize("case", ["in front", "beside", "filtered out"])
def test_no_warning_where_the_body_is_not_behind_a_mesh_it_can_touch(case: str) -> None:
    facing_up, position, body = {
        "in front": (True, (0.3, 0.2, 0.5), {}),
        "beside": (False, (3.0, 0.0, 0.5), {}),
        "filtered out": (False, (0.3, 0.2, 0.5), {"collision_group": 2, "collision_mask": 2}),
    }[case]
    said, world, ball = build(facing_up, position, **body)
    assert said == []
    if case == "in front":
        world.step(120)
        assert world.bodies.position[ball, 2] == pytest.approx(0.1, abs=1e-5)
