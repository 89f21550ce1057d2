//! The contact points of a face resting on a face: the incident face (shape
//! 2's) clipped by the side planes of the reference face (shape 1's), as Box2D
//! and Bullet clip, with points on a side plane kept. parry's clipping of two
//! faces that coincide exactly (equal hulls stacked, a box on a hull of the
//! same size) kept two or three of the four corners as round-off fell, and a
//! face held at two corners rocks.

use nalgebra::{Isometry3, Point3, Unit, Vector3};
use parry3d_f64::shape::{PackedFeatureId, PolygonalFeature};

use super::narrow_phase::{Manifold, Tracked};

/// Share of the faces' size within which a point on a side plane is inside,
/// and two points are one.
const EDGE: f64 = 1e-9;

/// A vertex of the clipped polygon (frame 1) and the features it comes from.
#[derive(Clone, Copy)]
struct Corner {
    p: Point3<f64>,
    fid1: PackedFeatureId,
    fid2: PackedFeatureId,
    /// The incident edge from this corner to the next, if it is one.
    edge2: PackedFeatureId,
}

/// A polygon of a shape (its own frame), or an edge (two vertices): its
/// vertices in order, their features, the edge from each to the next, and
/// its face. parry's features hold at most four vertices; a cylinder's cap
/// has more (see [`super::cylinder_cap`]).
#[derive(Clone, Copy)]
pub struct Face<'a> {
    pub vertices: &'a [Point3<f64>],
    pub vids: &'a [PackedFeatureId],
    pub eids: &'a [PackedFeatureId],
    pub fid: PackedFeatureId,
}

impl<'a> Face<'a> {
    pub fn of(f: &'a PolygonalFeature) -> Self {
        let n = f.num_vertices.min(f.vertices.len());
        Face { vertices: &f.vertices[..n], vids: &f.vids[..n], eids: &f.eids[..n], fid: f.fid }
    }
}

/// Replaces the points of `m` by those of face `f1` (frame 1) against face
/// `f2` (frame 2; `pos12` takes it to frame 1) along normal `n1`. False (and
/// `m` untouched) unless both are faces.
pub fn faces(m: &mut Manifold, pos12: &Isometry3<f64>, n1: &Unit<Vector3<f64>>, f1: &PolygonalFeature, f2: &PolygonalFeature) -> bool {
    f1.num_vertices >= 3 && f2.num_vertices >= 3 && clip_on(m, pos12, n1, &Face::of(f1), &Face::of(f2))
}

/// Replaces the points of `m` by those of an edge lying on a face, either way
/// round (`f1` frame 1, `f2` frame 2, normal `n1` from 1 to 2): the edge
/// clipped by the face's side planes, its ends on them kept. A can's cap
/// standing on a log touches along the log's top line, which runs through
/// two corners of parry's polygon of the cap: clipped without a tolerance,
/// one of them came and went with round-off, and the can tipped at 3 rad/s.
/// False (and `m` untouched) unless one is an edge and the other a face.
pub fn edge_and_face(m: &mut Manifold, pos12: &Isometry3<f64>, n1: &Unit<Vector3<f64>>, f1: &PolygonalFeature, f2: &PolygonalFeature) -> bool {
    match (f1.num_vertices, f2.num_vertices) {
        (n, 2) if n >= 3 => clip_on(m, pos12, n1, &Face::of(f1), &Face::of(f2)),
        (2, n) if n >= 3 => clip_either(m, pos12, n1, (&Face::of(f1), &Face::of(f2)), false),
        _ => false,
    }
}

/// Replaces the points of `m` by those of the incident polygon or edge
/// clipped by the side planes of the reference face, points on them kept:
/// `faces.0` is shape 1's (frame 1), `faces.1` shape 2's (frame 2), and the
/// reference is shape 1's if `reference_is_1`. A reference of one vertex is
/// a plane through it, with no sides. False (and `m` untouched) if nothing
/// is left.
pub fn clip_either(m: &mut Manifold, pos12: &Isometry3<f64>, n1: &Unit<Vector3<f64>>, faces: (&Face, &Face), reference_is_1: bool) -> bool {
    if reference_is_1 {
        return clip_on(m, pos12, n1, faces.0, faces.1);
    }
    let mut seen = Manifold::new();
    seen.points = m.points.iter().map(swapped).collect();
    let n2 = Unit::new_unchecked(pos12.inverse_transform_vector(&-n1.into_inner()));
    if !clip_on(&mut seen, &pos12.inverse(), &n2, faces.1, faces.0) {
        return false;
    }
    m.points = seen.points.iter().map(swapped).collect();
    true
}

/// A point seen from the other shape.
fn swapped(p: &Tracked) -> Tracked {
    let mut q = *p;
    std::mem::swap(&mut q.local_p1, &mut q.local_p2);
    std::mem::swap(&mut q.fid1, &mut q.fid2);
    q
}

/// The incident feature `f2` (a face or an edge) clipped by the side planes
/// of the reference face `f1` (see [`faces`]).
fn clip_on(m: &mut Manifold, pos12: &Isometry3<f64>, n1: &Unit<Vector3<f64>>, f1: &Face, f2: &Face) -> bool {
    let reference = f1.vertices;
    let Some(&origin) = reference.first() else { return false };
    let size = reference.iter().map(|v| (v - origin).norm()).fold(0.0, f64::max);
    let tol = EDGE * size.max(f64::MIN_POSITIVE);
    let mut poly: Vec<Corner> =
        f2.vertices.iter().zip(f2.vids.iter().zip(f2.eids)).map(|(v, (&vid, &eid))| Corner { p: pos12 * v, fid1: f1.fid, fid2: vid, edge2: eid }).collect();
    let centre = reference.iter().fold(Vector3::zeros(), |s, v| s + v.coords) / reference.len() as f64;
    for k in 0..reference.len() {
        let (a, b) = (reference[k], reference[(k + 1) % reference.len()]);
        let mut side = (b - a).cross(n1);
        if side.dot(&(centre - a.coords)) > 0.0 {
            side = -side;
        }
        let Some(side) = Unit::try_new(side, 0.0) else { continue };
        poly = clip(&poly, &a, &side, tol, f1.eids.get(k).copied().unwrap_or(f1.fid));
        if poly.is_empty() {
            return false;
        }
    }
    let old = m.points.clone();
    m.clear();
    for c in dedup(&poly, tol) {
        let dist = n1.dot(&(c.p - origin));
        let local_p1 = c.p - n1.into_inner() * dist;
        let local_p2 = pos12.inverse_transform_point(&c.p);
        m.points.push(Tracked::new(local_p1, local_p2, c.fid1, c.fid2, dist));
    }
    m.match_contacts(&old);
    true
}

/// `poly` cut by the plane through `a` with outward normal `side`, keeping
/// what lies within `tol` of its inside; a new corner lies on the reference
/// edge `edge1` and on the incident edge it cuts.
fn clip(poly: &[Corner], a: &Point3<f64>, side: &Unit<Vector3<f64>>, tol: f64, edge1: PackedFeatureId) -> Vec<Corner> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    let d = |c: &Corner| side.dot(&(c.p - a));
    for k in 0..poly.len() {
        let (c, next) = (poly[k], poly[(k + 1) % poly.len()]);
        let (dc, dn) = (d(&c), d(&next));
        if dc <= tol {
            out.push(c);
        }
        if (dc > tol) != (dn > tol) {
            let t = dc / (dc - dn);
            // Leaving, the polygon goes on along the cut; entering, along the
            // incident edge.
            let edge2 = if dc <= tol { PackedFeatureId::UNKNOWN } else { c.edge2 };
            out.push(Corner { p: c.p + (next.p - c.p) * t, fid1: edge1, fid2: c.edge2, edge2 });
        }
    }
    out
}

/// The corners less the repeats (within `tol` of one kept before).
fn dedup(poly: &[Corner], tol: f64) -> Vec<Corner> {
    let mut out: Vec<Corner> = Vec::with_capacity(poly.len());
    for c in poly {
        if out.iter().all(|o| (o.p - c.p).norm() > tol) {
            out.push(*c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feature(vertices: &[[f64; 3]]) -> PolygonalFeature {
        let mut f = PolygonalFeature::default();
        for (k, v) in vertices.iter().enumerate() {
            f.vertices[k] = Point3::from(*v);
            f.vids[k] = PackedFeatureId::vertex(k as u32);
            f.eids[k] = PackedFeatureId::edge(k as u32);
        }
        f.fid = PackedFeatureId::face(0);
        f.num_vertices = vertices.len();
        f
    }

    /// A line resting across a diamond through two of its corners (a log's top
    /// line under a can's cap, as parry's polygon of the cap has it), either
    /// way round and nudged by round-off: always both corners, touching.
    #[test]
    fn an_edge_through_two_corners_of_a_face_keeps_both() {
        let r = 0.05;
        let diamond = feature(&[[r, 0.0, 0.0], [0.0, r, 0.0], [-r, 0.0, 0.0], [0.0, -r, 0.0]]);
        let up = Unit::new_unchecked(Vector3::z());
        for k in 0..20 {
            let nudge = (k as f64 - 10.0) * 1e-17;
            let line = feature(&[[-1.0, nudge, 0.0], [1.0, -nudge, 0.0]]);
            // The line on body 1 under the face of body 2, then the face on body 1.
            let cases = [(&line, &diamond, up), (&diamond, &line, up)];
            for (f1, f2, n1) in cases {
                let mut m = Manifold::new();
                assert!(edge_and_face(&mut m, &Isometry3::identity(), &n1, f1, f2));
                let mut xs: Vec<f64> = m.points.iter().map(|p| p.local_p1.x).collect();
                xs.sort_by(f64::total_cmp);
                assert_eq!(xs.len(), 2, "nudge {nudge}: {xs:?}");
                assert!((xs[0] + r).abs() < 1e-12 && (xs[1] - r).abs() < 1e-12, "{xs:?}");
                assert!(m.points.iter().all(|p| p.dist.abs() < 1e-15 && (p.local_p1 - p.local_p2).norm() < 1e-15));
            }
        }
    }
}
