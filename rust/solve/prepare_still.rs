//! The build of a still pair's constraints (see `collide::narrow_phase::STILL`):
//! taken whole from last step's, without their points being laid out, while
//! the bound of [`reuse::still_slack`] says the check would keep them; and
//! what each pair carries over from last step.

use super::{Job, Shared, Source};
use crate::body::Bodies;
use crate::math::{Quat, Vec3};
use crate::solve::contact::{Constraint, ContactSolver, Point};
use crate::solve::reuse;

/// What a pair's constraints may carry over from last step's.
#[derive(Clone, Copy)]
pub(crate) struct Carry {
    /// Start from the impulses the manifolds carry and keep last step's
    /// geometry if it holds (not for an impact's contact).
    pub warm: bool,
    /// The manifolds are last step's (see `NarrowPhase::still`).
    pub still: bool,
    /// The pair keeps its manifolds while it is still: its constraints'
    /// slack is tracked (see [`reuse::still_slack`]).
    pub tracked: bool,
}

impl Carry {
    /// A pair's, from its state (its constraints warm started).
    pub(super) fn of(state: &crate::collide::narrow_phase::PairState) -> Self {
        Carry { warm: true, still: state.still, tracked: state.keeps_manifolds() }
    }

    /// An impact's contact: nothing carried over.
    pub(crate) const NONE: Carry = Carry { warm: false, still: false, tracked: false };
}

impl ContactSolver {
    /// Notes the orientation of body 1 of each tracked constraint, for next
    /// step's [`reuse::still_slack`].
    pub(super) fn note_orientations(&mut self, b: &Bodies) {
        let at = &mut self.previous.built_at;
        if at.len() < b.len() {
            at.resize(b.len(), Quat::new(0.0, 0.0, 0.0, 0.0));
        }
        // Only body 1 of a tracked constraint is asked about (see
        // `reuse::still_slack`).
        for c in self.constraints.iter().filter(|c| c.arm > 0.0) {
            if let Some(q) = at.get_mut(c.b1 as usize) {
                *q = b.q(c.b1 as usize);
            }
        }
    }
}

impl Source<'_, '_> {
    /// The points of a still pair as last step's constraint `old` laid them out
    /// and kept them (see [`reuse::still_slack`]), each handed to `put`, with
    /// this step's warm start; false (some handed already) if a point is not
    /// where `old` has it.
    #[inline(always)]
    pub(super) fn still_points(&self, old: &[Point], normal: &Vec3, mut put: impl FnMut(Point)) -> bool {
        let mut old = old.iter();
        for (index, m) in self.members {
            for (k, tp) in m.points.iter().enumerate().filter(|(_, tp)| tp.dist <= self.reach) {
                let Some(q) = old.next().filter(|q| q.manifold == *index && q.manifold_point as usize == k) else {
                    return false;
                };
                put(Point {
                    r1: q.anchor1,
                    r2: q.anchor2,
                    // As `reuse::keep` writes it.
                    base_separation: tp.dist - normal.dot(&(q.anchor2 - q.anchor1)),
                    separation: tp.dist,
                    normal_impulse: if self.warm { tp.data.normal_impulse } else { 0.0 },
                    curve: 0.0,
                    total_normal: 0.0,
                    part: 0,
                    ..*q
                });
            }
        }
        old.next().is_none()
    }
}

impl Shared<'_> {
    /// Last step's constraint `o` of a still pair kept with slack `slack` (see
    /// [`Self::still`]), its points laid out.
    #[inline(always)]
    pub(super) fn kept_still(&self, job: &Job, src: &Source, (o, slack): (usize, f64)) -> (Constraint, Option<usize>) {
        let c = &self.previous.constraints[o];
        let c = Constraint { still: true, central: c.central, ..Self::assemble(job, src, (c.normal, c.t1, c.t2), (slack, c.arm)) };
        (c, Some(o))
    }

    /// If `src`'s pair is still and the slack of last step's constraint of its
    /// manifold allows (see [`reuse::still_slack`]), its points through `put`,
    /// as [`Self::constraint`] would keep them, and that constraint and the
    /// slack left; else `None` (some points may have been handed over).
    #[inline(always)]
    pub(super) fn still(&self, job: &Job, src: &Source, put: impl FnMut(Point)) -> Option<(usize, f64)> {
        let o = job.previous.filter(|_| src.still && src.warm)?;
        let q1 = self.world.q(src.ctx.b1 as usize);
        let slack = reuse::still_slack(self.previous, self.bodies, o, src.ctx, (job.len, q1))?;
        let c = &self.previous.constraints[o];
        let old = &self.previous.points[c.start as usize..(c.start + c.len) as usize];
        src.still_points(old, &c.normal, put).then_some((o, slack))
    }
}
