//! The normal impulse `J = j n` of the seed, as a sequential-impulse solve on a
//! soft constraint: `j = −(1/K)·s_m·(v_n + bias) − s_i·λ`, the accumulated impulse
//! `λ` clamped at zero (contacts push, never pull), with
//! `K = 1/m1 + 1/m2 + n·(I1⁻¹(r1×n)×r1 + I2⁻¹(r2×n)×r2)` the effective mass.
//!
//! A separated (speculative) point lets the bodies close the gap within the
//! substep and no more: `bias = s/h`. A penetrating one is pushed out at the soft
//! constraint's rate, at most `max_push_velocity`; the relax pass then solves
//! without that bias, so the push-out moves the bodies but leaves no velocity
//! behind: penetration is corrected without adding energy. The relax pass leaves
//! separated points alone.

use super::contact::ContactSolver;

/// Sweeps over the points of a manifold that has no warm start.
const FRESH_SWEEPS: u32 = 4;
use super::solver_body::{Gap, Pair};

impl ContactSolver {
    pub fn solve_normal(&mut self, relax: bool) {
        let soft = self.softness;
        let max_push = self.settings.max_push_velocity;
        let inv_h = self.inv_h;
        for c in &self.constraints {
            let mut pair = Pair::load(&self.bodies, c);
            let gap = Gap::new(&self.bodies, c);
            // A manifold with nothing to warm start from is swept a few times, so its
            // points share the load from the start: one sweep gives the first point
            // all of it, and the torque of that rocks a box set down flat.
            let sweeps = if c.fresh && c.len > 1 && !relax { FRESH_SWEEPS } else { 1 };
            for p in (0..sweeps).flat_map(|_| c.start..c.start + c.len) {
                let p = &mut self.points[p as usize];
                let s = gap.separation(p);
                if relax && s > 0.0 {
                    // After the drift a gap is the next substep's business: closing it
                    // here would brake a body that has not arrived yet.
                    continue;
                }
                let (bias, mass_scale, impulse_scale) = if s > 0.0 {
                    (s * inv_h, 1.0, 0.0)
                } else if !relax {
                    ((soft.bias_rate * s).max(-max_push), soft.mass_scale, soft.impulse_scale)
                } else {
                    (0.0, 1.0, 0.0)
                };
                let vn = pair.normal_velocity(c, p);
                let mass = if c.frozen != 0 { p.shock_mass } else { p.normal_mass };
                let imp = -mass * mass_scale * (vn + bias) - impulse_scale * p.normal_impulse;
                let total = (p.normal_impulse + imp).max(0.0);
                let delta = total - p.normal_impulse;
                p.normal_impulse = total;
                pair.apply_normal_one_way(c, p, delta);
            }
            pair.store(&mut self.bodies, c);
        }
    }
}
