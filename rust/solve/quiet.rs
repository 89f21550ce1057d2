//! Which support blocks a pass solves: an island of blocks (bodies joined by
//! support contacts, the fixed ones apart) is solved whole or not at all.
//!
//! A block within the residual of its targets after the warm start is left
//! alone, and a resting pile costs nothing. Gated block by block, that left
//! relative velocities below the residual in place and undamped, and what the
//! solves around them did came back as the warm start's echo (a body stopped
//! in one substep is pushed back by the impulse that stopped it in the next):
//! a dead band in a loop, which settles into a limit cycle. A resting 210-box
//! pyramid went from no block solves per step to 600 after 160 steps and never
//! came back, nothing moving more than 1e-7 m/s.
//!
//! Solved whole, an island ends each pass exactly at its targets; the pass
//! after takes back the echo; after that the warm start leaves only round-off
//! and the island is quiet again. So an island is solved while the largest
//! residual of its blocks exceeds the residual tolerance, or, if it was solved
//! in the pass before, while a block's residual exceeds [`QUIET`] of the
//! tolerance or of the change that pass made to the block's upper body,
//! whichever is smaller. A fixed [`QUIET`] of the tolerance left echoes of small
//! corrections in place: a column of a grid of cubes solved at the first
//! substep of each step for a speed of 1e-14 m/s had that correction repeated
//! by the warm start of each later substep, and so its speed grew fourfold a
//! step until it rocked at 1 cm/s.

use super::block::{RowKind, Target};
use super::contact::ContactSolver;
use super::impulse::{Rule, REST_DEPTH, TOUCHING};
use super::islands::find;

/// Relative growth of a lever allowed for between its bound, taken once a
/// step, and the arms the substeps refresh.
const ARM_SLACK: f64 = 1e-3;

/// Fraction of the residual tolerance below which an island solved in the
/// last pass is taken as settled: above the round-off of a warm start (1e-15
/// m/s in a pyramid), below anything a pass leaves to be taken back.
const QUIET: f64 = 1e-3;

/// Fraction of the residual tolerance that is the round-off of a warm start
/// (4e-15 m/s at 240 Hz substeps; 1e-15 in a resting pyramid): an echo below
/// it is not taken back.
const ROUND_OFF: f64 = 1e-7;

/// What [`ContactSolver::look_at_block`] compares a block with.
struct Look<'a> {
    rule: &'a Rule,
    /// Speed (m/s) under which a block's rows are not looked at.
    quiet: f64,
    /// Touching band (m).
    band: f64,
    /// The last velocity pass.
    last: u64,
}

impl ContactSolver {
    /// Numbers the islands of the support blocks (`Block::island`).
    pub(crate) fn group_blocks(&mut self) {
        let n = self.bodies.len();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        let s = &self.support;
        for b in &s.blocks {
            for r in &s.rows[b.rows.0 as usize..b.rows.1 as usize] {
                if self.bodies.get(r.lower as usize).is_some_and(|l| l.dynamic) {
                    let (x, y) = (find(&mut parent, b.body), find(&mut parent, r.lower));
                    parent[x.max(y) as usize] = x.min(y);
                }
            }
        }
        let mut id = vec![u32::MAX; n];
        let mut count = 0;
        for g in 0..self.support.blocks.len() {
            let top = find(&mut parent, self.support.blocks[g].body) as usize;
            if id[top] == u32::MAX {
                id[top] = count;
                count += 1;
            }
            self.support.blocks[g].island = id[top];
        }
        self.support.islands = count as usize;
    }

    /// Decides which islands this pass solves (`Support::active`) from their
    /// blocks' residuals after the warm start, marks their bodies, and sets
    /// the targets of their blocks' rows.
    ///
    /// A block whose bodies move too little for any of its points to leave
    /// the touching band since the step start, and too slowly for any row to
    /// be [`QUIET`] of the tolerance from its zero target, is within it
    /// without looking at its rows (see [`Self::block_motion`]): the targets
    /// and residuals of every row of a resting pyramid cost a quarter of its
    /// step.
    pub(crate) fn choose_islands(&mut self, rule: &Rule) {
        let (tol, last) = (self.support.residual, self.support.last_velocity_pass);
        let band = TOUCHING * REST_DEPTH * self.settings.slop;
        let islands = self.support.islands;
        let (mut worst, mut echo) = (vec![0.0f64; islands], vec![false; islands]);
        let look = Look { rule, quiet: QUIET * tol, band, last };
        let looks = self.look_at_blocks(&look);
        let mut targeted = vec![false; self.support.blocks.len()];
        for (g, &(w, t, was)) in looks.iter().enumerate() {
            let i = self.support.blocks[g].island as usize;
            worst[i] = worst[i].max(w);
            echo[i] |= was && w > self.echo_bound(g, tol);
            targeted[g] = t;
        }
        let active: Vec<bool> = worst.iter().zip(&echo).map(|(&w, &e)| w > tol || e).collect();
        for (g, &set) in targeted.iter().enumerate() {
            let b = self.support.blocks[g];
            if !active[b.island as usize] {
                continue;
            }
            // An island the last velocity pass overshot gets Gauss–Seidel
            // alone in this one (see `super::overshoot`), which reads no target.
            if !set && !self.support.skips_sweeps(b.island as usize, rule) {
                self.block_targets(g, rule);
            }
            if rule.relax {
                continue;
            }
            let world = self.bodies[b.body as usize].body as usize;
            let s = &mut self.support;
            if s.disturbed.len() <= world {
                s.disturbed.resize(world + 1, 0);
            }
            s.disturbed[world] = s.pass;
        }
        self.support.active = active;
        if !rule.relax {
            self.support.last_velocity_pass = self.support.pass;
        }
    }

    /// After the sweeps of a velocity pass: how much they changed the upper
    /// body of each block of the islands they solved (m/s, `|Δv| + arm |Δω|`),
    /// the echo the next warm start will bring back.
    pub(crate) fn record_changes(&mut self) {
        let s = &mut self.support;
        for b in &s.blocks {
            if s.active.get(b.island as usize) != Some(&true) {
                continue;
            }
            let k = b.body as usize;
            let (Some(sb), Some(&(v0, w0))) = (self.bodies.get(k), s.start_velocity.get(k)) else { continue };
            let moved = s.touched.get(k) == Some(&s.pass);
            let change = if moved { (sb.v - v0).norm() + b.arm * (sb.w - w0).norm() } else { 0.0 };
            let world = sb.body as usize;
            if s.change.len() <= world {
                s.change.resize(world + 1, 0.0);
            }
            s.change[world] = change;
        }
    }

    /// The residual above which block `g`, whose island the last velocity
    /// pass solved, has that pass's echo to take back: [`QUIET`] of the
    /// tolerance, or of the change that pass made to its upper body if that
    /// was smaller (the warm start repeats it), but not below [`ROUND_OFF`]
    /// of the tolerance.
    fn echo_bound(&self, g: usize, tol: f64) -> f64 {
        let world = self.bodies[self.support.blocks[g].body as usize].body as usize;
        let change = self.support.change.get(world).copied().unwrap_or(f64::INFINITY);
        (QUIET * tol.min(change)).max(ROUND_OFF * tol)
    }

    /// [`Self::look_at_block`] of every block, on the pool's threads when the
    /// islands are swept there (each block writes only its rows' targets).
    fn look_at_blocks(&mut self, look: &Look) -> Vec<(f64, bool, bool)> {
        let (n, wide) = (self.support.blocks.len(), self.wide());
        // Each body's motion once, not once per block it is in (three in a
        // pyramid: its own, and as the lower body of two): the norms were 7 %
        // of a resting 820-box pyramid's step.
        let mut motions = std::mem::take(&mut self.support.motions);
        motions.clear();
        motions.extend(self.bodies.iter().map(motion_of));
        self.support.motions = motions;
        self.par_map(n, wide, |cs, g| cs.look_at_block(g, look))
    }

    /// Of block `g`, after the warm start: how far it is from its targets
    /// (its bound, if it is within the quiet bound without looking at its
    /// rows; else its rows' targets set and their largest residual), whether
    /// its rows' targets were set, and whether its island was solved in the
    /// last velocity pass.
    fn look_at_block(&mut self, g: usize, look: &Look) -> (f64, bool, bool) {
        let b = self.support.blocks[g];
        let (speed, moved) = self.block_motion(g, |k| self.support.motions[k]);
        let world = self.bodies[b.body as usize].body as usize;
        let was = self.support.disturbed.get(world) == Some(&look.last);
        if speed <= look.quiet && b.high + moved <= look.band {
            (speed, false, was)
        } else {
            self.block_targets(g, look.rule);
            (self.block_residual(g), true, was)
        }
    }

    /// For the relax pass, which islands of blocks to sweep again: those with
    /// a body that a contact solved both ways between bodies that met faster
    /// than settled pushes. Such a contact (a box landing on a column) pushes
    /// the body under it into its supports after their sweep, and without
    /// another the body ended the substep moving down (at up to 0.8 m/s,
    /// measured), the position pass lifting it back each substep: a loop that
    /// kept a column of dropped cubes jiggling until it toppled and threw
    /// columns of a tumbling pile up at 2 m/s. Islands no
    /// such contact pushes are as their sweep left them.
    pub(crate) fn pushed_islands(&self) -> Vec<bool> {
        let mut pushed = Vec::new();
        for &ci in &self.ordinary {
            let c = &self.constraints[ci as usize];
            if c.settled || self.points[c.start as usize..(c.start + c.len) as usize].iter().all(|p| p.normal_impulse <= 0.0) {
                continue;
            }
            pushed.resize(self.bodies.len(), false);
            for k in [c.s1, c.s2] {
                if let Some(p) = pushed.get_mut(k as usize) {
                    *p |= k != 0;
                }
            }
        }
        if pushed.is_empty() {
            return Vec::new();
        }
        let s = &self.support;
        let mut keep = vec![false; s.islands];
        for r in &s.rows {
            if let Some(b) = s.blocks.get(r.block as usize) {
                let hit = |k: u32| pushed.get(k as usize).copied().unwrap_or(false);
                if let Some(k) = keep.get_mut(b.island as usize) {
                    *k |= hit(b.body) || hit(r.lower);
                }
            }
        }
        keep
    }

    /// Once a step (the plan made or taken back): each block's range of
    /// effective separations at the step start and the longest lever of its
    /// rows, for [`Self::block_motion`]. A block of a plan taken back whose
    /// faces were all kept as still (see `super::reuse::still_slack`) has the
    /// rows, anchors and separations of last step, bit for bit, and keeps its
    /// bounds (a resting pyramid of 820 boxes found them in 6 % of its step).
    pub(crate) fn bound_blocks(&mut self, restored: bool) {
        let rest = REST_DEPTH * self.settings.slop;
        let s = &mut self.support;
        let restored = restored && s.bound_rest == rest;
        s.bound_rest = rest;
        let (rows, points, faces, constraints) = (&s.rows, &self.points, &s.faces, &self.constraints);
        let bound = |b: &mut super::block::Block| {
            if restored && faces[b.faces.0 as usize..b.faces.1 as usize].iter().all(|&ci| constraints[ci as usize].still) {
                return;
            }
            // The longest arm squared: one square root a block, not four a row
            // (the same bits: a square root is monotone and correctly rounded).
            let (mut low, mut high, mut arm2) = (f64::INFINITY, f64::NEG_INFINITY, 1.0f64);
            for r in &rows[b.rows.0 as usize..b.rows.1 as usize] {
                arm2 = arm2.max(r.ju[1].norm_squared()).max(r.jl[1].norm_squared());
                if let RowKind::Normal(pi) = r.kind {
                    let p = &points[pi as usize];
                    let sep = p.separation + rest;
                    (low, high) = (low.min(sep), high.max(sep));
                    arm2 = arm2.max(p.anchor1.norm_squared()).max(p.anchor2.norm_squared());
                }
            }
            // The arms follow the bodies within the kept geometry's tolerance.
            (b.low, b.high, b.arm) = (low, high, arm2.sqrt() * (1.0 + ARM_SLACK) + super::gather::MOVE_EPS);
        };
        // Each block from its own rows: the same bits on any thread.
        if self.parallel && s.blocks.len() >= super::support::MIN_PARALLEL_PLAN {
            use rayon::prelude::*;
            s.blocks.par_iter_mut().with_min_len(super::support::PER_TASK).for_each(bound);
        } else {
            s.blocks.iter_mut().for_each(bound);
        }
    }

    /// Bounds for block `g` now, each body's motion (`|v|`, `|ω|`, `|Δp|`,
    /// `|Δq⃗|`: [`motion_of`]) taken from `of`: how fast any of its rows can
    /// move (m/s; a normal or friction row is `n·Δv` plus a lever's worth of
    /// `ω`, a twist row `n·Δω`), and how far any of its points can have moved
    /// along its normal since the step start (m; a turn by `θ` moves a point
    /// at arm `r` by `2 r sin(θ/2)`, which is `2 r |q⃗|` for the turn's
    /// quaternion), for the upper body and the fastest of the lower ones
    /// together.
    pub(crate) fn block_motion(&self, g: usize, of: impl Fn(usize) -> [f64; 4]) -> (f64, f64) {
        let s = &self.support;
        let b = s.blocks[g];
        let motion = |k: usize| {
            let [v, w, dp, dq] = of(k);
            (v + b.arm * w, dp + 2.0 * b.arm * dq)
        };
        let (mut speed, mut moved) = (0.0f64, 0.0f64);
        for &ci in &s.faces[b.faces.0 as usize..b.faces.1 as usize] {
            let c = &self.constraints[ci as usize];
            let lower = if c.lower == 1 { c.s1 } else { c.s2 };
            let (v, d) = motion(lower as usize);
            (speed, moved) = (speed.max(v), moved.max(d));
        }
        let (v, d) = motion(b.body as usize);
        (v + speed, d + moved)
    }

    /// How far any point of block `g` can have moved along its normal since
    /// the step start (m): [`Self::block_motion`]'s second bound alone (the
    /// position passes, where the bodies move between blocks).
    pub(crate) fn block_moved(&self, g: usize) -> f64 {
        let moved = |k: usize| {
            let sb = &self.bodies[k];
            [0.0, 0.0, sb.dp.norm(), sb.dq.vector().norm()]
        };
        self.block_motion(g, moved).1
    }

    /// Largest distance (m/s) of block `g`'s rows from their targets.
    fn block_residual(&self, g: usize) -> f64 {
        let s = &self.support;
        let b = s.blocks[g];
        let upper = &self.bodies[b.body as usize];
        let nu = (upper.v, upper.w);
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        s.rows[r0..r1].iter().zip(&s.targets[r0..r1]).fold(0.0f64, |worst, (row, t)| {
            if let Target::Skip = t {
                return worst;
            }
            let lo = &self.bodies[row.lower as usize];
            worst.max((t.value() - row.velocity(&nu, &(lo.v, lo.w))).abs())
        })
    }
}

/// `|v|`, `|ω|`, `|Δp|` and `|Δq⃗|` of a solver body (the turn since the step
/// start moves a point at arm `r` by `2 r |Δq⃗|`).
fn motion_of(sb: &super::solver_body::SolverBody) -> [f64; 4] {
    [sb.v.norm(), sb.w.norm(), sb.dp.norm(), sb.dq.vector().norm()]
}

#[cfg(test)]
mod tests {
    use crate::body::Shape;
    use crate::solve::block::RowKind;
    use crate::solve::solver_body::Gap;
    use crate::world::{BodySpec, Scene, Settings};

    /// The bounds of `block_motion` hold every row's speed and every point's
    /// separation, for a resting stack and for one whose top box is turned
    /// (slowly enough for its contacts to stay support contacts).
    #[test]
    fn block_bounds_hold_the_rows_and_points() {
        for throw in [0.0, 0.05] {
            let mut scene = Scene::new([0.0, 0.0, -9.81]).unwrap();
            let ground = Shape::plane([0.0, 0.0, 1.0], 0.0).unwrap();
            scene.add_body(BodySpec { shape: Some(ground), fixed: true, ..Default::default() }).unwrap();
            for (x, z) in [(-0.51, 0.5), (0.51, 0.5), (0.0, 1.5)] {
                let cube = Some(Shape::cuboid([0.5; 3]).unwrap());
                scene.add_body(BodySpec { shape: cube, density: Some(1000.0), position: [x, 0.0, z], ..Default::default() }).unwrap();
            }
            let mut settings = Settings::new(1.0 / 60.0);
            settings.sleep.enabled = false;
            let mut w = scene.build(&settings).unwrap();
            w.step(60).unwrap();
            w.bodies.angular_velocity[3] = [throw, -throw, 2.0 * throw];
            w.step(1).unwrap();
            let s = &w.collision.as_ref().unwrap().solver;
            let rest = crate::solve::impulse::REST_DEPTH * s.settings.slop;
            assert_eq!(s.support.blocks.len(), 3);
            for g in 0..s.support.blocks.len() {
                let b = s.support.blocks[g];
                let (speed, moved) = s.block_motion(g, |k| super::motion_of(&s.bodies[k]));
                for r in &s.support.rows[b.rows.0 as usize..b.rows.1 as usize] {
                    let (u, l) = (&s.bodies[b.body as usize], &s.bodies[r.lower as usize]);
                    assert!(r.velocity(&(u.v, u.w), &(l.v, l.w)).abs() <= speed * (1.0 + 1e-12));
                    if let RowKind::Normal(pi) = r.kind {
                        let sep = Gap::new(&s.bodies, &s.constraints[r.face as usize]).separation(&s.points[pi as usize]) + rest;
                        assert!(sep >= b.low - moved - 1e-15 && sep <= b.high + moved + 1e-15, "{sep} {b:?} {moved}");
                    }
                }
            }
        }
    }
}
