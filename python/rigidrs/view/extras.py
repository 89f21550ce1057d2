"""Per-frame quantities the core's :class:`rigidrs.Recording` does not hold: energies and
contacts, captured from Python while it steps the world.

``world.record(every)`` captures poses inside the core's step loop, whatever calls
``step``; energies and contacts are read through the Python API, so they are captured
only by stepping through a :class:`Capture`::

    rec = world.record(every=4)
    cap = Capture(world, every=4, contacts=True)   # frame 0 now, as rec's
    cap.step(600)                                  # instead of world.step(600)
    cap.extras.kinetic, cap.extras.contacts(10)    # (T,) J; frame 10's contact points
    cap.extras.save("run.npz", rec)                # one file; rr.Recording.load reads it too

The frames are the recording's (same ``steps``) when both are attached at the same
step with the same ``every``.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .mesh import F64, quat_matrix
from .render import _atomic, _writable_folder

CONTACT_FIELDS = ("body_a", "body_b", "point", "normal", "depth", "normal_impulse", "friction_impulse")
"""The arrays of ``World.contacts()`` kept per frame."""
PREFIX = "extras_"
"""Key prefix of these arrays in a ``.npz`` file (the recording's keys have none)."""


def kinetic_energy(world: Any) -> F64:
    """(N,) kinetic energy of each body (J) from the state read back through the views:
    ½ m |v|² + ½ ωᵀ R diag(I) Rᵀ ω (principal moments I in the body frame, R from the
    orientation); 0 for fixed bodies. Particles are in :func:`particle_kinetic_energy`."""
    b = world.bodies
    m = np.asarray(b.mass)
    moving = np.isfinite(m)
    v, w = np.asarray(b.linear_velocity), np.asarray(b.angular_velocity)
    r = quat_matrix(np.asarray(b.orientation))
    w_body = np.einsum("nji,nj->ni", r, w)  # Rᵀ ω
    e = 0.5 * np.where(moving, m, 0.0) * np.einsum("ni,ni->n", v, v)
    return np.asarray(e + 0.5 * np.where(moving, np.einsum("ni,ni,ni->n", w_body, np.asarray(b.inertia), w_body), 0.0))


def particle_kinetic_energy(world: Any) -> float:
    """½ Σ m |v|² over the particles that are not pinned (J)."""
    p = world.particles
    free = np.asarray(p.inverse_mass) > 0
    v = np.asarray(p.velocity)
    return float(0.5 * np.sum(np.asarray(p.mass)[free] * np.einsum("ni,ni->n", v, v)[free]))


@dataclass
class Extras:
    """Energies and contacts per frame: ``times`` (T,) (s), ``steps`` (T,), ``kinetic``
    (T,) bodies plus particles (J, from :func:`kinetic_energy`), ``potential`` (T,)
    gravitational (J, ``World.potential_energy``), and, when captured, the contacts of
    every frame concatenated: ``contact[name]`` for each of :data:`CONTACT_FIELDS`
    ((K, ...), as ``World.contacts()`` gives them), frame k's rows being
    ``contact_start[k]:contact_start[k + 1]``. Empty arrays when not captured."""

    times: F64 = field(default_factory=lambda: np.zeros(0))
    steps: Any = field(default_factory=lambda: np.zeros(0, np.int64))
    kinetic: F64 = field(default_factory=lambda: np.zeros(0))
    potential: F64 = field(default_factory=lambda: np.zeros(0))
    contact_start: Any = field(default_factory=lambda: np.zeros(1, np.int64))
    contact: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.times)

    def contacts(self, k: int) -> dict[str, Any]:
        """Frame ``k``'s contacts, as ``World.contacts()`` returned them at that frame."""
        if not self.contact:
            raise ValueError("no contacts were captured (Capture(..., contacts=True))")
        k = range(len(self))[k]
        a, b = int(self.contact_start[k]), int(self.contact_start[k + 1])
        return {name: arr[a:b] for name, arr in self.contact.items()}

    def arrays(self) -> dict[str, Any]:
        out = {"times": self.times, "steps": self.steps, "kinetic": self.kinetic, "potential": self.potential,
               "contact_start": self.contact_start}
        out.update({f"contact_{k}": v for k, v in self.contact.items()})
        return {PREFIX + k: np.asarray(v) for k, v in out.items()}

    def save(self, path: str | os.PathLike[str], rec: Any = None) -> None:
        """Writes these arrays (keys prefixed ``extras_``) to ``path`` (.npz), with the
        recording ``rec``'s arrays when given (then ``rr.Recording.load(path)`` reads the
        same file), through a temporary name and a rename."""
        path = Path(path)
        _writable_folder(path)

        def write(tmp: Path) -> None:
            data = {}
            if rec is not None:
                rec.save(tmp)
                with np.load(tmp) as f:
                    data = {k: f[k] for k in f.files}
            data.update(self.arrays())
            with open(tmp, "wb") as fh:
                np.savez(fh, **data)

        _atomic(path, write)

    @staticmethod
    def load(path: str | os.PathLike[str]) -> Extras:
        """Reads the arrays :meth:`save` wrote; ``ValueError`` if the file has none."""
        with np.load(Path(path)) as f:
            if PREFIX + "times" not in f.files:
                raise ValueError(f"{path}: holds no energies or contacts (no '{PREFIX}times' array)")
            get = {k[len(PREFIX):]: f[k] for k in f.files if k.startswith(PREFIX)}
        contact = {k[len("contact_"):]: v for k, v in get.items() if k.startswith("contact_") and k != "contact_start"}
        return Extras(get["times"], get["steps"], get["kinetic"], get["potential"], get["contact_start"], contact)


class Capture:
    """Steps a world and captures :class:`Extras` at the step it is made and then every
    ``every``-th step (default 1), as ``world.record(every)`` does for poses.
    ``energies`` (default True), ``contacts`` (default False). Step with :meth:`step`."""

    def __init__(self, world: Any, every: int = 1, *, energies: bool = True, contacts: bool = False) -> None:
        if int(every) < 1:
            raise ValueError(f"every must be a positive number of steps, got {every!r}")
        self.world, self.every = world, int(every)
        self.energies, self.with_contacts = energies, contacts
        self._start = world.steps
        self._rows: list[tuple[float, int, float, float]] = []
        self._contacts: list[dict[str, Any]] = []
        self._grab()

    def _grab(self) -> None:
        w = self.world
        ke = float(kinetic_energy(w).sum() + particle_kinetic_energy(w)) if self.energies else np.nan
        pe = float(w.potential_energy()) if self.energies else np.nan
        self._rows.append((w.time, w.steps, ke, pe))
        if self.with_contacts:
            c = w.contacts()
            self._contacts.append({k: np.array(c[k]) for k in CONTACT_FIELDS})

    def step(self, n: int = 1) -> None:
        """Steps the world ``n`` times, in runs up to each capture step. A failing step
        raises as ``World.step`` does; the frames before it are kept."""
        left = int(n)
        while left > 0:
            to_next = self.every - (self.world.steps - self._start) % self.every
            k = min(left, to_next)
            self.world.step(k)
            left -= k
            if (self.world.steps - self._start) % self.every == 0:
                self._grab()

    @property
    def extras(self) -> Extras:
        """The frames captured so far."""
        rows = np.array(self._rows, dtype=float).reshape(-1, 4)
        contact: dict[str, Any] = {}
        start = np.zeros(len(self._contacts) + 1, np.int64)
        if self.with_contacts:
            start[1:] = np.cumsum([len(c["depth"]) for c in self._contacts])
            contact = {k: np.concatenate([c[k] for c in self._contacts]) for k in CONTACT_FIELDS}
        return Extras(rows[:, 0], rows[:, 1].astype(np.int64), rows[:, 2], rows[:, 3], start, contact)
