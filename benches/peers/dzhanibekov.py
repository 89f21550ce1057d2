#!/usr/bin/env python
"""Scene 4 in rigidrs: torque-free body with principal inertia (1, 2, 3) spun near its
intermediate axis (the Dzhanibekov / tennis-racket flip).

The same scene, reference and JSON fields as the peer-engine script of the same name:
the body is given mass 1 kg and the diagonal inertia directly (no shape, no gravity),
omega0 = (0.01, 5, 0) in the body frame (= world frame at t = 0), 60 s at dt = 1/240,
the omega_y flip times compared with solve_ivp (DOP853, rtol 1e-12) on Euler's
equations. One JSON line per integrator (the peers print one per MuJoCo integrator or
PyBullet body kind); stepping and the per-step read-back are timed together, as there.

    python benches/peers/dzhanibekov.py                      # every integrator
    python benches/peers/dzhanibekov.py --integrator strang
"""
import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp

from common import emit, quat_to_mat

I = np.array([1.0, 2.0, 3.0])
MASS = 1.0


def build_rigidrs(a, integrator):
    import rigidrs as rr
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    b = scene.add_body(mass=MASS, inertia=I, angular_velocity=a.w0)  # identity orientation: world = body at t = 0
    world = scene.build(dt=a.dt, integrator=integrator)
    bodies = world.bodies
    assert np.allclose(bodies.inertia[b], I) and bodies.mass[b] == MASS
    assert np.allclose(np.abs(bodies.orientation[b]), [0, 0, 0, 1])  # principal frame = the given frame
    q, w = bodies.orientation, bodies.angular_velocity

    def read():
        R = quat_to_mat(q[b])[0]
        return R.T @ w[b]

    return world.step, read


def euler_rhs(t, w):
    return [(I[1] - I[2]) * w[1] * w[2] / I[0], (I[2] - I[0]) * w[2] * w[0] / I[1], (I[0] - I[1]) * w[0] * w[1] / I[2]]


def crossings(t, y):
    """Times where y changes sign, linearly interpolated between samples."""
    i = np.nonzero(np.sign(y[1:]) != np.sign(y[:-1]))[0]
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])


def invariants(w):
    return 0.5 * np.sum(I * w ** 2, axis=-1), np.linalg.norm(I * w, axis=-1)


def main():
    import rigidrs as rr
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--integrator", default="all", help=f"one of {', '.join(rr.INTEGRATORS)}, or all")
    ap.add_argument("--dt", type=float, default=1 / 240)
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--w0", type=float, nargs=3, default=[0.01, 5.0, 0.0], help="initial body-frame omega")
    a = ap.parse_args()
    a.w0 = np.array(a.w0)
    names = list(rr.INTEGRATORS) if a.integrator == "all" else [a.integrator]
    for name in names:
        if name not in rr.INTEGRATORS:
            ap.error(f"unknown integrator {name!r}; choose one of {', '.join(rr.INTEGRATORS)} or all")

    steps = int(round(a.duration / a.dt))
    ref = solve_ivp(euler_rhs, (0, a.duration), a.w0, method="DOP853", rtol=1e-12, atol=1e-12,
                    events=lambda t, w: w[1])
    t_ref = ref.t_events[0]
    p_ref = float(np.diff(t_ref).mean())
    E0, L0 = invariants(a.w0)

    for variant in names:
        step, read = build_rigidrs(a, variant)
        w = np.empty((steps + 1, 3))
        w[0] = read()
        t0 = time.perf_counter()
        for k in range(steps):
            step()
            w[k + 1] = read()  # one body: per-step readback is cheap; timed together with stepping
        wall = time.perf_counter() - t0
        t = np.arange(steps + 1) * a.dt
        tc = crossings(t, w[:, 1])
        E, L = invariants(w)
        period = float(np.diff(tc).mean()) if len(tc) > 1 else float("nan")
        emit({
            "scene": "dzhanibekov", "engine": "rigidrs", "variant": variant, "dt": a.dt, "steps": steps,
            "wall_s": round(wall, 4),
            "E_rel_drift": float(E[-1] / E0 - 1), "L_rel_drift": float(L[-1] / L0 - 1),
            "E_max_abs_drift": float(np.abs(E / E0 - 1).max()), "L_max_abs_drift": float(np.abs(L / L0 - 1).max()),
            "flip_period": period, "flip_period_ref": p_ref, "flip_period_rel_err": period / p_ref - 1,
            "n_flips": int(len(tc)), "n_flips_ref": int(len(t_ref)),
            "first_flip": float(tc[0]) if len(tc) else None, "first_flip_ref": float(t_ref[0]),
            "flip_interval_std": float(np.diff(tc).std()) if len(tc) > 2 else None,
            # sign of L^2 - 2 E I2: which side of the separatrix the motion is on (ref: -1, about axis 1)
            "separatrix_side_end": int(np.sign(L[-1] ** 2 - 2 * E[-1] * I[1])),
            "separatrix_side_ref": int(np.sign(L0 ** 2 - 2 * E0 * I[1])),
            "w_end": w[-1].round(4).tolist(), "w_end_ref": ref.y[:, -1].round(4).tolist(),
        })


if __name__ == "__main__":
    main()
