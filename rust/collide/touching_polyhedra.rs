//! Convex polyhedra placed exactly touching. parry's manifold of two convex
//! polyhedra (other than two boxes) starts from GJK's closest points, and GJK
//! ending at distance zero (to round-off) hands back an arbitrary direction:
//! two equal cube hulls stacked exactly got a sideways normal and points 0.2 m
//! deep, which the solver pushed apart sideways (a tower of ten fell). Of 4000
//! touching placements of cube hulls (equal or not, shifted, turned about the
//! vertical), 489 got a wrong normal, each at a GJK distance below 1e-15 m.
//!
//! So a manifold of two polyhedra (or of two compounds' polyhedral parts)
//! whose GJK point (the one parry adds at
//! GJK's closest points) is within [`TOUCH`] of touching is checked by the
//! separating-axis test over both shapes' face normals: where a face normal
//! separates the shapes at least as well as the manifold's normal, the
//! manifold is built again on it, two faces by clipping that keeps the
//! corners on a side (see [`super::face_clip`]). An edge–edge axis that
//! separates better than every face normal is kept. Checking every fresh
//! manifold instead (which would also square up the 1e-5 rad tilts of
//! parry's penetration depth) cost a pile of 392 tumbling hulls of 26
//! vertices 3.0x its narrow phase, and a pile of cube hulls 2x its contact
//! solve.

use nalgebra::{Isometry3, Unit, Vector3};
use parry3d_f64::shape::{PackedFeatureId, PolygonalFeature, Shape};

use super::narrow_phase::Manifold;

/// GJK distances (m) within this of zero are touching to round-off (those of
/// the 489 wrong normals were below 1e-15 m; 392 cube hulls tumbling into a
/// pile for 240 steps never came this close).
const TOUCH: f64 = 1e-9;

/// Separations (m) that differ by less than this are the same.
const SAME: f64 = 1e-12;

/// Whether the pair is one this module checks: two convex polyhedra (hulls or
/// boxes) other than two boxes, which parry solves by the separating-axis
/// test itself.
fn applies(s1: &dyn Shape, s2: &dyn Shape) -> bool {
    let flat = |s: &dyn Shape| s.as_convex_polyhedron().is_some() || s.as_cuboid().is_some();
    flat(s1) && flat(s2) && !two_boxes(s1, s2)
}

/// Whether both shapes are boxes (parry's own separating-axis pair).
fn two_boxes(s1: &dyn Shape, s2: &dyn Shape) -> bool {
    s1.as_cuboid().is_some() && s2.as_cuboid().is_some()
}

/// Whether some manifold of the pair may be one this module checks (a
/// compound's parts may be hulls).
pub fn may_apply(s1: &dyn Shape, s2: &dyn Shape) -> bool {
    let worth = |s: &dyn Shape| s.as_convex_polyhedron().is_some() || s.as_cuboid().is_some() || s.as_compound().is_some();
    worth(s1) && worth(s2)
}

/// Rebuilds each manifold of the pair (`pos12`: shape 2 in shape 1's frame)
/// found touching whose normal a face normal matches or beats.
pub fn repair(manifolds: &mut [Manifold], s1: &dyn Shape, s2: &dyn Shape, pos12: &Isometry3<f64>) {
    for m in manifolds.iter_mut() {
        let (p1, p2) = (part(s1, m.subshape1), part(s2, m.subshape2));
        let boxes = two_boxes(p1, p2);
        if !touching(m, p1, p2, boxes) {
            continue;
        }
        let pos = part_pose(m, pos12);
        let Some(n) = Unit::try_new(m.local_n1, 1e-12) else { continue };
        let Some((best, s)) = best_face_axis(p1, p2, &pos) else { continue };
        // Two boxes: their edge–edge axes can be a face normal exactly, with
        // the points of two edges, so the manifold is clipped again on the best
        // face whatever its normal.
        if (boxes || best != n) && s >= separation(p1, p2, &pos, &n) - SAME {
            rebuild(m, p1, p2, &pos, &best, false);
        }
    }
}

/// Whether manifold `m` of parts `p1` and `p2` (`boxes`: both are boxes) is
/// one to check: two polyhedra other than two boxes whose GJK point is within
/// [`TOUCH`], or two boxes touching, within it, at one or two points.
/// parry's separating-axis test of two boxes takes an edge–edge axis over a
/// face normal when round-off puts it ahead by 1e-17 m: two cubes stacked
/// exactly then touched at two opposite corners, the weight they carried
/// warm-started at one, and a grid of cubes stacked edge to edge was kicked at
/// 0.6 rad/s out of rest. (Checking every
/// touching manifold of two boxes rebuilt the faces of a resting pyramid
/// whenever its depths fell within [`TOUCH`], and parry's own otherwise: the
/// warm start lost its points at each change, and the pyramid rocked at 10
/// steps a second.)
fn touching(m: &Manifold, p1: &dyn Shape, p2: &dyn Shape, boxes: bool) -> bool {
    if boxes {
        let edges = (1..3).contains(&m.points.len());
        return edges && m.points.iter().all(|p| p.dist.abs() <= TOUCH);
    }
    let gjk = m.points.iter().find(|p| p.fid1 == PackedFeatureId::UNKNOWN).map(|p| p.dist);
    gjk.is_some_and(|d| d.abs() <= TOUCH) && applies(p1, p2)
}

/// Manifold `m`'s part of shape 2 in its part of shape 1's frame (`pos12`:
/// the shapes'): a compound's manifold is in its parts' frames.
pub(super) fn part_pose(m: &Manifold, pos12: &Isometry3<f64>) -> Isometry3<f64> {
    let at = |p: Option<Isometry3<f64>>| p.unwrap_or_else(Isometry3::identity);
    at(m.subshape_pos1).inv_mul(&(pos12 * at(m.subshape_pos2)))
}

/// Part `index` of a compound, or the shape itself.
pub(super) fn part(s: &dyn Shape, index: u32) -> &dyn Shape {
    match s.as_compound().and_then(|c| c.shapes().get(index as usize)) {
        Some((_, p)) => p.as_ref(),
        None => s,
    }
}

/// How far shape 2 lies beyond shape 1 along `u` (frame 1; m, negative when
/// they overlap along it).
fn separation(s1: &dyn Shape, s2: &dyn Shape, pos12: &Isometry3<f64>, u: &Unit<Vector3<f64>>) -> f64 {
    let (Some(a), Some(b)) = (s1.as_support_map(), s2.as_support_map()) else {
        return f64::NEG_INFINITY;
    };
    let far1 = a.local_support_point_toward(u);
    let near2 = pos12 * b.local_support_point(&(pos12.inverse_transform_vector(&-u.into_inner())));
    u.dot(&(near2 - far1))
}

/// The face normal of either shape (in frame 1, from 1 toward 2) along which
/// they are furthest apart.
fn best_face_axis(s1: &dyn Shape, s2: &dyn Shape, pos12: &Isometry3<f64>) -> Option<(Unit<Vector3<f64>>, f64)> {
    let mut best: Option<(f64, Unit<Vector3<f64>>)> = None;
    let mut consider = |u: Unit<Vector3<f64>>| {
        let s = separation(s1, s2, pos12, &u);
        if best.is_none_or(|(b, _)| s > b) {
            best = Some((s, u));
        }
    };
    for u in face_normals(s1) {
        consider(u);
    }
    for u in face_normals(s2) {
        consider(Unit::new_unchecked(pos12.rotation * -u.into_inner()));
    }
    best.map(|(s, u)| (u, s))
}

/// The outward face normals of a hull or a box, in its own frame.
pub(super) fn face_normals(s: &dyn Shape) -> Vec<Unit<Vector3<f64>>> {
    if let Some(h) = s.as_convex_polyhedron() {
        return h.faces().iter().map(|f| f.normal).collect();
    }
    if s.as_cuboid().is_some() {
        let axes = [Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()];
        return axes.iter().flat_map(|a| [*a, -*a]).collect();
    }
    Vec::new()
}

/// Manifold `m` built again on normal `n1` (frame 1) by clipping the two
/// shapes' support features (`edges`: an edge on a face too, see
/// [`super::face_clip::edge_and_face`]), carrying the warm-start data of
/// points that match.
pub(super) fn rebuild(m: &mut Manifold, s1: &dyn Shape, s2: &dyn Shape, pos12: &Isometry3<f64>, n1: &Unit<Vector3<f64>>, edges: bool) {
    let (Some((f1, _)), Some((f2, _))) = (s1.as_polygonal_feature_map(), s2.as_polygonal_feature_map()) else {
        return;
    };
    let n2 = Unit::new_unchecked(pos12.inverse_transform_vector(&-n1.into_inner()));
    let (mut feature1, mut feature2) = (PolygonalFeature::default(), PolygonalFeature::default());
    f1.local_support_feature(n1, &mut feature1);
    f2.local_support_feature(&n2, &mut feature2);
    let clipped = super::face_clip::faces(m, pos12, n1, &feature1, &feature2)
        || (edges && super::face_clip::edge_and_face(m, pos12, n1, &feature1, &feature2));
    if !clipped {
        let old = m.points.clone();
        m.clear();
        PolygonalFeature::contacts(pos12, &pos12.inverse(), n1, &n2, &feature1, &feature2, m, false);
        m.match_contacts(&old);
    }
    m.local_n1 = n1.into_inner();
    m.local_n2 = n2.into_inner();
}
