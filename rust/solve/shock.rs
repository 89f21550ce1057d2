//! Shock propagation (after Guendelman et al. 2003) for a body much heavier than
//! the one it rests on. A soft contact is a spring as stiff as its effective mass
//! allows: with a light body under a heavy one that effective mass is the light
//! body's, so the contact sags by the mass ratio times the `g/ω²` of a body on the
//! ground (0.28 mm at 30 Hz: 28 cm for 1000:1), and the Gauss–Seidel sweep moves
//! the heavy load through the light body by a light body's worth of momentum per
//! pass. A support contact (normal within 45° of the vertical) whose upper body is
//! more than `MASS_RATIO` times heavier than its lower one, the lower one standing
//! on the ground through supports of its own, is solved one way: the lower body is
//! held as if fixed, the contact's effective masses (normal and friction) are the
//! upper body's, and its impulses act on the upper body only. The heavy body then
//! rests on the light one as on the ground; the light one does not feel the load,
//! so its own contacts neither sag nor report it, and its friction on what it
//! stands on is that of its own weight. Momentum is not exchanged through such a
//! contact (the ground takes it, as through a rigid light body), which is why it
//! is kept to the contacts that need it.

use super::contact::{Constraint, ContactSolver};
use crate::math::Vec3;

/// Normal within 45° of the vertical: a contact that supports.
const SUPPORT_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// Mass ratio (upper over lower) above which a support contact between two
/// dynamic bodies is solved one way.
const MASS_RATIO: f64 = 4.0;

impl ContactSolver {
    /// Marks the support contacts to solve one way (`Constraint::frozen`: which
    /// body is held) and gives them the upper body's effective masses. Heights in
    /// the support graph (a breadth-first walk from the fixed and kinematic
    /// bodies) are computed only when some contact may need it.
    pub(crate) fn plan_shock(&mut self, up: &Vec3, gravity: f64) {
        if gravity <= 0.0 {
            return;
        }
        let held_side = |c: &Constraint| {
            let rising = c.normal.dot(up);
            if rising >= SUPPORT_COS && self.heavier(c.s1, c.s2) {
                1
            } else if rising <= -SUPPORT_COS && self.heavier(c.s2, c.s1) {
                2
            } else {
                0
            }
        };
        let sides: Vec<u8> = self.constraints.iter().map(held_side).collect();
        if sides.iter().all(|&side| side == 0) {
            return;
        }
        let level = self.levels(up);
        for (ci, &side) in sides.iter().enumerate() {
            let c = &self.constraints[ci];
            let (l1, l2) = (level[c.s1 as usize], level[c.s2 as usize]);
            let held = match side {
                1 if l1 < l2 => 1,
                2 if l2 < l1 => 2,
                _ => continue,
            };
            self.constraints[ci].frozen = held;
            self.shock_masses(ci);
            self.refresh_patch(ci);
        }
    }

    /// Height of each solver body in the support graph: breadth first from the
    /// fixed and kinematic bodies over the contacts whose normal is within 45° of
    /// the vertical.
    fn levels(&self, up: &Vec3) -> Vec<u32> {
        let n = self.bodies.len();
        // The support graph as adjacency lists in one array (CSR).
        let supports = || self.constraints.iter().filter(|c| c.normal.dot(up).abs() >= SUPPORT_COS);
        let mut start = vec![0u32; n + 1];
        for c in supports() {
            start[c.s1 as usize + 1] += 1;
            start[c.s2 as usize + 1] += 1;
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut next = vec![0u32; start[n] as usize];
        for c in supports() {
            for (a, b) in [(c.s1, c.s2), (c.s2, c.s1)] {
                next[fill[a as usize] as usize] = b;
                fill[a as usize] += 1;
            }
        }
        let mut level = vec![u32::MAX; n];
        let mut queue: std::collections::VecDeque<usize> = (0..n).filter(|&k| !self.bodies[k].dynamic).collect();
        queue.iter().for_each(|&k| level[k] = 0);
        while let Some(a) = queue.pop_front() {
            for &b in &next[start[a] as usize..start[a + 1] as usize] {
                if level[b as usize] == u32::MAX {
                    level[b as usize] = level[a] + 1;
                    queue.push_back(b as usize);
                }
            }
        }
        level
    }

    /// Whether `upper` is a dynamic body more than `MASS_RATIO` times heavier than
    /// the dynamic body `lower` (a fixed or kinematic lower body holds anyway).
    fn heavier(&self, lower: u32, upper: u32) -> bool {
        let (l, u) = (&self.bodies[lower as usize], &self.bodies[upper as usize]);
        l.dynamic && u.dynamic && u.inv_m * MASS_RATIO < l.inv_m
    }

    /// Effective masses of a one-way contact's points, its lower body held.
    pub(crate) fn shock_masses(&mut self, ci: usize) {
        let c = self.constraints[ci];
        if c.frozen == 0 {
            return;
        }
        let m = self.bodies[if c.frozen == 1 { c.s2 } else { c.s1 } as usize].inv_m;
        for p in &mut self.points[c.start as usize..(c.start + c.len) as usize] {
            let (rn, irn) = if c.frozen == 1 { (p.rn2, p.irn2) } else { (p.rn1, p.irn1) };
            let k = m + rn.dot(&irn);
            p.shock_mass = if k > 0.0 { 1.0 / k } else { 0.0 };
        }
    }
}
