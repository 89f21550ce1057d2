//! Position correction, split from the velocities: after the drift, penetration
//! is removed by moving the bodies along the contact normals (non-linear
//! Gauss–Seidel on the current separations, as in Box2D v2's position solver),
//! without touching their velocities. Correcting it through a velocity bias
//! instead (Baumgarte, or a soft contact's push-out) leaves the push-out speed to
//! be taken back by another pass; where that pass does not converge (a tall
//! column) the difference bounces the bodies, and a soft contact that leaks its
//! load to stay stable sags by it.
//!
//! Each pass moves a penetrating point out by `position_rate` of its depth (at
//! most `max_push_velocity · h`). Support blocks (see `super::support`) are
//! corrected bottom up, each body on its held supports and without sliding on
//! them: a column is set straight in one pass, from the ground up, whatever its
//! masses; other contacts move both bodies by their inverse masses.

use super::contact::{Constraint, ContactSolver, Point};
use super::solver_body::{Gap, SolverBody};
use crate::body::Bodies;
use crate::math::{quat, Vec3};

impl ContactSolver {
    /// One position pass: the contacts solved both ways by Gauss–Seidel, then
    /// the support blocks bottom up, each body moved on its held supports.
    pub fn correct_positions(&mut self, h: f64) {
        let rate = self.position_rate(h);
        let cap = self.settings.max_push_velocity * h;
        let (cs, points, bodies) = (&self.constraints, &self.points, &mut self.bodies);
        for &ci in &self.ordinary {
            push(&cs[ci as usize], points, bodies, rate, cap);
        }
        for g in 0..self.support.blocks.len() {
            self.push_block(g, rate, cap);
        }
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

/// One position pass over the points of `c`, moving both bodies.
fn push(c: &Constraint, points: &[Point], bodies: &mut [SolverBody], rate: f64, cap: f64) {
    for p in &points[c.start as usize..(c.start + c.len) as usize] {
        let s = Gap::new(bodies, c).separation(p);
        if s >= 0.0 {
            continue;
        }
        let lambda = -(rate * s).max(-cap) * p.normal_mass;
        shift(&mut bodies[c.s1 as usize], &(-c.normal * lambda), &(-p.irn1 * lambda));
        shift(&mut bodies[c.s2 as usize], &(c.normal * lambda), &(p.irn2 * lambda));
    }
}

/// Moves a solver body by a position impulse: `dx = Δ/m`, `dθ = I⁻¹ (r × Δ)`
/// (given pre-multiplied as `turn`).
#[inline(always)]
fn shift(s: &mut SolverBody, impulse: &Vec3, turn: &Vec3) {
    if !s.dynamic {
        return;
    }
    s.dp += impulse * s.inv_m;
    s.dq = quat::exp(turn) * s.dq;
    s.pushed = true;
}
