//! Continuous collision detection for bodies that ask for it. After a drift, a
//! fast body's motion over the substep (translation and rotation, from its pose
//! before to its pose after) is swept against the colliders near its path with
//! parry's nonlinear shape cast; at the first time of impact the body is put back
//! to the pose it had then, keeping its velocity, and the contact is resolved by
//! the solver next. Half-spaces are swept linearly (parry has no nonlinear cast
//! for them). Slow bodies, which move less than half their thickness, skip it:
//! speculative contacts already catch them.
//!
//! Parry's nonlinear cast (conservative advancement) has no iteration bound: its
//! steps shrink with the shapes' thickness against their motion, and a compound
//! at 10⁴ m/s took minutes for one step. It is used only where it is needed and
//! bounded: a body that moves more than [`MAX_SWEPT_THICKNESSES`] of its
//! thickness over the sweep is swept linearly if its rotation moves no point by
//! more than half its thickness (its rotation cannot make it miss a contact);
//! otherwise, and whenever it turns by more than [`MAX_SWEPT_TURN`], it is
//! swept as the ball that holds it (its centre moving linearly, radius its reach): a body turning that much
//! sweeps about that ball anyway, and the ball's time of impact is at most the
//! body's, so the body is stopped at or before its contact. Linear casts end in
//! a bounded number of GJK iterations.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use parry3d_f64::query::{self, NonlinearRigidMotion, ShapeCastOptions, ShapeCastStatus};
use parry3d_f64::shape::Ball;

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

/// Largest rotation (rad) over one sweep that parry's nonlinear cast is asked
/// to follow; beyond it the body is swept as its ball. (The spinning-rod test
/// turns the rod by 1.04 rad per substep, within it.)
pub const MAX_SWEPT_TURN: f64 = std::f64::consts::FRAC_PI_2;

/// Largest travel over one sweep, in the body's CCD thicknesses, that parry's
/// nonlinear cast is asked to follow (the tests' bullets: 10 to 40).
pub const MAX_SWEPT_THICKNESSES: f64 = 1000.0;

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
    let thickness = c.shape.ccd_thickness();
    // A ball about the body's centre is the same shape at every rotation.
    let round = c.ball.is_some_and(|r| c.reach <= r);
    let turn = if round { 0.0 } else { dtheta.norm() };
    let far = dx.norm() + turn * c.reach > MAX_SWEPT_THICKNESSES * thickness;
    let linear = far && turn * c.reach <= 0.5 * thickness;
    let ball = (!linear && (far || turn > MAX_SWEPT_TURN)).then(|| Ball::new(c.reach));
    let centre = Isometry3::from_parts(Translation3::from(start.position), UnitQuaternion::identity());
    let mut first: Option<f64> = None;
    for (k, other) in colliders.iter().enumerate() {
        if other.body == c.body || !c.filter.allows(&other.filter) {
            continue;
        }
        let hit = if other.infinite || (linear && swept.overlaps(&boxes[k])) {
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
            if let Some(ball) = &ball {
                let options = ShapeCastOptions { max_time_of_impact: 1.0, stop_at_penetration: false, ..Default::default() };
                let other_pose = other.pose(b);
                let cast = query::cast_shapes(&centre, &dx, ball, &other_pose, &Vec3::zeros(), other.shape.as_ref(), options);
                match cast.ok().flatten() {
                    // The ball already overlaps (a spinner next to a wall):
                    // it says nothing; the body's own shape swept linearly does.
                    Some(h) if h.status == ShapeCastStatus::PenetratingOrWithinTargetDist => query::cast_shapes(
                        &(start_pose * c.local),
                        &dx,
                        c.shape.as_ref(),
                        &other_pose,
                        &Vec3::zeros(),
                        other.shape.as_ref(),
                        options,
                    )
                    .ok()
                    .flatten()
                    .map(|h| h.time_of_impact),
                    h => h.map(|h| h.time_of_impact),
                }
            } else {
                let still = NonlinearRigidMotion::constant_position(other.pose(b));
                let cast = query::cast_shapes_nonlinear(&motion, c.shape.as_ref(), &still, other.shape.as_ref(), 0.0, 1.0, false);
                cast.ok().flatten().map(|h| h.time_of_impact)
            }
        };
        if let Some(t) = hit {
            if t < 1.0 && first.is_none_or(|f| t < f) {
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
