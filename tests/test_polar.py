"""``rr.polar_decomposition`` on every matrix of REFERENCES.md, for every method.

Checked for each (matrix, method):
- R orthonormal to 1e-12 and det R = +1 to 1e-12, no NaN (the REFERENCES bar);
- R S = M to 1e-14 ‖M‖: S is Rᵀ M, so this only costs the rounding of two
  products with an orthonormal R (a few ε);
- R is the nearest proper rotation: tr(Rᵀ M) = σ₁ + σ₂ + sign(det M) σ₃, the
  maximum over SO(3), to 1e-12 σ₁ (holds also where R is not unique: rank 1, zero);
- where R is unique (σ₂ + sign(det M) σ₃ > 0), R agrees with LAPACK's SVD
  (NumPy) and S is symmetric, to 20 ε κ with κ = σ₁ / (σ₂ + sign(det M) σ₃):
  R moves by ~κ ‖δM‖/‖M‖ under a perturbation δM, and each of the two
  computations is exact for an M moved by at most ~5 ε ‖M‖ (measured ≤ 4 ε).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rigidrs as rr

METHODS = ["svd", "higham", "muller"]
EPS = np.finfo(float).eps


def spd(cond: float, mid: float, seed: int) -> np.ndarray:
    """A symmetric positive definite matrix with eigenvalues 1, 1/mid, 1/cond."""
    q = Rotation.random(random_state=seed).as_matrix()
    return q @ np.diag([1.0, 1.0 / mid, 1.0 / cond]) @ q.T


def reference_matrices() -> dict[str, np.ndarray]:
    rots = Rotation.random(40, random_state=1).as_matrix()
    cases: dict[str, np.ndarray] = {"identity": np.eye(3)}
    for k in range(20):
        cases[f"random rotation {k}"] = rots[k]
    for name, axis in {"x": [1, 0, 0], "y": [0, 1, 0], "z": [0, 0, 1], "oblique": [1, -2, 0.5]}.items():
        cases[f"180° about {name}"] = Rotation.from_rotvec(math.pi * np.asarray(axis) / np.linalg.norm(axis)).as_matrix()
    cases["1e-6·R"] = 1e-6 * rots[20]
    cases["1e6·R"] = 1e6 * rots[21]
    for i, cond in enumerate([1e3, 1e6, 1e9]):
        for j, mid in enumerate([1.0, math.sqrt(cond), cond]):
            cases[f"R·S cond {cond:.0e}, middle 1/{mid:.0e}"] = rots[22 + 3 * i + j] @ spd(cond, mid, seed=10 * i + j)
    cases["inverted diag(2, 1, -0.5)"] = np.diag([2.0, 1.0, -0.5])
    cases["rotated inverted"] = rots[31] @ np.diag([2.0, 1.0, -0.5]) @ rots[32]
    cases["singular diag(1, 1, 0)"] = np.diag([1.0, 1.0, 0.0])
    cases["rotated singular"] = rots[33] @ np.diag([3.0, 1.0, 0.0]) @ rots[34]
    cases["near-singular diag(1, 1, 1e-8)"] = np.diag([1.0, 1.0, 1e-8])
    cases["rank 1"] = np.outer([1.0, 2.0, -3.0], [0.5, -1.0, 0.25])
    cases["zero"] = np.zeros((3, 3))
    return cases


CASES = reference_matrices()


def lapack_rotation(m: np.ndarray) -> np.ndarray:
    u, _, vt = np.linalg.svd(m)
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
    return u @ d @ vt


def kappa(m: np.ndarray) -> float | None:
    """σ₁ / (σ₂ + sign(det) σ₃), or None where R is not unique."""
    s = np.linalg.svd(m, compute_uv=False)
    gap = s[1] + np.sign(np.linalg.det(m)) * s[2]
    return s[0] / gap if gap > 1e-14 * s[0] else None


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name", list(CASES))
def test_every_reference_matrix(name: str, method: str) -> None:
    m = CASES[name]
    r, s = rr.polar_decomposition(m, method=method)
    assert r.shape == (3, 3) and s.shape == (3, 3)
    assert np.all(np.isfinite(r)) and np.all(np.isfinite(s))
    assert np.abs(r.T @ r - np.eye(3)).max() <= 1e-12
    assert abs(np.linalg.det(r) - 1.0) <= 1e-12
    scale = np.abs(m).max()
    assert np.abs(r @ s - m).max() <= 1e-14 * scale
    sv = np.linalg.svd(m, compute_uv=False)
    best = sv[0] + sv[1] + np.sign(np.linalg.det(m)) * sv[2]
    assert np.trace(r.T @ m) >= best - 1e-12 * max(sv[0], 1e-300)
    k = kappa(m)
    if k is not None:
        tol = 20 * EPS * k
        assert np.abs(r - lapack_rotation(m)).max() <= tol
        assert np.abs(s - s.T).max() <= tol * scale


def test_methods_agree_where_unique() -> None:
    for name, m in CASES.items():
        k = kappa(m)
        if k is None:
            continue
        rs = [rr.polar_decomposition(m, method=x)[0] for x in METHODS]
        for r in rs[1:]:
            assert np.abs(r - rs[0]).max() <= 20 * EPS * k, name


def test_inverted_diagonal_gives_identity() -> None:
    m = np.diag([2.0, 1.0, -0.5])
    for method in METHODS:
        r, s = rr.polar_decomposition(m, method=method)
        # κ = 2 / (1 − 0.5) = 4: exact up to a few ε.
        assert np.abs(r - np.eye(3)).max() <= 4 * EPS
        assert np.abs(s - m).max() <= 4 * EPS


@pytest.mark.parametrize("method", METHODS)
def test_batch_matches_one_by_one(method: str) -> None:
    mats = np.stack(list(CASES.values()))
    r, s = rr.polar_decomposition(mats, method=method)
    assert r.shape == mats.shape and s.shape == mats.shape and r.dtype == np.float64
    for k, m in enumerate(mats):
        r1, s1 = rr.polar_decomposition(m, method=method)
        assert np.array_equal(r[k], r1) and np.array_equal(s[k], s1)
    empty_r, empty_s = rr.polar_decomposition(np.zeros((0, 3, 3)), method=method)
    assert empty_r.shape == (0, 3, 3) and empty_s.shape == (0, 3, 3)


def test_muller_warm_start() -> None:
    rots = Rotation.random(5, random_state=3).as_matrix()
    m = rots @ spd(10.0, 3.0, seed=4)
    r_cold, _ = rr.polar_decomposition(m, method="muller")
    r_warm, _ = rr.polar_decomposition(m, method="muller", initial=rots)
    # Same fixed point from either start; κ ≤ 10 here.
    assert np.abs(r_warm - r_cold).max() <= 20 * EPS * 10
    shared, _ = rr.polar_decomposition(m, method="muller", initial=np.eye(3))
    assert np.abs(shared - r_cold).max() <= 20 * EPS * 10


@pytest.mark.parametrize(
    "call, exc, words",
    [
        (lambda: rr.polar_decomposition(np.eye(2)), ValueError, ["M", "(3, 3)", "(N, 3, 3)"]),
        (lambda: rr.polar_decomposition(np.zeros((2, 3, 4))), ValueError, ["M", "shape"]),
        (lambda: rr.polar_decomposition(np.diag([1.0, math.nan, 1.0])), rr.RigidError, ["M", "finite"]),
        (lambda: rr.polar_decomposition(np.stack([np.eye(3), np.full((3, 3), math.inf)])), rr.RigidError, ["M[1]", "finite"]),
        (lambda: rr.polar_decomposition(np.eye(3), method="qr"), rr.RigidError, ["method", "qr", "svd", "higham", "muller"]),
        (lambda: rr.polar_decomposition(np.eye(3), method="svd", initial=np.eye(3)), ValueError, ["initial", "muller"]),
        (lambda: rr.polar_decomposition(np.eye(3), method="muller", initial=2 * np.eye(3)), rr.RigidError, ["initial", "rotation"]),
        (lambda: rr.polar_decomposition(np.eye(3), method="muller", initial=np.diag([1.0, 1.0, -1.0])), rr.RigidError, ["initial", "rotation"]),
        (lambda: rr.polar_decomposition(np.zeros((2, 3, 3)), method="muller", initial=np.zeros((3, 3, 3))), ValueError, ["initial", "3", "2"]),
        (lambda: rr.polar_decomposition("abc"), TypeError, ["M"]),
    ],
    ids=["2x2", "3x4", "nan", "inf in batch", "unknown method", "initial without muller", "scaled initial", "reflection initial", "initial count", "text"],
)
def test_bad_input(call, exc, words) -> None:
    with pytest.raises(exc) as info:
        call()
    for w in words:
        assert w in str(info.value), (w, str(info.value))
