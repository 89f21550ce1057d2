"""Runs for the sweep tests, importable by the worker processes (spawned
children import this module by name to unpickle ``slide``)."""
from __future__ import annotations

import rigidrs as rr

G = 9.81
V0 = 2.0
DT = 1 / 240


def slide(mu: float) -> float:
    """How far a box launched at V0 m/s along the ground slides with friction
    ``mu`` (box and ground alike) before it stops (m)."""
    scene = rr.Scene(gravity=(0, 0, -G))
    scene.add_body(rr.Plane(), fixed=True, friction=mu)
    scene.add_body(rr.Box((0.1, 0.1, 0.05)), density=500.0, position=(0, 0, 0.05), linear_velocity=(V0, 0, 0), friction=mu)
    world = scene.build(DT, threads=1)
    t_stop = V0 / (mu * G)
    world.step(int(1.3 * t_stop / DT))
    return float(world.bodies.position[1, 0])
