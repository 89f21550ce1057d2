#!/usr/bin/env python
"""Scene 1 in rigidrs: N free boxes spinning torque-free (no gravity, collisions disabled).

The same scene, initial state and JSON fields as the peer-engine script of the same
name (MuJoCo, PyBullet, Rapier): times the stepping loop alone (one `world.step()`
call per step, as the peers are stepped), then reads orientations and angular
velocities back through the NumPy views to measure the drift of the rotational
invariants. Extra fields: `integrator`, `step_s_batch` / `body_steps_per_s_batch`
(the same steps as one `world.step(steps)` call on a fresh world),
`batch_vs_loop_max_q_diff` (largest quaternion difference between the two), `stages`.

    python benches/peers/free_bodies.py --integrator strang
    python benches/peers/free_bodies.py --integrator all     # one line per integrator
"""
import argparse
import time

import numpy as np

from common import box_inertia, emit, random_quats_xyzw, rot_invariants

SIZE = np.array([0.1, 0.2, 0.4])  # full edge lengths (m)


def initial_state(a):
    """Identical to the peer script: grid positions, uniform quaternions, |ω| = a.omega."""
    rng = np.random.default_rng(a.seed)
    side = int(np.ceil(a.n ** (1 / 3)))
    i = np.arange(a.n)
    pos = a.spacing * np.stack([i % side, (i // side) % side, i // side ** 2], 1).astype(float)
    quat = random_quats_xyzw(rng, a.n)
    d = rng.normal(size=(a.n, 3))
    omega = a.omega * d / np.linalg.norm(d, axis=1, keepdims=True)  # world frame, |w| = 5
    return pos, quat, omega


def build_rigidrs(a, integrator, pos, quat, omega):
    import rigidrs as rr
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    box = rr.Box(half_extents=SIZE / 2)
    # Collisions disabled, as the peer scripts disable them (MuJoCo's contact
    # flag, PyBullet's and Rapier's empty collision groups): the bodies keep
    # their box shapes for the mass properties, and no collision stage runs.
    for x, q, w in zip(pos, quat, omega):
        scene.add_body(box, density=a.density, position=x, orientation=q, angular_velocity=w, collision_mask=0)
    world = scene.build(dt=a.dt, integrator=integrator)
    bodies = world.bodies
    # A box's principal frame is its own frame: the state is the pose we gave.
    assert np.allclose(np.abs(np.sum(bodies.orientation * quat, axis=1)), 1.0, atol=1e-12)

    def read():
        return bodies.orientation.copy(), bodies.angular_velocity.copy(), bodies.linear_velocity.copy()

    return world, read, bodies.mass.copy(), bodies.inertia[0].copy()


def run(a, integrator, pos, quat, omega):
    t0 = time.perf_counter()
    world, read, mass, inertia = build_rigidrs(a, integrator, pos, quat, omega)
    build_s = time.perf_counter() - t0

    m_ref = a.density * np.prod(SIZE)
    I_ref = box_inertia(m_ref, SIZE)
    ke_ref, _ = rot_invariants(quat, omega, I_ref)
    q0, w0, _ = read()
    ke0, L0 = rot_invariants(q0, w0, I_ref)

    step = world.step
    t0 = time.perf_counter()
    for _ in range(a.steps):
        step()
    step_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    q1, w1, v1 = read()
    read_s = time.perf_counter() - t0
    ke1, L1 = rot_invariants(q1, w1, I_ref)

    # The same steps in one call (the GIL released once), on a fresh world.
    world2, _, _, _ = build_rigidrs(a, integrator, pos, quat, omega)
    t0 = time.perf_counter()
    world2.step(a.steps)
    step_s_batch = time.perf_counter() - t0
    # Not bit-identical: each step() call re-normalises the quaternions on entry.
    batch_diff = float(np.abs(world2.bodies.orientation - q1).max())

    L0n, L1n = np.linalg.norm(L0, axis=1), np.linalg.norm(L1, axis=1)
    emit({
        "scene": "free_bodies", "engine": "rigidrs", "n": a.n, "steps": a.steps, "dt": a.dt,
        "variant": integrator,
        "build_s": round(build_s, 4), "step_s": round(step_s, 4), "read_s": round(read_s, 5),
        "body_steps_per_s": a.n * a.steps / step_s,
        "ke_rel_drift": float(ke1.sum() / ke0.sum() - 1),
        "L_rel_drift": float(L1n.sum() / L0n.sum() - 1),  # sum of |L_i|
        "Ltot_rel_drift": float(np.linalg.norm(L1.sum(0)) / np.linalg.norm(L0.sum(0)) - 1),  # |sum of L_i|
        "L_vec_rel_err": float(np.linalg.norm(L1 - L0, axis=1).sum() / L0n.sum()),
        "max_body_ke_rel_drift": float(np.max(np.abs(ke1 / ke0 - 1))),
        "init_ke_mismatch": float(ke0.sum() / ke_ref.sum() - 1),
        "mass_rel_err": float(np.max(np.abs(mass / m_ref - 1))),
        "inertia_rel_err": float(np.max(np.abs(np.asarray(inertia) / I_ref - 1))),
        "max_linvel_end": float(np.abs(v1).max()),
        "integrator": integrator, "stages": world.stages,
        "step_s_batch": round(step_s_batch, 4), "body_steps_per_s_batch": a.n * a.steps / step_s_batch,
        "batch_vs_loop_max_q_diff": batch_diff,
    })


def main():
    import rigidrs as rr
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--integrator", default="strang", help=f"one of {', '.join(rr.INTEGRATORS)}, or all")
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--dt", type=float, default=1 / 240)
    ap.add_argument("--density", type=float, default=1000.0)
    ap.add_argument("--omega", type=float, default=5.0, help="|angular velocity| (rad/s)")
    ap.add_argument("--spacing", type=float, default=1.0, help="grid spacing (m)")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    names = list(rr.INTEGRATORS) if a.integrator == "all" else [a.integrator]
    for name in names:
        if name not in rr.INTEGRATORS:
            ap.error(f"unknown integrator {name!r}; choose one of {', '.join(rr.INTEGRATORS)} or all")

    pos, quat, omega = initial_state(a)
    for name in names:
        run(a, name, pos, quat, omega)


if __name__ == "__main__":
    main()
