//! A serial build whose contacts are last step's, pair for pair, each kept
//! whole: the records are updated where they lie instead of laid out again
//! and copied.
//!
//! The build writes a constraint, a point, a patch and a patch shape per
//! contact (1064 bytes) into arrays last written two steps before, and reads
//! last step's to keep the geometry: a 1000-ball pit at rest spent 500 µs a
//! step there against Rapier's 64 for its constraints (`benches/README.md`).
//! While this step's pairs come in last step's order and each is a ball's
//! (one point, central: see `Constraint::central`), each record is rebuilt by
//! the same code in its own slot of last step's arrays, its geometry kept
//! where `reuse::holds` keeps it; when every pair was, those arrays become
//! this step's. The arithmetic is the serial build's, so are the bits.
//!
//! A pair that does not qualify stops the update there: the records updated
//! so far go first in this step's arrays and the serial build takes the rest
//! (last step's records it may still look up are as they were, and those
//! updated before hold the same geometry, one point each).

use super::{warm_patch, within, Carry, Job, Shared, Source};
use crate::body::Bodies;
use crate::collide::collider::Collider;
use crate::collide::narrow_phase::NarrowPhase;
use crate::solve::contact::{ContactSolver, Point};
use crate::solve::friction::Patch;
use crate::solve::reuse;

impl ContactSolver {
    /// Builds this step's constraints of the pairs `order` (slots in the
    /// narrow phase) by updating last step's in place, as far as they
    /// qualify (see the module docs); returns how many pairs it built.
    /// Before the build's other path: this step's arrays then hold exactly
    /// those pairs' records, and `previous.kept` theirs.
    pub(super) fn build_in_place(&mut self, narrow: &NarrowPhase, order: &[u32], colliders: &[Collider], b: &Bodies) -> usize {
        self.constraints.clear();
        self.points.clear();
        self.patches.clear();
        self.shapes.clear();
        let mut kept = std::mem::take(&mut self.previous.kept);
        kept.clear();
        for (k, &slot) in order.iter().enumerate() {
            match self.update_one(narrow, (k, slot), colliders, b) {
                Some(o) => kept.push(o.map_or(reuse::NONE, |o| o as u32)),
                None => break,
            }
        }
        let done = kept.len();
        let p = &mut self.previous;
        p.kept = kept;
        if done == order.len() && done > 0 {
            std::mem::swap(&mut self.constraints, &mut p.constraints);
            std::mem::swap(&mut self.points, &mut p.points);
            std::mem::swap(&mut self.patches, &mut p.patches);
            std::mem::swap(&mut self.shapes, &mut p.shapes);
            // Last step's pairs beyond this step's.
            self.constraints.truncate(done);
            self.points.truncate(done);
            self.patches.truncate(done);
            self.shapes.truncate(done);
        } else {
            self.constraints.extend_from_slice(&p.constraints[..done]);
            self.points.extend_from_slice(&p.points[..done]);
            self.patches.extend_from_slice(&p.patches[..done]);
            self.shapes.extend_from_slice(&p.shapes[..done]);
        }
        done
    }

    /// Whether last step's `k`-th constraint is pair `slot`'s, a ball's (one
    /// point, the `k`-th, central) and may be updated where it lies: not an
    /// articulated link's, nor of a pair that keeps its manifolds (those take
    /// the still path: see `prepare_still`).
    fn may_update(&self, state: &crate::collide::narrow_phase::PairState, (k, slot): (usize, u32)) -> bool {
        let p = &self.previous;
        let slots = k < p.points.len() && k < p.patches.len() && k < p.shapes.len();
        let simple = |c: &crate::solve::contact::Constraint| {
            c.slot == slot && c.central && c.len == 1 && c.start as usize == k && !c.generalized
        };
        slots && p.constraints.get(k).is_some_and(simple) && !state.still && !state.keeps_manifolds()
    }

    /// The records of pair `slot`, the `k`-th, written over last step's at
    /// `k` as the serial build would write them, and the last step's
    /// constraint whose geometry they kept (`k` or none); `None` (nothing
    /// written) if they do not qualify.
    fn update_one(&mut self, narrow: &NarrowPhase, (k, slot): (usize, u32), colliders: &[Collider], b: &Bodies) -> Option<Option<usize>> {
        let state = narrow.pairs.get(slot as usize).filter(|s| self.may_update(s, (k, slot)))?;
        let ctx = self.pair_context((colliders, Some(narrow)), b, state.key, slot);
        let (carry, reach) = (Carry::of(state), state.prediction);
        // The pair's one manifold with a point within reach (as `each_group`
        // finds it), last step's, with that one point.
        let manifold = self.previous.constraints[k].manifold;
        let mut touching = state.contacts().filter(|(_, c)| within(c, reach) > 0);
        let member = touching.next().filter(|(m, c)| *m == manifold && within(c, reach) == 1)?;
        let job = Job { ctx: 0, members: (0, 1), start: k as u32, len: 1, previous: Some(k), generalized: self.generalized(([ctx.s1, ctx.s2], [ctx.b1, ctx.b2])) };
        if touching.next().is_some() || job.generalized {
            return None;
        }
        let members = [member];
        let src = Source::new(&ctx, &members, carry, reach);
        let mut point = Point::default();
        src.points(|p| point = p);
        let rest = self.rest_depth();
        let shared = Shared { bodies: &self.bodies, previous: &self.previous, world: b, rest };
        // A ball's, its geometry kept (by `reuse::holds`) or found afresh.
        let (constraint, kept) = shared.constraint(&job, &src, std::slice::from_mut(&mut point));
        if !constraint.central {
            return None;
        }
        let p = &mut self.previous;
        let (patch, pts) = (&mut p.patches[k], std::slice::from_ref(&point));
        // As `Shared::patch` leaves it: the kept geometry is the slot's own.
        match kept {
            Some(_) => patch.forget_impulses(),
            None => {
                *patch = Patch::default();
                patch.set_geometry(&mut p.shapes[k], &constraint, pts, &self.bodies);
            }
        }
        warm_patch(patch, &constraint, &src, pts, rest);
        p.points[k] = point;
        p.constraints[k] = constraint;
        Some(kept)
    }
}

#[cfg(test)]
#[path = "prepare_in_place_tests.rs"]
mod tests;
