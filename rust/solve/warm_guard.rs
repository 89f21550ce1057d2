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
//! [`SLACK`]) in some group of bodies in contact is done again from those
//! velocities without the warm start. (Soft contacts
//! alone, which store energy in their overlap and give it back, and contacts on
//! articulated links, which keep their own impulses, are left alone.)

use super::contact::{Constraint, ContactSolver};
use super::impulse::Rule;
use super::islands::find;
use super::solver_body::{Gap, SolverBody};
use crate::math::Vec3;

/// Relative energy gain of a pass let through: the soft contacts solved both
/// ways give back what their overlap stored (1–2 % of a settling pile's energy
/// in a substep, measured), a pump multiplies it (×7 in one substep of the
/// knocked-over pyramid).
const SLACK: f64 = 0.1;

/// Kinetic energy (J) beyond which the bodies are diverging, not colliding.
const DIVERGING: f64 = 1e200;

/// The solver bodies' velocities before the warm start, and which group of
/// bodies in contact each belongs to (found when a pass is checked).
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct WarmGuard {
    velocities: Vec<(Vec3, Vec3)>,
    group: Vec<u32>,
    /// Per solver body, while a pass is done again: whether its group is
    /// among those done again (empty otherwise).
    pub(crate) redo: Vec<bool>,
}

/// Kinetic energy of a solver body at velocities `(v, w)` (J; 0 unless
/// dynamic).
fn kinetic(b: &SolverBody, (v, w): (Vec3, Vec3)) -> f64 {
    if !b.dynamic || b.inv_m <= 0.0 {
        return 0.0;
    }
    let iw = b.inv_i.try_inverse().map_or(Vec3::zeros(), |i| i * w);
    0.5 * (v.norm_squared() / b.inv_m + w.dot(&iw))
}

/// The groups of dynamic solver bodies connected by contacts (union–find;
/// fixed and kinematic bodies join nothing): a pump in one pile must not hide
/// in the energy of a thousand bodies falling elsewhere.
pub(crate) fn groups(solver: &ContactSolver) -> Vec<u32> {
    let n = solver.bodies.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    for c in &solver.constraints {
        let (a, b) = (c.s1 as usize, c.s2 as usize);
        if a < n && b < n && solver.bodies[a].dynamic && solver.bodies[b].dynamic {
            let (ra, rb) = (find(&mut parent, a as u32), find(&mut parent, b as u32));
            parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }
    (0..n as u32).map(|k| find(&mut parent, k)).collect()
}

impl ContactSolver {
    /// Keeps the velocities the warm start is about to change (when the guard
    /// applies: support blocks and no contact on an articulated link).
    pub(crate) fn remember_before_warm(&mut self) {
        self.guard.velocities.clear();
        if self.support.blocks.is_empty() || !self.gen.constraints.is_empty() {
            return;
        }
        self.guard.velocities.extend(self.bodies.iter().map(|b| (b.v, b.w)));
    }

    /// Whether the velocity pass ended with more energy in some group of bodies
    /// than it may add there. A pass that `changed` nothing after the warm
    /// start (every island within its residual, no contact solved both ways or
    /// released) is the warm start alone, within the residual of its targets:
    /// one that pumped would have left residuals to solve.
    pub(crate) fn gained_energy(&mut self, rule: &Rule, changed: bool) -> bool {
        if !changed || self.guard.velocities.len() != self.bodies.len() || self.guard.velocities.is_empty() {
            return false;
        }
        self.guard.group = groups(self);
        let g = &self.guard;
        let (mut before, mut now) = (vec![0.0; self.bodies.len()], vec![0.0; self.bodies.len()]);
        for ((b, &k), &start) in self.bodies.iter().zip(&g.group).zip(&g.velocities) {
            before[k as usize] += kinetic(b, start);
            now[k as usize] += kinetic(b, (b.v, b.w));
        }
        let allowed = self.push_out_energy(rule);
        // A diverging body is the step guard's to name (`world::guard`): a
        // pass done again would hand its velocity to what it touches first.
        let gained: Vec<bool> = (0..now.len())
            .map(|k| {
                let (before, after) = (before[k], now[k]);
                before < DIVERGING && after < DIVERGING && after > before * (1.0 + SLACK) + allowed[k]
            })
            .collect();
        if !gained.contains(&true) {
            return false;
        }
        let g = &mut self.guard;
        g.redo.clear();
        g.redo.extend(g.group.iter().map(|&k| gained[k as usize]));
        true
    }

    /// The groups that gained energy back to their velocities before the warm
    /// start, their contact impulses of this substep at zero. The others keep
    /// their pass: one collapsing corner of a pile once took the warm start of
    /// the whole pile with it (the guard fired in 62 % of the 4000-cube pile's
    /// substeps), and the pile, solved from zero each time, never settled.
    pub(crate) fn without_warm_start(&mut self) {
        let redo = &self.guard.redo;
        for ((b, &(v, w)), _) in self.bodies.iter_mut().zip(&self.guard.velocities).zip(redo).filter(|(_, &r)| r) {
            b.v = v;
            b.w = w;
        }
        for (c, f) in self.constraints.iter().zip(&mut self.patches) {
            if !redone(redo, c) {
                continue;
            }
            self.points[c.start as usize..(c.start + c.len) as usize].iter_mut().for_each(|p| p.normal_impulse = 0.0);
            f.impulse = [0.0; 2];
            f.twist = 0.0;
        }
    }

    /// While a pass is done again for some groups: only their islands of
    /// support blocks are solved.
    pub(crate) fn keep_to_redo(&mut self) {
        if self.guard.redo.is_empty() {
            return;
        }
        let s = &mut self.support;
        let mut keep = vec![false; s.active.len()];
        for b in &s.blocks {
            if let Some(k) = keep.get_mut(b.island as usize) {
                *k |= self.guard.redo.get(b.body as usize).copied().unwrap_or(false);
            }
        }
        s.active.iter_mut().zip(&keep).for_each(|(a, &k)| *a &= k);
    }

    /// The pass done again is over: every group is solved from now on.
    pub(crate) fn end_redo(&mut self) {
        self.guard.redo.clear();
    }

    /// Most energy the push-out of penetrating points solved both ways can add
    /// in each group: `½ m_n v²` each, `v` its push-out speed (J).
    fn push_out_energy(&self, rule: &Rule) -> Vec<f64> {
        let mut total = vec![0.0; self.bodies.len()];
        for &ci in &self.ordinary {
            let c = &self.constraints[ci as usize];
            let side = if self.bodies[c.s1 as usize].dynamic { c.s1 } else { c.s2 };
            let k = self.guard.group.get(side as usize).copied().unwrap_or(0) as usize;
            let gap = Gap::new(&self.bodies, c);
            for p in &self.points[c.start as usize..(c.start + c.len) as usize] {
                let v = rule.push_out_speed(rule.effective(gap.separation(p)));
                if let Some(t) = total.get_mut(k) {
                    *t += 0.5 * p.normal_mass * v * v;
                }
            }
        }
        total
    }
}

/// Whether constraint `c` is solved in this pass: always, except while a pass
/// is done again for some groups only (`redo` per solver body, empty
/// otherwise).
pub(crate) fn in_pass(redo: &[bool], c: &Constraint) -> bool {
    redo.is_empty() || redone(redo, c)
}

/// Whether constraint `c` joins a body of a group done again (its fixed or
/// kinematic side, solver body 0 or not dynamic, never is: its group is its
/// own).
fn redone(redo: &[bool], c: &Constraint) -> bool {
    redo.get(c.s1 as usize).copied().unwrap_or(false) && c.s1 != 0 || redo.get(c.s2 as usize).copied().unwrap_or(false) && c.s2 != 0
}
