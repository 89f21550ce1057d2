"""Snapshots: stepping on from a restored snapshot is bitwise what never stopping
gives, on every kind of scene; copies are independent; a snapshot of another
layout is refused."""
from __future__ import annotations

import copy
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import rigidrs as rr
from snapshot_scenes import G, SCENES, assert_same, state

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
    # Views taken before the restore stay valid and show the restored state
    # (the restore copies into the arrays they view).
    views = {"bodies.position": world.bodies.position, "bodies.angular_velocity": world.bodies.angular_velocity,
             "particles.position": world.particles.position, "particles.velocity": world.particles.velocity,
             "joints.position": world.joints.position, "joints.velocity": world.joints.velocity}
    world.restore(snap)
    assert_same(state(world), at)
    for key, view in views.items():
        assert np.array_equal(view, at[key], equal_nan=True), key
        assert view.size == 0 or np.shares_memory(view, state_view(world, key)), key
    world.step(AFTER)
    assert_same(state(world), references[name])


def state_view(world: rr.World, key: str) -> np.ndarray:
    """The view `key` ("bodies.position", ...) of `world`, taken now."""
    group, field = key.split(".")
    return getattr(getattr(world, group), field)


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
    # Stage timings are the world object's, not state: they carry on.
    assert world.profile()["steps"] == 30 + 3 * 20


def test_restore_refuses_another_layout_and_changes_nothing() -> None:
    world = SCENES["pyramid"]()
    other = SCENES["sleeping"]()
    world.step(5)
    before = state(world)
    with pytest.raises(rr.RigidError, match="snapshot has 8 bodies.*this world 37"):
        world.restore(other.snapshot())
    assert_same(state(world), before)


# --- bytes, pickle, files --------------------------------------------------------


@pytest.mark.parametrize("name", list(SCENES))
def test_restore_from_bytes_and_pickle_is_bitwise(name: str, references: dict[str, dict[str, np.ndarray]]) -> None:
    world = SCENES[name]()
    world.step(BEFORE)
    data = world.snapshot().to_bytes()
    pickled = pickle.dumps(world)
    world.step(3)  # whatever happens after the snapshot is undone by the restore
    world.restore(rr.Snapshot.from_bytes(data))
    world.step(AFTER)
    assert_same(state(world), references[name])
    thawed = pickle.loads(pickled)
    thawed.step(AFTER)
    assert_same(state(thawed), references[name])
    # (Re-encoded bytes may differ from `data` for meshes: parry's workspaces
    # are hash maps, written in their order. What they decode to steps the same.)
    world.restore(pickle.loads(pickle.dumps(rr.Snapshot.from_bytes(data))))
    world.step(AFTER)
    assert_same(state(world), references[name])


SUBPROCESS = """
import sys
import numpy as np
import rigidrs as rr
sys.path.insert(0, {tests!r})
from snapshot_scenes import state
world = rr.load({path!r})
world.step({after})
np.savez({out!r}, **state(world))
"""


@pytest.mark.parametrize("name", list(SCENES))
def test_saved_file_steps_on_bitwise_in_another_process(name: str, tmp_path: Path, references: dict[str, dict[str, np.ndarray]]) -> None:
    world = SCENES[name]()
    world.step(BEFORE)
    path, out = tmp_path / "run.rrw", tmp_path / "out.npz"
    world.save(path)
    assert [p.name for p in tmp_path.iterdir()] == ["run.rrw"]  # no temporary left
    code = SUBPROCESS.format(tests=str(Path(__file__).parent), path=str(path), after=AFTER, out=str(out))
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
    with np.load(out) as got:
        assert_same({k: got[k] for k in got.files}, references[name])


def test_save_takes_a_str_and_overwrites(tmp_path: Path) -> None:
    world = SCENES["sleeping"]()
    path = str(tmp_path / "run.rrw")
    world.save(path)
    world.step(10)
    world.save(path)
    assert rr.load(path).steps == 10


def test_scene_pickles_and_copies_to_an_equal_scene() -> None:
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(normal=(0.1, 0, 1)), fixed=True)
    scene.add_body(rr.Compound([(rr.Sphere(0.1), (0, 0, 0.2)), (rr.Box((0.1, 0.1, 0.1)), (0, 0, -0.2))]), mass=2.0, position=(0, 0, 1))
    scene.add_cloth((0, 0, 2), (1, 0, 0), (0, 1, 0), (4, 4), mass=0.1)
    worlds = [s.build(dt=1 / 60) for s in (scene, pickle.loads(pickle.dumps(scene)), copy.deepcopy(scene), copy.copy(scene))]
    for w in worlds:
        w.step(30)
    for w in worlds[1:]:
        assert_same(state(w), state(worlds[0]))


# --- data that is not a snapshot ---------------------------------------------------


@pytest.fixture(scope="module")
def data() -> bytes:
    world = SCENES["sleeping"]()
    world.step(5)
    return world.snapshot().to_bytes()


@pytest.mark.parametrize("cut", [0, 3, 8, 14, 20, 30, 40, -1, -1000])
def test_truncated_data_is_refused(data: bytes, cut: int) -> None:
    with pytest.raises(ValueError, match="truncated|not a rigidrs"):
        rr.Snapshot.from_bytes(data[:cut])


def test_corrupted_data_is_refused(data: bytes) -> None:
    rng = np.random.default_rng(0)
    for k in [*range(0, 64), *rng.integers(64, len(data), 200)]:
        bad = bytearray(data)
        bad[k] ^= 1 << int(rng.integers(8))
        with pytest.raises(ValueError):
            rr.Snapshot.from_bytes(bytes(bad))
    with pytest.raises(ValueError, match="corrupted: its checksum"):
        rr.Snapshot.from_bytes(data[:-10] + bytes(10))
    with pytest.raises(ValueError, match="bytes after its end"):
        rr.Snapshot.from_bytes(data + b"\0")


def test_foreign_data_and_other_versions_are_refused(data: bytes) -> None:
    with pytest.raises(ValueError, match=r'not a rigidrs world snapshot: the data starts with b"PK\\x03\\x04 som", not b"RIGIDRS\\x00"'):
        rr.Snapshot.from_bytes(b"PK\x03\x04 some zip file")
    scene = pickle.dumps(rr.Scene())
    with pytest.raises(ValueError, match="another kind"):
        rr.Snapshot.from_bytes(data[:8] + b"SCEN" + data[12:])
    ours = int.from_bytes(data[12:16], "little")
    newer = data[:12] + (99).to_bytes(4, "little") + data[16:]
    with pytest.raises(ValueError, match=rf"format 99\); this is rigidrs .* \(format {ours}\)"):
        rr.Snapshot.from_bytes(newer)
    other = data.replace(rr.__version__.encode(), b"9.9.9", 1)
    with pytest.raises(ValueError, match="written by rigidrs 9.9.9"):
        rr.Snapshot.from_bytes(other)
    assert scene  # a scene's bytes are framed the same way, as another kind


def test_load_names_a_missing_or_bad_file(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="nowhere.rrw"):
        rr.load(tmp_path / "nowhere.rrw")
    (tmp_path / "notes.txt").write_text("hello")
    with pytest.raises(ValueError, match="notes.txt: not a rigidrs world snapshot"):
        rr.load(tmp_path / "notes.txt")
    with pytest.raises(IsADirectoryError):
        rr.load(tmp_path)


@pytest.mark.parametrize("name", list(SCENES))
def test_step_n_is_n_single_steps(name: str, references: dict[str, dict[str, np.ndarray]]) -> None:
    """What the README states: stepping in calls of any size gives the same bits
    (a Ctrl-C or a failure that stops a call part way loses nothing)."""
    world = SCENES[name]()
    for n in (1, 7, 1, 0, 51, 60):
        world.step(n)
    assert_same(state(world), references[name])
