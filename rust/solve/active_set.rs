//! Active-set solve of a block whose exact answer pulls at some of its points:
//! a box tipping onto an edge, one resting on a corner of the box below, the
//! most common block of a tumbling pile.
//!
//! The points that pull are let go (their impulse set to zero), the rest of the
//! block solved exactly again, and a let-go point whose velocity then falls
//! below its target taken back, until no point changes side (block principal
//! pivoting on the normals, Júdice & Pires 1994). Each round is one factored
//! solve of the rows kept; a projected Gauss–Seidel pass over the same block ran
//! its twelve sweeps without converging on most of them (1.9 M sweeps in 160
//! steps of a 400-box pile), and stops short of the answer this finds.

use super::block::{RowKind, Scratch, Target};
use super::ldlt::{factor, solve_factored};
use super::contact::ContactSolver;
use super::small_lcp::SLOW;

/// Whether a row's target is a point's push (which may be let go).
fn pushes(t: Target) -> bool {
    matches!(t, Target::AtLeast(_))
}

/// Rounds before a block is left to projected Gauss–Seidel: a point changes
/// side at most once or twice in the blocks of a pile.
const ROUNDS: usize = 8;

/// Scratch space of [`ContactSolver::active_set`]: per row, whether it is
/// kept; the kept rows in solve order, their `K`, its factor, their targets
/// and answer.
#[derive(Clone, Default)]
pub struct Pivot {
    kept: Vec<bool>,
    order: Vec<usize>,
    k: Vec<f64>,
    factor: Vec<f64>,
    r: Vec<f64>,
    y: Vec<f64>,
}

impl ContactSolver {
    /// Solves block `g` for `sc.r` with the points that pull let go; `sc.y`
    /// holds the exact solve's answer on entry. Returns whether the answer
    /// found pushes at every point kept, leaves every point let go separating,
    /// and fits the friction cones (else `sc.y` is for the caller to redo).
    pub(crate) fn active_set(&mut self, g: usize, sc: &mut Scratch) -> bool {
        let b = self.support.blocks[g];
        // A patch that slid is Coulomb's law at the cone's edge, which this
        // solve, holding every patch, cannot give.
        let faces = &self.support.faces[b.faces.0 as usize..b.faces.1 as usize];
        if faces.iter().any(|&f| self.patches[f as usize].sliding) {
            return false;
        }
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        let m = r1 - r0;
        let tiny = sc.round_off();
        let slow = SLOW * sc.r[..m].iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let pulls = |sc: &Scratch, i: usize| sc.lambda[i] + sc.y[i] < -tiny;
        sc.pivot.kept.clear();
        for i in 0..m {
            let let_go = pushes(self.support.targets[r0 + i]) && pulls(sc, i);
            sc.pivot.kept.push(!let_go);
        }
        // Every point pushes: the exact answer failed on friction alone.
        if sc.pivot.kept.iter().all(|&k| k) {
            return false;
        }
        self.ensure_k(g);
        for _ in 0..ROUNDS {
            self.solve_kept(g, sc);
            let mut changed = false;
            for i in 0..m {
                if sc.pivot.kept[i] && pushes(self.support.targets[r0 + i]) && pulls(sc, i) {
                    sc.pivot.kept[i] = false;
                    changed = true;
                }
            }
            if !changed {
                let k = &self.support.k[b.k as usize..b.k as usize + m * m];
                for i in 0..m {
                    if !sc.pivot.kept[i] {
                        let ky: f64 = k[i * m..(i + 1) * m].iter().zip(&sc.y[..m]).map(|(a, y)| a * y).sum();
                        if sc.r[i] - ky > slow {
                            sc.pivot.kept[i] = true;
                            changed = true;
                        }
                    }
                }
            }
            if !changed {
                return self.well_conditioned(g, sc) && self.fits(g, sc);
            }
        }
        false
    }

    /// `sc.y` with the let-go points at zero impulse and the kept rows solved
    /// exactly for what is left of their targets, normals ordered first so that
    /// a friction row the normals already hold is the one dropped as dependent.
    fn solve_kept(&self, g: usize, sc: &mut Scratch) {
        let b = self.support.blocks[g];
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        let m = r1 - r0;
        let k = &self.support.k[b.k as usize..b.k as usize + m * m];
        let rows = &self.support.rows[r0..r1];
        sc.pivot.order.clear();
        let is_normal = |i: usize| matches!(rows[i].kind, RowKind::Normal(_));
        sc.pivot.order.extend((0..m).filter(|&i| sc.pivot.kept[i] && is_normal(i)));
        sc.pivot.order.extend((0..m).filter(|&i| sc.pivot.kept[i] && !is_normal(i)));
        for i in 0..m {
            if !sc.pivot.kept[i] {
                sc.y[i] = -sc.lambda[i];
            }
        }
        let n = sc.pivot.order.len();
        sc.pivot.k.clear();
        sc.pivot.k.resize(n * n, 0.0);
        sc.pivot.factor.clear();
        sc.pivot.factor.resize(n * n, 0.0);
        sc.pivot.r.clear();
        sc.pivot.y.clear();
        sc.pivot.y.resize(n, 0.0);
        for (p, &i) in sc.pivot.order.iter().enumerate() {
            for (q, &j) in sc.pivot.order.iter().enumerate() {
                sc.pivot.k[p * n + q] = k[i * m + j];
            }
            let held: f64 = (0..m).filter(|&j| !sc.pivot.kept[j]).map(|j| k[i * m + j] * sc.y[j]).sum();
            sc.pivot.r.push(sc.r[i] - held);
        }
        factor(&sc.pivot.k, &mut sc.pivot.factor, n);
        solve_factored(&sc.pivot.factor, &sc.pivot.r, &mut sc.pivot.y);
        for (p, &i) in sc.pivot.order.iter().enumerate() {
            sc.y[i] = sc.pivot.y[p];
        }
    }
}
