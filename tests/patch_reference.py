"""Coulomb friction over a flat contact patch under uniform pressure
(REFERENCES.md, "Spinning plate (torsional friction)"): the exact references the
engine's patch friction is measured against. Nothing here imports rigidrs.

A square plate of half side ``a`` on a flat floor, mass ``m``, moment ``I`` about
the vertical, friction ``μ``: each point ``r`` of the patch (area ``A``) slides at
``u = v + ω × r`` and feels ``−μ (m g / A) u/|u|`` per unit area. Force and torque
are the integrals of that over the patch (a midpoint grid), and the planar motion
(x, y, θ, vx, vy, ω) is integrated with DOP853 until it stops.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp


def mean_distance_square(a: float) -> float:
    """Mean distance of a square's points from its centre, half side ``a``:
    ``r̄ = a (√2 + asinh 1) / 3`` (≈ 0.7652 a)."""
    return a * (math.sqrt(2.0) + math.asinh(1.0)) / 3.0


def spin_stop_time(a: float, mass: float, inertia: float, mu: float, g: float, omega0: float) -> float:
    """A plate spun at ``ω0`` without sliding stops after ``I ω0 / (μ m g r̄)``."""
    return inertia * omega0 / (mu * mass * g * mean_distance_square(a))


def slide_and_spin(a: float, inertia_per_mass: float, mu: float, g: float, v0: float, omega0: float,
                   grid: int = 100) -> dict[str, float]:
    """Stop time, distance and total rotation of a plate launched at ``v0`` (along
    x) spinning at ``ω0``, by DOP853 (rtol 1e-10) on the patch integrals over a
    ``grid × grid`` midpoint grid."""
    xs = (np.arange(grid) + 0.5) / grid * 2.0 * a - a
    x, y = (c.ravel() for c in np.meshgrid(xs, xs))
    cell = 1.0 / (grid * grid)  # fraction of the area per point

    def rhs(_t: float, s: np.ndarray) -> list[float]:
        vx, vy, w = s[3], s[4], s[5]
        ux, uy = vx - w * y, vy + w * x
        norm = np.hypot(ux, uy) + 1e-300
        fx, fy = -mu * g * np.sum(ux / norm) * cell, -mu * g * np.sum(uy / norm) * cell
        tz = -mu * g * np.sum((x * uy - y * ux) / norm) * cell / inertia_per_mass
        return [vx, vy, w, fx, fy, tz]

    r_bar = mean_distance_square(a)

    def stopped(_t: float, s: np.ndarray) -> float:
        return math.hypot(s[3], s[4]) + abs(s[5]) * r_bar - 1e-6 * (v0 + abs(omega0) * r_bar)

    stopped.terminal = True  # type: ignore[attr-defined]
    horizon = 4.0 * (v0 + abs(omega0) * r_bar) / (mu * g) + 1.0
    sol = solve_ivp(rhs, [0.0, horizon], [0, 0, 0, v0, 0, omega0], method="DOP853", rtol=1e-10, atol=1e-12,
                    events=stopped)
    return {"time": float(sol.t[-1]), "distance": float(sol.y[0, -1]), "rotation": float(sol.y[2, -1])}
