//! Contacts between a half-space and a convex hull. parry describes a face by at
//! most four vertices, so a hull resting on a face of five or more (a hexagonal
//! prism) would get an edge, two points, and topple. Here every vertex of the hull
//! within reach of the plane is a candidate, and the manifold keeps up to four
//! that span them: the deepest, the one farthest from it, the one farthest from
//! their line, and the one farthest on the other side. Points keep their vertex as
//! feature id, so warm starting follows them from step to step.

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query::TrackedContact;
use parry3d_f64::shape::{ConvexPolyhedron, HalfSpace, PackedFeatureId};

use super::narrow_phase::{ContactData, Manifold};

/// Fills `manifold` with the contacts of `plane` (shape 1, at the origin of its
/// frame) and `hull` (shape 2, at `pos12` in the plane's frame) closer than
/// `prediction` (m).
pub fn plane_hull(pos12: &Isometry3<f64>, plane: &HalfSpace, hull: &ConvexPolyhedron, prediction: f64, manifold: &mut Manifold) {
    let n = plane.normal.into_inner();
    let near: Vec<(usize, Point3<f64>, f64)> = hull
        .points()
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let p = pos12 * v;
            (i, p, n.dot(&p.coords))
        })
        .filter(|&(_, _, d)| d <= prediction)
        .collect();
    let old: Vec<TrackedContact<ContactData>> = std::mem::take(&mut manifold.points);
    manifold.local_n1 = n;
    manifold.local_n2 = pos12.inverse_transform_vector(&-n);
    manifold.subshape1 = 0;
    manifold.subshape2 = 0;
    manifold.subshape_pos1 = None;
    manifold.subshape_pos2 = None;
    for k in spanning(&near, &n) {
        let (i, p, d) = near[k];
        let on_plane = p - n * d;
        let fid2 = PackedFeatureId::vertex(i as u32);
        let mut tc = TrackedContact::new(on_plane, hull.points()[i], PackedFeatureId::face(0), fid2, d);
        if let Some(o) = old.iter().find(|o| o.fid2 == fid2) {
            tc.data = o.data;
        }
        manifold.points.push(tc);
    }
}

/// Up to four of `near` (index, point, distance) spanning them in the plane of
/// normal `n`.
fn spanning(near: &[(usize, Point3<f64>, f64)], n: &Vector3<f64>) -> Vec<usize> {
    if near.len() <= 4 {
        return (0..near.len()).collect();
    }
    let flat = |k: usize| near[k].1.coords - n * near[k].2;
    let deepest = (0..near.len()).min_by(|&a, &b| near[a].2.total_cmp(&near[b].2)).unwrap_or(0);
    let far = |from: &dyn Fn(usize) -> f64| (0..near.len()).max_by(|&a, &b| from(a).total_cmp(&from(b))).unwrap_or(0);
    let a = flat(deepest);
    let second = far(&|k| (flat(k) - a).norm_squared());
    let b = flat(second);
    let side = |k: usize| (b - a).cross(&(flat(k) - a)).dot(n);
    let third = far(&|k| side(k));
    let fourth = far(&|k| -side(k));
    let mut out = vec![deepest, second, third, fourth];
    out.sort_unstable();
    out.dedup();
    out
}
