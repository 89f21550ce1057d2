//! Support sweeps: contacts that carry weight are solved in the order the load
//! travels, so a stack of any height and any mass ratio is solved exactly in one
//! pass.
//!
//! A Gauss–Seidel sweep over a column moves momentum one contact per pass, and
//! under a heavy body on a light one only a light body's worth of it: the column
//! sags until its warm start catches up (a soft contact sags by its load, a rigid
//! one overshoots and bounces). Here every support contact has a lower and an
//! upper body: its normal is within [`SUPPORT_ANGLE`] of the vertical, its two
//! bodies sit at different heights of the support graph (a breadth-first walk
//! from the fixed and kinematic bodies), and it is a face (three points or more)
//! or carries a body more than [`MASS_RATIO`] times heavier than the one under
//! it. The support contacts of one upper body form its block
//! ([`super::block`]): all their normal, friction and twist rows, solved
//! together and exactly with the lower bodies held. Each pass visits the blocks
//!
//! 1. bottom up: the lower bodies have just been stopped on their own supports,
//!    so the upper one is stopped on them; the reaction is kept back as a debt;
//! 2. top down: again (the upper body has meanwhile received the reactions of
//!    what rests on it), then the debt is paid to the lower bodies, whose own
//!    blocks come next and pass it on to the ground.
//!
//! After the two sweeps every body of a column is at rest on the one below and
//! each contact carries the weight above it, whatever the masses: a direct solve
//! of a tree, and of a pyramid, whose blocks are visited a level at a time. Where
//! a lower body is not held as assumed (it tips, slides, rests on something that
//! gives), the next pass continues from there: the impulses act on both bodies,
//! so any fixed point of the passes is the solution of the contact problem
//! itself.
//! Balls side by side, walls and contacts without gravity are solved both ways
//! by Gauss–Seidel.

use super::block::{Block, Row, RowKind, Target};
use super::contact::ContactSolver;
use super::impulse::Rule;
use super::solver_body::Gap;
use crate::body::Bodies;
use crate::math::Vec3;

/// Cosine of the largest angle (60°) between a contact normal and the vertical
/// for the contact to count as support: balls resting in the hollows of a square
/// layer touch at 45°, those of a close-packed pile at 35°.
const SUPPORT_ANGLE: f64 = 0.5;

/// Residual taken as solved, as a fraction of `g h` (4e-8 m/s at 240 Hz: a body
/// left that far from the exact solve drifts 2 µm in a minute).
const RESIDUAL: f64 = 1e-6;

/// Mass ratio (upper over lower) above which a contact of fewer than three
/// points is a support contact: a Gauss–Seidel pass moves a light body's worth of
/// momentum per pass through a light body under a heavy one.
const MASS_RATIO: f64 = 4.0;

/// Two moving bodies more than [`MASS_RATIO`] apart in mass: the heavier may
/// rest on the lighter as on a support.
pub(crate) fn unequal(a: &super::solver_body::SolverBody, b: &super::solver_body::SolverBody) -> bool {
    a.dynamic && b.dynamic && (a.inv_m * MASS_RATIO < b.inv_m || b.inv_m * MASS_RATIO < a.inv_m)
}

/// Relative speed, in substeps of gravity (`g h`), below which two moving
/// bodies count as resting on each other at the step start (on top of the
/// rest depth closed in one substep): a step of gravity at the default 4
/// substeps, 0.16 m/s at 60 Hz; a box rolling off a pile meets it at 1 m/s.
const SETTLED: f64 = 4.0;

/// Most speed, in substeps of gravity (`g h`), that closing the rest depth
/// in one substep adds to [`SETTLED`]. Without a bound it grew as `1/h`:
/// 1 µm in a substep of 62.5 µs (dt = 0.25 ms) is 1.6 cm/s, seven times
/// what gravity gives, and bodies jittering at 1–2 cm/s on each other counted
/// as resting, so the sweeps held the lower of two moving bodies, the guess
/// [`SETTLED`] is there to keep from moving ones: none of 36 kicked towers
/// came to rest at 0.25 ms, 18 at 0.5 ms (`examples/tower_matrix.rs`); with
/// this bound, all 36 at both. It binds only below substeps of 226 µs: every
/// default step of 1 ms or longer keeps its bits.
const REST_CLOSING: f64 = 2.0;

/// Speed, in substeps of gravity (`g h`), up to which a body landing flat on
/// one face counts as settled on it: 2.6 m/s at 60 Hz, above a cube landing
/// on a column from 30 cm. Flat: the bodies approach along the normal, at the
/// same velocity at every point within [`SETTLED`] (no rocking, no sliding).
/// Holding the lower body is exact for such a landing; with [`SETTLED`] alone
/// the landings were left to Gauss–Seidel, whose pass per substep left a
/// column of eight cubes dropped 2 cm onto each other jiggling at 0.2–0.5 m/s,
/// above the threshold for ever, until it toppled. A body on several faces, or
/// rocking or sliding on its one, keeps [`SETTLED`]: holding a lower body is a
/// guess where the two tumble.
const LANDING: f64 = 64.0;

/// Constraints from which, in a step on the pool, their settled states (and
/// the blocks' bounds, see `super::quiet`) are found over threads; and how
/// many a thread takes at a time.
pub(super) const MIN_PARALLEL_PLAN: usize = 256;
pub(super) const PER_TASK: usize = 64;

/// The support blocks of a step, bottom up, and the sweeps' scratch space.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Support {
    pub blocks: Vec<Block>,
    /// Constraint indices of the blocks' faces, block after block.
    pub faces: Vec<u32>,
    pub rows: Vec<Row>,
    /// `K` and its factor, block after block (`m²` numbers each).
    pub k: Vec<f64>,
    pub factor: Vec<f64>,
    /// Per row: what the pass asks of it.
    pub targets: Vec<Target>,
    /// Largest row residual (m/s) of an island taken as solved already: what
    /// the warm start leaves of bodies at rest under their load (see
    /// [`super::quiet`]). [`RESIDUAL`] of the velocity gravity gives in a
    /// substep.
    pub residual: f64,
    /// The serial sweeps' scratch, and each pool thread's (see
    /// [`super::island_sweeps`]).
    #[serde(skip)]
    pub(crate) sweep: super::island_sweeps::Sweep,
    #[serde(skip)]
    pub(crate) thread_sweeps: super::island_sweeps::ThreadSweeps,
    /// Per row: impulse kept back for the lower body, and the impulse before
    /// the sweeps of a pass (of the blocks solved in it).
    pub debt: Vec<f64>,
    pub start_lambda: Vec<f64>,
    /// Per solver body: velocities before the sweeps of a pass (of those the
    /// pass changed: `touched` is the pass's number), and the pass in which it
    /// was last paid a reaction.
    pub start_velocity: Vec<(Vec3, Vec3)>,
    pub touched: Vec<u64>,
    pub paid: Vec<u64>,
    /// Number of the current pass, and the blocks solved in it (first time).
    pub pass: u64,
    #[serde(skip)]
    pub solved: Vec<u32>,
    /// Number of islands of the blocks, and which of them this pass solves
    /// (see [`super::quiet`]).
    pub islands: usize,
    /// The blocks of each island.
    #[serde(skip)]
    pub(crate) index: super::lists::Lists,
    /// Some pass of this step had islands enough to sweep in parallel.
    #[serde(skip)]
    pub(crate) split: bool,
    /// Per solver body, while the blocks are looked at: `|v|`, `|ω|`, `|Δp|`,
    /// `|Δq⃗|` (see `super::quiet`).
    #[serde(skip)]
    pub(crate) motions: Vec<[f64; 4]>,
    pub active: Vec<bool>,
    /// Per world body: the last velocity pass that solved its island, and
    /// the number of the last velocity pass (relax passes do not count).
    pub disturbed: Vec<u64>,
    /// Per world body: how much the last velocity pass that solved its island
    /// changed its velocity (m/s, see `super::quiet`).
    #[serde(default)]
    pub change: Vec<f64>,
    #[serde(default)]
    pub last_velocity_pass: u64,
    /// See [`super::rocking`].
    pub rocking: super::rocking::Rocking,
    /// The rest depth (m) the blocks' bounds were found for (see `super::quiet`).
    pub bound_rest: f64,
    /// Per island: the last velocity pass of this step overshot it, so the
    /// next one passes Gauss–Seidel over it instead of sweeping (see
    /// `super::overshoot`). Cleared with each step's plan.
    #[serde(skip)]
    pub(crate) overshot: Vec<bool>,
}

impl Support {
    /// The velocity gravity gives in a substep, `g h` (m/s).
    pub fn substep_gravity(&self) -> f64 {
        self.residual / RESIDUAL
    }

    /// Whether island `i` gets Gauss–Seidel alone in this pass, a velocity
    /// pass after one that overshot it (see `super::overshoot`).
    pub(crate) fn skips_sweeps(&self, i: usize, rule: &super::impulse::Rule) -> bool {
        !rule.relax && self.overshot.get(i) == Some(&true)
    }

    /// Marks block `g` for reassembly (a body of it moved).
    pub fn touch(&mut self, g: u32) {
        if let Some(b) = self.blocks.get_mut(g as usize) {
            b.dirty = true;
        }
    }
}

impl ContactSolver {
    /// This step's support blocks, the islands they form and the blocks of
    /// the largest (for profiling).
    pub fn support_blocks(&self) -> (usize, usize, usize) {
        let largest = (0..self.support.index.len()).map(|i| self.support.index.of(i).len()).max();
        (self.support.blocks.len(), self.support.islands, largest.unwrap_or(0))
    }

    /// Finds the support contacts, their lower sides and the blocks.
    pub(crate) fn plan_support(&mut self, up: &Vec3, gravity: f64, b: &Bodies) {
        self.support.residual = RESIDUAL * gravity / self.inv_h;
        self.ordinary.clear();
        let s = &mut self.support;
        s.blocks.clear();
        s.faces.clear();
        s.rows.clear();
        s.overshot.clear();
        if gravity <= 0.0 || self.constraints.is_empty() {
            self.ordinary.extend(0..self.constraints.len() as u32);
            self.support.islands = 0;
            self.index_islands();
            return;
        }
        if !self.constraints.iter().any(|c| self.may_support(c)) {
            // Nothing to plan: each contact's settled state only decides
            // which support contacts hold their lower body.
            self.ordinary.extend(0..self.constraints.len() as u32);
            self.support.islands = 0;
            self.index_islands();
            self.index_groups();
            return;
        }
        let gh = gravity / self.inv_h;
        let closing = (super::impulse::REST_DEPTH * self.settings.slop * self.inv_h).min(REST_CLOSING * gh);
        let speed = SETTLED * gh + closing;
        let landing = speed.max(LANDING * gravity / self.inv_h);
        let faces = self.faces_below(up);
        let state = |ci: usize| {
            let c = &self.constraints[ci];
            let sole = self.face(c) && self.upper_of(ci, up).is_some_and(|u| faces[u as usize] == 1);
            let slow = self.settled(ci, b, speed);
            let settled = slow || (sole && self.lands_flat(ci, b, speed, landing));
            (settled, settled && !slow)
        };
        // Each constraint's state from its own points and bodies: the same
        // on any thread.
        let n = self.constraints.len();
        let states: Vec<(bool, bool)> = if self.parallel && n >= MIN_PARALLEL_PLAN {
            use rayon::prelude::*;
            (0..n).into_par_iter().with_min_len(PER_TASK).map(state).collect()
        } else {
            (0..n).map(state).collect()
        };
        for (c, (settled, landing)) in self.constraints.iter_mut().zip(states) {
            c.settled = settled;
            c.landing = landing;
        }
        let restored = self.plan_unchanged();
        if restored {
            self.restore_plan();
        } else {
            self.plan_afresh(up);
        }
        self.bound_blocks(restored);
        self.index_islands();
        self.index_groups();
    }

    /// The support contacts, their lower sides and the blocks, found from the
    /// support graph.
    fn plan_afresh(&mut self, up: &Vec3) {
        let level = self.levels(up, |_| true);
        // Only an unsettled contact asks whether its lower body is held.
        let held = if self.constraints.iter().all(|c| c.settled) {
            Vec::new()
        } else {
            self.levels(up, |ci| self.constraints[ci].settled)
        };
        let mut supports: Vec<(u32, u32, u32)> = Vec::new();
        for ci in 0..self.constraints.len() {
            let mut lower = self.lower_side(ci, up, &level);
            if lower != 0 && !self.holds(ci, lower, &held) {
                lower = 0;
            }
            self.constraints[ci].lower = lower;
            if lower == 0 {
                self.ordinary.push(ci as u32);
            } else {
                let upper = self.constraints[ci].upper_body();
                supports.push((level[upper as usize], upper, ci as u32));
            }
        }
        // Bottom up; a body's faces together, in the narrow phase's order.
        supports.sort_unstable();
        let mut k = 0;
        while k < supports.len() {
            let (lvl, body, _) = supports[k];
            let first = self.support.faces.len() as u32;
            while k < supports.len() && supports[k].1 == body {
                let ci = supports[k].2;
                self.constraints[ci as usize].group = self.support.blocks.len() as u32;
                self.support.faces.push(ci);
                k += 1;
            }
            let faces = (first, self.support.faces.len() as u32);
            self.support.blocks.push(Block { body, level: lvl, faces, ..Default::default() });
        }
        self.assemble_blocks(true);
        self.group_blocks();
    }

    /// Whether constraint `c` is a face (three points or more, not a
    /// ball's) that may hold what rests on it. A ball on the corner where four
    /// flush tiles meet touches each (see `super::flush_pairs`): as a block,
    /// its four points had no row for the friction against its spin (see
    /// `Patch::spin`), and it spun on there.
    fn face(&self, c: &super::contact::Constraint) -> bool {
        c.len >= 3 && !c.ball
    }

    /// Whether constraint `c` can be a support contact, whatever its normal
    /// and the support graph (see [`Self::lower_side`]): a 1000-ball pit has
    /// none, and planning found that in 5 % of its step.
    fn may_support(&self, c: &super::contact::Constraint) -> bool {
        if c.generalized {
            return false;
        }
        if self.face(c) {
            return true;
        }
        unequal(&self.bodies[c.s1 as usize], &self.bodies[c.s2 as usize])
    }

    /// Which side of constraint `ci` is the lower body of a support contact (0:
    /// none).
    fn lower_side(&self, ci: usize, up: &Vec3, level: &[u32]) -> u8 {
        let c = &self.constraints[ci];
        if c.generalized {
            return 0;
        }
        let (l1, l2) = (level[c.s1 as usize], level[c.s2 as usize]);
        let lower = match self.lower_by_normal(ci, up) {
            1 if l1 < l2 => 1,
            2 if l2 < l1 => 2,
            _ => return 0,
        };
        let (lo, hi) = if lower == 1 { (c.s1, c.s2) } else { (c.s2, c.s1) };
        let (lo, hi) = (&self.bodies[lo as usize], &self.bodies[hi as usize]);
        let heavy = lo.dynamic && hi.inv_m * MASS_RATIO < lo.inv_m;
        if self.face(c) || heavy {
            lower
        } else {
            0
        }
    }

    /// Whether the lower body of support contact `ci` (side `lower`) can be
    /// held while its upper body is solved on it. The sweeps assume it: exact
    /// for a stack at rest and for a body landing on one, a guess that
    /// overshoots where the two tumble against each other; the reaction paid
    /// down then comes back up with the next warm start, and boxes were thrown
    /// out of a collapsing pile at 10 m/s. So: a contact that has settled; or
    /// a body landing flat on one face (see [`LANDING`]), or much heavier than
    /// the one under it, on a body held by settled contacts down to the ground
    /// (Gauss–Seidel moves a light body's worth of momentum per pass through
    /// it).
    fn holds(&self, ci: usize, lower: u8, held: &[u32]) -> bool {
        let c = &self.constraints[ci];
        let (below, above) = if lower == 1 { (c.s1, c.s2) } else { (c.s2, c.s1) };
        let heavy = self.bodies[above as usize].inv_m * MASS_RATIO < self.bodies[below as usize].inv_m;
        let below_held = held.is_empty() || held.get(below as usize).is_some_and(|&l| l != u32::MAX);
        (c.settled && !c.landing) || ((c.landing || heavy) && below_held)
    }

    /// Which side of constraint `ci` is below by its normal alone (within
    /// [`SUPPORT_ANGLE`] of the vertical; 0: neither).
    fn lower_by_normal(&self, ci: usize, up: &Vec3) -> u8 {
        let rising = self.constraints[ci].normal.dot(up);
        if rising >= SUPPORT_ANGLE {
            1
        } else if rising <= -SUPPORT_ANGLE {
            2
        } else {
            0
        }
    }

    /// The upper body of constraint `ci` if its normal is within
    /// [`SUPPORT_ANGLE`] of the vertical.
    fn upper_of(&self, ci: usize, up: &Vec3) -> Option<u32> {
        let c = &self.constraints[ci];
        match self.lower_by_normal(ci, up) {
            1 => Some(c.s2),
            2 => Some(c.s1),
            _ => None,
        }
    }

    /// How many faces (manifolds of three points or more) each solver body
    /// rests on.
    fn faces_below(&self, up: &Vec3) -> Vec<u32> {
        let mut faces = vec![0u32; self.bodies.len()];
        for (ci, c) in self.constraints.iter().enumerate() {
            if let Some(u) = self.upper_of(ci, up).filter(|_| self.face(c)) {
                faces[u as usize] += 1;
            }
        }
        faces
    }

    /// Whether the bodies of constraint `ci` meet at its points slower than
    /// `speed` (m/s) at the step start, or one of them is fixed or kinematic
    /// (it holds whatever the speed).
    fn settled(&self, ci: usize, b: &Bodies, speed: f64) -> bool {
        let c = &self.constraints[ci];
        if !self.bodies[c.s1 as usize].dynamic || !self.bodies[c.s2 as usize].dynamic {
            return true;
        }
        let rel = relative_velocity(c, b);
        self.points[c.start as usize..(c.start + c.len) as usize].iter().all(|p| rel(p).norm() <= speed)
    }

    /// Whether the bodies of constraint `ci` meet as a flat landing: their
    /// relative velocity at its points is within `speed` (m/s) of the points'
    /// mean, that mean is along the normal within `speed` and below `landing`.
    fn lands_flat(&self, ci: usize, b: &Bodies, speed: f64, landing: f64) -> bool {
        let c = &self.constraints[ci];
        let points = &self.points[c.start as usize..(c.start + c.len) as usize];
        let rel = relative_velocity(c, b);
        let mean = points.iter().map(&rel).sum::<Vec3>() / points.len() as f64;
        let across = mean - c.normal * c.normal.dot(&mean);
        mean.norm() <= landing && across.norm() <= speed && points.iter().all(|p| (rel(p) - mean).norm() <= speed)
    }

    /// Height of each solver body in the support graph: breadth first from the
    /// fixed and kinematic bodies over the contacts whose normal is within
    /// [`SUPPORT_ANGLE`] of the vertical and that `keep` accepts (unreached:
    /// `u32::MAX`).
    fn levels(&self, up: &Vec3, keep: impl Fn(usize) -> bool) -> Vec<u32> {
        let n = self.bodies.len();
        // The support graph as adjacency lists in one array (CSR).
        let supports = || {
            self.constraints.iter().enumerate().filter(|(ci, c)| c.normal.dot(up).abs() >= SUPPORT_ANGLE && keep(*ci))
        };
        let mut start = vec![0u32; n + 1];
        for (_, c) in supports() {
            start[c.s1 as usize + 1] += 1;
            start[c.s2 as usize + 1] += 1;
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut next = vec![0u32; start[n] as usize];
        for (_, c) in supports() {
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

    /// The two sweeps over the blocks, then the fraction of their change that
    /// leaves the least violation, per island (see [`Self::sweep_steps`]);
    /// Gauss–Seidel instead of the sweeps where the last velocity pass
    /// overshot (see `super::overshoot`).
    pub(crate) fn sweep_supports(&mut self, rule: &Rule) {
        if self.support.blocks.is_empty() {
            return;
        }
        let pushed = if rule.relax { self.pushed_islands() } else { Vec::new() };
        if rule.relax && !pushed.contains(&true) {
            return;
        }
        self.assemble_blocks(false);
        let rows = self.support.rows.len();
        self.support.targets.resize(rows, Target::Skip);
        self.support.pass += 1;
        self.support.solved.clear();
        // See `super::quiet`: an island is solved whole or left as it is.
        self.choose_islands(rule);
        self.keep_to_redo();
        if rule.relax {
            self.support.active.iter_mut().zip(&pushed).for_each(|(a, &k)| *a &= k);
        }
        if !self.support.active.contains(&true) {
            return;
        }
        let s = &mut self.support;
        s.debt.clear();
        s.debt.resize(s.rows.len(), 0.0);
        s.start_velocity.resize(self.bodies.len(), (Vec3::zeros(), Vec3::zeros()));
        s.touched.resize(self.bodies.len(), 0);
        s.paid.resize(self.bodies.len(), 0);
        s.start_lambda.resize(s.rows.len(), 0.0);
        let active: Vec<u32> = (0..s.islands as u32).filter(|&i| s.active.get(i as usize) == Some(&true)).collect();
        let (active, overshot) = self.set_overshot_aside(active, rule);
        self.in_islands(&active, |cs, i, sw| cs.sweep_island(i, sw));
        if !self.support.solved.is_empty() {
            self.take_back_overshoot(&active, rule);
        }
        if !overshot.is_empty() {
            self.in_islands(&overshot, |cs, i, _| cs.island_gauss_seidel(i, rule));
        }
        if !rule.relax {
            self.record_changes();
        }
    }

    /// Keeps the velocities of solver body `k` as they were before the sweeps,
    /// the first time this pass changes them.
    pub(crate) fn touch_body(&mut self, k: usize) {
        let s = &mut self.support;
        if s.touched[k] != s.pass {
            s.touched[k] = s.pass;
            s.start_velocity[k] = (self.bodies[k].v, self.bodies[k].w);
        }
    }

    /// Targets of block `g`'s rows for a velocity pass: a gap may close within
    /// the substep; friction and twist stop the slip.
    pub(crate) fn block_targets(&mut self, g: usize, rule: &Rule) {
        let rate = self.drift_rate(rule.relax);
        let s = &mut self.support;
        let (r0, r1) = (s.blocks[g].rows.0 as usize, s.blocks[g].rows.1 as usize);
        let mut i = r0;
        while i < r1 {
            let face = s.rows[i].face;
            let gap = Gap::new(&self.bodies, &self.constraints[face as usize]);
            while i < r1 && s.rows[i].face == face {
                s.targets[i] = match s.rows[i].kind {
                    RowKind::Normal(pi) => {
                        let p = &self.points[pi as usize];
                        let sep = rule.effective(gap.separation(p));
                        if rule.relax && sep > 0.0 {
                            // After the drift a gap is the next substep's business:
                            // closing it here would brake a body that has not arrived.
                            Target::Skip
                        } else {
                            // A rounded side's point falls by its curve besides.
                            let c = &self.constraints[face as usize];
                            let curve = super::rounded_curve::curve_now(&self.bodies, c, p, None, rule.inv_h);
                            Target::AtLeast(-rule.bias(sep) - curve * rule.inv_h)
                        }
                    }
                    // Sticking, the points travel their chords together (see
                    // `Patch::drift`); a row reads body 2's velocity relative
                    // to body 1's when body 1 is the lower.
                    RowKind::Tangent(a) => {
                        let c = &self.constraints[face as usize];
                        let sign = if c.lower == 1 { 1.0 } else { -1.0 };
                        Target::Friction(-sign * self.patches[face as usize].holding_drift()[a as usize] * rate)
                    }
                    RowKind::Twist => Target::Friction(0.0),
                };
                i += 1;
            }
        }
    }

    /// Applies the impulses block `k` kept back to its lower bodies.
    pub(super) fn pay(&mut self, k: usize) {
        let b = self.support.blocks[k];
        for ri in b.rows.0 as usize..b.rows.1 as usize {
            let d = std::mem::take(&mut self.support.debt[ri]);
            if d == 0.0 {
                continue;
            }
            let r = self.support.rows[ri];
            let l = r.lower as usize;
            if !self.bodies[l].dynamic {
                continue;
            }
            self.touch_body(l);
            self.support.paid[l] = self.support.pass;
            let lo = &mut self.bodies[l];
            lo.v += r.jl[0] * (d * lo.inv_m);
            lo.w += lo.inv_i * (r.jl[1] * d);
        }
    }
}

/// The velocity of body 2 relative to body 1 of constraint `c` at a point, from
/// the world's velocities at the step start (m/s).
fn relative_velocity(c: &super::contact::Constraint, b: &Bodies) -> impl Fn(&super::contact::Point) -> Vec3 {
    let (i, j) = (c.b1 as usize, c.b2 as usize);
    let (v1, w1) = (Vec3::from(b.linear_velocity[i]), Vec3::from(b.angular_velocity[i]));
    let (v2, w2) = (Vec3::from(b.linear_velocity[j]), Vec3::from(b.angular_velocity[j]));
    move |p| (v2 + w2.cross(&p.r2)) - (v1 + w1.cross(&p.r1))
}
