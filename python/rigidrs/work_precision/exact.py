"""Exact references of REFERENCES.md in NumPy alone (no SciPy needed to run the report).

* Jacobi elliptic functions and integrals: ``ellipk``, ``ellipf`` (Carlson's R_F,
  duplication) and ``ellipj`` (the AGM / descending Landen transformation,
  Abramowitz & Stegun 16.4), accurate to a few ulps for 0 ≤ m < 1;
* the torque-free asymmetric top (Landau–Lifshitz §37): body ω(t) in elliptic
  functions, the flip times, and the orientation R(t) from the Euler angles of L
  in the body frame plus one quadrature (LL eq. 37.14), done by composite
  Gauss–Legendre to ~1e-14 rad;
* the symmetric top in closed form, and the rotation-angle error ‖log(R_refᵀR)‖.

Conventions are the engine's: principal moments in body order, ``R`` maps body
vectors to the world, ``ω_w = R ω_b``, ``dR/dt = R ω̂_b``.
``tests/test_accuracy_report.py`` checks all of it against SciPy and DOP853.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]


# --------------------------------------------------------------------------------------
# Elliptic functions
# --------------------------------------------------------------------------------------


def carlson_rf(x: float, y: float, z: float) -> float:
    """Carlson's symmetric integral R_F(x, y, z) (x, y, z ≥ 0, at most one zero)."""
    for _ in range(60):
        a = (x + y + z) / 3.0
        dev = max(abs(a - x), abs(a - y), abs(a - z))
        if dev < 1e-3 * abs(a):
            break
        lam = math.sqrt(x * y) + math.sqrt(y * z) + math.sqrt(z * x)
        x, y, z = (x + lam) / 4.0, (y + lam) / 4.0, (z + lam) / 4.0
    a = (x + y + z) / 3.0
    dx, dy = 1.0 - x / a, 1.0 - y / a
    dz = -(dx + dy)
    e2, e3 = dx * dy - dz * dz, dx * dy * dz
    # Series truncated after the 5th order: error ~ dev⁶ < 1e-18.
    return (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0) / math.sqrt(a)


def ellipk(m: float, m1: float | None = None) -> float:
    """Complete elliptic integral of the first kind K(m); ``m1 = 1 − m`` if known
    more precisely than ``1 − m`` (near the separatrix)."""
    return carlson_rf(0.0, 1.0 - m if m1 is None else m1, 1.0)


def ellipf(phi: float, m: float, m1: float | None = None) -> float:
    """Incomplete elliptic integral F(φ | m), any real φ: F(φ + jπ) = F(φ) + 2jK."""
    m1 = 1.0 - m if m1 is None else m1
    j = round(phi / math.pi)
    p = phi - j * math.pi  # in [−π/2, π/2]
    s, c = math.sin(p), math.cos(p)
    return 2 * j * ellipk(m, m1) + s * carlson_rf(c * c, m1 + m * c * c, 1.0)


def ellipj(u: npt.ArrayLike, m: float, m1: float | None = None) -> tuple[F64, F64, F64]:
    """Jacobi ``(sn, cn, dn)(u | m)`` for 0 ≤ m < 1, by the AGM (A&S 16.4.3)."""
    u = np.asarray(u, dtype=float)
    m1 = 1.0 - m if m1 is None else m1
    a, b, c = [1.0], math.sqrt(m1), [math.sqrt(m)]
    while abs(c[-1]) > 1e-17 * a[-1] and len(a) < 40:
        a_prev = a[-1]
        c.append((a_prev - b) / 2.0)
        a.append((a_prev + b) / 2.0)
        b = math.sqrt(a_prev * b)
    n = len(a) - 1
    phi = 2.0**n * a[n] * u
    for i in range(n, 0, -1):
        phi = (np.arcsin(c[i] / a[i] * np.sin(phi)) + phi) / 2.0
    sn, cn = np.sin(phi), np.cos(phi)
    # dn = √(1 − m sn²) as a sum of two positive terms (A&S's cn/cos(φ1 − φ0) is 0/0 at u = K).
    return sn, cn, np.sqrt(m1 + m * cn * cn)


# --------------------------------------------------------------------------------------
# Rotations
# --------------------------------------------------------------------------------------


def hat(v: F64) -> F64:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def expm_so3(rotvec: npt.ArrayLike) -> F64:
    """Rotation matrices of rotation vectors (..., 3) -> (..., 3, 3) (Rodrigues)."""
    v = np.asarray(rotvec, dtype=float)
    theta = np.linalg.norm(v, axis=-1)[..., None, None]
    k = np.zeros(v.shape[:-1] + (3, 3))
    k[..., 0, 1], k[..., 0, 2], k[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    k = k - np.swapaxes(k, -1, -2)
    small = theta < 1e-8
    safe = np.where(small, 1.0, theta)
    s = np.where(small, 1.0 - theta**2 / 6.0, np.sin(safe) / safe)
    c = np.where(small, 0.5 - theta**2 / 24.0, (1.0 - np.cos(safe)) / safe**2)
    return np.eye(3) + s * k + c * (k @ k)


def quat_to_matrix(q: npt.ArrayLike) -> F64:
    """Rotation matrix of a unit quaternion (x, y, z, w)."""
    x, y, z, w = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def matrix_to_quat(r: F64) -> F64:
    """Unit quaternion (x, y, z, w) of a rotation matrix (Shepperd's method)."""
    t = np.trace(r)
    k = int(np.argmax([r[0, 0], r[1, 1], r[2, 2], t]))
    if k == 3:
        w = math.sqrt(1.0 + t) / 2.0
        q = np.array([(r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w), w])
    else:
        i, j, l = k, (k + 1) % 3, (k + 2) % 3
        s = math.sqrt(1.0 + r[i, i] - r[j, j] - r[l, l]) * 2.0
        q = np.empty(4)
        q[i], q[j], q[l] = s / 4.0, (r[j, i] + r[i, j]) / s, (r[l, i] + r[i, l]) / s
        q[3] = (r[l, j] - r[j, l]) / s
    return q


def rotation_angle(r_ref: F64, r: F64) -> F64:
    """‖log(R_refᵀ R)‖ (rad) of (..., 3, 3) stacks: ``atan2(|sin θ|, cos θ)`` from the
    antisymmetric part and the trace, so tiny angles keep full relative precision."""
    d = np.swapaxes(np.asarray(r_ref), -1, -2) @ np.asarray(r)
    axis = np.stack([d[..., 2, 1] - d[..., 1, 2], d[..., 0, 2] - d[..., 2, 0], d[..., 1, 0] - d[..., 0, 1]], -1)
    cos = (np.trace(d, axis1=-2, axis2=-1) - 1.0) / 2.0
    return np.arctan2(np.linalg.norm(axis, axis=-1) / 2.0, cos)


def _rz(a: F64) -> F64:
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2)


def _rx(a: F64) -> F64:
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.stack([np.stack([o, z, z], -1), np.stack([z, c, -s], -1), np.stack([z, s, c], -1)], -2)


# --------------------------------------------------------------------------------------
# Torque-free tops
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class EllipticTop:
    """A torque-free asymmetric top: ``ω_body(t)`` in Jacobi elliptic functions and
    ``R(t)`` by one quadrature.

    In the frame of ascending moments ``I1 < I2 < I3``, for ``M² > 2EI2``:
    ``ω1 = a1 cn, ω2 = a2 sn, ω3 = ±a3 dn`` of ``u = u0 + σλt``; for ``M² < 2EI2`` the
    indices 1 and 3 swap (REFERENCES.md). ``M² − 2EIk = Σ Ij (Ij − Ik) ωj²`` is
    formed without cancellation, so the top may sit close to the separatrix.
    """

    inertia: F64
    r0: F64
    perm: npt.NDArray[np.intp]
    cn_axis: int
    amp: F64
    lam: float
    m: float
    m1: float
    u0: float
    sigma: float
    s_dn: float
    energy: float
    momentum: float

    @classmethod
    def from_initial(cls, inertia: npt.ArrayLike, w0_body: npt.ArrayLike, r0: npt.ArrayLike | None = None) -> EllipticTop:
        i_body = np.asarray(inertia, dtype=float)
        w0 = np.asarray(w0_body, dtype=float)
        perm = np.argsort(i_body, kind="stable")
        i1, i2, i3 = i_body[perm]
        if not i1 < i2 < i3:
            raise ValueError(f"needs three distinct moments, got {i_body}")
        w = w0[perm]
        iw = np.array([i1, i2, i3])
        energy = 0.5 * float(np.sum(iw * w * w))
        d = [float(np.sum(iw * (iw - ik) * w * w)) for ik in (i1, i2, i3)]  # M² − 2E Ik
        hi, lo, mid = -d[2], d[0], d[1]  # 2EI3 − M², M² − 2EI1, M² − 2EI2
        parity = float(np.linalg.det(np.eye(3)[perm]))
        if mid > 0:
            cn_axis = 0
            amp = np.sqrt([hi / (i1 * (i3 - i1)), hi / (i2 * (i3 - i2)), lo / (i3 * (i3 - i1))])
            lam = math.sqrt((i3 - i2) * lo / (i1 * i2 * i3))
            m, m1 = (i2 - i1) * hi / ((i3 - i2) * lo), (i3 - i1) * mid / ((i3 - i2) * lo)
        elif mid < 0:
            cn_axis = 2
            amp = np.sqrt([hi / (i1 * (i3 - i1)), lo / (i2 * (i2 - i1)), lo / (i3 * (i3 - i1))])
            lam = math.sqrt((i2 - i1) * hi / (i1 * i2 * i3))
            m, m1 = (i3 - i2) * lo / ((i2 - i1) * hi), -(i3 - i1) * mid / ((i2 - i1) * hi)
        else:
            raise ValueError("M² = 2 E I2: on the separatrix")
        dn_axis = 2 - cn_axis
        phi = math.atan2(w[1] / amp[1], w[cn_axis] / amp[cn_axis])
        s_dn = float(np.sign(w[dn_axis]))
        momentum = float(np.linalg.norm(i_body * w0))
        r0m = np.eye(3) if r0 is None else np.asarray(r0, dtype=float)
        return cls(i_body, r0m, perm, cn_axis, amp, lam, m, m1, ellipf(phi, m, m1), parity * s_dn, s_dn, energy,
                   momentum)

    @property
    def quarter(self) -> float:
        """K(k²)."""
        return ellipk(self.m, self.m1)

    @property
    def period(self) -> float:
        """Period of ω_body: 4K/λ (s)."""
        return 4.0 * self.quarter / self.lam

    @property
    def intermediate_axis(self) -> int:
        return int(self.perm[1])

    def omega(self, t: npt.ArrayLike) -> F64:
        """Body-frame ω (N, 3) at times ``t`` (N,)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        sn, cn, dn = ellipj(self.u0 + self.sigma * self.lam * t, self.m, self.m1)
        ws = np.empty(t.shape + (3,))
        ws[:, self.cn_axis] = self.amp[self.cn_axis] * cn
        ws[:, 1] = self.amp[1] * sn
        ws[:, 2 - self.cn_axis] = self.s_dn * self.amp[2 - self.cn_axis] * dn
        out = np.empty_like(ws)
        out[:, self.perm] = ws
        return out

    def flip_times(self, n: int) -> F64:
        """The first ``n`` times t > 0 at which the intermediate component of ω changes
        sign: zeros of sn(u0 + σλt), at u = 2jK."""
        k2 = 2.0 * self.quarter
        j0 = math.floor(self.u0 / k2) + 1 if self.sigma > 0 else math.ceil(self.u0 / k2) - 1
        j = j0 + self.sigma * np.arange(n)
        return np.asarray((j * k2 - self.u0) / (self.sigma * self.lam), dtype=float)

    def rotation(self, t: npt.ArrayLike) -> F64:
        """R(t) (N, 3, 3): z–x–z Euler angles of L in the body frame, about the body
        axis L never comes near (the cn axis), with φ̇ = M (Ii ωi² + Ij ωj²)/(Ii² ωi² + Ij² ωj²)
        (LL eq. 37.14) integrated by Gauss–Legendre."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        k = int(self.perm[self.cn_axis])
        axes = [(k + 1) % 3, (k + 2) % 3, k]  # cyclic: a proper rotation
        p = np.eye(3)[axes]
        euler0 = self._euler_matrix(np.zeros(1), axes)[0]
        a = self.r0 @ p.T @ euler0.T
        return np.asarray(a @ self._euler_matrix(t, axes) @ p)

    def _euler_matrix(self, t: F64, axes: list[int]) -> F64:
        i, j, k = axes
        lb = self.inertia * self.omega(t)
        theta = np.arccos(np.clip(lb[:, k] / self.momentum, -1.0, 1.0))
        psi = np.arctan2(lb[:, i], lb[:, j])
        phi = self._phi(t, i, j)
        return np.asarray(_rz(phi) @ _rx(theta) @ _rz(psi))

    def _phi_rate(self, t: F64, i: int, j: int) -> F64:
        w = self.omega(t)
        ii, ij = self.inertia[i], self.inertia[j]
        num = ii * w[:, i] ** 2 + ij * w[:, j] ** 2
        return np.asarray(self.momentum * num / (ii**2 * w[:, i] ** 2 + ij**2 * w[:, j] ** 2))

    def _phi(self, t: F64, i: int, j: int) -> F64:
        """φ(t) − φ(0) by composite 12-point Gauss–Legendre on panels of at most a
        256th of the period, each running from one sorted time to the next."""
        order = np.argsort(t)
        ts = np.concatenate([[0.0], t[order]])
        edges = [0.0]
        step = self.period / 256.0
        for lo, hi in zip(ts[:-1], ts[1:]):
            cuts = max(1, math.ceil((hi - lo) / step))
            edges.extend(np.linspace(lo, hi, cuts + 1)[1:])
        e = np.array(edges)
        x, wq = np.polynomial.legendre.leggauss(12)
        mid, half = (e[1:] + e[:-1]) / 2, (e[1:] - e[:-1]) / 2
        nodes = mid[:, None] + half[:, None] * x[None, :]
        panel = half * (self._phi_rate(nodes.ravel(), i, j).reshape(nodes.shape) @ wq)
        cum = np.concatenate([[0.0], np.cumsum(panel)])
        at = cum[np.searchsorted(e, ts[1:])]
        out = np.empty_like(t)
        out[order] = at
        return out


def symmetric_top(inertia: npt.ArrayLike, r0: npt.ArrayLike, w0_world: npt.ArrayLike, t: npt.ArrayLike) -> F64:
    """R(t) = exp(t L̂/I1) R0 exp(t ((I1 − I3)/I1) ω3 ê3) (N, 3, 3), ``I1`` the transverse
    moment, ``I3`` and ``ê3`` the symmetry axis (body), ``L`` world (REFERENCES.md)."""
    i = np.asarray(inertia, dtype=float)
    r0 = np.asarray(r0, dtype=float)
    t = np.atleast_1d(np.asarray(t, dtype=float))
    s = next(k for k in range(3) if i[(k + 1) % 3] == i[(k + 2) % 3] != i[k])
    i1, i3 = i[(s + 1) % 3], i[s]
    w_body = r0.T @ np.asarray(w0_world, dtype=float)
    l_world = r0 @ (i * w_body)
    e3 = np.eye(3)[s]
    outer = expm_so3(t[:, None] * (l_world / i1))
    inner = expm_so3(t[:, None] * ((i1 - i3) / i1 * w_body[s]) * e3)
    return np.asarray(outer @ r0 @ inner)


def pendulum_period(length: float, theta0: float, g: float) -> float:
    """Exact period of a simple pendulum of amplitude θ0: 4 K(sin²(θ0/2)) √(L/g)."""
    return 4.0 * ellipk(math.sin(theta0 / 2.0) ** 2) * math.sqrt(length / g)


def heavy_top_slow_root(m: float, l: float, i1: float, i3: float, w3: float, theta: float, g: float) -> float:
    """Steady precession rate of a heavy symmetric top (I1 about the pivot), slow root:
    φ̇ = (I3ω3 − √(I3²ω3² − 4 I1 M g l cos θ)) / (2 I1 cos θ)."""
    c = math.cos(theta)
    return (i3 * w3 - math.sqrt((i3 * w3) ** 2 - 4.0 * i1 * m * g * l * c)) / (2.0 * i1 * c)
