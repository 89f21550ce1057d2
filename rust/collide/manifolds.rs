//! The contact manifolds of one pair of colliders at one relative pose: parry's,
//! with this crate's repairs (half-space and hull, polyhedra and cylinders
//! touching exactly, faces of many corners, meshes and rolling shapes computed
//! afresh), and the single point of two balls.

use nalgebra::{Isometry3, Vector3};
use parry3d_f64::query::{ContactManifoldsWorkspace, DefaultQueryDispatcher, PersistentQueryDispatcher};
use parry3d_f64::shape::PackedFeatureId;

use super::collider::Collider;
use super::narrow_phase::{BallContact, Manifold, Tracked};

/// The manifolds of two colliders (`pos12`: 2 in 1's frame) up to
/// `prediction`, into `manifolds` and parry's `workspace` (last step's, whose
/// points carry their warm-start data, or empty): a half-space and a hull by
/// [`super::plane_hull`], the rest by parry, its manifolds of polyhedra
/// touching exactly repaired ([`super::touching_polyhedra`]) and the corners
/// it leaves out of faces of more than four added ([`super::face_points`]),
/// those of cylinders and cones touching exactly computed a hair apart
/// ([`super::touching_axial`]) and their caps resting on faces given their
/// round shape ([`super::cylinder_cap`]).
/// Used by the narrow phase and by the impacts' contacts at their time of
/// impact, where the bodies touch exactly.
pub fn manifolds_of(c1: &Collider, c2: &Collider, pos12: &Isometry3<f64>, prediction: f64, (manifolds, workspace): (&mut Vec<Manifold>, &mut Option<ContactManifoldsWorkspace>)) {
    if plane_and_hull(c1, c2, pos12, prediction, manifolds) {
        return;
    }
    let many_cornered = c1.many_cornered || c2.many_cornered;
    let kept = if many_cornered { super::face_points::keep(manifolds) } else { Vec::new() };
    let (s1, s2) = (c1.shape.as_ref(), c2.shape.as_ref());
    let afresh = afresh(s1) || afresh(s2);
    let old = if afresh { take_points(manifolds) } else { Vec::new() };
    // Unsupported pairs are rejected when the world is built; none reach here.
    let _ = DefaultQueryDispatcher.contact_manifolds(pos12, s1, s2, prediction, manifolds, workspace);
    if super::touching_axial::may_apply(s1, s2) {
        super::touching_axial::repair(manifolds, s1, s2, pos12, prediction);
    }
    if super::cylinder_cap::may_apply(s1, s2) {
        super::cylinder_cap::refine(manifolds, s1, s2, pos12, prediction);
    }
    if afresh {
        rematch(manifolds, &old);
    }
    if super::touching_polyhedra::may_apply(s1, s2) {
        super::touching_polyhedra::repair(manifolds, s1, s2, pos12);
    }
    if many_cornered {
        super::face_points::complete(manifolds, c1, c2, pos12, prediction, &kept);
    }
    super::coincident_points::merge(manifolds, s1, s2);
}

/// Whether parry's manifolds of a shape are computed afresh each step (see
/// [`take_points`]): a mesh's, or a shape that rolls.
pub(super) fn afresh(s: &dyn parry3d_f64::shape::Shape) -> bool {
    s.as_trimesh().is_some() || rolls(s)
}

/// Whether a shape can roll on a curved side (a capsule, a cylinder, a
/// cone): its manifolds are computed afresh each step (see [`take_points`]).
/// parry keeps the points of a manifold while they have moved less than
/// 1 mm, turning them with the body: on a body rolling on its curved side
/// they rise off the floor (`r (1 − cos θ)`), the solver let it fall to
/// them, and the manifold computed again found it that deep. A capsule or a
/// cylinder rolling at 0.05 m/s on a box at 240 Hz (0.2 mm a step) bounced on
/// its stale points and gained speed: its kinetic energy ×6.8 in 2 s.
fn rolls(s: &dyn parry3d_f64::shape::Shape) -> bool {
    s.as_capsule().is_some() || s.as_cylinder().is_some() || s.as_cone().is_some()
}

/// Each manifold's points, taken out of it, by its pair of parts.
///
/// A manifold that has points is kept by parry while its points have moved
/// less than 1 mm along it since the last step (spatial coherence), moved
/// with the second shape and never clipped again: a box sliding over a mesh
/// at 3 m/s in steps of 1/3000 s kept points beyond the triangle they were
/// clipped to, and its patch turned it at 2.7 rad/s. Handed over empty, a
/// mesh's manifolds are computed afresh each step, and their points take the
/// warm-start data of the old ones by feature ([`rematch`]).
fn take_points(manifolds: &mut [Manifold]) -> Vec<((u32, u32), Vec<Tracked>)> {
    manifolds.iter_mut().map(|m| ((m.subshape1, m.subshape2), std::mem::take(&mut m.points))).collect()
}

/// Carries the warm-start data of the `old` points (see [`take_points`]) to the
/// manifolds of the same parts: mostly in the same place, else searched for
/// (a face on 1250 triangles would otherwise search 1250 times).
fn rematch(manifolds: &mut [Manifold], old: &[((u32, u32), Vec<Tracked>)]) {
    for (k, m) in manifolds.iter_mut().enumerate() {
        let key = (m.subshape1, m.subshape2);
        let same = old.get(k).filter(|(o, _)| *o == key).or_else(|| old.iter().find(|(o, _)| *o == key));
        if let Some((_, points)) = same {
            m.match_contacts(points);
        }
    }
}

/// The contact of two balls of radii `r1`, `r2` (`pos12`: ball 2 in ball 1's
/// frame), as parry's ball–ball manifold has it: none beyond `prediction`, and the
/// warm-start data kept while it lasts.
pub(super) fn ball_ball(pos12: &Isometry3<f64>, r1: f64, r2: f64, prediction: f64, ball: &mut Option<BallContact>) {
    let d = pos12.translation.vector;
    let centres = d.norm();
    let dist = centres - r1 - r2;
    if dist >= prediction {
        *ball = None;
        return;
    }
    let local_n1 = if centres != 0.0 { d / centres } else { Vector3::y() };
    let local_n2 = pos12.inverse_transform_vector(&-local_n1);
    let face = PackedFeatureId::face(0);
    let data = ball.map(|b| b.point.data).unwrap_or_default();
    let mut point = Tracked::new((local_n1 * r1).into(), (local_n2 * r2).into(), face, face, dist);
    point.data = data;
    *ball = Some(BallContact { local_n1, point });
}

/// The half-space–hull pair, either way round, by [`super::plane_hull`].
/// Returns whether it was one.
fn plane_and_hull(c1: &Collider, c2: &Collider, pos12: &nalgebra::Isometry3<f64>, prediction: f64, manifolds: &mut Vec<Manifold>) -> bool {
    let flipped = match (c1.shape.as_halfspace(), c2.shape.as_halfspace()) {
        (Some(_), None) if c2.shape.as_convex_polyhedron().is_some() => false,
        (None, Some(_)) if c1.shape.as_convex_polyhedron().is_some() => true,
        _ => return false,
    };
    let (plane, hull, pos) = if flipped { (c2, c1, pos12.inverse()) } else { (c1, c2, *pos12) };
    let (Some(plane), Some(hull)) = (plane.shape.as_halfspace(), hull.shape.as_convex_polyhedron()) else {
        return false;
    };
    manifolds.truncate(1);
    if manifolds.is_empty() {
        manifolds.push(Manifold::new());
    }
    let m = &mut manifolds[0];
    if flipped {
        swap_sides(m);
    }
    super::plane_hull::plane_hull(&pos, plane, hull, prediction, m);
    if flipped {
        swap_sides(m);
    }
    true
}

/// The same manifold seen from the other shape.
fn swap_sides(m: &mut Manifold) {
    std::mem::swap(&mut m.local_n1, &mut m.local_n2);
    std::mem::swap(&mut m.subshape1, &mut m.subshape2);
    std::mem::swap(&mut m.subshape_pos1, &mut m.subshape_pos2);
    for p in &mut m.points {
        std::mem::swap(&mut p.local_p1, &mut p.local_p2);
        std::mem::swap(&mut p.fid1, &mut p.fid2);
    }
}
