//! The warm start: each substep begins with the impulses the last one ended
//! with (the step's first with the last step's, kept in the manifolds),
//! applied to the bodies again.

use super::contact::{Constraint, ContactSolver, Point};
use super::friction::Patch;
use super::pair::Pair;
use super::solver_body::SolverBody;

impl ContactSolver {
    /// The warm start's impulses (those of the last substep) scaled by
    /// `ratio`, the new substep's length over the one they were found for: a
    /// step that took 16 substeps after steps of 4 applied four substeps'
    /// support in its first, and the columns of a resting grid of cubes
    /// jumped to 4e-5 m/s; back to 4, a quarter of it. Ratios within
    /// round-off of one leave the impulses as they are.
    pub(crate) fn scale_warm_start(&mut self, ratio: f64) {
        if (ratio - 1.0).abs() <= 1e-9 || !ratio.is_finite() {
            return;
        }
        self.points.iter_mut().for_each(|p| p.normal_impulse *= ratio);
        for f in &mut self.patches {
            f.impulse = [f.impulse[0] * ratio, f.impulse[1] * ratio];
            f.twist *= ratio;
        }
    }

    /// Re-applies the impulses of the previous substep (or step) and adds the
    /// previous substep's to the step totals.
    pub fn warm_start(&mut self) {
        self.remember_before_warm();
        let first = self.substeps_done == 0;
        self.substeps_done += 1;
        if self.by_groups() {
            if !first {
                self.constraints.iter_mut().for_each(|c| c.fresh = false);
            }
            return self.warm_start_by_groups(first);
        }
        if let Some(h) = self.by_halves() {
            self.each_half(h, |cs, r| {
                cs.warm_range(r, first);
                false
            });
            return;
        }
        self.warm_all(first);
    }

    /// The warm start of every constraint, in order (one loop with [`warm`]
    /// inlined: called per constraint, the ball pit stepped 1.5 % slower).
    #[inline(never)]
    fn warm_all(&mut self, first: bool) {
        let (points, patches, bodies) = (&mut self.points, &mut self.patches, &mut self.bodies);
        for (c, f) in self.constraints.iter_mut().zip(patches.iter_mut()) {
            c.fresh &= first;
            warm(c, points, f, bodies, first);
        }
    }

    /// The warm start of constraint `ci` (see [`warm`]), for the
    /// group-by-group warm start (`super::contact_groups`).
    #[inline(never)]
    pub(crate) fn warm_one(&mut self, ci: usize, first: bool) {
        if let (Some(c), Some(f)) = (self.constraints.get(ci), self.patches.get_mut(ci)) {
            warm(c, &mut self.points, f, &mut self.bodies, first);
        }
    }

    /// The warm start of the constraints `range`, in order (see [`warm`]):
    /// one loop with `warm` inlined, as [`Self::warm_all`], for the halves
    /// of a split step (see `super::seams`).
    #[inline(never)]
    pub(crate) fn warm_range(&mut self, range: std::ops::Range<usize>, first: bool) {
        let (points, patches, bodies) = (&mut self.points, &mut self.patches, &mut self.bodies);
        let (Some(cs), Some(fs)) = (self.constraints.get_mut(range.clone()), patches.get_mut(range)) else { return };
        // Each thread marks its own half's constraints as warm started (a pass
        // over all of them on the stepping thread left their lines in its
        // cache for the helper to fetch back).
        for (c, f) in cs.iter_mut().zip(fs) {
            c.fresh &= first;
            warm(c, points, f, bodies, first);
        }
    }
}

/// The warm start of constraint `c` with patch `f` (`first`: the step's
/// first substep, whose impulses are not added to the totals): last
/// substep's impulses applied again.
#[inline(always)]
fn warm(c: &Constraint, points: &mut [Point], f: &mut Patch, bodies: &mut [SolverBody], first: bool) {
    let mut pair = Pair::load(bodies, c);
    let mut settled = 0.0;
    for p in &mut points[c.start as usize..(c.start + c.len) as usize] {
        if !first {
            p.total_normal += p.normal_impulse;
        }
        settled += p.normal_impulse;
        if c.central {
            pair.apply_central(c, p.normal_impulse);
        } else {
            pair.apply_normal(c, p, p.normal_impulse);
        }
    }
    f.settled = settled;
    if !first {
        f.total[0] += f.impulse[0];
        f.total[1] += f.impulse[1];
    }
    pair.apply_patch(c, f, f.impulse);
    if f.twist != 0.0 {
        pair.apply_twist(f, f.twist);
    }
    pair.store(bodies, c);
}
