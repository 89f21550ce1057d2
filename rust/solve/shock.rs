//! Shock propagation (after Guendelman et al. 2003) for heavy loads on light
//! bodies. A soft contact is a spring as stiff as its effective mass allows: under
//! a body much heavier than the one below it, or under a load many times the
//! weight of the body it rests on, it sags as far as the mass ratio (a 1000:1
//! stack sinks through). After each solve pass those support contacts (normal
//! within 45° of vertical) are revisited from the ground up, each holding its
//! lower body still, and an upper body still moving into the one under it is
//! stopped by itself. It is a velocity projection only: the accumulated impulses,
//! and through warm starting the loads the lower bodies feel (and so their
//! friction), are the full solve's. It is kept to where it is needed because
//! between two moving bodies it gives the upper one momentum the lower one does
//! not lose.

use super::contact::{Constraint, ContactSolver};
use super::solver_body::{Gap, Pair};
use crate::math::Vec3;

/// Normal within 45° of the vertical: a contact that supports.
const SUPPORT_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// Mass ratio (upper over lower) above which a contact between two dynamic bodies
/// is projected.
const MASS_RATIO: f64 = 4.0;
/// Load (carried mass over the supported body's effective mass) above which a
/// contact on a fixed body is projected. A box at the bottom of a 20-high stack
/// carries 20: the soft solve holds that.
const LOAD_RATIO: f64 = 50.0;
/// Passes over the points of one manifold, so the correction spreads over them.
const PASSES: usize = 2;

impl ContactSolver {
    /// Heights in the support graph (breadth first from the fixed and kinematic
    /// bodies), the lower body of each contact that needs projecting, and their
    /// list from the ground up. `h`: the substep (s).
    pub(crate) fn plan_shock(&mut self, up: &Vec3, gravity: f64, h: f64) {
        self.shock.clear();
        if gravity <= 0.0 {
            return;
        }
        // Which way up a contact would be projected, if at all; the heights are
        // only needed (a breadth-first walk) when some contact may be.
        let way = |c: &Constraint| {
            let rising = c.normal.dot(up);
            if rising >= SUPPORT_COS && self.needs(c, c.s1, c.s2, gravity * h) {
                1
            } else if rising <= -SUPPORT_COS && self.needs(c, c.s2, c.s1, gravity * h) {
                2
            } else {
                0
            }
        };
        let ways: Vec<u8> = self.constraints.iter().map(way).collect();
        for c in self.constraints.iter_mut() {
            c.frozen = 0;
        }
        if ways.iter().all(|&w| w == 0) {
            return;
        }
        let level = self.levels(up);
        for (ci, &w) in ways.iter().enumerate() {
            let c = self.constraints[ci];
            let (l1, l2) = (level[c.s1 as usize], level[c.s2 as usize]);
            let frozen = match w {
                1 if l1 < l2 => 1,
                2 if l2 < l1 => 2,
                _ => 0,
            };
            self.constraints[ci].frozen = frozen;
            if frozen != 0 {
                self.shock.push((l1.min(l2), ci as u32));
                self.shock_masses(ci);
            }
        }
        self.shock.sort_unstable();
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

    /// Whether the support contact `c` (lower solver body `lower`) needs projecting.
    /// `gh`: the impulse of gravity on a unit mass over a substep (N·s/kg).
    fn needs(&self, c: &Constraint, lower: u32, upper: u32, gh: f64) -> bool {
        let (l, u) = (&self.bodies[lower as usize], &self.bodies[upper as usize]);
        if l.dynamic {
            return u.inv_m * MASS_RATIO < l.inv_m;
        }
        let carried: f64 = self.points[c.start as usize..(c.start + c.len) as usize].iter().map(|p| p.normal_impulse).sum();
        carried * u.inv_m > LOAD_RATIO * gh
    }

    /// Effective masses of a projected contact's points with its lower body held.
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

    /// The projection after a solve pass (`relax`: after the relax pass, where
    /// separated points are left to the next substep).
    pub fn shock(&mut self, relax: bool) {
        let inv_h = self.inv_h;
        for k in 0..self.shock.len() {
            let c = self.constraints[self.shock[k].1 as usize];
            let mut pair = Pair::load(&self.bodies, &c);
            let gap = Gap::new(&self.bodies, &c);
            for _ in 0..PASSES {
                for p in &self.points[c.start as usize..(c.start + c.len) as usize] {
                    let s = gap.separation(p);
                    // Only stops sinking; pushing out stays the soft solve's business.
                    let target = if s <= 0.0 {
                        0.0
                    } else if relax {
                        continue;
                    } else {
                        -s * inv_h
                    };
                    let vn = pair.normal_velocity(&c, p);
                    if vn < target {
                        pair.apply_normal_to_upper(&c, p, p.shock_mass * (target - vn));
                    }
                }
            }
            pair.store(&mut self.bodies, &c);
        }
    }
}
