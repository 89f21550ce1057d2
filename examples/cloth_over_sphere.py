"""The README's cloth dropped over a sphere at the default settings, drawn.

REFERENCES.md's "Cloth over a sphere": a 30 × 30 cloth of 1 m (0.3 kg, compliance
1e-7, bending compliance 1) falls from 1 m over a fixed sphere of radius 0.3 m on the
ground, built with ``scene.build(dt=1/60)`` and nothing else. Draws four moments of
the drop (matplotlib, no display needed) and, beside them, its kinetic energy over
the energy the drop releases and its largest link strain, then writes a PNG.

    python examples/cloth_over_sphere.py [--out docs/cloth_over_sphere.png] [--seconds 7]

Needs ``matplotlib`` (``pip install matplotlib``).
"""
from __future__ import annotations

import argparse

import numpy as np

import rigidrs as rr

N, SIZE, RADIUS, HEIGHT, DT = 30, 1.0, 0.3, 1.0, 1 / 60


def scene() -> rr.Scene:
    s = rr.Scene(gravity=(0.0, 0.0, -9.81))
    s.add_body(rr.Plane(normal=(0, 0, 1)), fixed=True)
    s.add_body(rr.Sphere(RADIUS), fixed=True, position=(SIZE / 2, SIZE / 2, RADIUS))
    s.add_cloth((0, 0, HEIGHT), (SIZE, 0, 0), (0, SIZE, 0), (N, N), mass=0.3, compliance=1e-7,
                bending_compliance=1.0)
    return s


def triangles(n: int) -> np.ndarray:
    """The cloth builder's triangles: each cell split along its (i, j)–(i+1, j+1) diagonal."""
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1))
    a = (j * n + i).ravel()
    return np.concatenate([np.stack([a, a + 1, a + n + 1], 1), np.stack([a, a + n + 1, a + n], 1)])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="docs/cloth_over_sphere.png")
    ap.add_argument("--seconds", type=float, default=7.0)
    args = ap.parse_args()

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    world = scene().build(dt=DT)
    tri = triangles(N)
    edges = np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [0, 2]]]), axis=1), axis=0)
    x = world.particles.position
    rest = np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1)
    pe0 = world.potential_energy()
    moments = [0.25, 0.5, 1.0, args.seconds]
    frames, t, ke, pe, strain = {}, [], [], [], []
    while world.time < args.seconds - 1e-9:
        world.step()
        x = world.particles.position
        t.append(world.time)
        ke.append(world.kinetic_energy())
        pe.append(world.potential_energy())
        strain.append((np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1) / rest - 1).max())
        for m in moments:
            if m not in frames and world.time >= m - 1e-9:
                frames[m] = x.copy()
    released = pe0 - pe[-1]

    fig = plt.figure(figsize=(11, 5.6), dpi=80)
    grid = fig.add_gridspec(2, 3, width_ratios=(1, 1, 1.15), wspace=0.02, hspace=0.02,
                            left=0.0, right=0.97, top=0.88, bottom=0.09)
    u, v = np.mgrid[0 : 2 * np.pi : 24j, 0 : np.pi : 12j]
    sphere = [SIZE / 2 + RADIUS * np.cos(u) * np.sin(v), SIZE / 2 + RADIUS * np.sin(u) * np.sin(v),
              RADIUS + RADIUS * np.cos(v)]
    for k, m in enumerate(moments):
        ax = fig.add_subplot(grid[k // 2, k % 2], projection="3d")
        ax.plot_surface(*sphere, color="0.7", linewidth=0, alpha=0.6)
        p = frames[m]
        ax.plot_trisurf(p[:, 0], p[:, 1], p[:, 2], triangles=tri, cmap="viridis", vmin=0.0, vmax=HEIGHT,
                        linewidth=0.15, edgecolor=(0, 0, 0, 0.3))
        ax.set(xlim=(-0.1, 1.1), ylim=(-0.1, 1.1), zlim=(0, 1.05), xticks=[], yticks=[], zticks=[])
        ax.set_box_aspect((1.2, 1.2, 1.05), zoom=1.25)
        ax.view_init(elev=20, azim=-55)
        ax.text2D(0.05, 0.9, f"t = {m:g} s", transform=ax.transAxes, fontsize=10)
    ax = fig.add_subplot(grid[:, 2])
    ax.semilogy(t, np.array(ke) / released, label="kinetic energy / energy released")
    ax.semilogy(t, np.maximum(strain, 1e-6), label="largest link strain")
    ax.axhline(0.1, color="tab:orange", lw=0.8, ls="--")
    ax.axhline(1e-5, color="tab:blue", lw=0.8, ls="--")
    ax.set(xlabel="t (s)", ylim=(1e-8, 2))
    ax.legend(fontsize=8, loc="lower left")
    ax.set_title(f"{world.substeps} substeps per 1/60 s step (the default)", fontsize=10)
    fig.suptitle("The README cloth over a sphere at scene.build(dt=1/60). Dashed: the bars, "
                 "10 % strain and rest at 1e-5 of the released energy", fontsize=10)
    fig.savefig(args.out)
    print(f"{args.out}: max KE / released {max(ke) / released:.3f}, max strain {max(strain):.4f}, "
          f"KE over the last second / released {max(ke[-int(1 / DT):]) / released:.2e}")


if __name__ == "__main__":
    main()
