//! Hinge (revolute) joint: the anchors coincide and the axes of a and b stay
//! aligned; a turns freely about the axis, within `limits` if given.
//!
//! The hinge angle is the angle by which a has turned relative to b about the
//! axis since build (right hand about the axis), in (−π, π]. With `limits =
//! [lo, hi]` an angle below `lo` or above `hi` is turned back to the limit (a hard
//! constraint: an inequality, projected only while violated).

use super::angles::{signed_angle, turn_between, world};
use super::correction::Pair;
use super::{attach, slot, Joint};

pub fn project(j: &Joint, pair: &mut Pair<'_>) {
    align(j, pair);
    if let Some(limits) = j.limits {
        limit(j, pair, limits);
    }
    attach(j, pair);
}

/// Turns a's axis onto b's: a is turned by `turn(b's axis → a's axis)` too far.
fn align(j: &Joint, pair: &mut Pair<'_>) {
    let (pa, pb) = (pair.pose_a(), pair.pose_b());
    let (axis_a, axis_b) = (world(&pa.q, &j.axis_a), world(&pb.q, &j.axis_b));
    pair.angular(slot::ORIENTATION, &turn_between(&axis_b, &axis_a), j.angular_compliance);
}

/// The current hinge angle (rad).
pub fn angle(j: &Joint, pair: &Pair<'_>) -> f64 {
    let (pa, pb) = (pair.pose_a(), pair.pose_b());
    let axis = world(&pb.q, &j.axis_b);
    signed_angle(&world(&pb.q, &j.ref_b), &world(&pa.q, &j.ref_a), &axis)
}

fn limit(j: &Joint, pair: &mut Pair<'_>, [lo, hi]: [f64; 2]) {
    let phi = angle(j, pair);
    let excess = if phi < lo {
        phi - lo
    } else if phi > hi {
        phi - hi
    } else {
        return;
    };
    let axis = world(&pair.pose_b().q, &j.axis_b);
    pair.angular(slot::LIMIT, &(axis * excess), 0.0);
}
