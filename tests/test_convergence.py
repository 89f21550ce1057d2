"""Measured convergence order of every integrator against its nominal order
(``rigidrs.INTEGRATORS``), REFERENCES.md bar: within ±0.1 over two decades of dt.

Problem: a torque-free asymmetric top, I = (1, 1.6, 2.1) kg·m², body ω0 =
(1, 0.5, 1.5) rad/s (|ω0| = 1.9 rad/s, M² > 2EI2), a generic initial orientation,
integrated to T = 4 s (about half a period of ω, 7.6 s). It is smooth and far
from the separatrix, so errors grow gently with T; the Dzhanibekov case is not
used here: its instability amplifies explicit Euler's error until that is
useless for a slope, and near a flip error constants depend on where T falls.

Error at T: ‖log(R_refᵀR)‖ (rad) + |ω_b − ω_ref|/|ω_ref|, the orientation against
DOP853 (rtol = atol = 1e-13: ~1e-13 rad at T here) and ω against the elliptic
solution (exact to round-off).

Each method gets its own two decades of dt (n = T/dt steps, 9 values log-spaced):
the top end where its error is still in the asymptotic regime, the bottom end
where truncation still dominates round-off. Round-off grows like ~1e-15 per
step (the energy and |L| move by a fraction of an ulp per stage, which shifts
the phase), so the smallest errors must stay ≳ 1e-11 at ~10³ steps; two decades
at 4th order span 8 decades of error, which forces the top end to h·|ω| ≈ 1-2
for the methods with small error constants. That both ends are asymptotic is
checked, not assumed: the local slopes of the first and of the last pair of
points must be within ±0.2 of the nominal order as well (a pre-asymptotic top or
a round-off-dominated bottom bends them first).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr
import reference as ref

INERTIA = np.array([1.0, 1.6, 2.1])
W0 = np.array([1.0, 0.5, 1.5])
ROT0 = Rotation.from_rotvec([0.3, -0.5, 0.8])
T = 4.0

# Steps (largest dt, smallest dt) per integrator: two decades each.
STEPS = {
    "euler": (100, 10_000),
    "symplectic_euler": (100, 10_000),
    "implicit_gyro": (100, 10_000),
    "strang": (20, 2_000),
    "rk4": (10, 1_000),
    "yoshida4": (7, 700),
    "suzuki4": (4, 400),
}


@pytest.fixture(scope="module")
def reference_state() -> tuple[np.ndarray, np.ndarray]:
    """(R_ref(T), ω_ref(T) body)."""
    r_ref, w_dop = ref.free_body_dop853(INERTIA, ROT0.as_matrix(), W0, [0.0, T])
    w_ref = ref.EllipticTop.from_initial(INERTIA, W0).omega([T])[0]
    # The two references agree (DOP853's error at T is ~1e-15 in ω here).
    assert np.abs(w_dop[-1] - w_ref).max() < 1e-12
    return r_ref[-1], w_ref


def error_at_t(integrator: str, n: int, r_ref: np.ndarray, w_ref: np.ndarray) -> float:
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(mass=1.0, inertia=INERTIA, orientation=ROT0.as_quat(), angular_velocity=ROT0.apply(W0))
    # The bare method: its coarsest steps turn the body by up to h·W = 0.38 (strang) to
    # 1.9 rad (suzuki4) per step (W = 1.88 rad/s, the largest |ω| of the orbit), where
    # the automatic rotation substeps would subdivide them (above max_rotation_angle,
    # 0.2 / 0.5 / 0.6 rad) and flatten the slope.
    world = scene.build(dt=T / n, integrator=integrator, max_rotation_angle=math.inf)
    world.profiling = False
    world.step(n)
    assert abs(world.time - T) < 1e-12
    r = world.bodies.rotation[0]
    wb = r.T @ world.bodies.angular_velocity[0]
    return float(ref.rotation_angle(r_ref, r) + np.linalg.norm(wb - w_ref) / np.linalg.norm(w_ref))


def test_every_integrator_has_a_range() -> None:
    """A new integrator needs its dt range chosen here (and a reason for it)."""
    assert set(STEPS) == set(rr.INTEGRATORS)


@pytest.mark.parametrize("integrator", list(rr.INTEGRATORS))
def test_convergence_order(integrator: str, reference_state: tuple[np.ndarray, np.ndarray]) -> None:
    order = rr.INTEGRATORS[integrator]
    lo, hi = STEPS[integrator]
    assert hi >= 100 * lo  # two decades of dt
    steps = np.unique(np.round(np.geomspace(lo, hi, 9)).astype(int))
    dt = T / steps
    err = np.array([error_at_t(integrator, int(n), *reference_state) for n in steps])
    slope = np.polyfit(np.log(dt), np.log(err), 1)[0]
    local = np.diff(np.log(err)) / np.diff(np.log(dt))
    print(f"\n{integrator}: order {order}, measured {slope:.4f}; dt {dt[0]:.3g}..{dt[-1]:.3g} s, "
          f"error {err[0]:.2e}..{err[-1]:.2e}; local slopes {np.round(local, 3)}")
    assert abs(slope - order) <= 0.1
    assert abs(local[0] - order) <= 0.2
    assert abs(local[-1] - order) <= 0.2
