//! Distance joint: the anchors of a and b stay `rest_length` apart, or, with
//! `limits = [min, max]`, between `min` and `max` (a rope is `[0, L]`); every
//! rotation is free. Compliance: the joint's `compliance` (m/N).

use super::correction::Pair;
use super::{slot, Joint};

/// Below this length (m) the direction between the anchors is undefined.
const COINCIDENT: f64 = 1e-12;

pub fn project(j: &Joint, pair: &mut Pair<'_>) {
    let (pa, pb) = (pair.pose_a(), pair.pose_b());
    let (ra, rb) = (pa.offset(&j.anchor_a), pb.offset(&j.anchor_b));
    let gap = (pa.x + ra) - (pb.x + rb);
    let len = gap.norm();
    let [lo, hi] = j.limits.unwrap_or([j.rest_length, j.rest_length]);
    let excess = if len < lo {
        len - lo
    } else if len > hi {
        len - hi
    } else {
        return;
    };
    if len < COINCIDENT {
        if hi == 0.0 {
            pair.positional(slot::POSITION, &ra, &rb, &gap, j.compliance);
        }
        return;
    }
    pair.positional(slot::POSITION, &ra, &rb, &(gap * (excess / len)), j.compliance);
}
