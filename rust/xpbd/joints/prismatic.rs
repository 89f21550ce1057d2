//! Prismatic (slider) joint: a keeps its orientation relative to b, and a's
//! anchor stays on the line through b's anchor along b's axis; the slide `s`
//! (m, a's anchor minus b's along the axis, 0 at build unless the anchors differ)
//! is free, within `limits` if given (hard).

use super::angles::world;
use super::correction::Pair;
use super::{keep_orientation, slot, Joint};

pub fn project(j: &Joint, pair: &mut Pair<'_>) {
    keep_orientation(j, pair);
    let (pa, pb) = (pair.pose_a(), pair.pose_b());
    let (ra, rb) = (pa.offset(&j.anchor_a), pb.offset(&j.anchor_b));
    let axis = world(&pb.q, &j.axis_b);
    let gap = (pa.x + ra) - (pb.x + rb);
    let slide = gap.dot(&axis);
    pair.positional(slot::POSITION, &ra, &rb, &(gap - axis * slide), j.compliance);
    if let Some([lo, hi]) = j.limits {
        let (pa, pb) = (pair.pose_a(), pair.pose_b());
        let (ra, rb) = (pa.offset(&j.anchor_a), pb.offset(&j.anchor_b));
        let slide = ((pa.x + ra) - (pb.x + rb)).dot(&axis);
        let excess = if slide < lo { slide - lo } else if slide > hi { slide - hi } else { return };
        pair.positional(slot::LIMIT, &ra, &rb, &(axis * excess), 0.0);
    }
}
