//! The warm start must not pump energy into a pile.
//!
//! A substep starts from the impulses of the one before (the warm start) and
//! corrects them. At rest that is the whole solve; in a collapsing pile the
//! support sweeps (see [`super::support`]) hold the lower bodies while they
//! move, large impulses that cancel in one configuration are applied again in
//! the next, and one pass does not take the excess back: a ball knocking over
//! 15 boxes quadrupled their energy in one step.
//!
//! The velocity pass's targets let a contact close or stop, and push apart only
//! a penetration, at most at `max_push_velocity`: from the velocities before
//! the warm start its exact solution takes energy out, except for what the
//! push-out adds. A pass with support blocks that ends with more than that (and
//! [`SLACK`]) is done again from those velocities without the warm start. (Soft contacts
//! alone, which store energy in their overlap and give it back, and contacts on
//! articulated links, which keep their own impulses, are left alone.)

use super::contact::ContactSolver;
use super::impulse::Rule;
use super::solver_body::{Gap, SolverBody};
use crate::math::Vec3;

/// Relative energy gain of a pass let through: the soft contacts solved both
/// ways give back what their overlap stored (1–2 % of a settling pile's energy
/// in a substep, measured), a pump multiplies it (×7 in one substep of the
/// knocked-over pyramid).
const SLACK: f64 = 0.1;

/// Kinetic energy (J) beyond which the bodies are diverging, not colliding.
const DIVERGING: f64 = 1e200;

/// The solver bodies' velocities and kinetic energy before the warm start.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct WarmGuard {
    velocities: Vec<(Vec3, Vec3)>,
    energy: f64,
}

/// Kinetic energy of the dynamic solver bodies (J).
pub(crate) fn kinetic_energy(bodies: &[SolverBody]) -> f64 {
    bodies
        .iter()
        .filter(|b| b.dynamic && b.inv_m > 0.0)
        .map(|b| {
            let iw = b.inv_i.try_inverse().map_or(Vec3::zeros(), |i| i * b.w);
            0.5 * (b.v.norm_squared() / b.inv_m + b.w.dot(&iw))
        })
        .sum()
}

impl ContactSolver {
    /// Keeps the velocities the warm start is about to change (when the guard
    /// applies: support blocks and no contact on an articulated link).
    pub(crate) fn remember_before_warm(&mut self) {
        let g = &mut self.guard;
        g.velocities.clear();
        if self.support.blocks.is_empty() || self.constraints.iter().any(|c| c.generalized) {
            return;
        }
        g.velocities.extend(self.bodies.iter().map(|b| (b.v, b.w)));
        g.energy = kinetic_energy(&self.bodies);
    }

    /// Whether the velocity pass ended with more energy than it may add.
    pub(crate) fn gained_energy(&self, rule: &Rule) -> bool {
        let g = &self.guard;
        if g.velocities.len() != self.bodies.len() || g.velocities.is_empty() {
            return false;
        }
        let now = kinetic_energy(&self.bodies);
        // A diverging body is the step guard's to name (`world::guard`): a
        // pass done again would hand its velocity to what it touches first.
        g.energy < DIVERGING && now < DIVERGING && now > g.energy * (1.0 + SLACK) + self.push_out_energy(rule)
    }

    /// Back to the velocities before the warm start, every contact impulse of
    /// this substep at zero.
    pub(crate) fn without_warm_start(&mut self) {
        for (b, &(v, w)) in self.bodies.iter_mut().zip(&self.guard.velocities) {
            b.v = v;
            b.w = w;
        }
        self.points.iter_mut().for_each(|p| p.normal_impulse = 0.0);
        for f in &mut self.patches {
            f.impulse = [0.0; 2];
            f.twist = 0.0;
        }
    }

    /// Most energy the push-out of penetrating points solved both ways can add:
    /// `½ m_n v²` each, `v` its push-out speed (J).
    fn push_out_energy(&self, rule: &Rule) -> f64 {
        let mut total = 0.0;
        for &ci in &self.ordinary {
            let c = &self.constraints[ci as usize];
            let gap = Gap::new(&self.bodies, c);
            for p in &self.points[c.start as usize..(c.start + c.len) as usize] {
                let v = rule.push_out_speed(rule.effective(gap.separation(p)));
                total += 0.5 * p.normal_mass * v * v;
            }
        }
        total
    }
}
