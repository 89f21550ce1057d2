//! Shapes a body can be made of, each validated when it is made, with its parry
//! collision shape and its mass properties for a uniform density.
//!
//! Axial shapes (capsule, cylinder, cone) have their axis along local z, the up
//! axis of the engine; parry's cylinder and cone (axis y) are posed accordingly.

use std::collections::HashMap;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::shape::{SharedShape, TriMeshFlags};

use super::mass::MassProps;
use crate::error::{finite3, positive, Error, Result};
use crate::math::{Mat3, Vec3};

/// The geometry, as the user described it (kept for reporting and rebuilding).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub enum ShapeKind {
    /// A ball of radius `radius` (m).
    Sphere { radius: f64 },
    /// A box with half extents along local x, y, z (m).
    Box { half_extents: [f64; 3] },
    /// A capsule: a segment of length `2·half_height` along z, swept by `radius` (m).
    Capsule { radius: f64, half_height: f64 },
    /// A solid cylinder of length `2·half_height` along z (m).
    Cylinder { radius: f64, half_height: f64 },
    /// A solid cone along z: base disc at `z = −half_height`, apex at `+half_height` (m).
    Cone { radius: f64, half_height: f64 },
    /// The convex hull of points (m).
    ConvexHull { points: Arc<Vec<[f64; 3]>> },
    /// A triangle mesh (m); closed and outward-oriented to carry mass.
    TriMesh { vertices: Arc<Vec<[f64; 3]>>, triangles: Arc<Vec<[u32; 3]>> },
    /// The half-space `normal · x ≤ offset` (unit normal, offset in m): only for
    /// fixed bodies. `given`: the normal as given (any length), kept so that a
    /// scene file rebuilds the same bits.
    Plane { normal: [f64; 3], offset: f64, given: [f64; 3] },
    /// Convex parts at poses in this shape's frame; `orientations`: each part's
    /// orientation (x, y, z, w) as given, before normalisation (for scene files).
    Compound { parts: Arc<Vec<(Isometry3<f64>, Shape)>>, orientations: Arc<Vec<[f64; 4]>> },
}

/// A validated shape: its description, parry's collision shape and the pose of
/// parry's shape in the local frame of ours.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct Shape {
    pub kind: ShapeKind,
    pub parry: SharedShape,
    pub parry_pose: Isometry3<f64>,
}

impl std::fmt::Debug for Shape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.kind.fmt(f)
    }
}

/// Parry's axial shapes run along y; ours run along z: a quarter turn about x.
fn y_to_z() -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Vec3::x_axis(), std::f64::consts::FRAC_PI_2),
    )
}

impl Shape {
    fn new(kind: ShapeKind, parry: SharedShape, parry_pose: Isometry3<f64>) -> Self {
        Self { kind, parry, parry_pose }
    }

    pub fn sphere(radius: f64) -> Result<Self> {
        positive("Sphere radius", radius)?;
        Ok(Self::new(ShapeKind::Sphere { radius }, SharedShape::ball(radius), Isometry3::identity()))
    }

    pub fn cuboid(half_extents: [f64; 3]) -> Result<Self> {
        for (axis, h) in ["x", "y", "z"].iter().zip(half_extents) {
            positive(&format!("Box half_extents.{axis}"), h)?;
        }
        let [x, y, z] = half_extents;
        Ok(Self::new(ShapeKind::Box { half_extents }, SharedShape::cuboid(x, y, z), Isometry3::identity()))
    }

    pub fn capsule(radius: f64, half_height: f64) -> Result<Self> {
        positive("Capsule radius", radius)?;
        positive("Capsule half_height", half_height)?;
        let parry = SharedShape::capsule_z(half_height, radius);
        Ok(Self::new(ShapeKind::Capsule { radius, half_height }, parry, Isometry3::identity()))
    }

    pub fn cylinder(radius: f64, half_height: f64) -> Result<Self> {
        positive("Cylinder radius", radius)?;
        positive("Cylinder half_height", half_height)?;
        let parry = SharedShape::cylinder(half_height, radius);
        Ok(Self::new(ShapeKind::Cylinder { radius, half_height }, parry, y_to_z()))
    }

    pub fn cone(radius: f64, half_height: f64) -> Result<Self> {
        positive("Cone radius", radius)?;
        positive("Cone half_height", half_height)?;
        let parry = SharedShape::cone(half_height, radius);
        Ok(Self::new(ShapeKind::Cone { radius, half_height }, parry, y_to_z()))
    }

    pub fn plane(normal: [f64; 3], offset: f64) -> Result<Self> {
        finite3("Plane normal", normal)?;
        crate::error::finite("Plane offset", offset)?;
        let n = Vec3::from(normal);
        // Scaled by its largest component first, so that |n|² cannot overflow (a normal
        // of (1e300, 1e300, 0) used to become (0, 0, 0)).
        let big = n.amax();
        let len = big * (n / big).norm();
        if !(len > 1e-12) {
            return Err(Error::shape(format!("Plane normal must be non-zero, got {normal:?}")));
        }
        let unit = Unit::new_normalize(n / big);
        let pose = Isometry3::from_parts(Translation3::from(unit.into_inner() * offset), UnitQuaternion::identity());
        let kind = ShapeKind::Plane { normal: unit.into_inner().into(), offset, given: normal };
        Ok(Self::new(kind, SharedShape::halfspace(unit), pose))
    }

    pub fn convex_hull(points: Vec<[f64; 3]>) -> Result<Self> {
        check_points("ConvexHull points", &points)?;
        if points.len() < 4 {
            return Err(Error::shape(format!("ConvexHull needs at least 4 points, got {}", points.len())));
        }
        check_spans_volume("ConvexHull points", &points)?;
        let (vertices, triangles) = hull_mesh(&points)?;
        // parry can panic on inputs that are degenerate to round-off; the check above
        // rejects those, this guard turns any that slip by into an error.
        let hull = std::panic::catch_unwind(|| SharedShape::convex_mesh(vertices, &triangles)).ok().flatten();
        let parry = hull.ok_or_else(|| Error::shape("ConvexHull: parry could not build a hull of these points"))?;
        let kind = ShapeKind::ConvexHull { points: Arc::new(points) };
        Ok(Self::new(kind, parry, Isometry3::identity()))
    }

    pub fn trimesh(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        check_points("TriMesh vertices", &vertices)?;
        if triangles.is_empty() {
            return Err(Error::shape("TriMesh needs at least one triangle"));
        }
        let n = vertices.len();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&bad) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(Error::input(format!("TriMesh triangles[{t}] has index {bad}, but there are {n} vertices")));
            }
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                return Err(Error::shape(format!("TriMesh triangles[{t}] repeats a vertex: {tri:?}")));
            }
            let [a, b, c] = tri.map(|i| Vec3::from(vertices[i as usize]));
            let (e1, e2) = (b - a, c - a);
            if e1.cross(&e2).norm() <= 1e-12 * e1.norm_squared().max(e2.norm_squared()) {
                return Err(Error::shape(format!(
                    "TriMesh triangles[{t}] has no area (its vertices are collinear): {tri:?}"
                )));
            }
        }
        let pts: Vec<Point3<f64>> = vertices.iter().map(|p| Point3::from(*p)).collect();
        // Internal edges get the normals of their faces, not their own: a ball rolling
        // over the seam between two triangles of a flat floor feels no bump.
        let flags = TriMeshFlags::FIX_INTERNAL_EDGES;
        let parry = SharedShape::trimesh_with_flags(pts.clone(), triangles.clone(), flags)
            .or_else(|_| SharedShape::trimesh(pts, triangles.clone()))
            .map_err(|e| Error::shape(format!("TriMesh: {e:?}")))?;
        let kind = ShapeKind::TriMesh { vertices: Arc::new(vertices), triangles: Arc::new(triangles) };
        Ok(Self::new(kind, parry, Isometry3::identity()))
    }

    /// A union of shapes at poses (in this shape's frame). Parts may not be
    /// meshes, planes or compounds themselves.
    pub fn compound(parts: Vec<(Isometry3<f64>, Shape)>) -> Result<Self> {
        let given = parts.iter().map(|(p, _)| p.rotation.coords.into()).collect();
        Self::compound_as_given(parts, given)
    }

    /// [`Shape::compound`], keeping each part's orientation as the user gave it
    /// (`given`, one per part) for [`ShapeKind::Compound`].
    pub fn compound_as_given(parts: Vec<(Isometry3<f64>, Shape)>, given: Vec<[f64; 4]>) -> Result<Self> {
        if parts.is_empty() {
            return Err(Error::shape("Compound needs at least one part"));
        }
        let mut parry_parts = Vec::with_capacity(parts.len());
        for (k, (pose, part)) in parts.iter().enumerate() {
            if matches!(part.kind, ShapeKind::TriMesh { .. } | ShapeKind::Plane { .. } | ShapeKind::Compound { .. }) {
                return Err(Error::shape(format!(
                    "Compound part {k} is a {}: parts must be spheres, boxes, capsules, cylinders, cones or convex hulls",
                    part.name()
                )));
            }
            parry_parts.push((pose * part.parry_pose, part.parry.clone()));
        }
        let kind = ShapeKind::Compound { parts: Arc::new(parts), orientations: Arc::new(given) };
        Ok(Self::new(kind, SharedShape::compound(parry_parts), Isometry3::identity()))
    }

    /// A short name for messages ("Sphere", "TriMesh", ...).
    pub fn name(&self) -> &'static str {
        match self.kind {
            ShapeKind::Sphere { .. } => "Sphere",
            ShapeKind::Box { .. } => "Box",
            ShapeKind::Capsule { .. } => "Capsule",
            ShapeKind::Cylinder { .. } => "Cylinder",
            ShapeKind::Cone { .. } => "Cone",
            ShapeKind::ConvexHull { .. } => "ConvexHull",
            ShapeKind::TriMesh { .. } => "TriMesh",
            ShapeKind::Plane { .. } => "Plane",
            ShapeKind::Compound { .. } => "Compound",
        }
    }

    /// Mass properties for a uniform density (kg/m³), in this shape's frame.
    pub fn mass_properties(&self, density: f64) -> Result<MassProps> {
        positive("density", density)?;
        let mp = match &self.kind {
            ShapeKind::Plane { .. } => {
                return Err(Error::input("a Plane has no finite mass: add it with fixed=True"));
            }
            ShapeKind::TriMesh { vertices, triangles } => {
                check_closed_outward(vertices, triangles)?;
                self.parry.mass_properties(density)
            }
            // From the hull's own triangles: parry's polyhedron merges nearly coplanar
            // faces (normals within ~1e-4 rad) and fans them, dropping the vertices
            // inside a merged face, which on a thin hull is a large part of its volume.
            ShapeKind::ConvexHull { points } => {
                let (vertices, triangles) = hull_mesh(points)?;
                MassProperties::from_trimesh(density, &vertices, &triangles)
            }
            _ => self.parry.mass_properties(density),
        };
        // parry keeps 1/mass and reads a zero back as a zero mass: a mass that
        // overflowed (a 1e200 m sphere) would be reported as "got 0".
        if mp.inv_mass == 0.0 || !mp.inv_mass.is_finite() {
            return Err(Error::shape(format!(
                "{}: mass overflows at density {density} kg/m³ (density × volume is not a finite number): \
                 the shape is too large",
                self.name()
            )));
        }
        let mp = mp.transform_by(&self.parry_pose);
        let props = MassProps {
            mass: mp.mass(),
            com: mp.local_com.coords,
            inertia: symmetrize(mp.reconstruct_inertia_matrix()),
        };
        props.validate(self.name()).map_err(|e| Error::shape(e.message))?;
        Ok(props)
    }

    /// Volume (m³).
    pub fn volume(&self) -> Result<f64> {
        Ok(self.mass_properties(1.0)?.mass)
    }
}

fn symmetrize(m: Mat3) -> Mat3 {
    0.5 * (m + m.transpose())
}

fn check_points(what: &str, points: &[[f64; 3]]) -> Result<()> {
    for (i, p) in points.iter().enumerate() {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(Error::input(format!("{what}[{i}] must be finite, got {p:?}")));
        }
    }
    Ok(())
}

/// Mean and (unnormalised) covariance of a point set.
fn spread(points: &[[f64; 3]]) -> (Vec3, Mat3) {
    let n = points.len() as f64;
    let mean = points.iter().fold(Vec3::zeros(), |a, p| a + Vec3::from(*p)) / n;
    let mut cov = Mat3::zeros();
    for p in points {
        let r = Vec3::from(*p) - mean;
        cov += r * r.transpose();
    }
    (mean, cov)
}

/// The convex hull of `points` (checked by [`check_spans_volume`]) as an outward
/// triangle mesh over the given points.
///
/// parry's quickhull takes a cloud as flat when a covariance eigenvalue of the cloud
/// scaled to a unit box is below 1e-7: a plate thinner than about 1/1000 of its width
/// came back as a double-sided polygon, whose mass was zero or, once rotated, a
/// fraction of the true one. A convex hull is invariant under affine maps, so it is
/// computed on the whitened cloud (unit spread along every principal axis) and its
/// vertices mapped back to the points they came from, exactly.
fn hull_mesh(points: &[[f64; 3]]) -> Result<(Vec<Point3<f64>>, Vec<[u32; 3]>)> {
    let (mean, cov) = spread(points);
    let eig = cov.symmetric_eigen();
    let unit = Vec3::from_fn(|k, _| 1.0 / eig.eigenvalues[k].sqrt());
    let whiten = Mat3::from_diagonal(&unit) * eig.eigenvectors.transpose();
    let key = |p: &Point3<f64>| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let white: Vec<Point3<f64>> = points.iter().map(|p| Point3::from(whiten * (Vec3::from(*p) - mean))).collect();
    let source: HashMap<[u64; 3], usize> = white.iter().enumerate().map(|(i, w)| (key(w), i)).collect();
    let failed = || Error::shape("ConvexHull: parry could not build a hull of these points");
    let hull = std::panic::catch_unwind(|| parry3d_f64::transformation::try_convex_hull(&white));
    let (vertices, triangles) = hull.ok().and_then(|h| h.ok()).ok_or_else(failed)?;
    let vertices = vertices
        .iter()
        .map(|w| source.get(&key(w)).map(|&i| Point3::from(points[i])))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(failed)?;
    // A whitening with a reflection (eigenvectors of either handedness) turns the
    // hull's outward winding inward once mapped back: undo it.
    let triangles = if whiten.determinant() < 0.0 {
        triangles.into_iter().map(|[a, b, c]| [a, c, b]).collect()
    } else {
        triangles
    };
    Ok((vertices, triangles))
}

/// Rejects point sets that are (to round-off) coplanar, collinear or a single point.
fn check_spans_volume(what: &str, points: &[[f64; 3]]) -> Result<()> {
    let (_, cov) = spread(points);
    let ev = cov.symmetric_eigenvalues();
    let (lo, hi) = (ev.min(), ev.max());
    if !(hi > 0.0) || lo <= 1e-18 * hi {
        return Err(Error::shape(format!("{what} are coplanar, collinear or coincident: they enclose no volume")));
    }
    Ok(())
}

/// A mesh carries mass only if it is closed (every edge shared by exactly two
/// triangles, traversed once each way) and its triangles face outward.
fn check_closed_outward(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<()> {
    let mut edges: HashMap<(u32, u32), i32> = HashMap::with_capacity(triangles.len() * 3);
    for tri in triangles {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    for (&(a, b), &count) in &edges {
        if count != 1 || edges.get(&(b, a)) != Some(&1) {
            return Err(Error::shape(format!(
                "TriMesh is not a closed, consistently oriented surface (edge {a}-{b}): it has no volume to carry mass. \
                 For a dynamic body repair it (TriMesh.from_file(path, fix=True)), use its convex hull \
                 (ConvexHull.from_file) or convex parts (Compound.from_file(path, decompose=\"coacd\")), \
                 or give mass= with inertia=; a fixed or kinematic body may be open"
            )));
        }
    }
    let mut six_volume = 0.0;
    for t in triangles {
        let [a, b, c] = t.map(|i| Vec3::from(vertices[i as usize]));
        six_volume += a.dot(&b.cross(&c));
    }
    if !(six_volume > 0.0) {
        return Err(Error::shape(format!(
            "TriMesh encloses a volume of {:.3e} m³: its triangles face inward or it is flat (reverse the vertex order of each triangle)",
            six_volume / 6.0
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_axis_is_z_with_centre_a_quarter_up_from_the_base() {
        let (r, hh) = (0.3, 0.5);
        let mp = Shape::cone(r, hh).unwrap().mass_properties(1.0).unwrap();
        assert!((mp.com - Vec3::new(0.0, 0.0, -hh / 2.0)).norm() < 1e-15);
        let m = mp.mass;
        let axial = 0.3 * m * r * r;
        assert!((mp.inertia[(2, 2)] - axial).abs() < 1e-14 * axial);
    }

    #[test]
    fn open_mesh_has_no_mass() {
        let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let s = Shape::trimesh(v, vec![[0, 1, 2]]).unwrap();
        assert!(s.mass_properties(1.0).is_err());
    }

    #[test]
    fn thin_rotated_plate_hull_keeps_its_mass() {
        // A 2 x 1.4 x 0.002 m plate, turned off the axes: parry alone took it for flat.
        let (h, r) = ([1.0, 0.7, 1e-3], crate::math::quat::exp(&Vec3::new(0.3, -0.5, 0.8)));
        let mut pts = Vec::new();
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                for sz in [-1.0, 1.0] {
                    pts.push(crate::math::quat::rotate(&r, &Vec3::new(sx * h[0], sy * h[1], sz * h[2])).into());
                }
            }
        }
        let mp = Shape::convex_hull(pts).unwrap().mass_properties(1.0).unwrap();
        let volume = 8.0 * h[0] * h[1] * h[2];
        assert!((mp.mass - volume).abs() < 1e-12 * volume, "{} vs {volume}", mp.mass);
    }

    #[test]
    fn huge_plane_normal_is_normalised() {
        let s = Shape::plane([1e300, 1e300, 0.0], 0.0).unwrap();
        let ShapeKind::Plane { normal, .. } = s.kind else { unreachable!() };
        assert!((normal[0] - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15, "{normal:?}");
    }

    #[test]
    fn coplanar_hull_is_rejected() {
        let pts = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        assert!(Shape::convex_hull(pts).is_err());
    }

    #[test]
    fn hull_faces_point_outward_whatever_the_whitening() {
        // A hexagonal prism: its covariance eigenvectors come out left-handed, which
        // once inverted the hull's winding (a hull fell through a plane).
        let mut pts = Vec::new();
        for k in 0..6 {
            let a = k as f64 * std::f64::consts::PI / 3.0;
            for z in [-0.3, 0.3] {
                pts.push([0.4 * a.cos(), 0.4 * a.sin(), z]);
            }
        }
        let (v, t) = hull_mesh(&pts).unwrap();
        let centre = v.iter().fold(Vec3::zeros(), |a, p| a + p.coords) / v.len() as f64;
        for tri in &t {
            let [a, b, c] = tri.map(|i| v[i as usize].coords);
            let outward = (b - a).cross(&(c - a)).dot(&(a - centre));
            assert!(outward > 0.0, "triangle {tri:?} faces inward");
        }
    }
}
