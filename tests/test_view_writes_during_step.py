"""A NaN written through a view from another thread while a step runs (the GIL is
released) is never consumed by that step (issue 10). The steps run on copies of the
view-writable arrays, set aside with the GIL held; a write made meanwhile is kept, as
if made after the call, and the next call's input check refuses it with a
`StateError` naming the body. Before, the step read it: the world "diverged" in some
stage and the engine was blamed (`SimulationError`), or a NaN force was simply used.
"""
from __future__ import annotations

import threading

import numpy as np

import rigidrs as rr


def pile() -> rr.World:
    scene = rr.Scene()
    scene.add_body(rr.Plane(), fixed=True)
    for k in range(40):
        scene.add_body(rr.Box((0.2, 0.2, 0.2)), density=500.0, position=(0.03 * (k % 7), 0.5 * (k // 7), 0.3 + 0.45 * k))
    return scene.build(dt=1 / 240)


def test_a_nan_written_through_a_view_during_a_step_is_never_consumed() -> None:
    world = pile()
    position, force = world.bodies.position, world.bodies.force  # views taken before the steps
    stop = threading.Event()
    writes = [0]

    def writer() -> None:
        while not stop.is_set():
            position[7] = np.nan
            force[9] = (np.nan, 0.0, 0.0)
            writes[0] += 1

    refused = 0
    thread = threading.Thread(target=writer)
    thread.start()
    try:
        for _ in range(60):
            try:
                world.step(5)
            except rr.SimulationError as e:  # the step would have used the NaN
                raise AssertionError(f"a NaN written during the step reached it: {e}") from e
            except rr.StateError as e:  # refused before any step, naming the body
                assert "body 7: position is not finite" in str(e) or "body 9: force is not finite" in str(e), str(e)
                refused += 1
                stop.set()
                thread.join()
                position[7] = (5.0, 5.0, 0.3)
                force[9] = (0.0, 0.0, 0.0)
                stop.clear()
                thread = threading.Thread(target=writer)
                thread.start()
    finally:
        stop.set()
        thread.join()
    assert writes[0] > 0 and refused > 0  # the writer did run, and its writes were seen
    position[7] = (5.0, 5.0, 0.3)
    force[9] = (0.0, 0.0, 0.0)
    world.step(10)
    b = world.bodies
    assert all(np.isfinite(a).all() for a in (b.position, b.linear_velocity, b.angular_velocity, b.orientation))


def test_a_write_during_a_step_is_kept_as_if_made_after_it() -> None:
    # A finite write made while the GIL is released survives the call (it is not
    # overwritten by the step's result) and is what the next call starts from.
    world = pile()
    velocity = world.bodies.linear_velocity
    started = threading.Event()
    done = threading.Event()

    def writer() -> None:
        started.wait()
        velocity[3] = (0.0, 0.0, 42.0)
        done.set()

    thread = threading.Thread(target=writer)
    thread.start()
    while not done.is_set():
        started.set()
        world.step(20)  # the writer runs while one of these calls has the GIL released
    thread.join()
    assert tuple(velocity[3]) == (0.0, 0.0, 42.0)
