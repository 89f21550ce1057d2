//! Contacts give back what they push beyond their target.
//!
//! After a velocity pass a point that pushes (`λ > 0`) may leave at most at
//! its push-out speed `t` (0 unless it penetrates). A point whose bodies leave
//! faster pushes too hard: what the warm start re-applied in a configuration
//! that no longer needs it, and what an unconverged sweep left. Taking the
//! excess back, point by point, only ever removes kinetic energy: the impulse
//! `−δ n` acts where the bodies separate at `v_n > t` and leaves them at
//! `v_n' ≥ t ≥ 0`, so its work `−δ (v_n + v_n')/2` is negative. (A gap still
//! closing slower than it may is the next pass's business: speeding the
//! approach up would add energy.)

use super::contact::ContactSolver;
use super::impulse::Rule;
use super::warm_guard::in_pass;
use super::pair::Pair;
use super::solver_body::Gap;

impl ContactSolver {
    /// One pass (of the first, velocity pass: `rule` pushes out) over the points
    /// of every contact not on an articulated link and not a settled support
    /// contact: each point that pushes and ends faster apart than its push-out
    /// speed gives back the excess (at most all it pushes); the patch's friction
    /// and twist shrink with its normal impulse to stay in its cone.
    ///
    /// Without support blocks the contacts are plain Gauss–Seidel with a warm
    /// start (as in Box2D and Rapier), whose own pass takes any excess back:
    /// nothing to do.
    /// Whether it released anything.
    pub(crate) fn release_excess(&mut self, rule: &Rule) -> bool {
        if self.support.blocks.is_empty() {
            return false;
        }
        // What gravity gives in a substep is not an excess: contacts settling
        // into a stack leave that much while the sweeps converge, and taking
        // it back point by point tipped a 30-cube tower at dt = 1/3000 s.
        let tolerance = self.support.substep_gravity();
        let mut released = false;
        for ci in 0..self.constraints.len() {
            released |= self.release_one(ci, rule, tolerance);
        }
        released
    }

    /// The release of constraint `ci` (see [`Self::release_excess`]): whether
    /// it gave anything back. `tolerance`: the excess let through (m/s).
    pub(crate) fn release_one(&mut self, ci: usize, rule: &Rule, tolerance: f64) -> bool {
        let c = &self.constraints[ci];
        // Settled support contacts are solved exactly on a held body.
        if c.generalized || (c.lower != 0 && c.settled) || !in_pass(&self.guard.redo, c) {
            return false;
        }
        let (points, bodies) = (&mut self.points, &mut self.bodies);
        let mut pair = Pair::load(bodies, c);
        let gap = Gap::new(bodies, c);
        let (mut before, mut after) = (0.0, 0.0);
        for p in &mut points[c.start as usize..(c.start + c.len) as usize] {
            before += p.normal_impulse;
            if p.normal_impulse > 0.0 {
                let s = rule.effective(gap.separation(p));
                let excess = pair.normal_velocity(c, p) + pair.curve(bodies, c, p, rule.inv_h) * rule.inv_h - rule.push_out_speed(s);
                if excess > tolerance {
                    let d = (p.normal_mass * excess).min(p.normal_impulse);
                    p.normal_impulse -= d;
                    pair.apply_normal(c, p, -d);
                }
            }
            after += p.normal_impulse;
        }
        let released = after < before;
        if released {
            let f = &mut self.patches[ci];
            let keep = if before > 0.0 { after / before } else { 0.0 };
            let d = [f.impulse[0] * (keep - 1.0), f.impulse[1] * (keep - 1.0)];
            let dt = f.twist * (keep - 1.0);
            f.impulse = [f.impulse[0] * keep, f.impulse[1] * keep];
            f.twist *= keep;
            pair.apply_patch(c, f, d);
            pair.apply_twist(f, dt);
        }
        pair.store(bodies, c);
        released
    }
}
