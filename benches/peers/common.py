"""Small helpers shared by the rigidrs versions of the peer-engine scenes (numpy only).

Copied from the peer-engine scenes' common.py (shared/bench/peers/common.py of this
project's workspace, the scripts that build the same scenes in MuJoCo, PyBullet and
Rapier), so that both sides generate identical initial states and measure the same
invariants; kept verbatim except for this docstring and `versions()`, which also
reports rigidrs. Keep the two in step if either changes.
"""
import json
import os
import sys

import numpy as np

ENGINES = ("mujoco", "pybullet", "rapier3d")


def box_inertia(mass, size):
    """Principal moments (3,) of a solid box with full edge lengths `size`."""
    a, b, c = size
    return mass / 12.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])


def random_quats_xyzw(rng, n):
    """Uniform random unit quaternions, (n, 4) in (x, y, z, w) order."""
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[q[:, 3] < 0] *= -1
    return q


def quat_to_mat(q_xyzw):
    """(n, 4) quaternions in (x, y, z, w) order -> (n, 3, 3) rotation matrices."""
    q = np.asarray(q_xyzw, dtype=float).reshape(-1, 4)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    x, y, z, w = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], 1)


def wxyz(q_xyzw):
    q = np.asarray(q_xyzw)
    return q[..., [3, 0, 1, 2]]


def xyzw(q_wxyz):
    q = np.asarray(q_wxyz)
    return q[..., [1, 2, 3, 0]]


def rot_invariants(q_xyzw, w_world, inertia):
    """Rotational KE (per body) and world-frame angular momentum (n, 3).

    inertia: (3,) or (n, 3) principal moments in the body frame."""
    R = quat_to_mat(q_xyzw)
    w_body = np.einsum("nji,nj->ni", R, np.asarray(w_world, dtype=float).reshape(-1, 3))
    I = np.broadcast_to(inertia, w_body.shape)
    ke = 0.5 * np.sum(I * w_body ** 2, axis=1)
    L = np.einsum("nij,nj->ni", R, I * w_body)
    return ke, L


def emit(result):
    """Print the one JSON line of a run."""
    print(json.dumps(result, sort_keys=False), flush=True)


def versions():
    """Installed versions of the interpreter and the peer engines (without importing them)."""
    from importlib.metadata import PackageNotFoundError, version
    out = {"python": sys.version.split()[0]}
    for dist in ("numpy", "scipy", "rigidrs", "mujoco", "pybullet", "rapier3d", "warp-lang"):
        try:
            out[dist] = version(dist)
        except PackageNotFoundError:
            out[dist] = None
    return out


def import_pybullet():
    """Import pybullet, sending its C-level build banner to stderr (stdout stays JSON)."""
    sys.stdout.flush()
    saved = os.dup(1)
    os.dup2(2, 1)
    try:
        import pybullet
    finally:
        os.dup2(saved, 1)
        os.close(saved)
    return pybullet
