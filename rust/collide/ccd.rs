//! Continuous collision detection for bodies that ask for it. After a drift, a
//! fast body's motion over the substep (translation and rotation, from its pose
//! before to its pose after) is swept against the colliders near its path with
//! parry's nonlinear shape cast; at the first time of impact the body is put back
//! to the pose it had then, keeping its velocity, and the contact is resolved by
//! the solver next. Half-spaces are swept linearly (parry has no nonlinear cast
//! for them). Slow bodies, which move less than half their thickness, skip it:
//! speculative contacts already catch them.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use parry3d_f64::query::{self, NonlinearRigidMotion, ShapeCastOptions};

use super::broad_phase::Aabb;
use super::collider::Collider;
use crate::body::Bodies;
use crate::math::{quat, so3, Quat, Vec3};

/// A body's pose before its drift.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Start {
    pub position: Vec3,
    pub orientation: Quat,
}

/// Sweeps body `i` (with collider `ci`) from `start` to its current pose against
/// `colliders` (their boxes in `boxes`, half-spaces apart) and moves it back to the
/// first time of impact. Returns whether it was moved.
pub fn sweep(b: &mut Bodies, ci: usize, colliders: &[Collider], boxes: &[Aabb], start: &Start) -> bool {
    let c = &colliders[ci];
    let i = c.body as usize;
    let p1 = Vec3::from(b.position[i]);
    let q1 = b.q(i);
    let dx = p1 - start.position;
    let dtheta = so3::log(&quat::to_matrix(&(q1 * start.orientation.conjugate())));
    let travel = dx.norm() + dtheta.norm() * c.reach;
    if travel < 0.5 * c.shape.ccd_thickness() {
        return false;
    }
    let start_pose = Isometry3::from_parts(
        Translation3::from(start.position),
        UnitQuaternion::new_unchecked(start.orientation),
    );
    let swept = Aabb::from_parry(&c.shape.compute_aabb(&(start_pose * c.local)))
        .swept(dx.into())
        .loosened(dtheta.norm() * c.reach);
    let local_center = c.local.inverse_transform_point(&Point3::origin());
    let motion = NonlinearRigidMotion::new(start_pose * c.local, local_center, dx, dtheta);
    let mut first: Option<f64> = None;
    for (k, other) in colliders.iter().enumerate() {
        if other.body == c.body || !c.filter.allows(&other.filter) {
            continue;
        }
        let hit = if other.infinite {
            let cast = query::cast_shapes(
                &(start_pose * c.local),
                &dx,
                c.shape.as_ref(),
                &other.pose(b),
                &Vec3::zeros(),
                other.shape.as_ref(),
                ShapeCastOptions { max_time_of_impact: 1.0, stop_at_penetration: false, ..Default::default() },
            );
            cast.ok().flatten().map(|h| h.time_of_impact)
        } else {
            if !swept.overlaps(&boxes[k]) {
                continue;
            }
            let still = NonlinearRigidMotion::constant_position(other.pose(b));
            let cast = query::cast_shapes_nonlinear(&motion, c.shape.as_ref(), &still, other.shape.as_ref(), 0.0, 1.0, false);
            cast.ok().flatten().map(|h| h.time_of_impact)
        };
        if let Some(t) = hit {
            if t < 1.0 && first.map_or(true, |f| t < f) {
                first = Some(t);
            }
        }
    }
    let Some(t) = first else { return false };
    b.position[i] = (start.position + dx * t).into();
    let q = quat::exp(&(dtheta * t)) * start.orientation;
    b.orientation[i] = quat::to_xyzw(&(q / q.norm()));
    true
}
