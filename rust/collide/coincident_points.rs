//! Points of one manifold at the same place, merged. parry clips the faces of
//! two boxes that share corners (a box stacked exactly on another, or on the
//! edge of its neighbour) into each shared corner twice, once as a vertex of
//! each face: a face of four corners became eight points and an edge line four,
//! so an edge counted as a face among the support contacts and the least-norm
//! load split gave each doubled corner twice its share. In a grid of cubes
//! stacked edge to edge, the columns' neighbours then carried 0.2 N·s of a
//! 0.65 N·s weight at their edges, with 0.08 N·s of friction, at rest.

use parry3d_f64::shape::Shape;

use super::narrow_phase::Manifold;

/// Points closer than this share of their distance from the shape's origin
/// (m; at least this many metres) are one.
const SAME: f64 = 1e-9;

/// Merges the points of each manifold of two boxes that lie at the same place
/// (frame 1), the first kept: its warm-start impulses are the sum of the two
/// (parry matches each by its own features, so one of them carries what the
/// merged point carried last step).
pub fn merge(manifolds: &mut [Manifold], s1: &dyn Shape, s2: &dyn Shape) {
    if s1.as_cuboid().is_none() || s2.as_cuboid().is_none() {
        return;
    }
    for m in manifolds.iter_mut() {
        let mut k = 1;
        while k < m.points.len() {
            let p = m.points[k].local_p1;
            let near = SAME * (1.0 + p.coords.norm());
            match m.points[..k].iter().position(|q| (q.local_p1 - p).norm() <= near) {
                Some(j) => {
                    let d = m.points.remove(k).data;
                    let e = &mut m.points[j].data;
                    e.normal_impulse += d.normal_impulse;
                    for (a, b) in e.friction_impulse.iter_mut().zip(d.friction_impulse) {
                        *a += b;
                    }
                    e.twist_impulse += d.twist_impulse;
                    e.sliding |= d.sliding;
                }
                None => k += 1,
            }
        }
    }
}
