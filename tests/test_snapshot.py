"""Snapshots: stepping on from a restored snapshot is bitwise what never stopping
gives, on every kind of scene; copies are independent; a snapshot of another
layout is refused."""
from __future__ import annotations

import copy

import numpy as np
import pytest

import rigidrs as rr
from snapshot_scenes import SCENES, assert_same, state

BEFORE, AFTER = 60, 60


def reference(name: str) -> dict[str, np.ndarray]:
    world = SCENES[name]()
    world.step(BEFORE)
    world.step(AFTER)
    return state(world)


@pytest.fixture(scope="module")
def references() -> dict[str, dict[str, np.ndarray]]:
    return {name: reference(name) for name in SCENES}


@pytest.mark.parametrize("name", list(SCENES))
def test_restore_in_process_is_bitwise(name: str, references: dict[str, dict[str, np.ndarray]]) -> None:
    world = SCENES[name]()
    world.step(BEFORE)
    snap = world.snapshot()
    at = state(world)
    world.step(AFTER)
    assert_same(state(world), references[name])
    # Views taken before the restore stay valid and show the restored state.
    position = world.bodies.position
    world.restore(snap)
    assert_same(state(world), at)
    assert np.array_equal(position, at["bodies.position"])
    world.step(AFTER)
    assert_same(state(world), references[name])


@pytest.mark.parametrize("name", list(SCENES))
def test_copies_step_on_bitwise_and_independently(name: str, references: dict[str, dict[str, np.ndarray]]) -> None:
    world = SCENES[name]()
    world.step(BEFORE)
    twins = [copy.deepcopy(world), copy.copy(world)]
    world.bodies.linear_velocity[:] += 1.0  # the copies do not see it
    for twin in twins:
        twin.step(AFTER)
        assert_same(state(twin), references[name])


def test_a_snapshot_restores_many_times() -> None:
    world = SCENES["pyramid"]()
    world.step(30)
    snap = world.snapshot()
    assert snap.time == world.time and snap.steps == 30
    runs = []
    for _ in range(3):
        world.restore(snap)
        world.step(20)
        runs.append(state(world))
    assert_same(runs[0], runs[1])
    assert_same(runs[0], runs[2])


def test_restore_refuses_another_layout_and_changes_nothing() -> None:
    world = SCENES["pyramid"]()
    other = SCENES["sleeping"]()
    world.step(5)
    before = state(world)
    with pytest.raises(rr.RigidError, match="snapshot has 8 bodies.*this world 37"):
        world.restore(other.snapshot())
    assert_same(state(world), before)
