//! What the support sweeps do where they overshoot.
//!
//! The sweeps ([`super::support`]) solve a column exactly while every block's
//! lower body is held as they assume. Where it is not (a face rocking on an
//! edge, a patch sliding: most often a column just kicked or landed), they
//! overshoot, and would feed on it from pass to pass. Two remedies, per
//! island:
//!
//! 1. keep the fraction of the sweeps' change that leaves the least violation
//!    of the island's rows (1 where the sweeps were exact);
//! 2. where that fraction is below [`SHORT`] in an island of two blocks or
//!    more, one Gauss–Seidel pass over its contacts, both ways (normals, then
//!    friction): the fraction alone threw most of the support away. A column
//!    of 30 cubes kicked at 1 cm/s kept 3–8 % of each sweep's change in its
//!    first step, its cubes fell into each other at 6 cm/s, and it collapsed
//!    within 4 s (`tests/test_kicked_towers.py`). Gauss–Seidel solves each
//!    contact on both its bodies at once, so it does not overshoot as the
//!    sweeps do (they hold the lower body and pay it later), and one pass
//!    takes up what the fraction left (two brought 30 of the 36 towers of
//!    `examples/tower_matrix.rs` to rest at 60 Hz, four 29, one all 36);
//! 3. the next velocity pass of the step gives such an island that
//!    Gauss–Seidel pass alone, without sweeping it first, and the pass after
//!    sweeps it again. Where a lower body is not held, the sweeps' change is
//!    mostly taken back: in a tumbling 4000-cube pile (steps 100–120) 92 % of
//!    the blocks swept were in islands that kept less than 0.9 of it (67 %
//!    less than 0.5), and the velocity passes, two exact or projected
//!    Gauss–Seidel solves a block, were two thirds of the step. Every other
//!    velocity pass instead of every one: the pile's step 233 → 167 ms
//!    (steps 100–120). Over the 36 kicked towers of
//!    `examples/tower_matrix.rs` at six step sizes (30 Hz to 500 Hz), 3 were
//!    left moving after 4 s and none toppled (before: 4, one of them toppled
//!    at 60 Hz), in 14.4 s of CPU time (18.2 s before). The one left moving,
//!    30 cubes 5 cm off axis kicked at 0.1 m/s, jiggles at 0.04–0.4 m/s at
//!    half the step sizes either way.
//!    Two passes of Gauss–Seidel for one of sweeps toppled a tilted tower of
//!    `tests/test_tilted_towers.py`: a column needs its sweeps.

use super::block::{RowKind, Target};
use super::contact::ContactSolver;
use super::friction::FrictionPass;
use super::impulse::Rule;

/// Fraction of the sweeps' change kept below which an island of two blocks or
/// more gets a Gauss–Seidel pass. Measured on 36 kicked towers at 60 Hz
/// (`examples/tower_matrix.rs`): from 0.5 to 0.99 all 36 come to rest; at
/// 1.0 (every island shortened, round-off included) 34 of them kept
/// jittering at 1 cm/s, Gauss–Seidel's soft step undoing what the sweeps had
/// solved.
const SHORT: f64 = 0.9;

impl ContactSolver {
    /// Per island of `active`, keeps the fraction of the sweeps' change that
    /// leaves the least violation, and passes Gauss–Seidel over those that
    /// kept little (in a velocity pass; a relax pass moves positions).
    pub(super) fn take_back_overshoot(&mut self, active: &[u32], rule: &Rule) {
        let steps = self.sweep_steps(active);
        if steps.iter().all(|&t| t >= 1.0) {
            return;
        }
        let relax = rule.relax;
        self.in_islands(active, |cs, i, _| {
            let step = steps.get(i).copied().unwrap_or(1.0);
            cs.shorten_island(i, step);
            if step < SHORT && !relax && cs.support.index.of(i).len() >= 2 {
                if let Some(o) = cs.support.overshot.get_mut(i) {
                    *o = true;
                }
                cs.island_gauss_seidel(i, rule);
            }
        });
    }

    /// Splits the `active` islands of a velocity pass into those to sweep and
    /// those the last velocity pass overshot (remedy 3 of the module docs),
    /// which the one after sweeps again.
    pub(super) fn set_overshot_aside(&mut self, active: Vec<u32>, rule: &Rule) -> (Vec<u32>, Vec<u32>) {
        let s = &mut self.support;
        s.overshot.resize(s.islands, false);
        if rule.relax || !s.overshot.contains(&true) {
            return (active, Vec::new());
        }
        let (overshot, sweep): (Vec<u32>, Vec<u32>) = active.into_iter().partition(|&i| s.skips_sweeps(i as usize, rule));
        for &i in &overshot {
            s.overshot[i as usize] = false;
        }
        (sweep, overshot)
    }

    /// One Gauss–Seidel pass over the support contacts of island `i`, block by
    /// block bottom up: the normals both ways, then the friction of each patch.
    pub(super) fn island_gauss_seidel(&mut self, i: usize, rule: &Rule) {
        let (s, every) = (&self.support, &[][..]);
        let faces = |g: &u32| {
            let b = &s.blocks[*g as usize];
            &s.faces[b.faces.0 as usize..b.faces.1 as usize]
        };
        for list in s.index.of(i).iter().map(faces) {
            super::impulse::solve_each(list, &self.constraints, &mut self.points, &mut self.bodies, (every, rule));
        }
        let rate = self.drift_rate(rule.relax);
        for list in s.index.of(i).iter().map(faces) {
            let pass = FrictionPass { closing: None, rate };
            super::friction::rub_each(list, &self.constraints, &mut self.points, (&mut self.patches, &self.shapes), &mut self.bodies, &pass);
        }
    }

    /// Per island, the fraction of the sweeps' change to keep: the one that
    /// leaves the least violation `Σ (row velocity − target)²` over its rows
    /// that hold (pushing points, sticking patches), quadratic in the fraction.
    /// It is 1 where the sweeps solved the blocks exactly (a column, a pyramid
    /// at rest); less where a lower body was not held as the sweeps assumed and
    /// they overshot, which would otherwise feed on itself from pass to pass.
    /// Islands share no body: one that overshoots does not hold back the
    /// others (with one fraction for all, a tumbling island kept the sweeps of
    /// every other island of the pile at a fraction of their change). Found
    /// for the `active` islands (1 for the others, which the sweeps left
    /// alone), on the pool's threads when the islands were swept there.
    fn sweep_steps(&self, active: &[u32]) -> Vec<f64> {
        let mut steps = vec![1.0; self.support.islands];
        let found: Vec<f64> = if self.wide() {
            use rayon::prelude::*;
            active.par_iter().map(|&i| self.island_step(i as usize)).collect()
        } else {
            active.iter().map(|&i| self.island_step(i as usize)).collect()
        };
        for (&i, t) in active.iter().zip(found) {
            if let Some(s) = steps.get_mut(i as usize) {
                *s = t;
            }
        }
        steps
    }

    /// [`Self::sweep_steps`] of island `i`, over its rows in order.
    fn island_step(&self, i: usize) -> f64 {
        let s = &self.support;
        let (mut along, mut square, mut worst) = (0.0, 0.0, 0.0f64);
        let now = |k: usize| (self.bodies[k].v, self.bodies[k].w);
        let before = |k: usize| if s.touched[k] == s.pass { s.start_velocity[k] } else { now(k) };
        for &g in s.index.of(i) {
            let block = &s.blocks[g as usize];
            for ri in block.rows.0 as usize..block.rows.1 as usize {
                let target = match s.targets[ri] {
                    Target::Skip => continue,
                    t => t.value(),
                };
                let r = &s.rows[ri];
                let (upper, lower) = (block.body as usize, r.lower as usize);
                if s.touched[upper] != s.pass && s.touched[lower] != s.pass {
                    continue;
                }
                let v0 = r.velocity(&before(upper), &before(lower)) - target;
                let v1 = r.velocity(&now(upper), &now(lower)) - target;
                let holds = match r.kind {
                    RowKind::Normal(_) => r.lambda(&self.points, &self.patches) > 0.0 || v0 < 0.0 || v1 < 0.0,
                    _ => !self.patches[r.face as usize].sliding,
                };
                if holds {
                    worst = worst.max(v1.abs());
                    along += v0 * (v1 - v0);
                    square += (v1 - v0) * (v1 - v0);
                }
            }
        }
        // Rows the sweeps left within the residual taken as solved have
        // nothing to take back, and the fraction of a change at round-off is
        // round-off.
        if worst <= s.residual {
            1.0
        } else if square > 0.0 {
            (-along / square).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// Keeps `step` of the sweeps' change in the velocities and impulses of
    /// island `i`: each body it touched, once (then marked untouched), and
    /// each block solved in this pass.
    fn shorten_island(&mut self, i: usize, step: f64) {
        let pass = self.support.pass;
        for k in 0..self.support.index.of(i).len() {
            let g = self.support.index.of(i)[k] as usize;
            let blk = self.support.blocks[g];
            for ri in blk.rows.0 as usize..blk.rows.1 as usize {
                for body in [blk.body, self.support.rows[ri].lower] {
                    self.shorten_body(body as usize, step);
                }
            }
            if blk.solved_pass != pass {
                continue;
            }
            for ri in blk.rows.0 as usize..blk.rows.1 as usize {
                let r = self.support.rows[ri];
                let l0 = self.support.start_lambda[ri];
                let l = r.lambda(&self.points, &self.patches);
                r.set_lambda(&mut self.points, &mut self.patches, l0 + (l - l0) * step);
            }
        }
    }

    /// Keeps `step` of the change of body `k`'s velocities in this pass, if
    /// the pass touched it and it was not shortened already.
    fn shorten_body(&mut self, k: usize, step: f64) {
        let s = &mut self.support;
        if s.touched.get(k) != Some(&s.pass) {
            return;
        }
        s.touched[k] = 0;
        let (v, w) = s.start_velocity[k];
        let b = &mut self.bodies[k];
        b.v = v + (b.v - v) * step;
        b.w = w + (b.w - w) * step;
    }
}
