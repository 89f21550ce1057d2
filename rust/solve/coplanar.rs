//! A pair's manifolds gathered into constraints by their normals.
//!
//! parry gives a manifold per triangle of a mesh (and per part of a
//! compound): a box face resting on a triangulated floor touches several,
//! each with the same normal. As constraints of their own, each would carry a
//! friction patch limited by its own share of the load, and how a rigid face's
//! load splits between them is arbitrary, so their friction need not add up to
//! no torque: a box sliding straight over a floor of 20 × 20 squares yawed at
//! up to 7.8 rad/s. Manifolds of one pair whose normals agree form one
//! constraint instead, with one patch over all their points: a face's on
//! several triangles, two halves of a compound cube on another, or two feet
//! of a compound on a floor. The patch is centred where a uniform pressure
//! over the union of its manifolds is (see `super::friction`), under the
//! centre of mass of a body on prismatic feet, not at the centroid of their
//! hull.

use super::contact::PairContext;
use crate::collide::narrow_phase::Contacts;
use crate::math::Vec3;

/// Cosine of the largest angle between the normals of two manifolds that share
/// a constraint (1.4 mrad): a triangulated plane's triangles agree to round-off,
/// while a terrain's facets that meet at an angle keep their own normals.
pub(crate) const SAME_NORMAL_COS: f64 = 1.0 - 1e-6;

/// One manifold of a pair: its index in the pair and its points.
pub(crate) type Member<'a> = (u32, Contacts<'a>);

/// The world normal of a manifold of the pair `ctx`.
pub(crate) fn normal_of(ctx: &PairContext, m: &Contacts) -> Vec3 {
    let sub1 = m.subshape_pos1.map_or(ctx.pose1, |s| ctx.pose1 * s);
    sub1.rotation * m.local_n1
}

/// `members` grouped by normal, in order: each group led by the first of its
/// manifolds, the others those after it whose normal agrees with the
/// leader's. `leads[k]` is the group of member `k`.
pub(crate) fn group(ctx: &PairContext, members: &[Member], leads: &mut Vec<u32>) -> usize {
    leads.clear();
    let mut leaders: Vec<Vec3> = Vec::new();
    for (_, m) in members {
        let n = normal_of(ctx, m);
        match leaders.iter().position(|l| l.dot(&n) >= SAME_NORMAL_COS) {
            Some(g) => leads.push(g as u32),
            None => {
                leads.push(leaders.len() as u32);
                leaders.push(n);
            }
        }
    }
    leaders.len()
}
