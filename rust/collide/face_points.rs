//! Contact points for the corners of hull faces that parry leaves out. parry
//! hands a face of a convex polyhedron to its clipping as at most four vertices
//! (the first four of the face: `ConvexPolyhedron::local_support_feature`), so a
//! hexagonal face resting on a box is held at four of its six corners and tips
//! into the box at the other two. Each corner of such a face in contact that the
//! manifold lacks gets a point of its own, against the other shape's closest
//! surface point, when that point lies along the manifold's normal (the corner
//! faces the other shape's face, not an edge or a side of it).

use nalgebra::{Isometry3, Vector3};
use parry3d_f64::shape::{ConvexPolyhedron, PackedFeatureId, Shape};

use super::collider::Collider;
use super::narrow_phase::{Manifold, Tracked};

/// A face whose normal is within this cosine of the manifold's normal is in
/// contact (0.9999: 0.8°).
const FACE_COS: f64 = 0.9999;
/// The other shape's closest point must lie along the normal to within this
/// share of its distance.
const ALONG: f64 = 0.05;
/// A point of the manifold this close to a corner (relative to the corner's
/// distance from the hull's origin, m) is at that corner.
const SAME: f64 = 1e-9;

/// Whether the collider's shape, or a part of its compound, is a hull with a face
/// of more than four corners: the pairs it is in need [`complete`].
pub fn many_cornered(shape: &dyn Shape) -> bool {
    let hull = |s: &dyn Shape| s.as_convex_polyhedron().is_some_and(|h| h.faces().iter().any(|f| f.num_vertices_or_edges > 4));
    match shape.as_compound() {
        Some(c) => c.shapes().iter().any(|(_, s)| hull(s.as_ref())),
        None => hull(shape),
    }
}

/// A point of the last step, where in the pair it was (the sub-shapes of its
/// manifold), to carry its warm-start data over.
pub type Kept = (u32, u32, Tracked);

/// The points of `manifolds`, to be given back to [`complete`] after parry has
/// recomputed them.
pub fn keep(manifolds: &[Manifold]) -> Vec<Kept> {
    manifolds.iter().flat_map(|m| m.points.iter().map(move |p| (m.subshape1, m.subshape2, *p))).collect()
}

/// Adds to each manifold of colliders `c1`, `c2` (`pos12`: shape 2 in shape 1's
/// frame) a point for every corner of a hull face in contact that it lacks, up to
/// `prediction` (m) apart; `kept`: the last step's points.
pub fn complete(manifolds: &mut [Manifold], c1: &Collider, c2: &Collider, pos12: &Isometry3<f64>, prediction: f64, kept: &[Kept]) {
    for m in manifolds.iter_mut().filter(|m| !m.points.is_empty()) {
        let (Some(s1), Some(s2)) = (part(c1, m.subshape1, &m.subshape_pos1), part(c2, m.subshape2, &m.subshape_pos2)) else {
            continue;
        };
        let from_sub1 = m.subshape_pos1.map_or(Isometry3::identity(), |p| p.inverse());
        let sub12 = from_sub1 * pos12 * m.subshape_pos2.unwrap_or(Isometry3::identity());
        let old: Vec<&Tracked> = kept.iter().filter(|k| (k.0, k.1) == (m.subshape1, m.subshape2)).map(|k| &k.2).collect();
        if let Some(h) = s1.as_convex_polyhedron() {
            let n = m.local_n1;
            add_corners(m, &Side { hull: h, other: s2, hull_from_other: sub12, n, second: false }, prediction, &old);
        }
        if let Some(h) = s2.as_convex_polyhedron() {
            let n = m.local_n2;
            add_corners(m, &Side { hull: h, other: s1, hull_from_other: sub12.inverse(), n, second: true }, prediction, &old);
        }
    }
}

/// The sub-shape of a collider a manifold refers to: the shape itself, or a part
/// of a compound; none for other composite shapes (a mesh's triangles have three
/// corners).
fn part<'a>(c: &'a Collider, sub: u32, pos: &Option<Isometry3<f64>>) -> Option<&'a dyn Shape> {
    match (c.shape.as_compound(), pos) {
        (Some(comp), Some(_)) => comp.shapes().get(sub as usize).map(|(_, s)| s.as_ref()),
        (None, None) => Some(c.shape.as_ref()),
        _ => None,
    }
}

/// One way round: a hull, the shape it touches, that shape's pose in the hull's
/// frame, the manifold's normal out of the hull (hull frame), and whether the hull
/// is the manifold's second shape.
struct Side<'a> {
    hull: &'a ConvexPolyhedron,
    other: &'a dyn Shape,
    hull_from_other: Isometry3<f64>,
    n: Vector3<f64>,
    second: bool,
}

fn add_corners(m: &mut Manifold, s: &Side, prediction: f64, old: &[&Tracked]) {
    let hull = s.hull;
    let Some(face) = hull.faces().iter().max_by(|a, b| a.normal.dot(&s.n).total_cmp(&b.normal.dot(&s.n))) else {
        return;
    };
    if face.num_vertices_or_edges <= 4 || face.normal.dot(&s.n) < FACE_COS {
        return;
    }
    let first = face.first_vertex_or_edge as usize;
    for &vid in &hull.vertices_adj_to_face()[first..first + face.num_vertices_or_edges as usize] {
        let fid = PackedFeatureId::vertex(vid);
        let corner = hull.points()[vid as usize];
        // parry's own point at this corner may carry the corner's id, or that of
        // an edge clipped there.
        let held = |p: &Tracked| {
            let (id, at) = if s.second { (p.fid2, p.local_p2) } else { (p.fid1, p.local_p1) };
            id == fid || (at - corner).norm() <= SAME * (1.0 + corner.coords.norm())
        };
        if m.points.iter().any(held) {
            continue;
        }
        let there = s.hull_from_other.inverse_transform_point(&corner);
        let proj = s.other.project_local_point(&there, false);
        let w = s.hull_from_other.rotation * (proj.point - there);
        let dist = w.dot(&s.n);
        let lateral = (w - s.n * dist).norm();
        // Inside or outside is only meaningful off the surface: a corner resting on
        // it (|w| at round-off, as a rigid contact leaves it) may come out either way.
        let off = w.norm() > SAME * (1.0 + corner.coords.norm());
        if (off && (lateral > ALONG * w.norm() || proj.is_inside != (dist < 0.0))) || dist > prediction {
            continue;
        }
        let mut p = if s.second {
            Tracked::new(proj.point, corner, PackedFeatureId::UNKNOWN, fid, dist)
        } else {
            Tracked::new(corner, proj.point, fid, PackedFeatureId::UNKNOWN, dist)
        };
        if let Some(o) = old.iter().find(|o| (o.fid1, o.fid2) == (p.fid1, p.fid2)) {
            p.data = o.data;
        }
        m.points.push(p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collide::narrow_phase::Manifold;
    use nalgebra::{Point3, Translation3};
    use parry3d_f64::query::{DefaultQueryDispatcher, PersistentQueryDispatcher};
    use parry3d_f64::shape::{Cuboid, SharedShape};

    /// A collider of body 0 at the origin, for the shapes of these tests.
    fn test_collider(shape: SharedShape) -> Collider {
        Collider {
            body: 0,
            many_cornered: many_cornered(shape.as_ref()),
            shape,
            local: Isometry3::identity(),
            material: Default::default(),
            filter: Default::default(),
            infinite: false,
            reach: 1.0,
            ccd: false,
            ball: None,
            corners: Default::default(),
        }
    }

    /// A hexagonal prism (corners 0.4 m from its axis, 0.6 m tall) 1 mm above the
    /// top face of a box, face down: parry's manifold and the completed one.
    fn hex_on_box(turn: f64) -> (Manifold, Manifold) {
        let corners: Vec<Point3<f64>> = (0..6)
            .flat_map(|k| {
                let a = turn + k as f64 * std::f64::consts::FRAC_PI_3;
                [-0.3, 0.3].map(|z| Point3::new(0.4 * a.cos(), 0.4 * a.sin(), z))
            })
            .collect();
        let hull = SharedShape::convex_hull(&corners).unwrap();
        let slab = SharedShape::new(Cuboid::new(nalgebra::Vector3::new(3.0, 3.0, 0.5)));
        let (c1, c2) = (test_collider(slab), test_collider(hull));
        assert!(c2.many_cornered && !c1.many_cornered);
        let pos12 = Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.5 + 0.3 + 0.001), Default::default());
        let mut manifolds: Vec<Manifold> = Vec::new();
        let mut ws = None;
        DefaultQueryDispatcher.contact_manifolds(&pos12, c1.shape.as_ref(), c2.shape.as_ref(), 0.005, &mut manifolds, &mut ws).unwrap();
        let parry = manifolds[0].clone();
        complete(&mut manifolds, &c1, &c2, &pos12, 0.005, &[]);
        (parry, manifolds.swap_remove(0))
    }

    #[test]
    fn every_corner_of_a_hexagonal_face_on_a_box_is_a_point_once() {
        for turn in [0.0, 0.1, 0.5] {
            let (parry, m) = hex_on_box(turn);
            assert!(parry.points.len() < 6, "parry keeps at most four corners: {}", parry.points.len());
            // parry's points may include one where its clipping crossed an edge:
            // the completion adds the corners it lacks, nothing else.
            let bottom: Vec<Point3<f64>> = m.points.iter().map(|p| p.local_p2).collect();
            let corners = |ps: &[Point3<f64>]| ps.iter().filter(|p| (p.coords.xy().norm() - 0.4).abs() < 1e-12).count();
            let parry_bottom: Vec<Point3<f64>> = parry.points.iter().map(|p| p.local_p2).collect();
            assert_eq!(bottom.len() - corners(&bottom), parry_bottom.len() - corners(&parry_bottom), "turn {turn}: {bottom:?}");
            for k in 0..6 {
                let a = turn + k as f64 * std::f64::consts::FRAC_PI_3;
                let corner = Point3::new(0.4 * a.cos(), 0.4 * a.sin(), -0.3);
                assert_eq!(bottom.iter().filter(|p| (**p - corner).norm() < 1e-12).count(), 1, "turn {turn}, corner {k}");
            }
            for p in &m.points {
                assert!((p.dist - 0.001).abs() < 1e-12, "{}", p.dist);
            }
        }
    }

    /// A rigid contact leaves a resting prism's corners on the floor to the
    /// round-off; which side of the surface round-off puts one must not drop it.
    #[test]
    fn hexagonal_prism_resting_at_exact_contact_keeps_all_six_corners() {
        let corners: Vec<Point3<f64>> = (0..6)
            .flat_map(|k| {
                let a = k as f64 * std::f64::consts::FRAC_PI_3;
                [-0.3, 0.3].map(|z| Point3::new(0.4 * a.cos(), 0.4 * a.sin(), z))
            })
            .collect();
        let hull = SharedShape::convex_hull(&corners).unwrap();
        // The floor as a hull (a box's corners): parry projects onto it numerically.
        let box_corners: Vec<Point3<f64>> =
            (0..8).map(|k| Point3::new(if k & 1 == 0 { -3.0 } else { 3.0 }, if k & 2 == 0 { -3.0 } else { 3.0 }, if k & 4 == 0 { -0.5 } else { 0.5 })).collect();
        let slab = SharedShape::convex_hull(&box_corners).unwrap();
        let (c1, c2) = (test_collider(slab), test_collider(hull));
        for (k, eps) in (0..400).map(|k| (k, (k % 9) as f64 * 2.7e-17 - 1.1e-16)) {
            let yaw = nalgebra::UnitQuaternion::from_axis_angle(&nalgebra::Vector3::z_axis(), 0.013 * k as f64);
            let shift = Translation3::new(0.37 * (k as f64).sin(), 0.21 * (k as f64).cos(), 0.5 + 0.3 + eps);
            let pos12 = Isometry3::from_parts(shift, yaw);
            let mut manifolds: Vec<Manifold> = Vec::new();
            let mut ws = None;
            DefaultQueryDispatcher.contact_manifolds(&pos12, c1.shape.as_ref(), c2.shape.as_ref(), 0.005, &mut manifolds, &mut ws).unwrap();
            complete(&mut manifolds, &c1, &c2, &pos12, 0.005, &[]);
            let bottom: Vec<Point3<f64>> = manifolds[0].points.iter().map(|p| p.local_p2).collect();
            for j in 0..6 {
                let a = j as f64 * std::f64::consts::FRAC_PI_3;
                let corner = Point3::new(0.4 * a.cos(), 0.4 * a.sin(), -0.3);
                assert!(bottom.iter().any(|p| (p - corner).norm() < 1e-9), "case {k}, eps {eps}, corner {j}: {bottom:?}");
            }
        }
    }
}
