"""Nothing lost when a step fails or is interrupted: a step that leaves a body or
particle not finite is undone (the world bitwise as before it, time included),
raises ``SimulationError`` naming the body or particle, the stage and the time,
and the world steps on; Ctrl-C stops ``step(n)`` at a step boundary; ``len`` of
the views while another thread steps raises instead of panicking."""
from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import rigidrs as rr
from snapshot_scenes import assert_same, cloth, pile, state


def runaway(world: rr.World, body: int) -> None:
    """Sends ``body`` off at 1.75e308 m/s, pushed on by a force that takes its
    velocity past the largest double (1.8e308) some twenty steps later."""
    world.bodies.linear_velocity[body] = (1.75e308, 0, 0)
    world.apply_force(body, (world.bodies.mass[body] * 3e307, 0, 0))


def test_body_blow_up_within_a_call_is_undone_and_named() -> None:
    world, twin = pile(rocket=True), pile(rocket=True)
    world.step(30)
    runaway(world, 61)
    with pytest.raises(rr.SimulationError) as info:
        world.step(50)
    message = str(info.value)
    done = world.steps
    assert 31 < done < 80  # within the call, some steps after its start
    assert f"the step from t = {world.time:.6f} s diverged in stage" in message
    assert "body 61: linear_velocity is not finite" in message
    assert f"back at t = {world.time:.6f} s" in message
    # Exactly as before the failing step: a twin stepped as far agrees bitwise.
    twin.step(30)
    runaway(twin, 61)
    twin.step(done - 30)
    assert_same(state(world), state(twin))
    # And it steps on (here without the force) as the twin does.
    for w in (world, twin):
        w.clear_forces()
        w.bodies.linear_velocity[61] = 0.0
        w.step(20)
    assert_same(state(world), state(twin))
    assert isinstance(info.value, RuntimeError) and isinstance(info.value, rr.StateError)


def test_blow_up_in_contact_is_undone_and_named() -> None:
    world = pile()
    world.step(30)
    runaway(world, 5)
    before = state(world)
    with pytest.raises(rr.SimulationError, match="diverged in stage 'contact_solve': body 5: linear_velocity is not finite"):
        world.step(50)
    assert_same(state(world), before)
    world.bodies.linear_velocity[5] = 0.0
    world.clear_forces()
    world.step(10)
    assert world.steps == 40


def test_particle_blow_up_is_undone_and_named() -> None:
    world = cloth()
    world.step(10)
    world.particles.velocity[7] = (0, 0, 1e308)
    before = state(world)
    with pytest.raises(rr.SimulationError, match=r"diverged in stage 'xpbd': particle [0-9]+: (position|velocity) is not finite"):
        world.step(5)
    assert_same(state(world), before)
    world.particles.velocity[7] = 0.0
    world.step(5)
    assert world.steps == 15 and np.isfinite(world.particles.position).all()


def test_failure_after_a_checkpoint_and_many_calls_with_writes_is_undone_exactly() -> None:
    """The undo replays from a checkpoint through calls whose inputs the user
    changed in between (velocities written, forces applied): still bitwise."""
    world, twin = pile(rocket=True), pile(rocket=True)
    for w in (world, twin):
        for k in range(300):
            w.bodies.linear_velocity[1 + k % 60, 2] += 0.01
            w.step(1 + k % 3)
    before = state(world)
    runaway(world, 61)
    with pytest.raises(rr.SimulationError, match="body 61"):
        world.step(100)
    runaway(twin, 61)
    twin.step(world.steps - int(before["steps"][0]))
    assert_same(state(world), state(twin))


SIGINT_SCRIPT = """
import sys, time
import signal
# Ctrl-C raises KeyboardInterrupt as in a terminal, whatever the parent left
# (Python keeps SIGINT ignored if it starts ignored, as under `nohup ... &`).
signal.signal(signal.SIGINT, signal.default_int_handler)
import numpy as np
import rigidrs as rr
sys.path.insert(0, {tests!r})
from snapshot_scenes import pile, state
world = pile()
print("ready", flush=True)
try:
    world.step(10**7)
except KeyboardInterrupt:
    caught = time.monotonic()
    k = world.steps
    assert k > 0 and world.time == k * world.dt, (k, world.time)
    twin = pile()
    twin.step(k)
    same = all(np.array_equal(a, b) for a, b in zip(state(world).values(), state(twin).values()))
    print("interrupted", k, same, caught, flush=True)
    world.step(3)
    raise
"""


def test_ctrl_c_stops_a_long_step_at_a_step_boundary() -> None:
    code = SIGINT_SCRIPT.format(tests=str(Path(__file__).parent))
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout is not None and p.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode != 0 and "KeyboardInterrupt" in err, err
    words = out.split()
    assert words[0] == "interrupted" and int(words[1]) > 0 and words[2] == "True", out
    # Caught within a fraction of a second of the signal (signals are checked
    # every 20 ms; a step of this pile takes a few ms). CLOCK_MONOTONIC is
    # system-wide, so the two processes' readings compare.
    assert float(words[3]) - sent < 0.5, float(words[3]) - sent


def test_len_while_another_thread_steps_raises_instead_of_panicking() -> None:
    world = pile()
    stepping = threading.Thread(target=world.step, args=(400,))
    stepping.start()
    seen = set()
    while stepping.is_alive():
        for view in (world.bodies, world.particles, world.joints):
            try:
                seen.add(len(view))
            except RuntimeError:  # "already mutably borrowed": the step holds the world
                seen.add("busy")
        time.sleep(0.001)
    stepping.join()
    assert "busy" in seen
    assert len(world.bodies) == 61 and world.steps == 400


def test_undo_replays_particle_writes_made_between_calls() -> None:
    world, twin = cloth(), cloth()
    for w in (world, twin):
        velocity = w.particles.velocity  # one view, kept and written through
        for k in range(100):
            velocity[k % 144, 0] += 0.01
            w.step(1)
    before = state(world)
    world.particles.velocity[20] = (0, 0, 1e308)
    with pytest.raises(rr.SimulationError, match="particle"):
        world.step(5)
    before["particles.velocity"][20] = (0, 0, 1e308)
    assert_same(state(world), before)
    twin.particles.velocity[20] = (0, 0, 1e308)
    assert_same(state(world), state(twin))
