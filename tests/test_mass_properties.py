"""Mass, centre of mass and inertia of every shape, of sampled densities, and of the
bodies built from them, against closed forms derived here or an independent
computation (a tetrahedron integration in NumPy).

Tolerances. The engine and the references below both evaluate closed forms or sums
of at most a few thousand terms in f64: their round-off is below ~1e-13 relative.
``RTOL = 1e-12`` keeps a margin of ten over that and is still ~1e9 times smaller
than any formula error (a wrong factor or a missed parallel-axis term changes a
moment by ≥ 1e-3 relative). Off-diagonal terms and vectors that should vanish are
compared with an absolute tolerance scaled by the largest entry of the same
quantity (``RTOL * scale``), since a relative test against zero cannot pass.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial import ConvexHull as SciHull
from scipy.spatial.transform import Rotation

import rigidrs as rr

RTOL = 1e-12
RHO = 1000.0  # kg/m³ (water): an ordinary magnitude, so absolute errors are not tiny by accident

Q_FRAME = Rotation.from_rotvec([0.3, -0.5, 0.8])  # a generic orientation (no symmetry)
P_FRAME = np.array([1.0, -2.0, 0.5])


def close(actual, expected, scale=None, rtol=RTOL):
    """Asserts |actual - expected| <= rtol * scale elementwise; scale defaults to the
    largest |expected| so that zero entries get an absolute tolerance of that size."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    if scale is None:
        scale = max(np.abs(expected).max(), 1e-300)
    err = np.abs(actual - expected).max()
    assert err <= rtol * scale, f"error {err:.3e} > {rtol:.0e} x {scale:.3e}\nactual\n{actual}\nexpected\n{expected}"


def same_rotation(q_xyzw, r_expected, tol=1e-13):
    """Compares a quaternion (either sign) with a rotation matrix. The matrix of a unit
    quaternion carries a few ulp of round-off per entry: 1e-13 bounds it."""
    close(Rotation.from_quat(q_xyzw).as_matrix(), r_expected, scale=1.0, rtol=tol)


# ---------------------------------------------------------------------------
# Closed forms, derived here (density RHO, shapes in their own frame, axis z)
# ---------------------------------------------------------------------------


def sphere_ref(r):
    m = RHO * 4.0 / 3.0 * math.pi * r**3
    return m, np.zeros(3), np.eye(3) * 0.4 * m * r**2


def box_ref(h):
    hx, hy, hz = h
    m = RHO * 8.0 * hx * hy * hz
    # ∫(y²+z²) dm over [-h, h]: each ∫x² dm = m h²/3.
    return m, np.zeros(3), np.diag([hy**2 + hz**2, hx**2 + hz**2, hx**2 + hy**2]) * m / 3.0


def cylinder_ref(r, hh):
    length = 2.0 * hh
    m = RHO * math.pi * r**2 * length
    axial = 0.5 * m * r**2
    transverse = m * (3.0 * r**2 + length**2) / 12.0
    return m, np.zeros(3), np.diag([transverse, transverse, axial])


def capsule_ref(r, hh):
    """Cylinder of length 2 hh plus two hemispheres, each shifted by the parallel-axis
    theorem from its own centre of mass (3r/8 from its flat face) to the capsule's."""
    m_cyl, _, i_cyl = cylinder_ref(r, hh)
    m_hemi = RHO * 2.0 / 3.0 * math.pi * r**3
    # A hemisphere about the centre of its flat face: 2/5 m r² about every axis through
    # that point (half a ball). About its own centre of mass, transverse:
    # 2/5 m r² − m (3r/8)² = 83/320 m r².
    i_hemi_t = (0.4 - (3.0 / 8.0) ** 2) * m_hemi * r**2
    d = hh + 3.0 * r / 8.0  # distance of each hemisphere's centre of mass from the middle
    transverse = i_cyl[0, 0] + 2.0 * (i_hemi_t + m_hemi * d**2)
    axial = i_cyl[2, 2] + 2.0 * (0.4 * m_hemi * r**2)
    return m_cyl + 2.0 * m_hemi, np.zeros(3), np.diag([transverse, transverse, axial])


def cone_ref(r, hh):
    """Solid cone, base disc at z = −hh, apex at z = +hh (height H = 2 hh).

    Slices at height s above the base have radius r (1 − s/H) and area ∝ (1 − s/H)²:
    m = ρ π r² H / 3, centre of mass at s = H/4 (so z = −hh + H/4 = −hh/2),
    I_zz = ∫ ½ r(s)² dm = 3/10 m r², and about the centre of mass
    I_xx = ∫ (¼ r(s)² + (s − H/4)²) dm = 3/20 m r² + 3/80 m H².
    """
    height = 2.0 * hh
    m = RHO * math.pi * r**2 * height / 3.0
    transverse = 3.0 / 20.0 * m * r**2 + 3.0 / 80.0 * m * height**2
    return m, np.array([0.0, 0.0, -hh + height / 4.0]), np.diag([transverse, transverse, 0.3 * m * r**2])


# ---------------------------------------------------------------------------
# An independent polyhedron integration (divergence theorem via tetrahedra)
# ---------------------------------------------------------------------------


def polyhedron_mass_properties(vertices, triangles, density):
    """Mass, centre of mass and inertia about it of a closed, outward-oriented
    triangle mesh: sum over the tetrahedra (origin, a, b, c) with signed volumes.

    For a tetrahedron with edge matrix A = [a b c] (columns), ∫ x xᵀ dV =
    det(A)/120 · A (1 + Id) Aᵀ with 1 the all-ones matrix; ∫ x dV = det(A)/24 (a+b+c).
    """
    v = np.asarray(vertices, float)
    t = np.asarray(triangles)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    volume = det.sum() / 6.0
    first = (det[:, None] * (a + b + c)).sum(0) / 24.0
    canonical = (np.ones((3, 3)) + np.eye(3)) / 120.0
    edges = np.stack([a, b, c], axis=2)  # (T, 3, 3): columns a, b, c
    second = np.einsum("t,tik,kl,tjl->ij", det, edges, canonical, edges)
    mass = density * volume
    com = first / volume
    cov = density * second - mass * np.outer(com, com)  # ∫ρ r rᵀ about the centre of mass
    inertia = np.trace(cov) * np.eye(3) - cov
    return mass, com, inertia


def outward_hull_mesh(points):
    """Triangles of the convex hull of ``points``, counter-clockwise seen from outside."""
    hull = SciHull(points)
    tris = []
    for simplex, eq in zip(hull.simplices, hull.equations):
        a, b, c = points[simplex]
        tris.append(simplex if np.cross(b - a, c - a) @ eq[:3] > 0 else simplex[::-1])
    return np.array(tris, dtype=np.int64)


def box_corners(h):
    return np.array([[sx * h[0], sy * h[1], sz * h[2]] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])


def fibonacci_ellipsoid(n, semi_axes):
    """``n`` points spread over an ellipsoid (a convex set, so its hull is a closed mesh)."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = math.pi * (3.0 - math.sqrt(5.0)) * k
    s = np.sqrt(1.0 - z * z)
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1) * semi_axes


# ---------------------------------------------------------------------------
# Primitive shapes: shape.mass_properties and a body's mass/inertia
# ---------------------------------------------------------------------------

PRIMITIVES = [
    ("sphere", lambda: rr.Sphere(0.3), lambda: sphere_ref(0.3)),
    ("box", lambda: rr.Box((0.1, 0.2, 0.45)), lambda: box_ref((0.1, 0.2, 0.45))),
    ("capsule", lambda: rr.Capsule(0.2, 0.5), lambda: capsule_ref(0.2, 0.5)),
    ("cylinder", lambda: rr.Cylinder(0.2, 0.5), lambda: cylinder_ref(0.2, 0.5)),
    ("cone", lambda: rr.Cone(0.3, 0.5), lambda: cone_ref(0.3, 0.5)),
    # A flat capsule/cylinder/cone, where the axial moment is the largest: catches a
    # swapped axis that the long ones above might hide.
    ("cylinder_flat", lambda: rr.Cylinder(0.5, 0.05), lambda: cylinder_ref(0.5, 0.05)),
    ("cone_flat", lambda: rr.Cone(0.5, 0.1), lambda: cone_ref(0.5, 0.1)),
    ("capsule_flat", lambda: rr.Capsule(0.4, 0.02), lambda: capsule_ref(0.4, 0.02)),
]


@pytest.mark.parametrize("name,make,ref", PRIMITIVES, ids=[p[0] for p in PRIMITIVES])
def test_shape_mass_properties_match_closed_form(name, make, ref):
    shape = make()
    m, com, inertia = ref()
    mp = shape.mass_properties(RHO)
    close(mp.mass, m)
    close(mp.center_of_mass, com, scale=max(np.abs(com).max(), 1.0))
    close(mp.inertia, inertia)
    close(shape.volume(), m / RHO)
    # The shape's axes are principal: moments in the given axis order, frame identity.
    close(mp.principal_moments, np.diag(inertia))
    close(mp.principal_axes, np.eye(3), scale=1.0)


@pytest.mark.parametrize("name,make,ref", PRIMITIVES, ids=[p[0] for p in PRIMITIVES])
def test_body_from_shape_is_its_centre_of_mass_in_the_shape_frame(name, make, ref):
    m, com, inertia = ref()
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    i = scene.add_body(make(), density=RHO, position=P_FRAME, orientation=Q_FRAME.as_quat())
    j = scene.add_body(make(), mass=2.5)  # uniform density scaled to 2.5 kg
    world = scene.build(dt=0.01)
    b = world.bodies
    r = Q_FRAME.as_matrix()
    close(b.mass[i], m)
    close(b.inverse_mass[i], 1.0 / m)
    close(b.inertia[i], np.diag(inertia))
    close(b.inverse_inertia[i], 1.0 / np.diag(inertia))
    # README: for these shapes the principal frame is the shape frame; the state is
    # the centre of mass, i.e. position + R com (the cone's sits below its middle).
    close(b.position[i], P_FRAME + r @ com, scale=np.abs(P_FRAME).max())
    same_rotation(b.orientation[i], r)
    close(b.inertia_world[i], r @ inertia @ r.T)
    # mass= scales the uniform-density inertia by 2.5/m.
    close(b.mass[j], 2.5)
    close(b.inertia[j], np.diag(inertia) * 2.5 / m)
    close(b.position[j], com, scale=max(np.abs(com).max(), 1.0))


def test_cone_centre_of_mass_is_a_quarter_of_the_height_above_the_base():
    r, hh = 0.25, 0.6
    mp = rr.Cone(r, hh).mass_properties(RHO)
    base, apex = -hh, hh
    close(mp.center_of_mass, [0.0, 0.0, base + 0.25 * (apex - base)], scale=hh)


# ---------------------------------------------------------------------------
# ConvexHull and TriMesh
# ---------------------------------------------------------------------------


def test_convex_hull_of_box_corners_is_the_box():
    h = np.array([0.1, 0.2, 0.45])
    m, _, inertia = box_ref(h)
    # Interior points must not change the hull: add a few strictly inside.
    rng = np.random.default_rng(1)
    inside = rng.uniform(-0.9, 0.9, size=(20, 3)) * h
    pts_local = np.vstack([box_corners(h), inside])
    r, t = Q_FRAME.as_matrix(), P_FRAME
    mp = rr.ConvexHull(pts_local @ r.T + t).mass_properties(RHO)
    close(mp.mass, m)
    close(mp.center_of_mass, t, scale=np.abs(t).max())
    close(mp.inertia, r @ inertia @ r.T)
    # Non-diagonal tensor: principal moments ascending, axes = box axes up to sign.
    order = np.argsort(np.diag(inertia))
    close(mp.principal_moments, np.diag(inertia)[order])
    overlap = np.abs(r[:, order].T @ mp.principal_axes)
    close(overlap, np.eye(3), scale=1.0, rtol=1e-10)  # eigenvectors: ~cond · eps ≈ 1e-15, margin


@pytest.mark.parametrize("thickness", [1e-3, 1e-5])
@pytest.mark.parametrize("rotvec", [[0.0, 0.0, 0.0], [0.3, -0.5, 0.8]], ids=["aligned", "rotated"])
def test_convex_hull_of_a_thin_plate_keeps_its_mass(thickness, rotvec):
    """Regression: parry's quickhull took a cloud thinner than ~1/1000 of its width for
    a flat polygon; the hull of a 2 x 1.4 m plate 2 mm thick had mass 0 (aligned) or
    ~1e-16 of the true one (rotated, silently accepted)."""
    h = np.array([1.0, 0.7, thickness])
    r = Rotation.from_rotvec(rotvec).as_matrix()
    m, _, inertia = box_ref(h)
    mp = rr.ConvexHull(box_corners(h) @ r.T).mass_properties(RHO)
    # A volume of relative thickness t from coordinates of size ~1 carries round-off
    # ~eps/t (measured 2.4e-14 at t = 1e-3, 1.3e-12 at 1e-5): 2e-14/t is the bar.
    tol = 2e-14 / thickness
    close(mp.mass, m, rtol=tol)
    close(mp.inertia, r @ inertia @ r.T, rtol=tol)


@pytest.mark.parametrize("thickness", [1e-3, 1e-4])
def test_convex_hull_of_a_thin_random_cloud_matches_tetrahedron_integration(thickness):
    """Regression, second half: even with the right hull, parry's polyhedron merges
    faces whose normals differ by < ~1.7e-4 rad and fans them, dropping the vertices
    inside; on a thin cloud that lost 0.2 % of the mass at t = 1e-3, 17 % at 1e-4."""
    rng = np.random.default_rng(3)
    local = rng.uniform(-1.0, 1.0, size=(40, 3)) * [1.0, 1.0, thickness]
    pts = local @ Q_FRAME.as_matrix().T
    m_ref, c_ref, i_ref = polyhedron_mass_properties(pts, outward_hull_mesh(pts), RHO)
    mp = rr.ConvexHull(pts).mass_properties(RHO)
    tol = 2e-14 / thickness  # as for the thin plate: round-off ~eps/t
    close(mp.mass, m_ref, rtol=tol)
    close(mp.center_of_mass, c_ref, scale=1.0, rtol=tol)
    close(mp.inertia, i_ref, rtol=tol)


def test_trimesh_of_rotated_translated_box_matches_box_and_tet_integration():
    h = np.array([0.1, 0.2, 0.45])
    corners = box_corners(h)
    tris = outward_hull_mesh(corners)  # 12 triangles
    r, t = Q_FRAME.as_matrix(), P_FRAME
    verts = corners @ r.T + t
    m, _, inertia = box_ref(h)
    mp = rr.TriMesh(verts, tris).mass_properties(RHO)
    m2, c2, i2 = polyhedron_mass_properties(verts, tris, RHO)
    close(m2, m)  # the reference integration itself reproduces the box
    close(i2, r @ inertia @ r.T)
    close(mp.mass, m)
    close(mp.center_of_mass, t, scale=np.abs(t).max())
    close(mp.inertia, r @ inertia @ r.T)


def test_trimesh_ellipsoid_matches_tetrahedron_integration_and_convex_hull():
    semi = np.array([0.15, 0.25, 0.4])  # distinct: three distinct principal moments
    local = fibonacci_ellipsoid(300, semi)
    r, t = Q_FRAME.as_matrix(), P_FRAME
    verts = local @ r.T + t
    tris = outward_hull_mesh(verts)
    m_ref, c_ref, i_ref = polyhedron_mass_properties(verts, tris, RHO)
    # Sanity of the reference: a 300-point polyhedron inscribed in the ellipsoid has
    # a slightly smaller volume (chord error ~ 1/N ≈ a few %), never a larger one.
    v_ell = 4.0 / 3.0 * math.pi * semi.prod()
    assert 0.95 * v_ell < m_ref / RHO < v_ell
    for shape in (rr.TriMesh(verts, tris), rr.ConvexHull(verts)):
        mp = shape.mass_properties(RHO)
        close(mp.mass, m_ref)
        close(mp.center_of_mass, c_ref, scale=np.abs(c_ref).max())
        close(mp.inertia, i_ref)
        axes = mp.principal_axes
        close(axes.T @ axes, np.eye(3), scale=1.0)
        close(np.linalg.det(axes), 1.0, scale=1.0)
        close(axes.T @ i_ref @ axes, np.diag(mp.principal_moments), scale=np.abs(i_ref).max(), rtol=1e-11)


def test_non_convex_trimesh_matches_tetrahedron_integration():
    # A star-shaped, bumpy surface: radial scaling of a sphere triangulation keeps it
    # closed and embedded, and the bumps make it non-convex.
    d = fibonacci_ellipsoid(400, np.ones(3))
    tris = outward_hull_mesh(d)
    radius = 0.3 * (1.0 + 0.35 * np.sin(5.0 * d[:, 0]) * np.cos(4.0 * d[:, 1]))
    verts = d * radius[:, None] * [1.0, 0.7, 1.3] + [0.5, 0.2, -0.3]
    m_ref, c_ref, i_ref = polyhedron_mass_properties(verts, tris, RHO)
    hull = rr.ConvexHull(verts).mass_properties(RHO)
    assert hull.mass > 1.2 * m_ref  # it is far from convex (measured: 151 kg vs 110 kg)
    mp = rr.TriMesh(verts, tris).mass_properties(RHO)
    close(mp.mass, m_ref)
    close(mp.center_of_mass, c_ref, scale=np.abs(c_ref).max())
    close(mp.inertia, i_ref)


def test_body_from_trimesh_is_re_expressed_in_its_principal_frame():
    semi = np.array([0.15, 0.25, 0.4])
    local = fibonacci_ellipsoid(200, semi)
    # An asymmetric, off-centre mesh in its own frame.
    shape_r = Rotation.from_rotvec([0.7, 0.2, -0.4]).as_matrix()
    verts = local @ shape_r.T + [0.3, -0.1, 0.2]
    tris = outward_hull_mesh(verts)
    m_ref, c_ref, i_ref = polyhedron_mass_properties(verts, tris, RHO)
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    i = scene.add_body(rr.TriMesh(verts, tris), density=RHO, position=P_FRAME, orientation=Q_FRAME.as_quat())
    b = scene.build(dt=0.01).bodies
    r_frame = Q_FRAME.as_matrix()
    close(b.mass[i], m_ref)
    close(b.position[i], P_FRAME + r_frame @ c_ref, scale=np.abs(P_FRAME).max())
    close(np.sort(b.inertia[i]), np.linalg.eigvalsh(i_ref))
    i_world = r_frame @ i_ref @ r_frame.T
    close(b.inertia_world[i], i_world, rtol=1e-11)  # through an eigen-decomposition: ~10 eps
    r_body = Rotation.from_quat(b.orientation[i]).as_matrix()
    close(r_body.T @ i_world @ r_body, np.diag(b.inertia[i]), scale=np.abs(i_ref).max(), rtol=1e-11)


# ---------------------------------------------------------------------------
# Sampled density: rigidrs.mass_properties(points, volumes, densities)
# ---------------------------------------------------------------------------

H_GRID = np.array([0.1, 0.2, 0.3])


def grid(h, a):
    """Cell centres of a grid of cubic cells of edge ``a`` filling the box [-h, h]."""
    axes = [np.arange(-hi + a / 2, hi, a) for hi in h]
    assert all(len(x) == round(2 * hi / a) for x, hi in zip(axes, h))
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def test_sampled_uniform_box_leaves_out_exactly_each_cells_own_inertia():
    a = 0.02
    pts = grid(H_GRID, a)  # 10 x 20 x 30 = 6000 samples
    mp = rr.mass_properties(pts, a**3, RHO)
    m, _, inertia = box_ref(H_GRID)
    close(mp.mass, m)
    close(mp.center_of_mass, np.zeros(3), scale=np.abs(H_GRID).max())
    # Midpoint rule per cell: ∫x² over a cell = a (x_c² + a²/12), so the point sum
    # misses m a²/12 per squared coordinate: m a²/6 on each diagonal moment.
    missing = m * a**2 / 6.0
    close(mp.inertia, inertia - missing * np.eye(3))


def test_sampled_linear_density_matches_closed_form():
    """ρ = ρ0 (1 + k x) on the box [-h, h]. With s_i = ∫ x_i² dV / V (= h_i²/3 for the
    continuum; = h_i²/3 − a²/12 for the midpoint sum on cells of edge a, exactly, since
    the odd moments vanish by symmetry in both):
    m = ρ0 V, c = (k s_x, 0, 0), and about c the second moments are
    m (s_x − k² s_x²), m s_y, m s_z with no cross terms (∫ x²y = ∫ xy = 0).
    """
    rho0, k, a = 800.0, 4.0, 0.01  # 1 + k x ∈ [0.6, 1.4]: positive
    pts = grid(H_GRID, a)  # 20 x 40 x 60 = 48000 samples
    rho = rho0 * (1.0 + k * pts[:, 0])
    mp = rr.mass_properties(pts, np.full(len(pts), a**3), rho)
    volume = 8.0 * H_GRID.prod()
    m = rho0 * volume

    def expected(s):
        second = m * np.array([s[0] - k**2 * s[0] ** 2, s[1], s[2]])
        return np.array([k * s[0], 0.0, 0.0]), np.diag(second.sum() - second)

    c_disc, i_disc = expected(H_GRID**2 / 3.0 - a**2 / 12.0)
    c_cont, i_cont = expected(H_GRID**2 / 3.0)
    close(mp.mass, m, rtol=1e-11)  # 48000-term sum: n·eps ≈ 5e-12 worst case
    close(mp.center_of_mass, c_disc, scale=H_GRID.max(), rtol=1e-11)
    close(mp.inertia, i_disc, rtol=1e-11)
    # Against the continuum the sampling error is O(a²): the centre of mass is off by
    # k a²/12 and every moment by at most m a²/6.
    close(mp.center_of_mass, c_cont, scale=k * a**2 / 12.0, rtol=1.0 + 1e-6)
    assert np.abs(mp.inertia - i_cont).max() <= m * a**2 / 6.0 * (1 + 1e-6)
    # And the centre of mass did move (a test that cannot fail otherwise is no test).
    assert mp.center_of_mass[0] > 0.5 * k * H_GRID[0] ** 2 / 3.0


def test_sampled_rotated_offset_set_has_known_principal_moments_and_axes():
    a = 0.04
    h = np.array([0.12, 0.2, 0.32])
    local = grid(h, a)  # 6 x 10 x 16 samples
    r = Rotation.from_rotvec([-0.9, 0.4, 1.3]).as_matrix()
    t = np.array([3.0, -2.0, 1.5])  # far from the origin: the inertia must be about c
    pts = local @ r.T + t
    densities = np.full(len(pts), RHO)
    mp = rr.mass_properties(pts, a**3, densities)
    m, _, inertia = box_ref(h)
    moments = np.diag(inertia) - m * a**2 / 6.0  # as in the uniform-grid test
    close(mp.mass, m)
    close(mp.center_of_mass, t, scale=np.abs(t).max())
    close(mp.inertia, r @ np.diag(moments) @ r.T, rtol=1e-11)  # |t|²/size² ≈ 100x cancellation
    order = np.argsort(moments)
    close(mp.principal_moments, moments[order], rtol=1e-11)
    axes = mp.principal_axes
    close(axes.T @ axes, np.eye(3), scale=1.0)
    close(np.linalg.det(axes), 1.0, scale=1.0)
    close(axes.T @ mp.inertia @ axes, np.diag(mp.principal_moments), scale=moments.max(), rtol=1e-11)
    close(np.abs(r[:, order].T @ axes), np.eye(3), scale=1.0, rtol=1e-10)
    same_rotation(mp.principal_orientation, axes)


def test_body_from_mass_properties_is_placed_in_its_principal_frame():
    a = 0.04
    h = np.array([0.12, 0.2, 0.32])
    r_src = Rotation.from_rotvec([-0.9, 0.4, 1.3]).as_matrix()
    c_src = np.array([0.3, -0.2, 0.1])
    mp = rr.mass_properties(grid(h, a) @ r_src.T + c_src, a**3, RHO)
    q_frame = Rotation.from_rotvec([0.2, 1.1, -0.3])
    p_frame = np.array([-1.0, 0.5, 2.0])
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    scene.add_body(rr.Sphere(0.1), density=RHO)  # body 0: make the index matter
    i = scene.add_body(mass_properties=mp, position=p_frame, orientation=q_frame.as_quat())
    b = scene.build(dt=0.01).bodies
    r_frame = q_frame.as_matrix()
    tensor = mp.inertia
    close(b.mass[i], mp.mass)
    close(b.position[i], p_frame + r_frame @ mp.center_of_mass, scale=np.abs(p_frame).max())
    close(b.inertia[i], mp.principal_moments)
    close(b.inertia_world[i], r_frame @ tensor @ r_frame.T, rtol=1e-11)
    same_rotation(b.orientation[i], r_frame @ mp.principal_axes)


# ---------------------------------------------------------------------------
# World inertia and angular momentum of a world of mixed bodies, after stepping
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("integrator", ["strang", "rk4", "symplectic_euler"])
def test_world_inertia_is_r_i0_rt_and_omega_is_inverse_inertia_times_l(integrator):
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    rng = np.random.default_rng(7)
    shapes = [
        rr.Box((0.05, 0.2, 0.45)),
        rr.Cone(0.3, 0.5),
        rr.Capsule(0.1, 0.3),
        rr.Sphere(0.2),
        rr.ConvexHull(fibonacci_ellipsoid(60, np.array([0.1, 0.2, 0.3]))),
    ]
    for s in shapes:
        scene.add_body(
            s,
            density=RHO,
            position=rng.normal(size=3),
            orientation=Rotation.random(random_state=rng).as_quat(),
            angular_velocity=rng.normal(scale=3.0, size=3),
        )
    scene.add_body(mass=2.0, inertia=[[0.3, 0.05, 0.0], [0.05, 0.2, 0.01], [0.0, 0.01, 0.25]], angular_velocity=(1, 2, 3))
    world = scene.build(dt=1 / 120, integrator=integrator)
    world.step(30)
    b = world.bodies
    for i in range(len(b)):
        r = Rotation.from_quat(b.orientation[i]).as_matrix()  # independent of the rotation view
        i_world = r @ np.diag(b.inertia[i]) @ r.T
        close(b.rotation[i], r, scale=1.0, rtol=1e-13)
        close(b.inertia_world[i], i_world)
        close(b.angular_momentum[i], i_world @ b.angular_velocity[i])
        # ω = I⁻¹ L; cond(I) ≤ 20 here, so 20 eps of amplification at most.
        close(np.linalg.solve(b.inertia_world[i], b.angular_momentum[i]), b.angular_velocity[i])


def test_fixed_body_has_infinite_mass_and_zero_inverse():
    scene = rr.Scene(gravity=(0.0, 0.0, -9.81))
    i = scene.add_body(rr.Box((1.0, 2.0, 3.0)), fixed=True, position=P_FRAME, orientation=Q_FRAME.as_quat())
    b = scene.build(dt=0.01).bodies
    assert np.isinf(b.mass[i]) and b.inverse_mass[i] == 0.0
    assert np.all(np.isinf(b.inertia[i])) and np.all(b.inverse_inertia[i] == 0.0)
    # A fixed body keeps the frame it was given (no centre-of-mass shift).
    close(b.position[i], P_FRAME, scale=np.abs(P_FRAME).max())
    same_rotation(b.orientation[i], Q_FRAME.as_matrix())


def test_mass_with_inertia_and_a_shape_takes_the_shapes_centre_of_mass():
    # mass= + inertia= with a shape: the inertia is the user's (about the centre of
    # mass, in the shape's axes); the centre of mass is the shape's (the cone's sits
    # hh/2 below its middle).
    r, hh = 0.3, 0.5
    moments = np.array([0.5, 0.6, 0.7])
    scene = rr.Scene(gravity=(0.0, 0.0, 0.0))
    i = scene.add_body(rr.Cone(r, hh), mass=3.0, inertia=moments, position=P_FRAME, orientation=Q_FRAME.as_quat())
    b = scene.build(dt=0.01).bodies
    rq = Q_FRAME.as_matrix()
    close(b.mass[i], 3.0)
    close(b.inertia[i], moments)
    close(b.position[i], P_FRAME + rq @ [0.0, 0.0, -hh / 2.0], scale=np.abs(P_FRAME).max())
    close(b.inertia_world[i], rq @ np.diag(moments) @ rq.T)
