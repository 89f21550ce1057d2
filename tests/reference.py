"""Exact references for the free rigid body, computed from the formulas of
REFERENCES.md (Landau–Lifshitz §37) for any parameters.

Conventions (the engine's): principal moments ``I`` (3,) in body-frame order,
``R`` maps body vectors to the world (``v_w = R v_b``), ``ω_w = R ω_b``,
so ``dR/dt = ω̂_w R = R ω̂_b`` and Euler's equations read ``I ω̇_b = (I ω_b) × ω_b``.

Nothing here imports rigidrs: these are the yardsticks the engine is measured
against, and they are checked against each other in the tests (the elliptic
solution against DOP853, the symmetric closed form against DOP853).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation
from scipy.special import ellipj, ellipk, ellipkinc

F64 = npt.NDArray[np.float64]


def hat(v: F64) -> F64:
    """Skew matrices ``v̂`` with ``v̂ u = v × u``; ``v`` (..., 3) -> (..., 3, 3)."""
    v = np.asarray(v, dtype=float)
    z = np.zeros(v.shape[:-1])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([np.stack([z, -w, y], -1), np.stack([w, z, -x], -1), np.stack([-y, x, z], -1)], -2)


def energy(inertia: F64, w_body: F64) -> F64:
    """Rotational kinetic energy ``½ Σ I_j ω_j²`` of body-frame ``ω`` (..., 3)."""
    return 0.5 * np.sum(np.asarray(inertia) * np.asarray(w_body) ** 2, axis=-1)


def momentum_sq(inertia: F64, w_body: F64) -> F64:
    """``M² = |I ω|²`` of body-frame ``ω`` (..., 3)."""
    return np.sum((np.asarray(inertia) * np.asarray(w_body)) ** 2, axis=-1)


def rotation_angle(r_ref: F64, r: F64) -> F64:
    """Rotation-angle error ``‖log(R_refᵀ R)‖`` (rad, in [0, π]) of (..., 3, 3) stacks.

    Computed as ``2 atan2(|v|, |w|)`` of the quaternion of ``R_refᵀ R``, which keeps
    full relative precision for tiny angles (``arccos((tr − 1)/2)`` would not)."""
    d = np.swapaxes(np.asarray(r_ref), -1, -2) @ np.asarray(r)
    shape = d.shape[:-2]
    q = Rotation.from_matrix(d.reshape(-1, 3, 3)).as_quat()
    ang = 2.0 * np.arctan2(np.linalg.norm(q[:, :3], axis=1), np.abs(q[:, 3]))
    return ang.reshape(shape)


# --------------------------------------------------------------------------------------
# Asymmetric top: the Landau–Lifshitz elliptic-function solution for ω_body(t)
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class EllipticTop:
    """Torque-free asymmetric top, ``ω_body(t)`` in Jacobi elliptic functions.

    In the frame of ascending moments ``I1 < I2 < I3``: for ``M² > 2 E I2``
    ``ω1 ∝ cn, ω2 ∝ sn, ω3 ∝ dn`` (REFERENCES.md); for ``M² < 2 E I2`` the indices 1
    and 3 swap. With ``u = u0 + σ λ t`` the amplitudes carry no free signs but two:
    the sign ``s_d`` of the dn component (dn > 0, so it never changes) and the
    direction ``σ``; the phase ``u0`` is fitted from the initial body-frame ω by
    ``am(u0) = atan2(ω2/a2, ω_cn/a_cn)``, ``u0 = F(am, k²)``. Euler's equation for
    ω2, ``I2 ω̇2 = p (I3 − I1) ω3 ω1`` (``p`` the parity of the sorting permutation,
    which flips the cross product), gives ``σ = p · s_d`` on both branches.
    """

    inertia: F64  # (3,) body order
    perm: npt.NDArray[np.intp]  # body axes in ascending order of moment
    cn_axis: int  # sorted index carrying cn (0 or 2); the dn axis is 2 - cn_axis
    amp: F64  # (3,) amplitudes in sorted order
    lam: float  # λ (1/s)
    m: float  # k²
    u0: float
    sigma: float
    s_dn: float
    energy: float
    momentum_sq: float

    @classmethod
    def from_initial(cls, inertia: npt.ArrayLike, w0_body: npt.ArrayLike) -> EllipticTop:
        inertia = np.asarray(inertia, dtype=float)
        w0 = np.asarray(w0_body, dtype=float)
        perm = np.argsort(inertia, kind="stable")
        i1, i2, i3 = inertia[perm]
        if not (i1 < i2 < i3):
            raise ValueError(f"needs three distinct moments, got {inertia}")
        w = w0[perm]
        e = float(energy(inertia, w0))
        m2 = float(momentum_sq(inertia, w0))
        # Parity of perm: sign of the determinant of its permutation matrix.
        parity = float(np.linalg.det(np.eye(3)[perm]))
        a_hi = 2 * e * i3 - m2  # >= 0
        a_lo = m2 - 2 * e * i1  # >= 0
        if m2 > 2 * e * i2:
            cn_axis, dn_axis = 0, 2
            amp = np.sqrt([a_hi / (i1 * (i3 - i1)), a_hi / (i2 * (i3 - i2)), a_lo / (i3 * (i3 - i1))])
            lam = np.sqrt((i3 - i2) * a_lo / (i1 * i2 * i3))
            m = (i2 - i1) * a_hi / ((i3 - i2) * a_lo)
        elif m2 < 2 * e * i2:
            cn_axis, dn_axis = 2, 0
            amp = np.sqrt([a_hi / (i1 * (i3 - i1)), a_lo / (i2 * (i2 - i1)), a_lo / (i3 * (i3 - i1))])
            lam = np.sqrt((i2 - i1) * a_hi / (i1 * i2 * i3))
            m = (i3 - i2) * a_lo / ((i2 - i1) * a_hi)
        else:  # pragma: no cover - the separatrix has no periodic solution
            raise ValueError("M² = 2 E I2: on the separatrix")
        phi = np.arctan2(w[1] / amp[1], w[cn_axis] / amp[cn_axis])
        u0 = float(ellipkinc(phi, m))
        s_dn = float(np.sign(w[dn_axis]))
        return cls(inertia, perm, cn_axis, amp, float(lam), float(m), u0, parity * s_dn, s_dn, e, m2)

    @property
    def quarter(self) -> float:
        """``K(k²)``."""
        return float(ellipk(self.m))

    @property
    def period(self) -> float:
        """Period of ``ω_body``: ``4 K(k²) / λ`` (s)."""
        return 4.0 * self.quarter / self.lam

    @property
    def intermediate_axis(self) -> int:
        """Body index of the intermediate moment (the sn component)."""
        return int(self.perm[1])

    def omega(self, t: npt.ArrayLike) -> F64:
        """Body-frame ``ω`` (N, 3) at times ``t`` (N,)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        sn, cn, dn, _ = ellipj(self.u0 + self.sigma * self.lam * t, self.m)
        ws = np.empty(t.shape + (3,))
        ws[:, self.cn_axis] = self.amp[self.cn_axis] * cn
        ws[:, 1] = self.amp[1] * sn
        ws[:, 2 - self.cn_axis] = self.s_dn * self.amp[2 - self.cn_axis] * dn
        out = np.empty_like(ws)
        out[:, self.perm] = ws
        return out

    def flip_times(self, n: int) -> F64:
        """The first ``n`` times ``t > 0`` at which the intermediate component of ω
        changes sign: zeros of ``sn(u0 + σ λ t)``, at ``u = 2 j K``."""
        k2 = 2.0 * self.quarter
        # t_j = (j·2K − u0) / (σ λ) > 0 needs j > u0/2K for σ = +1, j < u0/2K for σ = −1;
        # the first such j, then onwards in the direction of σ (increasing t).
        j0 = np.floor(self.u0 / k2) + 1 if self.sigma > 0 else np.ceil(self.u0 / k2) - 1
        j = j0 + self.sigma * np.arange(n)
        return (j * k2 - self.u0) / (self.sigma * self.lam)


# --------------------------------------------------------------------------------------
# DOP853 reference of the orientation (and ω) for any body
# --------------------------------------------------------------------------------------


def free_body_dop853(
    inertia: npt.ArrayLike, r0: npt.ArrayLike, w0_body: npt.ArrayLike, t_eval: npt.ArrayLike,
    rtol: float = 1e-13, atol: float = 1e-13,
) -> tuple[F64, F64]:
    """``(R(t), ω_body(t))`` of a torque-free body: ``dR/dt = R ω̂_b`` (= ``ω̂_w R``) with
    Euler's equations ``I ω̇_b = (I ω_b) × ω_b``, by ``solve_ivp(method="DOP853")``.
    Returns (N, 3, 3) rotations and (N, 3) body-frame angular velocities."""
    inertia = np.asarray(inertia, dtype=float)
    t_eval = np.asarray(t_eval, dtype=float)

    def rhs(_t: float, y: F64) -> F64:
        r = y[:9].reshape(3, 3)
        w = y[9:]
        dr = r @ hat(w)
        dw = np.cross(inertia * w, w) / inertia
        return np.concatenate([dr.ravel(), dw])

    y0 = np.concatenate([np.asarray(r0, dtype=float).ravel(), np.asarray(w0_body, dtype=float)])
    sol = solve_ivp(rhs, (0.0, float(t_eval[-1])), y0, method="DOP853", t_eval=t_eval, rtol=rtol, atol=atol)
    if not sol.success:  # pragma: no cover
        raise RuntimeError(sol.message)
    return sol.y[:9].T.reshape(-1, 3, 3), sol.y[9:].T


# --------------------------------------------------------------------------------------
# Symmetric top in closed form
# --------------------------------------------------------------------------------------


def symmetric_axis(inertia: npt.ArrayLike) -> int:
    """Index of the symmetry axis of moments with exactly two equal."""
    i = np.asarray(inertia, dtype=float)
    for k in range(3):
        a, b = i[(k + 1) % 3], i[(k + 2) % 3]
        if a == b and i[k] != a:
            return k
    raise ValueError(f"not a symmetric top: {i}")


def symmetric_top(inertia: npt.ArrayLike, r0: npt.ArrayLike, w0_world: npt.ArrayLike, t: npt.ArrayLike) -> F64:
    """``R(t) = exp(t L̂/I1) R0 exp(t ((I1 − I3)/I1) ω3 ê3)`` (N, 3, 3), ``I1`` the
    transverse moment, ``I3`` and ``ê3`` the symmetry axis (body frame), ``L`` world."""
    inertia = np.asarray(inertia, dtype=float)
    r0 = np.asarray(r0, dtype=float)
    t = np.atleast_1d(np.asarray(t, dtype=float))
    s = symmetric_axis(inertia)
    i1, i3 = inertia[(s + 1) % 3], inertia[s]
    w_body = r0.T @ np.asarray(w0_world, dtype=float)
    l_world = r0 @ (inertia * w_body)
    e3 = np.eye(3)[s]
    outer = Rotation.from_rotvec(t[:, None] * (l_world / i1))
    inner = Rotation.from_rotvec(t[:, None] * ((i1 - i3) / i1 * w_body[s]) * e3)
    return outer.as_matrix() @ r0 @ inner.as_matrix()


def quat_to_matrix(q_xyzw: npt.ArrayLike) -> F64:
    """Rotation matrices of (x, y, z, w) quaternions (..., 4) -> (..., 3, 3)."""
    q = np.asarray(q_xyzw, dtype=float)
    shape = q.shape[:-1]
    return Rotation.from_quat(q.reshape(-1, 4)).as_matrix().reshape(shape + (3, 3))
