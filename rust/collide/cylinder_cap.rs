//! A cylinder's cap, or a cone's base, resting on a face. parry stands a square
//! inscribed in the circle for it (its `PolygonalFeatureMap` of `Cylinder` and
//! `Cone`): a can spinning on its cap turned on the square's lever, 0.541 R
//! against the disk's 2/3 R, and stopped 23 % late; a can standing on an
//! incline with an edge of the square downhill pivoted 0.707 R from its axis
//! and tipped over at 19.5° where it stands up to atan(R / h) (26.6° for
//! R = h / 2): at 25° it fell in five yaws of six.
//!
//! Here the cap is a regular polygon of [`SIDES`] corners on its circle (its
//! lever 0.658 R, its edges' midpoints 0.981 R from the axis: it tips at most
//! 0.5° early), clipped by the face it rests on as two faces are clipped
//! ([`super::face_clip`]): a half-space, a box's face, a mesh's triangle, a
//! hull's face of up to four corners, or another cap (as the polygon about
//! its circle, whose corners lie at most 2 % of its radius beyond it). A hull's
//! face of more corners comes from parry as its first four, and an edge (a
//! log's top line) is left to parry's square ([`super::touching_axial`]).

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use parry3d_f64::shape::{PackedFeatureId, PolygonalFeature, Shape, Triangle};

use super::face_clip::{clip_either, Face};
use super::narrow_phase::Manifold;
use super::touching_axial::axial;
use super::touching_polyhedra::{part, part_pose};

/// Corners of a cap's polygon.
pub const SIDES: usize = 16;

/// Below this `|n × axis|`, a cap is flat on the face it rests on: its
/// polygon keeps its own orientation on the body (its corners stay where they
/// are on a resting can, whatever round-off tilts the normal). Above, its
/// first corner points where the cap tilts down, as parry's square's does:
/// the deepest point of its rim.
const FLAT: f64 = 1e-3;

/// Largest angle (rad) between the manifold's normal and the face a cap rests
/// on for the face to be taken flat under it.
const ALIGNED: f64 = 1e-3;

/// Largest `1 − (n·axis)²` for a contact of normal `n` to be flat on a cap
/// (the normal within 5.7° of the axis), its points material points of a flat
/// face; beyond, the rim touches at its deepest point, which parry's square
/// has as a corner, and the solver follows that point round the rim
/// (`solve::solver_body::Rounding`). A polygon's other corners there are
/// points of a rim spinning past, not of a face: a disk spinning at 30 rad/s
/// on a rim tilted 57° was thrown off the floor by them.
pub const ACROSS_AXIS: f64 = 0.01;

/// The cap of an axial shape that a normal `n` (outward, unit, its own
/// frame) leaves it through flat (see [`ACROSS_AXIS`]), if it is one.
#[derive(Clone, Copy)]
struct Cap {
    radius: f64,
    /// Height of its plane on the axis (parry's y).
    y: f64,
}

fn cap_of(s: &dyn Shape, n: &Vector3<f64>) -> Option<Cap> {
    let flat = 1.0 - n.y * n.y < ACROSS_AXIS;
    if let Some(c) = s.as_cylinder() {
        flat.then(|| Cap { radius: c.radius, y: c.half_height.copysign(n.y) })
    } else if let Some(c) = s.as_cone() {
        (flat && n.y < 0.0).then(|| Cap { radius: c.radius, y: -c.half_height })
    } else {
        None
    }
}

/// A cap's polygon (its shape's frame) for the outward normal `n`: corners on
/// the circle of `radius · scale`, with their vertex and edge features.
struct Polygon {
    vertices: [Point3<f64>; SIDES],
    vids: [PackedFeatureId; SIDES],
    eids: [PackedFeatureId; SIDES],
    fid: PackedFeatureId,
}

impl Polygon {
    fn new(cap: &Cap, n: &Vector3<f64>, scale: f64) -> Self {
        let across = (n.x * n.x + n.z * n.z).sqrt();
        let start = if across > FLAT * n.norm() { n.z.atan2(n.x) } else { 0.0 };
        let r = cap.radius * scale;
        // The top cap's features apart from the bottom's (parry's 9 and 19 for
        // the faces; vertices and edges numbered past parry's).
        let base = if cap.y > 0.0 { 200 } else { 100 };
        let mut p = Polygon {
            vertices: [Point3::origin(); SIDES],
            vids: [PackedFeatureId::UNKNOWN; SIDES],
            eids: [PackedFeatureId::UNKNOWN; SIDES],
            fid: PackedFeatureId::face(if cap.y > 0.0 { 19 } else { 9 }),
        };
        for k in 0..SIDES {
            let a = start + std::f64::consts::TAU * k as f64 / SIDES as f64;
            p.vertices[k] = Point3::new(r * a.cos(), cap.y, r * a.sin());
            p.vids[k] = PackedFeatureId::vertex(base + k as u32);
            p.eids[k] = PackedFeatureId::edge(base + k as u32);
        }
        p
    }

    fn face(&self) -> Face<'_> {
        Face { vertices: &self.vertices, vids: &self.vids, eids: &self.eids, fid: self.fid }
    }
}

/// A shape with a cap (a cylinder, a cone), or a compound with such a part.
fn capped(s: &dyn Shape) -> bool {
    match s.as_compound() {
        Some(c) => c.shapes().iter().any(|(_, p)| axial(p.as_ref())),
        None => axial(s),
    }
}

/// Whether some manifold of the pair may have a cap in it.
pub fn may_apply(s1: &dyn Shape, s2: &dyn Shape) -> bool {
    capped(s1) || capped(s2)
}

/// The manifolds of the pair (`pos12`: shape 2 in shape 1's frame) in which a
/// cap rests on a face, their points replaced by the cap's polygon clipped by
/// the face, those up to `prediction` (m) apart kept.
pub fn refine(manifolds: &mut [Manifold], s1: &dyn Shape, s2: &dyn Shape, pos12: &Isometry3<f64>, prediction: f64) {
    for m in manifolds.iter_mut().filter(|m| !m.points.is_empty()) {
        // A mesh's manifolds are its triangles'.
        let (t1, t2) = (triangle(s1, m.subshape1), triangle(s2, m.subshape2));
        let p1: &dyn Shape = t1.as_ref().map_or_else(|| part(s1, m.subshape1), |t| t as &dyn Shape);
        let p2: &dyn Shape = t2.as_ref().map_or_else(|| part(s2, m.subshape2), |t| t as &dyn Shape);
        let pos = part_pose(m, pos12);
        let (n1, n2) = (m.local_n1, m.local_n2);
        let Some(u1) = Unit::try_new(n1, 0.0) else { continue };
        let clipped = match (cap_of(p1, &n1), cap_of(p2, &n2)) {
            (None, None) => continue,
            (Some(c1), Some(c2)) => {
                // The other cap as the polygon about its circle.
                let reference = Polygon::new(&c1, &n1, 1.0 / (std::f64::consts::PI / SIDES as f64).cos());
                let incident = Polygon::new(&c2, &n2, 1.0);
                clip_either(m, &pos, &u1, (&reference.face(), &incident.face()), true)
            }
            (Some(c1), None) => {
                let Some(other) = Other::of(p2, &n2) else { continue };
                let incident = Polygon::new(&c1, &n1, 1.0);
                clip_either(m, &pos, &u1, (&incident.face(), &other.face()), false)
            }
            (None, Some(c2)) => {
                let Some(other) = Other::of(p1, &n1) else { continue };
                let incident = Polygon::new(&c2, &n2, 1.0);
                clip_either(m, &pos, &u1, (&other.face(), &incident.face()), true)
            }
        };
        if clipped {
            m.points.retain(|p| p.dist <= prediction);
        }
    }
}

/// Triangle `index` of a mesh.
fn triangle(s: &dyn Shape, index: u32) -> Option<Triangle> {
    s.as_trimesh().filter(|t| (index as usize) < t.num_triangles()).map(|t| t.triangle(index))
}

/// The face a cap rests on, in its shape's frame.
enum Other {
    /// A half-space: the plane through its origin.
    Plane([Point3<f64>; 1], [PackedFeatureId; 1]),
    Feature(PolygonalFeature),
}

impl Other {
    /// The face of `s` that the outward normal `n` (its frame) leaves it
    /// through, if it is flat across `n` (within [`ALIGNED`]).
    fn of(s: &dyn Shape, n: &Vector3<f64>) -> Option<Self> {
        if let Some(h) = s.as_halfspace() {
            let aligned = (h.normal.into_inner() - n).norm() <= ALIGNED;
            return aligned.then_some(Other::Plane([Point3::origin()], [PackedFeatureId::face(0)]));
        }
        // A hull's face of more than four corners comes as its first four.
        let simple = s.as_cuboid().is_some() || s.as_triangle().is_some() || s.as_convex_polyhedron().is_some_and(|h| h.faces().iter().all(|f| f.num_vertices_or_edges <= 4));
        let (map, _) = s.as_polygonal_feature_map().filter(|_| simple)?;
        let mut f = PolygonalFeature::default();
        map.local_support_feature(&Unit::new_normalize(*n), &mut f);
        if f.num_vertices < 3 {
            return None;
        }
        let v = &f.vertices;
        let normal = (v[1] - v[0]).cross(&(v[2] - v[0])).try_normalize(0.0)?;
        (normal.dot(n).abs() >= 1.0 - 0.5 * ALIGNED * ALIGNED).then_some(Other::Feature(f))
    }

    fn face(&self) -> Face<'_> {
        match self {
            Other::Plane(v, ids) => Face { vertices: v, vids: ids, eids: ids, fid: ids[0] },
            Other::Feature(f) => Face::of(f),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};
    use parry3d_f64::query::{DefaultQueryDispatcher, PersistentQueryDispatcher};
    use parry3d_f64::shape::{Cuboid, Cylinder, HalfSpace};

    /// The manifolds of `s2` standing on `s1` (both along y, parry's axis),
    /// its base `x` off `s1`'s centre, tilted `tilt` (rad) about z.
    fn stood(s1: &dyn Shape, top: f64, s2: &dyn Shape, h2: f64, x: f64, tilt: f64) -> Vec<Manifold> {
        let turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), tilt);
        let base = Vector3::new(x, top, 0.0);
        let pos12 = Translation3::from(base) * turn * Translation3::new(0.0, h2 + 1e-7, 0.0);
        let (mut m, mut ws) = (Vec::new(), None);
        DefaultQueryDispatcher.contact_manifolds(&pos12, s1, s2, 0.01, &mut m, &mut ws).unwrap();
        refine(&mut m, s1, s2, &pos12, 0.01);
        m
    }

    #[test]
    fn a_cap_flat_on_a_face_touches_on_its_round_polygon() {
        let can = Cylinder::new(0.1, 0.05);
        let cases: [(&dyn Shape, f64); 3] = [(&HalfSpace::new(Vector3::y_axis()), 0.0), (&Cuboid::new(Vector3::new(1.0, 0.1, 1.0)), 0.1), (&Cylinder::new(0.1, 0.05), 0.1)];
        for (base, top) in cases {
            let m = stood(base, top, &can, 0.1, 0.0, 0.0);
            assert_eq!(m.len(), 1);
            // Sixteen corners on the cap's circle, each 0.1 µm above the face.
            assert_eq!(m[0].points.len(), SIDES);
            for p in &m[0].points {
                assert!((p.local_p2.x.hypot(p.local_p2.z) - 0.05).abs() < 1e-12 && (p.local_p2.y + 0.1).abs() < 1e-12);
                assert!((p.dist - 1e-7).abs() < 1e-12, "{}", p.dist);
            }
        }
    }

    #[test]
    fn a_cap_over_an_edge_is_clipped_by_the_face() {
        // Half the can over the box's edge at x = 1: its corners up to the
        // edge, the two at the edge's ends on it.
        let m = stood(&Cuboid::new(Vector3::new(1.0, 0.1, 1.0)), 0.1, &Cylinder::new(0.1, 0.05), 0.1, 1.0, 0.0);
        let xs: Vec<f64> = m[0].points.iter().map(|p| p.local_p1.x).collect();
        assert!(xs.iter().all(|&x| x <= 1.0 + 1e-12), "{xs:?}");
        assert_eq!(xs.iter().filter(|&&x| (x - 1.0).abs() < 1e-12).count(), 2, "{xs:?}");
        assert_eq!(xs.len(), SIDES / 2 + 1);
    }

    #[test]
    fn a_tilted_cap_keeps_parrys_rim_point() {
        // Tilted 30°: the rim touches at its deepest point (parry's square's
        // corner); no polygon.
        let can = Cylinder::new(0.1, 0.05);
        let m = stood(&HalfSpace::new(Vector3::y_axis()), 0.0, &can, 0.1, 0.0, 0.5);
        assert!(m[0].points.len() <= 4);
    }
}
