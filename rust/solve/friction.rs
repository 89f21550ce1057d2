//! Coulomb friction on a true cone. The tangential impulse of a point is a 2D
//! vector solved as a block with the 2x2 tangent effective mass, then projected
//! onto the disc of radius `μ λn`: while it fits inside `μs λn` the point sticks;
//! beyond, it slides with `|λt| = μk λn` along the direction the block solve gave.
//! No pyramid: the friction force has no preferred axes.

use super::contact::{Constraint, ContactSolver, Pair, Point};

/// The tangential impulse `λ + Δλ` (with `Δλ = −K_t⁻¹ v_t`) limited to the cone of
/// a normal impulse `jn`.
#[inline(always)]
pub fn cone(c: &Constraint, p: &Point, vt: [f64; 2], lambda: [f64; 2], jn: f64) -> [f64; 2] {
    let [a, b, cc] = p.tangent_mass;
    let mut l = [lambda[0] - (a * vt[0] + b * vt[1]), lambda[1] - (b * vt[0] + cc * vt[1])];
    let norm = (l[0] * l[0] + l[1] * l[1]).sqrt();
    if norm > c.static_friction * jn {
        let scale = if norm > 0.0 { c.friction * jn / norm } else { 0.0 };
        l = [l[0] * scale, l[1] * scale];
    }
    l
}

impl ContactSolver {
    pub fn solve_friction(&mut self) {
        for c in &self.constraints {
            if c.static_friction == 0.0 {
                continue;
            }
            let mut pair = Pair::load(&self.bodies, c);
            for p in &mut self.points[c.start as usize..(c.start + c.len) as usize] {
                if p.normal_impulse == 0.0 && p.tangent_impulse == [0.0, 0.0] {
                    continue;
                }
                let l = cone(c, p, pair.tangent_velocity(c, p), p.tangent_impulse, p.normal_impulse);
                let d = [l[0] - p.tangent_impulse[0], l[1] - p.tangent_impulse[1]];
                p.tangent_impulse = l;
                pair.apply_tangent(c, p, d);
            }
            pair.store(&mut self.bodies, c);
        }
    }
}
