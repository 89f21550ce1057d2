//! Where a jointed system can reach: a ball that holds every point of its
//! bodies in every configuration its joints allow. A system joined to the
//! ground (the world or a fixed body) by rigid joints cannot leave the ball
//! about its ground anchor whose radius adds up, body by body, twice its
//! farthest joint anchor, its shape's reach and its slides' ranges; a floating
//! or soft system can go anywhere. The articulation builder uses it to tell a
//! chain that can touch a collider (it stays XPBD while contacts do not act on
//! articulations) from one that never can, whatever the collision filters say.

use super::scene::BodyDesc;
use super::Scene;
use crate::articulation::build::Component;
use crate::body::shape::ShapeKind;
use crate::body::BodyKind;
use crate::math::{quat, Vec3};
use crate::xpbd::joints::JointKind;

#[derive(Clone, Copy, Debug)]
pub struct Ball {
    pub center: Vec3,
    pub radius: f64,
}

/// Reach of a body's shape from its centre of mass (m): 0 without a shape,
/// infinite for a plane.
pub fn shape_reach(d: &BodyDesc) -> f64 {
    let Some(shape) = &d.shape else { return 0.0 };
    if matches!(shape.kind, ShapeKind::Plane { .. }) {
        return f64::INFINITY;
    }
    let local = d.shape_pose * shape.parry_pose;
    let s = shape.parry.compute_bounding_sphere(&local);
    s.center.coords.norm() + s.radius
}

/// The ball of a component, if it is joined to the ground by rigid joints only.
pub fn component_ball(scene: &Scene, comp: &Component) -> Option<Ball> {
    let descs = scene.bodies();
    let joints = scene.joints();
    let ground = |b: Option<u32>| b.is_none_or(|b| descs[b as usize].init.kind == BodyKind::Fixed);
    let mut center = None;
    let mut radius = 0.0;
    let mut anchor_max = vec![0.0f64; descs.len()];
    for &k in &comp.joints {
        let j = &joints[k];
        if j.compliance != 0.0 || j.angular_compliance != 0.0 {
            return None;
        }
        anchor_max[j.body_a as usize] = anchor_max[j.body_a as usize].max(j.anchor_a.norm());
        if let Some(b) = j.body_b {
            anchor_max[b as usize] = anchor_max[b as usize].max(j.anchor_b.norm());
        }
        radius += match j.kind {
            JointKind::Prismatic => j.limits.map_or(f64::INFINITY, |[lo, hi]| lo.abs().max(hi.abs())),
            JointKind::Distance => j.limits.map_or(j.rest_length, |[_, hi]| hi),
            _ => 0.0,
        };
        if ground(j.body_b) && center.is_none() {
            let a = &descs[j.body_a as usize].init;
            center = Some(a.position + quat::rotate(&a.orientation, &j.anchor_a));
        }
    }
    for &b in &comp.bodies {
        radius += 2.0 * anchor_max[b as usize] + shape_reach(&descs[b as usize]);
    }
    let center = center?;
    radius.is_finite().then_some(Ball { center, radius })
}

/// Whether something within `ball` could touch body `other` (its collision
/// filter allowing) when `other` is fixed or inside a ball of its own.
pub fn may_touch(ball: &Ball, other: &BodyDesc, other_ball: Option<&Ball>) -> bool {
    if other.shape.is_none() {
        return false;
    }
    if other.init.kind == BodyKind::Fixed {
        if let Some(ShapeKind::Plane { normal, offset }) = other.shape.as_ref().map(|s| &s.kind) {
            // The solid is n·x ≤ offset in the body's frame.
            let n = quat::rotate(&other.init.orientation, &Vec3::from(*normal));
            let offset = offset + n.dot(&other.init.position);
            return n.dot(&ball.center) - offset <= ball.radius;
        }
        return (other.init.position - ball.center).norm() <= ball.radius + shape_reach(other);
    }
    match other_ball {
        Some(o) => (o.center - ball.center).norm() <= ball.radius + o.radius,
        None => true,
    }
}
