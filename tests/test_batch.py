"""Batches: every copy of ``rr.Batch`` is bitwise the world ``scene.build`` makes
stepped alone, with per-copy parameters set through ``batch.set`` and states written
through the (B, N, ·) views; bad input is refused naming the copy and the body, and a
copy that diverges puts the whole batch back at the step before it."""
from __future__ import annotations

import threading

import numpy as np
import pytest

import rigidrs as rr

G = 9.81
DT = 1 / 120
FIELDS = ("position", "orientation", "linear_velocity", "angular_velocity")


def pile(mu: float = 0.5, gravity: tuple[float, float, float] = (0, 0, -G), mass: float | None = None) -> rr.Scene:
    """20 boxes and spheres dropped in two jittered layers on the ground: contacts
    from step ~10; every body (the ground too) has friction ``mu``."""
    scene = rr.Scene(gravity=gravity)
    scene.add_body(rr.Plane(), fixed=True, friction=mu)
    rng = np.random.default_rng(7)
    for k in range(20):
        x, y = 0.3 * (k % 5 - 2) + rng.uniform(-0.03, 0.03), 0.3 * (k // 5 % 2) + rng.uniform(-0.03, 0.03)
        shape = rr.Box((0.1, 0.08, 0.09)) if k % 2 else rr.Sphere(0.1)
        kw = {"mass": mass} if mass is not None else {"density": 500.0}
        scene.add_body(shape, **kw, position=(x, y, 0.15 + 0.25 * (k // 10)), linear_velocity=(0.5, 0, 0), friction=mu)
    return scene


def chain(links: int = 8) -> rr.Scene:
    """An articulated chain of spherical joints dropped across a fixed box, and
    an XPBD loop of hinged capsules: both kinds of joints, in contact."""
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True)
    scene.add_body(rr.Box((0.15, 0.15, 0.15)), fixed=True, position=(0, 0, 0.15))
    x0, prev = -links * 0.025, None
    for k in range(links):
        b = scene.add_body(rr.Box((0.025, 0.01, 0.01)), mass=0.05, position=(x0 + (k + 0.5) * 0.05, 0, 0.5))
        if prev is not None:
            scene.add_joint("spherical", b, prev, anchor=(x0 + k * 0.05, 0, 0.5), damping=2e-4)
        prev = b
    caps = [scene.add_body(rr.Capsule(0.05, 0.2), mass=1.0, position=(2 + 0.5 * k, 0, 2.0),
                           orientation=(0, 0.7071067811865476, 0, 0.7071067811865476)) for k in range(3)]
    scene.add_joint("spherical", caps[0], None, anchor=(1.75, 0, 2.0), solver="xpbd")
    for a, b in zip(caps[1:], caps[:-1]):
        scene.add_joint("hinge", a, b, anchor=(2 + 0.5 * (a - caps[0]) - 0.25, 0, 2.0), axis=(0, 1, 0), solver="xpbd")
    return scene


def bits(a: np.ndarray) -> bytes:
    return np.ascontiguousarray(a).tobytes()


def assert_copy_is(batch: rr.Batch, i: int, world: rr.World) -> None:
    """Copy ``i`` of ``batch`` and ``world`` hold the same bytes in every view."""
    for f in FIELDS:
        assert bits(getattr(batch.bodies, f)[i]) == bits(getattr(world.bodies, f)), f"copy {i}: {f}"
    assert batch.steps == world.steps


def test_contact_copies_with_their_own_friction_are_the_world_alone() -> None:
    mus = [0.1, 0.4, 0.9]
    batch = rr.Batch(pile(), copies=3, dt=DT, threads=2)
    batch.set("friction", mus)
    batch.step(30)
    batch.step(50)
    for i, mu in enumerate(mus):
        world = pile(mu).build(DT)
        world.step(30)
        world.step(50)
        assert_copy_is(batch, i, world)
    # Different friction, different motion: the copies are not one world repeated.
    assert bits(batch.bodies.position[0]) != bits(batch.bodies.position[2])


def test_jointed_copies_with_written_states_are_the_world_alone() -> None:
    scenes = [chain(), chain()]
    batch = rr.Batch(scenes, dt=1 / 60)
    spin = np.array([0.0, 0.0, 3.0])
    batch.bodies.angular_velocity[1, 12] = spin  # a capsule of copy 1 only
    batch.step(40)
    alone = [chain().build(1 / 60), chain().build(1 / 60)]
    alone[1].bodies.angular_velocity[12] = spin
    for i, world in enumerate(alone):
        world.step(40)
        assert_copy_is(batch, i, world)


def test_views_are_views_and_writes_take_effect() -> None:
    batch = rr.Batch(pile(), copies=2, dt=DT)
    p = batch.bodies.position
    assert p.shape == (2, 21, 3) and batch.bodies.orientation.shape == (2, 21, 4)
    assert np.shares_memory(p, batch.bodies.position) and p.flags.writeable
    p[1, 5, 2] += 1.0  # lift one body of copy 1 by 1 m
    batch.step(1)
    assert np.shares_memory(p, batch.bodies.position)
    world = pile().build(DT)
    world.bodies.position[5, 2] += 1.0
    world.step(1)
    assert_copy_is(batch, 1, world)
    # A copy taken out steps on as the batch's copy does.
    out = batch.world(1)
    out.step(10)
    world.step(10)
    assert bits(out.bodies.position) == bits(world.bodies.position)
    with pytest.raises(IndexError, match="copy 2 is out of range"):
        batch.world(2)


def test_gravity_and_mass_per_copy() -> None:
    """Masses set from a built 0.5 kg by powers of two, so that the scaled inertia
    is exactly what the scene computes for that mass (a scale by 2^k is exact);
    other ratios scale the inertia within an ulp of it."""
    gravities = np.array([[0, 0, -G], [0, 0, -1.62], [1.0, 0, -3.7]])
    masses = [0.25, 1.0, 2.0]
    batch = rr.Batch(pile(mass=0.5), copies=3, dt=DT)
    batch.set("gravity", gravities)
    batch.set("mass", np.array(masses))
    batch.step(40)
    for i, g in enumerate(gravities):
        world = pile(gravity=tuple(g), mass=masses[i]).build(DT)
        world.step(40)
        assert_copy_is(batch, i, world)
    scaled = rr.Batch(pile(mass=0.5), copies=1, dt=DT)
    scaled.set("mass_scale", [4.0])
    assert np.array_equal(scaled.world(0).bodies.inertia, pile(mass=2.0).build(DT).bodies.inertia)


def test_bad_parameters_are_refused_and_change_nothing() -> None:
    batch = rr.Batch(pile(), copies=2, dt=DT)
    before = bits(batch.bodies.position)
    with pytest.raises(rr.RigidError, match='unknown batch parameter "frcition".*friction.*restitution.*gravity.*mass'):
        batch.set("frcition", [0.1, 0.2])
    with pytest.raises(ValueError, match=r"friction must have shape \(2,\) or \(2, 21\)"):
        batch.set("friction", [0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match=r"gravity must have shape \(2, 3\)"):
        batch.set("gravity", [0, 0, -1])
    masses = np.ones((2, 21))
    masses[1, 7] = -1.0
    with pytest.raises(rr.RigidError, match="mass, copy 1: body 7: mass must be positive"):
        batch.set("mass", masses)
    with pytest.raises(rr.RigidError, match="copy 1.*body 4.*restitution must be in"):
        batch.set("restitution", np.where(np.arange(21) == 4, 2.0, 0.0)[None, :] * [[0], [1]])
    batch.step(20)
    world = pile().build(DT)
    world.step(20)
    assert_copy_is(batch, 1, world)
    assert before != bits(batch.bodies.position)


def test_layouts_must_agree_and_the_difference_is_named() -> None:
    other = pile()
    other.add_body(rr.Sphere(0.1), mass=1.0, position=(3, 3, 1))
    with pytest.raises(rr.RigidError, match="scene 1 has 22 bodies, scene 0 has 21"):
        rr.Batch([pile(), other, pile()], dt=DT)
    tied = pile()
    tied.add_joint("spherical", 1, 2, anchor=(0, 0, 0.2))
    with pytest.raises(rr.RigidError, match="scene 1 has 1 joints, scene 0 has 0"):
        rr.Batch([pile(), tied], dt=DT)


def test_a_bad_written_state_names_the_copy_and_nothing_moves() -> None:
    batch = rr.Batch(pile(), copies=3, dt=DT)
    batch.bodies.orientation[2, 3] = (0, 0, 0, 0)
    with pytest.raises(rr.StateError, match="copy 2: body 3"):
        batch.step(5)
    assert batch.steps == 0


def free_fall() -> rr.Scene:
    scene = rr.Scene(gravity=(0, 0, -G))
    for k in range(3):
        scene.add_body(rr.Sphere(0.1), mass=1.0, position=(k, 0, 0))
    return scene


def test_a_diverging_copy_is_named_and_the_batch_goes_back_before_its_step() -> None:
    """Copy 1's body 2 gets 1e308 m/s: its position overflows to inf after
    k = ceil(f64::MAX / (1e308 · dt)) steps, at a step count computed here; the
    batch is put back before that step, every copy at the same step count."""
    batch = rr.Batch(free_fall(), copies=3, dt=DT)
    batch.bodies.linear_velocity[1, 2, 0] = 1e308
    with pytest.raises(rr.SimulationError, match="copy 1: .*body 2") as info:
        batch.step(400)
    assert "every copy of the batch is back" in str(info.value)
    # p after k steps is k·(1e308·dt) (exact enough: the overflow step is where it
    # passes f64::MAX); the first step whose drift overflows is the one undone.
    k = int(np.floor(np.finfo(np.float64).max / (1e308 * DT)))
    assert abs(batch.steps - k) <= 1
    world = free_fall().build(DT)
    world.step(batch.steps)
    assert_copy_is(batch, 0, world)
    assert_copy_is(batch, 2, world)
    assert np.isfinite(batch.bodies.position).all()


def test_copies_far_past_the_failing_step_are_rewound_too() -> None:
    """On one thread the copies run one after another: copies 0 and 1 finish all
    2000 steps (past the guard's 1024-step checkpoint interval) before copy 2
    fails near step 220; they are still brought back to it."""
    batch = rr.Batch(free_fall(), copies=3, dt=DT, threads=1)
    batch.bodies.linear_velocity[2, 0, 0] = 1e308
    with pytest.raises(rr.SimulationError, match="copy 2: .*body 0.*every copy of the batch is back"):
        batch.step(2000)
    world = free_fall().build(DT)
    world.step(batch.steps)
    assert batch.steps < 300
    assert_copy_is(batch, 0, world)
    assert_copy_is(batch, 1, world)


SIGINT_SCRIPT = """
import sys
import signal
# Ctrl-C raises KeyboardInterrupt as in a terminal, whatever the parent left
# (Python keeps SIGINT ignored if it starts ignored, as under `nohup ... &`).
signal.signal(signal.SIGINT, signal.default_int_handler)
import threading

import numpy as np
sys.path.insert(0, {tests!r})
from test_batch import pile, DT
import rigidrs as rr
batch = rr.Batch(pile(), copies=4, dt=DT, threads=2)
print("ready", flush=True)
try:
    batch.step(10**7)
except KeyboardInterrupt:
    k = batch.steps
    world = pile().build(DT)
    world.step(k)
    same = all(np.array_equal(batch.bodies.position[i], world.bodies.position) for i in range(4))
    print("interrupted", k, same, flush=True)
    raise
"""


def test_ctrl_c_stops_every_copy_at_one_step_boundary() -> None:
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    p = subprocess.Popen([sys.executable, "-c", SIGINT_SCRIPT.format(tests=str(Path(__file__).parent))],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout is not None and p.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode != 0 and "KeyboardInterrupt" in err, err
    words = out.split()
    # Every copy at the same step, and bitwise the world stepped alone that far.
    assert words[0] == "interrupted" and int(words[1]) > 0 and words[2] == "True", out


def write_while_stepping(batch: rr.Batch, write) -> int:
    """Steps ``batch`` 200 steps a call until ``write()``, run on another thread
    (most likely while a call has the GIL released), has been made; the calls made."""
    started, done = threading.Event(), threading.Event()

    def writer() -> None:
        started.wait()
        write()
        done.set()

    thread = threading.Thread(target=writer)
    thread.start()
    calls = 0
    while not done.is_set():
        started.set()
        batch.step(200)
        calls += 1
    thread.join()
    return calls


def test_a_write_through_the_views_during_a_batch_step_is_kept_as_if_made_after_it() -> None:
    # `Batch.step` releases the GIL. A velocity written from another thread while
    # it runs survives the call (the copy back of the steps' results used to
    # overwrite it) and is what the next call starts from; every other row is
    # the steps' result.
    batch = rr.Batch(free_fall(), copies=4, dt=DT)
    velocity = batch.bodies.linear_velocity
    calls = write_while_stepping(batch, lambda: velocity.__setitem__((2, 1), (0.0, 0.0, 42.0)))
    assert tuple(velocity[2, 1]) == (0.0, 0.0, 42.0)
    # The rows nobody wrote hold the steps' result: free fall from rest, exact
    # for a constant force (v = -g t) to round-off.
    t = batch.time
    assert calls >= 1 and t == pytest.approx(200 * calls * DT)
    assert velocity[0, 0, 2] == pytest.approx(-G * t, rel=1e-9)
    batch.step(1)
    assert velocity[2, 1, 2] == pytest.approx(42.0 - G * DT, rel=1e-9)


def test_a_nan_written_during_a_batch_step_is_refused_by_the_next_naming_the_copy() -> None:
    batch = rr.Batch(free_fall(), copies=3, dt=DT)
    position = batch.bodies.position
    write_while_stepping(batch, lambda: position.__setitem__((1, 2), np.nan))
    steps = batch.steps
    with pytest.raises(rr.StateError, match="copy 1: body 2"):
        batch.step(5)
    assert batch.steps == steps
