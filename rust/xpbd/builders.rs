//! Builders for common particle structures. Each adds particles and constraints
//! to the model in one go (nothing if it fails) and returns the range of the
//! particles it added; their constraints are appended in a documented order.
//! Masses are totals (kg), shared equally among the particles.

use std::collections::HashMap;
use std::ops::Range;

use super::compliance::Compliance;
use super::model::XpbdModel;
use super::particles::ParticleSpec;
use super::shape_matching::ClusterSpec;
use crate::error::{finite3, non_negative, positive, Error, Result};
use crate::body::shape::{Shape, ShapeKind};
use crate::math::Vec3;
use nalgebra::Point3;
use parry3d_f64::shape::{SharedShape, TriMesh, TriMeshFlags};

/// Particle properties shared by a builder's particles.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Material {
    /// Total mass (kg) > 0, shared equally.
    pub mass: f64,
    /// Radius of each particle (m) ≥ 0. Default 0.
    pub radius: f64,
    /// Friction against rigid colliders and other particles (–). Default 0.5.
    pub friction: f64,
    /// Collision filter of every particle. Default: group 1, collides with all.
    pub filter: crate::collide::Filter,
}

fn add_points(m: &mut XpbdModel, points: &[Vec3], mat: &Material, pinned: &[usize]) -> Result<Range<usize>> {
    positive("mass", mat.mass)?;
    let start = m.particles.len();
    let each = mat.mass / points.len().max(1) as f64;
    for (k, p) in points.iter().enumerate() {
        let spec = ParticleSpec {
            position: (*p).into(),
            mass: each,
            radius: mat.radius,
            friction: mat.friction,
            filter: mat.filter,
            fixed: pinned.contains(&k),
            ..ParticleSpec::at((*p).into())
        };
        m.add_particle(&spec)?;
    }
    if let Some(&bad) = pinned.iter().find(|&&k| k >= points.len()) {
        return Err(Error::input(format!("pinned index {bad} is out of range: the builder makes {} particles", points.len())));
    }
    Ok(m.range_from(start))
}

fn count(name: &str, n: i64, min: i64) -> Result<usize> {
    if n < min || n > 1 << 24 {
        return Err(Error::input(format!("{name} must be an integer in [{min}, 2^24], got {n}")));
    }
    Ok(n as usize)
}

/// At most 2^24 particles per builder call.
fn total(n: &[usize]) -> Result<usize> {
    let t = n.iter().map(|&k| k as f64).product::<f64>();
    if t > (1u64 << 24) as f64 {
        return Err(Error::input(format!("{n:?} makes {t:.3e} particles; at most 2^24 per builder")));
    }
    Ok(t as usize)
}

/// A rope or chain from `start` to `end` (m): `segments + 1` particles joined by
/// `segments` distance constraints (in order along the rope). `pinned` lists
/// particles (0 = start, `segments` = end) that do not move.
pub fn rope(
    m: &mut XpbdModel,
    start: [f64; 3],
    end: [f64; 3],
    segments: i64,
    mat: &Material,
    k: Compliance,
    pinned: &[usize],
) -> Result<Range<usize>> {
    m.atomically(|m| {
        let n = count("segments", segments, 1)?;
        let (a, b) = (Vec3::from(finite3("start", start)?), Vec3::from(finite3("end", end)?));
        let pts: Vec<Vec3> = (0..=n).map(|s| a + (b - a) * (s as f64 / n as f64)).collect();
        let r = add_points(m, &pts, mat, pinned)?;
        for s in 0..n {
            let i = (r.start + s) as i64;
            m.add_distance(i, i + 1, k, None)?;
        }
        Ok(r)
    })
}

/// Distance constraints on every edge of `triangles` (local indices, once
/// each, in first-seen order), then a bending constraint on every edge shared by
/// two triangles (if `bending` is given). Indices are offsets from `base`.
fn cloth_constraints(
    m: &mut XpbdModel,
    base: usize,
    triangles: &[[usize; 3]],
    k: Compliance,
    bending: Option<Compliance>,
) -> Result<()> {
    let mut tips: HashMap<(usize, usize), usize> = HashMap::new();
    let mut edges = Vec::new();
    for t in triangles {
        for e in 0..3 {
            let (a, b, c) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
            tips.insert((a, b), c);
            if !tips.contains_key(&(b, a)) {
                edges.push((a, b));
            }
        }
    }
    for &(a, b) in &edges {
        m.add_distance((base + a) as i64, (base + b) as i64, k, None)?;
    }
    if let Some(kb) = bending {
        for &(a, b) in &edges {
            if let (Some(&c), Some(&d)) = (tips.get(&(a, b)), tips.get(&(b, a))) {
                m.add_bending([a, b, c, d].map(|i| (base + i) as i64), kb)?;
            }
        }
    }
    Ok(())
}

/// Default damping time of a cloth's bending (s): the dashpot on each dihedral
/// angle is `β = BENDING_DAMPING_TIME / α` (N·m·s/rad), damping proportional to
/// the bending stiffness (Rayleigh), so a bending mode of frequency `f` has the
/// damping ratio `π f · 0.05 s` whatever the compliance and the resolution
/// (XPBD's `γ = αβ/h` is `0.05 s / h`). Undamped, the README's cloth over a
/// sphere (a sheet stiff enough to overhang) keeps ringing at 1.25 Hz with 1.6 %
/// of its released energy as kinetic energy after 10 s; with it, below 1e-5 of
/// it for good after 4.7 s.
pub const BENDING_DAMPING_TIME: f64 = 0.05;

/// The compliance of a cloth's bending constraints: `alpha` (rad/(N·m)) and
/// `damping` (N·m·s/rad), by default `BENDING_DAMPING_TIME / alpha` (0 for a
/// rigid bend, where damping has no effect).
pub fn cloth_bending(alpha: f64, damping: Option<f64>) -> Result<Compliance> {
    non_negative("bending_compliance", alpha)?;
    let beta = match damping {
        Some(b) => non_negative("bending_damping", b)?,
        None if alpha > 0.0 => BENDING_DAMPING_TIME / alpha,
        None => 0.0,
    };
    if !beta.is_finite() {
        return Err(Error::input(format!(
            "bending_compliance {alpha} is too small for the default bending damping ({BENDING_DAMPING_TIME} s / compliance); give bending_damping"
        )));
    }
    Compliance::new(alpha, beta)
}

/// A rectangular cloth: `nu × nv` particles at `origin + i/(nu−1)·u + j/(nv−1)·v`
/// (m), particle `j·nu + i`; each cell split into two triangles along its
/// (i, j)–(i+1, j+1) diagonal. Distance constraints on every triangle edge
/// (stretch and shear, compliance `k`), then dihedral bending on every interior
/// edge (compliance `bending`, none if `None`). `pinned` lists local indices.
#[allow(clippy::too_many_arguments)]
pub fn cloth(
    m: &mut XpbdModel,
    origin: [f64; 3],
    u: [f64; 3],
    v: [f64; 3],
    nu: i64,
    nv: i64,
    mat: &Material,
    k: Compliance,
    bending: Option<Compliance>,
    pinned: &[usize],
) -> Result<Range<usize>> {
    m.atomically(|m| {
        let (nu, nv) = (count("nu", nu, 2)?, count("nv", nv, 2)?);
        total(&[nu, nv])?;
        let (o, u, v) = (Vec3::from(finite3("origin", origin)?), Vec3::from(finite3("u", u)?), Vec3::from(finite3("v", v)?));
        if !(u.cross(&v).norm() > 0.0) {
            return Err(Error::shape("u and v must span a rectangle (non-zero and not parallel)"));
        }
        let mut pts = Vec::with_capacity(nu * nv);
        for j in 0..nv {
            for i in 0..nu {
                pts.push(o + u * (i as f64 / (nu - 1) as f64) + v * (j as f64 / (nv - 1) as f64));
            }
        }
        let r = add_points(m, &pts, mat, pinned)?;
        let id = |i: usize, j: usize| j * nu + i;
        let mut tris = Vec::with_capacity(2 * (nu - 1) * (nv - 1));
        for j in 0..nv - 1 {
            for i in 0..nu - 1 {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        cloth_constraints(m, r.start, &tris, k, bending)?;
        Ok(r)
    })
}

/// The six tetrahedra of a cube along its main diagonal (Kuhn): conforming
/// across neighbouring cubes. Corners are indexed `x + 2y + 4z`.
const KUHN: [[usize; 4]; 6] =
    [[0, 1, 3, 7], [0, 1, 5, 7], [0, 2, 3, 7], [0, 2, 6, 7], [0, 4, 5, 7], [0, 4, 6, 7]];

/// A soft box of `cells = (nx, ny, nz)` cubes centred at `center` with
/// `half_extents` (m), axis-aligned: `(nx+1)(ny+1)(nz+1)` particles, particle
/// `i + (nx+1)(j + (ny+1) k)`; each cell split into six tetrahedra. Distance
/// constraints on every tetrahedron edge (once each, compliance `k`), then a
/// volume constraint per tetrahedron (compliance `volume`, none if `None`).
pub fn soft_box(
    m: &mut XpbdModel,
    center: [f64; 3],
    half_extents: [f64; 3],
    cells: [i64; 3],
    mat: &Material,
    k: Compliance,
    volume: Option<Compliance>,
) -> Result<Range<usize>> {
    m.atomically(|m| {
        let c = Vec3::from(finite3("center", center)?);
        for (a, &h) in half_extents.iter().enumerate() {
            positive(&format!("half_extents[{a}]"), h)?;
        }
        let n = [count("cells[0]", cells[0], 1)?, count("cells[1]", cells[1], 1)?, count("cells[2]", cells[2], 1)?];
        total(&[n[0] + 1, n[1] + 1, n[2] + 1])?;
        let id = |i: usize, j: usize, l: usize| i + (n[0] + 1) * (j + (n[1] + 1) * l);
        let mut pts = Vec::new();
        for l in 0..=n[2] {
            for j in 0..=n[1] {
                for i in 0..=n[0] {
                    let f = [i, j, l].map(|x| x as f64);
                    pts.push(c + Vec3::from_fn(|a, _| half_extents[a] * (2.0 * f[a] / n[a] as f64 - 1.0)));
                }
            }
        }
        let r = add_points(m, &pts, mat, &[])?;
        let mut tets = Vec::new();
        for l in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let corner = |k: usize| id(i + (k & 1), j + ((k >> 1) & 1), l + (k >> 2));
                    tets.extend(KUHN.iter().map(|t| t.map(corner)));
                }
            }
        }
        let mut seen = std::collections::HashSet::new();
        for t in &tets {
            for (a, b) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
                let e = (t[a].min(t[b]), t[a].max(t[b]));
                if seen.insert(e) {
                    m.add_distance((r.start + e.0) as i64, (r.start + e.1) as i64, k, None)?;
                }
            }
        }
        if let Some(kv) = volume {
            for t in &tets {
                m.add_tet_volume(t.map(|i| (r.start + i) as i64), kv)?;
            }
        }
        Ok(r)
    })
}

/// A shape-matched body from a point set (m): one particle per point, matched by
/// one cluster over all of them (`cluster_size = None`), or by overlapping
/// clusters: for every node of a grid of spacing `s = cluster_size` over the
/// points' bounding box, the points within the cube of edge `2s` around it
/// (clusters that would be degenerate are left out; every particle must end up
/// in one). Returns the particle range and the cluster indices.
pub fn shape_matched_body(
    m: &mut XpbdModel,
    points: &[[f64; 3]],
    mat: &Material,
    spec: ClusterSpec,
    cluster_size: Option<f64>,
) -> Result<(Range<usize>, Vec<usize>)> {
    m.atomically(|m| {
        let pts: Vec<Vec3> =
            points.iter().enumerate().map(|(k, p)| finite3(&format!("points[{k}]"), *p).map(Vec3::from)).collect::<Result<_>>()?;
        let r = add_points(m, &pts, mat, &[])?;
        let all: Vec<i64> = r.clone().map(|i| i as i64).collect();
        let Some(s) = cluster_size else {
            return Ok((r, vec![m.add_cluster(&all, spec)?]));
        };
        positive("cluster_size", s)?;
        let (lo, hi) = bounds(&pts);
        let nodes = ((hi - lo) / s).map(|x| x.ceil().min(1e9) as usize + 1);
        if nodes.iter().map(|&n| n as f64).product::<f64>() > (1u64 << 20) as f64 {
            return Err(Error::input(format!("cluster_size {s} is too small for points spanning {:?} m", (hi - lo).as_slice())));
        }
        let mut covered = vec![false; pts.len()];
        let mut ids = Vec::new();
        let cells = Cells::new(&pts, lo, s, nodes);
        let mut members = Vec::new();
        for node in grid(nodes) {
            let c = lo + Vec3::from_fn(|a, _| node[a] as f64 * s);
            cells.near(node, &mut members);
            members.retain(|&k| (pts[k] - c).amax() <= s);
            let idx: Vec<i64> = members.iter().map(|&k| (r.start + k) as i64).collect();
            if members.len() < 4 || m.add_cluster(&idx, spec).map(|id| ids.push(id)).is_err() {
                continue;
            }
            members.iter().for_each(|&k| covered[k] = true);
        }
        if let Some(k) = covered.iter().position(|c| !c) {
            return Err(Error::shape(format!(
                "particle {} is in no cluster: cluster_size {s} m leaves it with too few or degenerate neighbours",
                r.start + k
            )));
        }
        Ok((r, ids))
    })
}

/// The points bucketed by the grid cell they lie in (cell `i` spans nodes `i` and
/// `i + 1` along each axis): a node's cluster takes its members from the cells
/// around it instead of from every point, so clustering is linear in the points.
struct Cells {
    nodes: Vec3Usize,
    /// Point indices ordered by cell, and where each cell's run starts.
    order: Vec<usize>,
    start: Vec<usize>,
}

impl Cells {
    fn new(pts: &[Vec3], lo: Vec3, s: f64, nodes: Vec3Usize) -> Self {
        let cell = |p: &Vec3| -> usize {
            let c = Vec3Usize::from_fn(|a, _| (((p[a] - lo[a]) / s).floor().max(0.0) as usize).min(nodes[a] - 1));
            c[0] + nodes[0] * (c[1] + nodes[1] * c[2])
        };
        let count = nodes[0] * nodes[1] * nodes[2];
        let mut start = vec![0usize; count + 1];
        let keys: Vec<usize> = pts.iter().map(cell).collect();
        for &k in &keys {
            start[k + 1] += 1;
        }
        for i in 0..count {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut order = vec![0usize; pts.len()];
        for (k, &c) in keys.iter().enumerate() {
            order[fill[c]] = k;
            fill[c] += 1;
        }
        Cells { nodes, order, start }
    }

    /// Every point in the cells touching `node` (a superset of those within one
    /// cell size of it), in increasing index order.
    fn near(&self, node: [usize; 3], out: &mut Vec<usize>) {
        out.clear();
        let span = |a: usize| node[a].saturating_sub(1)..=(node[a] + 1).min(self.nodes[a] - 1);
        for k in span(2) {
            for j in span(1) {
                for i in span(0) {
                    let c = i + self.nodes[0] * (j + self.nodes[1] * k);
                    out.extend_from_slice(&self.order[self.start[c]..self.start[c + 1]]);
                }
            }
        }
        out.sort_unstable();
    }
}

fn bounds(p: &[Vec3]) -> (Vec3, Vec3) {
    let lo = p.iter().fold(Vec3::repeat(f64::INFINITY), |a, x| a.inf(x));
    let hi = p.iter().fold(Vec3::repeat(f64::NEG_INFINITY), |a, x| a.sup(x));
    (lo, hi)
}

fn grid(n: Vec3Usize) -> impl Iterator<Item = [usize; 3]> {
    (0..n[2]).flat_map(move |k| (0..n[1]).flat_map(move |j| (0..n[0]).map(move |i| [i, j, k])))
}

type Vec3Usize = nalgebra::Vector3<usize>;

/// Points filling a shape (in the shape's frame, m): the nodes of a grid of
/// spacing `spacing` (m) over the shape's bounding box, aligned with its lower
/// corner, that lie inside the shape or on its surface, and for a triangle mesh
/// its vertices as well. A box whose extents are multiples of `spacing` gets its
/// corners; a mesh must be closed and outward-oriented.
pub fn fill_shape(shape: &Shape, spacing: f64) -> Result<Vec<[f64; 3]>> {
    positive("spacing", spacing)?;
    let mut out: Vec<[f64; 3]> = Vec::new();
    let solid: SharedShape = match &shape.kind {
        ShapeKind::Plane { .. } => return Err(Error::shape("a Plane is infinite: it cannot be filled with particles")),
        ShapeKind::TriMesh { vertices, triangles } => {
            out.extend(vertices.iter().copied());
            let pts = vertices.iter().map(|v| Point3::from(Vec3::from(*v))).collect();
            let tris = triangles.to_vec();
            // parry checks the topology; a panic in it must not escape either.
            let built = std::panic::catch_unwind(|| TriMesh::with_flags(pts, tris, TriMeshFlags::ORIENTED));
            let mesh = built
                .map_err(|_| Error::shape("TriMesh: parry could not orient this mesh"))?
                .map_err(|e| Error::shape(format!("TriMesh: {e:?} (it must be closed and consistently oriented)")))?;
            SharedShape::new(mesh)
        }
        _ => shape.parry.clone(),
    };
    let is_mesh = matches!(shape.kind, ShapeKind::TriMesh { .. });
    let pose = shape.parry_pose;
    let aabb = solid.compute_aabb(&pose);
    let (lo, hi) = (aabb.mins.coords, aabb.maxs.coords);
    let nodes = ((hi - lo) / spacing).map(|x| (x * (1.0 + 1e-12)).floor().min(1e9) as usize + 1);
    if nodes.iter().map(|&n| n as f64).product::<f64>() > (1u64 << 22) as f64 {
        return Err(Error::input(format!("spacing {spacing} m is too small for a shape spanning {:?} m", (hi - lo).as_slice())));
    }
    let on_surface = 1e-9 * spacing;
    for node in grid(nodes) {
        let p = Point3::from(lo + Vec3::from_fn(|a, _| node[a] as f64 * spacing));
        // With a feature: a mesh's pseudo-normals then tell inside from outside.
        let (proj, _) = solid.project_point_and_get_feature(&pose, &p);
        let d = (proj.point - p).norm();
        // A mesh's surface points are its vertices already.
        let keep = if is_mesh { proj.is_inside && d > on_surface } else { proj.is_inside || d <= on_surface };
        if keep {
            out.push(p.coords.into());
        }
    }
    if out.is_empty() {
        return Err(Error::shape(format!("no grid point of spacing {spacing} m lies in the shape")));
    }
    Ok(out)
}
