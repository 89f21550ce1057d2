"""REFERENCES.md, "Contacts and joints at default settings": the cloth over a sphere.

The README's cloth (30 × 30 particles over 1 m, compliance 1e-7, bending compliance 1,
0.3 kg) dropped from 1 m over a fixed sphere of radius 0.3 m standing on the ground,
at the settings a user gets without asking (``scene.build(dt)``), and the same case at
other sizes and rates. Bars, computed in the test from the run itself:

* energy: the kinetic energy never exceeds the energy the drop releases,
  ``PE(0) − PE(rest)`` (potential energy relative to the rest height), and no energy
  is created: ``KE + PE ≤ PE(0)`` at every step;
* stretch: no distance link is ever longer than 1.1 × its rest length;
* rest: over the final second the kinetic energy stays below 1e-5 of the released
  energy. For the README cloth that is an rms particle speed under
  √(2·1e-5·1.74 J / 0.3 kg) ≈ 1.1 cm/s, 0.4 % of the 2.8 m/s it hits the sphere
  with (measured there: 3.3 mm/s rms, the fastest corner 3.7 cm/s, over the last
  second). The run lasts 7 s × √(size / 1 m): a drape's motions scale with
  √(size / g).

What broke, and the regression tests named after it:

* one forward Gauss–Seidel sweep per substep made the slowest in-plane modes of a
  cloth's stretch links grow by 0.8 % per substep (``rust/xpbd/solver.rs`` has the
  analysis): a flat cloth lying still pumped itself up, and with bending (which keeps
  it from crumpling the growth away) the README cloth over the sphere blew up
  (kinetic energy 3.7e4 J from 2.9 J of potential energy, links 1900 × their
  length, at the old default of one substep). Folds past ±π and the sphere's
  contacts were not needed for it: a cloth pinned at two corners in the air blew up
  the same way, its dihedral angles all below 0.02 rad while its energy grew, and a
  flat cloth without bending on a frictionless floor too;
* at the old default of one substep, even without the blow-up, a 60 Hz step moves
  the cloth 1.4 links per substep at impact: links stretched 180 %. Worlds with
  particle links now take the substeps their links ask for
  (``rust/xpbd/substeps.rs``).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rigidrs as rr

G = 9.81


def cloth_edges(n: int) -> np.ndarray:
    """The distance links of ``add_cloth``'s (n × n) grid: rows, columns and the
    (i, j)–(i+1, j+1) diagonals, as particle index pairs."""
    idx = np.arange(n * n).reshape(n, n)  # [j, i] -> j·n + i
    return np.concatenate([
        np.stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()], 1),
        np.stack([idx[:-1, :].ravel(), idx[1:, :].ravel()], 1),
        np.stack([idx[:-1, :-1].ravel(), idx[1:, 1:].ravel()], 1),
    ])


def cloth_over_sphere(n: int, size: float, radius: float, height: float, **cloth) -> rr.Scene:
    """The README cloth scaled: an n × n cloth of side ``size`` at ``height`` over a
    fixed sphere of ``radius`` resting on the ground under its centre."""
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(normal=(0, 0, 1)), fixed=True)
    scene.add_body(rr.Sphere(radius), fixed=True, position=(size / 2, size / 2, radius))
    scene.add_cloth((0, 0, height), (size, 0, 0), (0, size, 0), (n, n), mass=0.3, compliance=1e-7,
                    bending_compliance=1.0, **cloth)
    return scene


def drop(world: rr.World, n: int, seconds: float) -> dict[str, np.ndarray | float]:
    """Steps ``seconds`` and records, per step, the kinetic and potential energy and
    the largest link strain."""
    edges = cloth_edges(n)
    x = world.particles.position
    rest = np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1)
    pe0 = world.potential_energy()
    ke, pe, strain = [], [], []
    for _ in range(math.ceil(seconds / world.dt - 1e-9)):
        world.step()
        x = world.particles.position
        strain.append((np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1) / rest - 1).max())
        ke.append(world.kinetic_energy())
        pe.append(world.potential_energy())
    return {"pe0": pe0, "ke": np.array(ke), "pe": np.array(pe), "strain": np.array(strain)}


CASES = {
    # name: (n, size m, sphere radius m, height m, dt s)
    "readme, 60 Hz": (30, 1.0, 0.3, 1.0, 1 / 60),
    "0.6 m, 120 Hz": (20, 0.6, 0.18, 0.6, 1 / 120),
    "2 m, 30 Hz": (20, 2.0, 0.6, 2.0, 1 / 30),
}


@pytest.mark.parametrize("case", list(CASES))
def test_cloth_over_a_sphere_at_default_settings(case: str) -> None:
    """Measured (bars in brackets): largest kinetic energy 0.67 / 0.71 / 0.73 of the
    released energy [≤ 1]; KE + PE − PE(0) never above −5e-5 of PE(0) (the free fall
    loses ½g²h² per substep) [≤ 0]; largest strain 5.6 / 6.1 / 6.1 % [≤ 10 %];
    kinetic energy over the final second 2.5e-6 / 4.5e-7 / 4.5e-6 of the released
    energy [≤ 1e-5], below it for good after 4.7 / 3.0 / 8.0 s."""
    n, size, radius, height, dt = CASES[case]
    world = cloth_over_sphere(n, size, radius, height).build(dt=dt)
    r = drop(world, n, 7.0 * math.sqrt(size))
    ke, pe, pe0 = r["ke"], r["pe"], r["pe0"]
    released = pe0 - pe[-1]
    # The drape ends below where it started, on the sphere: a third to a half of the
    # height lost on average (the README cloth: mean height 1 m -> 0.39 m).
    assert 0.3 * pe0 < released < pe0
    assert ke.max() <= released, (ke.max() / released)
    # Energy created: none. Rounding of the sums is ~1e-16 of PE(0).
    assert (ke + pe).max() <= pe0 * (1 + 1e-12), ((ke + pe).max() / pe0 - 1)
    assert r["strain"].max() <= 0.10, r["strain"].max()
    last = int(round(1.0 / dt))
    assert ke[-last:].max() <= 1e-5 * released, (ke[-last:].max() / released)


def test_readme_cloth_over_a_sphere_does_not_blow_up_at_one_substep() -> None:
    """The old default (one substep of 1/60 s, one forward sweep) blew up: KE + PE
    reached 1.2e4 × PE(0) within 1.5 s. With the symmetric pass the same single
    substep creates no energy (measured: the largest KE + PE is PE(0) less 1.4e-3 of
    it); it stretches the cloth by 180 % (one substep is far too coarse for its
    links), which is why the default now takes more."""
    n = 30
    world = cloth_over_sphere(n, 1.0, 0.3, 1.0).build(dt=1 / 60, substeps=1)
    r = drop(world, n, 3.0)
    assert (r["ke"] + r["pe"]).max() <= r["pe0"] * (1 + 1e-12)
    assert np.isfinite(world.particles.position).all()


def test_gauss_seidel_pass_does_not_pump_a_flat_cloth() -> None:
    """A cloth lying flat on a frictionless floor, kicked in its plane by 1e-4 m/s
    noise: only its stretch links act in the plane. One forward sweep per substep
    grew the noise to 5.6 m/s rms within 2 s (0.8 % per substep); the symmetric pass
    is a self-adjoint contraction of the velocities, so the in-plane speed can only
    fall (measured: 1e-4 -> 5.5e-6 m/s, the rigid drift of the noise). Bar: never
    above its start."""
    n = 30
    scene = rr.Scene(gravity=(0.0, 0.0, -G))
    scene.add_body(rr.Plane(normal=(0, 0, 1)), fixed=True)
    scene.add_cloth((0, 0, 0), (1, 0, 0), (0, 1, 0), (n, n), mass=0.3, compliance=1e-7, friction=0.0)
    world = scene.build(dt=1 / 60, substeps=16)
    world.particles.velocity[:, :2] = 1e-4 * np.random.default_rng(0).standard_normal((n * n, 2))

    def rms() -> float:
        return float(np.sqrt((world.particles.velocity[:, :2] ** 2).sum(1).mean()))

    start = rms()
    for _ in range(120):
        world.step()
        assert rms() <= start


def test_particle_worlds_choose_their_substeps_from_their_links() -> None:
    """The default: per linked structure, h ≤ 0.1 · (shortest link) / v_ref with
    v_ref = max(√(2|g|ℓ), fastest initial speed), ℓ the structure's bounding-box
    diagonal; never fewer than the world would take anyway (4 with contacts)."""
    for dt in (1 / 30, 1 / 60, 1 / 240):
        world = cloth_over_sphere(30, 1.0, 0.3, 1.0).build(dt=dt)
        v_ref = math.sqrt(2 * G * math.sqrt(2.0))
        assert world.substeps == math.ceil(dt * v_ref / (0.1 / 29))
    assert cloth_over_sphere(30, 1.0, 0.3, 1.0).build(dt=1 / 60).substeps == 26
    assert cloth_over_sphere(30, 1.0, 0.3, 1.0).build(dt=1 / 60, substeps=3).substeps == 3  # the user's wins
    # A rope thrown at 20 m/s in zero gravity: its speed sets the bound.
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    rope = scene.add_rope((0, 0, 0), (1, 0, 0), 10, mass=0.1)
    assert scene.build(dt=1 / 60).substeps == 1  # at rest, without gravity: nothing to carry
    p = scene.add_particle((5, 0, 0), velocity=(0, 0, 20.0))  # not linked: does not count
    assert scene.build(dt=1 / 60).substeps == 1
    scene.add_distance_constraint(rope[-1], p)  # now it is: 20 m/s against links of 0.1 m
    assert scene.build(dt=1 / 60).substeps == math.ceil((1 / 60) * 20.0 / (0.1 * 0.1))


def flap_decay_rate(bending_damping: float | None) -> tuple[float, float]:
    """A 2 × 2 cloth with three corners pinned: the free corner flaps about the
    diagonal on its two rigid links, held by the one bending constraint. Returns the
    measured decay rate of the flap's amplitude (1/s) and ω² = 1/(α I)."""
    alpha, mass = 1.0, 1.0  # rad/(N·m); 0.25 kg per particle
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    kw = {} if bending_damping is None else {"bending_damping": bending_damping}
    scene.add_cloth((0, 0, 0), (1, 0, 0), (0, 1, 0), (2, 2), mass=mass, bending_compliance=alpha,
                    pinned=[0, 1, 3], **kw)
    world = scene.build(dt=1 / 60, substeps=16)
    world.particles.velocity[2] = (0.0, 0.0, 0.01)  # a small swing: the linear regime
    inertia = mass / 4 * 0.5  # the tip is 1/√2 m from the diagonal
    z = []
    for _ in range(600):
        world.step()
        z.append(world.particles.position[2, 2])
    z = np.array(z)
    peaks = [k for k in range(1, len(z) - 1) if z[k - 1] < z[k] >= z[k + 1]]
    t = np.array(peaks) / 60.0
    slope = np.polyfit(t, np.log(z[peaks]), 1)[0]
    return -slope, 1.0 / (alpha * inertia)


def test_cloth_bending_damping_defaults_to_stiffness_proportional() -> None:
    """Default ``bending_damping`` = 0.05 s / ``bending_compliance``: a flap of
    frequency ω decays as exp(−0.05 s · ω² t / 2) (damping ratio 0.05 s · ω / 2), on
    top of XPBD's own damping, which is implicit Euler's: exp(−h ω² t / 2) for a
    substep h. Here ω² = 8 /s², h = 1/960 s: rates 0.2042 /s and 0.00417 /s; measured
    0.2044 and 0.00417. Bar 1 %: peaks of a 0.45 Hz swing sampled at 60 Hz, and a
    swing of 1 cm/s keeps the angle below 0.01 rad, where the flap is linear to 1e-4."""
    h = 1 / 60 / 16
    rate, omega2 = flap_decay_rate(None)
    assert rate == pytest.approx((0.05 + h) * omega2 / 2, rel=0.01)
    undamped, _ = flap_decay_rate(0.0)
    assert undamped == pytest.approx(h * omega2 / 2, rel=0.01)
    explicit, _ = flap_decay_rate(0.05)  # 0.05 N·m·s/rad = the default at α = 1
    assert explicit == rate


def test_bending_damping_is_checked() -> None:
    scene = rr.Scene()
    with pytest.raises(ValueError, match="bending_damping"):
        scene.add_cloth((0, 0, 0), (1, 0, 0), (0, 1, 0), (3, 3), bending_compliance=1.0, bending_damping=-1.0)
    with pytest.raises(ValueError, match="bending_damping needs bending_compliance"):
        scene.add_cloth((0, 0, 0), (1, 0, 0), (0, 1, 0), (3, 3), bending_damping=1.0)
    assert scene.particle_count == 0 and scene.constraint_count == 0
