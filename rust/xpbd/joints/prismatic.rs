//! Prismatic (slider) joint: a keeps its orientation relative to b, and a's
//! anchor stays on the line through b's anchor along b's axis; the slide `s`
//! (m, a's anchor minus b's along the axis, 0 at build unless the anchors differ)
//! is free, within `limits` if given (hard).
//!
//! The corrections act on both bodies at the same world point, a's anchor (on b:
//! the point of its line there). Acting on b at b's own anchor instead, a slide
//! `s` away, would add a couple `s × p` that no force balances: a free spinning
//! pair then gained energy without bound (measured: ×1e3 in 3 s).

use super::angles::world;
use super::correction::Pair;
use super::{keep_orientation, slot, Joint};
use crate::math::Vec3;

pub fn project(j: &Joint, pair: &mut Pair<'_>) {
    keep_orientation(j, pair);
    let axis = world(&pair.pose_b().q, &j.axis_b);
    let (ra, rb, slide, gap) = slide(j, pair, &axis);
    pair.positional(slot::POSITION, &ra, &rb, &(gap - axis * slide), j.compliance);
    if let Some([lo, hi]) = j.limits {
        let (ra, rb, slide, _) = self::slide(j, pair, &axis);
        let excess = if slide < lo { slide - lo } else if slide > hi { slide - hi } else { return };
        pair.positional(slot::LIMIT, &ra, &rb, &(axis * excess), 0.0);
    }
}

/// Offsets of a's anchor from each centre, the slide along `axis`, and the gap
/// between the anchors.
fn slide(j: &Joint, pair: &Pair<'_>, axis: &Vec3) -> (Vec3, Vec3, f64, Vec3) {
    let (pa, pb) = (pair.pose_a(), pair.pose_b());
    let ra = pa.offset(&j.anchor_a);
    let at = pa.x + ra;
    let gap = at - pb.point(&j.anchor_b);
    (ra, at - pb.x, gap.dot(axis), gap)
}
