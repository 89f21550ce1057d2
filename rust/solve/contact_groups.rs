//! The passes over the contacts solved both ways (see [`super::impulse`],
//! [`super::friction`], [`super::release`]) and the warm start group by
//! group, the groups in
//! parallel, in a step whose support islands are swept in parallel (see
//! [`super::island_sweeps`]).
//!
//! A group is a set of dynamic bodies joined by contacts, the fixed bodies
//! apart (the groups of [`super::warm_guard`]). A Gauss–Seidel pass visits the
//! contacts in order, each changing only its own impulses and its two bodies:
//! restricted to one group, it is the same sequence of changes to the same
//! numbers, whatever the other groups do meanwhile. So each group is passed
//! over in the serial order of its contacts and the bits are those of one
//! thread. The fixed bodies' shared entry is never written (see
//! `Pair::store`); a step with kinematic bodies, which several groups could
//! write, or with contacts on articulated links, keeps the serial passes.
//! A tumbling 4000-cube pile has some 190 groups, the largest 250 bodies.

use super::contact::ContactSolver;
use super::friction::FrictionPass;
use super::impulse::Rule;
use super::lists::Lists;

/// The contacts of each group, in order: those solved both ways, and all.
#[derive(Clone, Default)]
pub struct Groups {
    ordinary: Lists,
    all: Lists,
    /// The passes of this step go group by group.
    ready: bool,
}

impl ContactSolver {
    /// After the plan: the groups of this step's contacts, if its passes may
    /// go group by group (see the module docs).
    pub(crate) fn index_groups(&mut self) {
        self.groups.ready = false;
        if !self.wide() || !self.gen.constraints.is_empty() || self.bodies.iter().skip(1).any(|b| !b.dynamic) {
            return;
        }
        let root = super::warm_guard::groups(self);
        let mut id = vec![u32::MAX; root.len()];
        let mut count = 0u32;
        let mut group_of = Vec::with_capacity(self.constraints.len());
        for c in &self.constraints {
            // Entry 0 is the fixed bodies; every other entry is dynamic here.
            let body = if c.s1 != 0 { c.s1 } else { c.s2 };
            let Some(&r) = root.get(body as usize).filter(|_| body != 0) else { return };
            let slot = &mut id[r as usize];
            if *slot == u32::MAX {
                *slot = count;
                count += 1;
            }
            group_of.push(*slot);
        }
        let n = count as usize;
        let ordinary = self.ordinary.iter().map(|&ci| (group_of[ci as usize], ci));
        self.groups.ordinary.fill(n, ordinary);
        self.groups.all.fill(n, group_of.iter().enumerate().map(|(ci, &g)| (g, ci as u32)));
        self.groups.ready = n >= 2;
    }

    /// No groups (until the plan finds them).
    pub(crate) fn forget_groups(&mut self) {
        self.groups.ready = false;
    }

    /// Whether this step's passes over the contacts solved both ways go
    /// group by group.
    pub(crate) fn by_groups(&self) -> bool {
        self.groups.ready
    }

    /// `work` on every group, in parallel (a group's passes touch only its
    /// bodies, contacts, points and patches); whether any returned true.
    fn each_group(&mut self, work: impl Fn(&mut ContactSolver, usize) -> bool + Sync) -> bool {
        let n = self.groups.ordinary.len();
        self.par_map(n, true, work).into_iter().any(|r| r)
    }

    /// A velocity pass (see `super::impulse`) whose contacts solved both ways
    /// go group by group: the support sweeps, then each group's Gauss–Seidel
    /// and (first pass) the release of its excess. Whether it changed anything
    /// after the warm start.
    #[inline(never)]
    pub(crate) fn velocity_pass_by_groups(&mut self, rule: &Rule) -> bool {
        self.sweep_supports(rule);
        let released = self.ordinary_by_groups(rule);
        released || !self.ordinary.is_empty() || !self.support.solved.is_empty()
    }

    /// The velocity pass's Gauss–Seidel over the contacts solved both ways,
    /// then (first pass) the release of their excess, group by group; whether
    /// any excess was released.
    fn ordinary_by_groups(&mut self, rule: &Rule) -> bool {
        let tolerance = self.support.substep_gravity();
        self.each_group(|cs, g| {
            let (list, redo) = (cs.groups.ordinary.of(g), &cs.guard.redo[..]);
            super::impulse::solve_each(list, &cs.constraints, &mut cs.points, &mut cs.bodies, (redo, rule));
            let mut released = false;
            if !rule.relax {
                for k in 0..cs.groups.all.of(g).len() {
                    released |= cs.release_one(cs.groups.all.of(g)[k] as usize, rule, tolerance);
                }
            }
            released
        })
    }

    /// The warm start (see `ContactSolver::warm_start`) group by group.
    pub(crate) fn warm_start_by_groups(&mut self, first: bool) {
        self.each_group(|cs, g| {
            for k in 0..cs.groups.all.of(g).len() {
                cs.warm_one(cs.groups.all.of(g)[k] as usize, first);
            }
            false
        });
    }

    /// The friction pass over the contacts solved both ways, group by group
    /// (`closing`: see `ContactSolver::solve_friction`).
    #[inline(never)]
    pub(crate) fn friction_by_groups(&mut self, pass: &FrictionPass) {
        self.each_group(|cs, g| {
            let list = cs.groups.ordinary.of(g);
            let patches = (&mut cs.patches[..], &cs.shapes[..]);
            super::friction::rub_each(list, &cs.constraints, &mut cs.points, patches, &mut cs.bodies, pass);
            false
        });
    }
}
