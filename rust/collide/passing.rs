//! Speculative contacts only for pairs whose paths meet.
//!
//! Contacts are predicted as far as two bodies can approach in a step, so that a
//! fast body is stopped where it would hit instead of tunnelling. But the points
//! parry reports are the closest features *now*, with the normal between them: a
//! box flying past a ball at 1400 m/s sees the ball metres ahead along that
//! normal, and a solver that lets it close only that gap within the step stops it
//! though its path misses the ball by a metre (a box at (1000, 1000, 0) m/s
//! passing 1.35 m from a sphere came out at (483, 1000, 0)). So for a pair whose
//! travel in the step is well beyond the margin, a linear sweep over the step
//! decides: if the shapes, moving as they do, never come within what their
//! rotation and the curvature of their path can add, nothing needs predicting
//! beyond that.

use nalgebra::Vector3;
use parry3d_f64::query::{cast_shapes, ShapeCastOptions};
use parry3d_f64::shape::ShapeType;

use super::collider::Collider;
use super::approach::Approach;
use super::narrow_phase::Prediction;
use crate::body::Bodies;

/// A pair is swept only when its travel in the step exceeds this many margins:
/// below, the speculative gap is small enough to be harmless and the sweep would
/// only cost.
const SWEEP_ABOVE: f64 = 4.0;

/// The prediction (m) for a pair whose full `prediction` came from `approach`:
/// unchanged unless a sweep shows the shapes pass clear.
pub(super) fn narrowed(c1: &Collider, c2: &Collider, bodies: &Bodies, pred: &Prediction, approach: &Approach, prediction: f64) -> f64 {
    let dt = pred.dt;
    if dt * approach.velocity_after(dt).norm() <= SWEEP_ABOVE * pred.margin || !(sweepable(c1) && sweepable(c2)) {
        return prediction;
    }
    // A linear sweep at the mean velocity ends where the accelerated path ends and
    // strays from it by at most |a| dt²/8; the surfaces' turning adds its own.
    let near = pred.margin + dt * approach.turning + approach.accel.norm() * dt * dt / 8.0;
    if near >= prediction {
        return prediction;
    }
    let mean = approach.velocity + approach.accel * (0.5 * dt);
    let options = ShapeCastOptions {
        max_time_of_impact: dt,
        target_distance: near,
        stop_at_penetration: true,
        compute_impact_geometry_on_penetration: false,
    };
    let (p1, p2) = (c1.pose(bodies), c2.pose(bodies));
    match cast_shapes(&p1, &mean, c1.shape.as_ref(), &p2, &Vector3::zeros(), c2.shape.as_ref(), options) {
        Ok(None) => near,
        _ => prediction,
    }
}

/// Shapes the sweep handles directly (convex shapes and half-spaces); the others
/// keep the full prediction.
fn sweepable(c: &Collider) -> bool {
    c.shape.is_convex() || c.shape.shape_type() == ShapeType::HalfSpace
}
