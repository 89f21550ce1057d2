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
//! in the pass before, [`QUIET`] of it.

use super::block::Target;
use super::contact::ContactSolver;

/// Fraction of the residual tolerance below which an island solved in the
/// last pass is taken as settled: above the round-off of a warm start (1e-15
/// m/s in a pyramid), below anything a pass leaves to be taken back.
const QUIET: f64 = 1e-3;

impl ContactSolver {
    /// Numbers the islands of the support blocks (`Block::island`).
    pub(crate) fn group_blocks(&mut self) {
        let n = self.bodies.len();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn root(parent: &mut [u32], mut k: u32) -> u32 {
            while parent[k as usize] != k {
                let up = parent[parent[k as usize] as usize];
                parent[k as usize] = up;
                k = up;
            }
            k
        }
        let s = &self.support;
        for b in &s.blocks {
            for r in &s.rows[b.rows.0 as usize..b.rows.1 as usize] {
                if self.bodies.get(r.lower as usize).is_some_and(|l| l.dynamic) {
                    let (x, y) = (root(&mut parent, b.body), root(&mut parent, r.lower));
                    parent[x.max(y) as usize] = x.min(y);
                }
            }
        }
        let mut id = vec![u32::MAX; n];
        let mut count = 0;
        for g in 0..self.support.blocks.len() {
            let top = root(&mut parent, self.support.blocks[g].body) as usize;
            if id[top] == u32::MAX {
                id[top] = count;
                count += 1;
            }
            self.support.blocks[g].island = id[top];
        }
        self.support.islands = count as usize;
    }

    /// Decides which islands this pass solves (`Support::active`) from their
    /// blocks' residuals after the warm start, and marks their bodies.
    pub(crate) fn choose_islands(&mut self) {
        let s = &self.support;
        let (tol, last) = (s.residual, s.pass - 1);
        let mut worst = vec![0.0f64; s.islands];
        let mut was_active = vec![false; s.islands];
        for g in 0..s.blocks.len() {
            let b = s.blocks[g];
            let i = b.island as usize;
            worst[i] = worst[i].max(self.block_residual(g));
            let world = self.bodies[b.body as usize].body as usize;
            was_active[i] |= s.disturbed.get(world) == Some(&last);
        }
        let active: Vec<bool> =
            worst.iter().zip(&was_active).map(|(&w, &was)| w > tol || (was && w > QUIET * tol)).collect();
        let s = &mut self.support;
        for b in &s.blocks {
            if active[b.island as usize] {
                let world = self.bodies[b.body as usize].body as usize;
                if s.disturbed.len() <= world {
                    s.disturbed.resize(world + 1, 0);
                }
                s.disturbed[world] = s.pass;
            }
        }
        s.active = active;
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
