"""Planar chains of hinged links: the scene in rigidrs and the exact reference.

A chain of N links hangs from a hinge at the origin (axis y); link k has length
l_k, mass m_k and centroidal inertia I_k about y, its centre of mass at the middle
of the link. With absolute angles θ_k from the downward vertical (rotation about
+y takes (0, 0, −1) to (−sin θ, 0, −cos θ)), the centre of mass of link k is
r_k = Σ_{j<k} l_j e(θ_j) + (l_k/2) e(θ_k), e(θ) = (−sin θ, −cos θ) in (x, z).
The Lagrangian L = Σ ½ m_k |ṙ_k|² + ½ I_k θ̇_k² − Σ m_k g z_k gives

    Σ_j B_ij cos(θ_i − θ_j) θ̈_j + Σ_j B_ij sin(θ_i − θ_j) θ̇_j² + g s_i sin θ_i = 0,

B_ij = Σ_k m_k a_ki a_kj + δ_ij I_i, a_ki = l_i (i < k), l_i/2 (i = k), 0 (i > k),
s_i = Σ_k m_k a_ki. Integrated with SciPy's DOP853 at rtol = atol = 1e-12, this is
the reference the articulation is held to (its own error is ~1e-10 here).
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import cho_factor, cho_solve

import rigidrs as rr

G = 9.81


def lever_matrix(lengths: np.ndarray) -> np.ndarray:
    n = len(lengths)
    a = np.zeros((n, n))
    for k in range(n):
        a[k, :k] = lengths[:k]
        a[k, k] = lengths[k] / 2
    return a


def reference(theta0: np.ndarray, lengths: np.ndarray, masses: np.ndarray, inertias: np.ndarray, times: np.ndarray,
              g: float = G) -> np.ndarray:
    """θ(t) (len(times), N) from θ(0) = theta0 at rest."""
    a = lever_matrix(lengths)
    b = np.einsum("k,ki,kj->ij", masses, a, a) + np.diag(inertias)
    s = masses @ a
    n = len(lengths)

    def rhs(_t: float, y: np.ndarray) -> np.ndarray:
        th, w = y[:n], y[n:]
        c, sn = np.cos(th), np.sin(th)
        # cos(θi − θj) and sin(θi − θj) from outer products (no N² trigonometry).
        m = b * (np.outer(c, c) + np.outer(sn, sn))
        f = -(b * (np.outer(sn, c) - np.outer(c, sn))) @ (w * w) - g * s * sn
        return np.concatenate([w, cho_solve(cho_factor(m), f)])

    y0 = np.concatenate([theta0, np.zeros(n)])
    sol = solve_ivp(rhs, (0.0, float(times[-1])), y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=times)
    return sol.y[:n].T


def joints_xz(theta: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """(…, N, 2) positions (x, z) of each link's far end."""
    e = np.stack([-np.sin(theta), -np.cos(theta)], axis=-1)
    return np.cumsum(lengths[:, None] * e, axis=-2)


def energy(theta: np.ndarray, omega: np.ndarray, lengths: np.ndarray, masses: np.ndarray, inertias: np.ndarray,
           g: float = G) -> float:
    a = lever_matrix(lengths)
    b = np.einsum("k,ki,kj->ij", masses, a, a) + np.diag(inertias)
    m = b * np.cos(theta[:, None] - theta[None, :])
    return 0.5 * omega @ m @ omega - g * (masses @ a) @ np.cos(theta)


def chain_scene(theta0: np.ndarray, lengths: np.ndarray, masses: np.ndarray, thickness: float,
                solver: str = "auto", gravity: float = G) -> tuple[rr.Scene, list[int]]:
    """The chain as boxes (length l_k along the link, square section `thickness`),
    hinged about y at the origin and end to end; no collisions (mask 0)."""
    scene = rr.Scene(gravity=(0, 0, -gravity))
    ends = joints_xz(theta0, lengths)
    starts = np.vstack([[0.0, 0.0], ends[:-1]])
    bodies = []
    for k, (l, m) in enumerate(zip(lengths, masses)):
        mid = (starts[k] + ends[k]) / 2
        q = np.array([0.0, np.sin(theta0[k] / 2), 0.0, np.cos(theta0[k] / 2)])  # about +y
        half = (thickness / 2, thickness / 2, l / 2)
        bodies.append(scene.add_body(rr.Box(half), mass=m, position=(mid[0], 0.0, mid[1]), orientation=q,
                                     collision_mask=0))
    for k, b in enumerate(bodies):
        anchor = (starts[k][0], 0.0, starts[k][1])
        scene.add_joint("hinge", b, None if k == 0 else bodies[k - 1], anchor=anchor, axis=(0, 1, 0), solver=solver)
    return scene, bodies


def box_inertia_about_y(masses: np.ndarray, lengths: np.ndarray, thickness: float) -> np.ndarray:
    return masses * (lengths**2 + thickness**2) / 12


def world_ends(world: rr.World, bodies: list[int], lengths: np.ndarray) -> np.ndarray:
    """(N, 2) the far end (x, z) of each link in the world."""
    p, r = world.bodies.position[bodies], world.bodies.rotation[bodies]
    tip = p + (r @ np.array([0.0, 0.0, -1.0])) * (lengths[:, None] / 2)
    return tip[:, [0, 2]]
