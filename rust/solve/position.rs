//! Position correction of the support blocks, split from the velocities: after
//! the drift, penetration is removed by moving the bodies (non-linear, on the
//! current separations, as Box2D v2's position solver), without touching their
//! velocities. Correcting it through a velocity bias instead (Baumgarte, or a
//! soft contact's push-out) leaves the push-out speed to be taken back by another
//! pass; where that pass does not converge (a tall column) the difference
//! bounces the bodies, and a soft contact that leaks its load to stay stable
//! sags by it.
//!
//! Each pass moves a point out by `position_rate` of its depth beyond the rest
//! depth (see `super::impulse::REST_DEPTH`; at
//! most `max_push_velocity · h`), block by block bottom up, each body on its held
//! supports and without sliding or turning on them: a column is set straight in
//! one pass, from the ground up, whatever its masses. (Contacts solved both ways
//! push out through the velocities, whose impulses come in equal and opposite
//! pairs, so that a collision in free space keeps its angular momentum.)

use super::contact::ContactSolver;
use crate::body::Bodies;
use crate::math::quat;

impl ContactSolver {
    /// One position pass over the support blocks, bottom up, each body moved on
    /// its held supports.
    pub fn correct_positions(&mut self, h: f64) {
        let rate = self.position_rate(h);
        let cap = self.settings.max_push_velocity * h;
        let rest = super::impulse::REST_DEPTH * self.settings.slop;
        let rows = self.support.rows.len();
        self.support.targets.resize(rows, super::block::Target::Skip);
        let islands: Vec<u32> = (0..self.support.islands as u32).collect();
        self.in_islands(&islands, |cs, i, sw| cs.push_island(i, sw, (rate, cap, rest)));
    }

    /// Fraction of a penetration removed per pass: the contact's natural
    /// frequency `ω` (`contact_hertz`, at most a quarter of the substep rate)
    /// taken implicitly over the substep, `hω / (1 + hω)`.
    fn position_rate(&self, h: f64) -> f64 {
        let omega = 2.0 * std::f64::consts::PI * self.settings.contact_hertz.min(0.25 / h);
        h * omega / (1.0 + h * omega)
    }

    /// Writes the poses of the solver bodies the position pass moved back to the
    /// world.
    pub fn write_poses(&mut self, b: &mut Bodies) {
        for k in 1..self.bodies.len() {
            let s = &mut self.bodies[k];
            if !s.pushed {
                continue;
            }
            s.pushed = false;
            let i = s.body as usize;
            b.position[i] = (self.p0[k] + s.dp).into();
            b.orientation[i] = quat::to_xyzw(&quat::normalize(&(s.dq * self.q0[k])));
        }
    }
}
